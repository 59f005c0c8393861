#include "scenes/medium_reader.h"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/input_limits.h"
#include "media/nanovdb_grid.h"
#include "media/openvdb_grid.h"
#include "media/scattering_presets.h"
#include "scenes/name_reference.h"
#include "scenes/shape_reader.h"
#include "scenes/type_table.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// What every medium has: its coefficients (times "scale") and its phase function.
struct Coefficients {
    Rgb sigmaA{0.0f}, sigmaS{0.0f};
    HenyeyGreenstein phase;
};

Coefficients readCoefficients(const JsonValue& value) {
    Coefficients c;
    float scale = 1.0f;
    if (auto v = value.member("scale")) scale = v->numberAtLeast(0.0f);
    if (auto v = value.member("sigma_a")) c.sigmaA = v->rgb(0.0f) * scale;
    if (auto v = value.member("sigma_s")) c.sigmaS = v->rgb(0.0f) * scale;
    if (!(c.sigmaA + c.sigmaS).isFinite())
        value.fail("sigma_a and sigma_s times scale do not fit a 32-bit float");
    // |g| = 1 is a delta distribution, which the phase function's sampling cannot take.
    if (auto v = value.member("g")) c.phase.g = v->numberInRange(-0.99f, 0.99f);
    return c;
}

MediumModel readHomogeneous(const JsonValue& value, const fs::path&) { return readHomogeneousMedium(value); }

// "density": {"resolution": [nx, ny, nz], "values": [nx * ny * nz numbers >= 0, x fastest]}, or
// {"file": a .vdb (OpenVDB) or .nvdb (NanoVDB) file, "grid": the float grid's name (default
// "density")}, placed where the file says.
DensityGrid readDensity(const JsonValue& value, const fs::path& folder, bool& fromFile) {
    const JsonObject object(value, {"resolution", "values", "file", "grid"});
    fromFile = object.get("file").has_value();
    if (fromFile) {
        if (auto v = object.get("resolution"))
            v->fail("give either \"file\" or \"resolution\" and \"values\"");
        const JsonValue fileValue = object.require("file");
        const fs::path file = fileValue.existingFile(folder, "volume file");
        const std::string grid = object.get("grid") ? object.get("grid")->string() : "density";
        const std::string extension = file.extension().string();
        if (extension == ".vdb") return readOpenVdbGrid(file, grid);
        if (extension == ".nvdb") return readNanoVdbGrid(file, grid);
        fileValue.failExpected("an OpenVDB (.vdb) or NanoVDB (.nvdb) file");
    }
    if (auto v = object.get("grid")) v->fail("\"grid\" names a grid of a \"file\"");
    const JsonValue resolution = object.require("resolution");
    if (resolution.arraySize() != 3) resolution.failExpected("[nx, ny, nz]");
    DensityGrid grid;
    int* sizes[3] = {&grid.nx, &grid.ny, &grid.nz};
    for (size_t i = 0; i < 3; ++i) *sizes[i] = int(resolution.element(i).integer(1, limits::kMaxGridSide));
    const JsonValue values = object.require("values");
    const uint64_t count = uint64_t(grid.nx) * uint64_t(grid.ny) * uint64_t(grid.nz);
    if (values.arraySize() != count)
        values.failExpected(
            fmt::format("{} numbers (nx * ny * nz = {} x {} x {})", count, grid.nx, grid.ny, grid.nz));
    grid.values.reserve(count);
    for (const JsonValue& v : values.elements()) grid.values.push_back(v.numberAtLeast(0.0f));
    return grid;
}

GridBounds readBounds(const JsonValue& v) {
    if (v.arraySize() != 2) v.failExpected("[[x0, y0, z0], [x1, y1, z1]]");
    const GridBounds bounds{v.element(0).vec3(), v.element(1).vec3()};
    const Vec3f extent = bounds.upper - bounds.lower;
    if (!(extent.x > 0.0f && extent.y > 0.0f && extent.z > 0.0f))
        v.fail("the upper corner must exceed the lower one in x, y and z");
    return bounds;
}

// A scalar grid beside the density (temperature, emission scale): inline ones span the density's
// bounds, a file's lies where the file says.
DensityGrid readCompanionGrid(const JsonValue& value, const fs::path& folder,
                              const GridBounds& densityBounds) {
    bool fromFile = false;
    DensityGrid grid = readDensity(value, folder, fromFile);
    if (!fromFile) grid.bounds = densityBounds;
    return grid;
}

// "emission" (a colour) or "temperature" (a grid of kelvin, with "temperature_offset" and
// "temperature_scale"), times "emission_scale" (a number, or a grid).
GridEmission readGridEmission(const JsonValue& value, const fs::path& folder,
                              const GridBounds& densityBounds) {
    GridEmission emission;
    if (auto v = value.member("emission")) {
        if (value.member("temperature")) v->fail("give either \"emission\" or \"temperature\"");
        emission.radiance = v->rgb(0.0f);
    }
    if (auto v = value.member("temperature"))
        emission.temperature = readCompanionGrid(*v, folder, densityBounds);
    for (const char* key : {"temperature_offset", "temperature_scale"})
        if (auto v = value.member(key); v && !emission.temperature)
            v->fail(fmt::format("\"{}\" applies to a \"temperature\" grid, and there is none", key));
    if (auto v = value.member("temperature_offset")) emission.temperatureOffset = v->number();
    if (auto v = value.member("temperature_scale")) emission.temperatureScale = v->numberAtLeast(0.0f);
    if (auto v = value.member("emission_scale")) {
        if (v->json().is_object())
            emission.scaleGrid = readCompanionGrid(*v, folder, densityBounds);
        else
            emission.scale = v->numberAtLeast(0.0f);
    }
    return emission;
}

MediumModel readGrid(const JsonValue& value, const fs::path& folder) {
    const Coefficients c = readCoefficients(value);
    GridMedium medium;
    medium.sigmaA = c.sigmaA;
    medium.sigmaS = c.sigmaS;
    medium.phase = c.phase;
    bool fromFile = false;
    medium.density = readDensity(value.requiredMember("density"), folder, fromFile);
    if (auto v = value.member("bounds")) {
        if (fromFile) v->fail("a grid read from a file is placed where the file says: give no \"bounds\"");
        medium.density.bounds = readBounds(*v);
    }
    medium.emission = readGridEmission(value, folder, medium.density.bounds);
    if (auto v = value.member("transform")) medium.toWorld = readTransform(*v);
    medium.buildMajorants();
    return medium;
}

// An RGB coefficient of an "rgb_grid": [r, g, b] the same throughout the box, or {"values": [...]}
// with 3 * nx * ny * nz numbers >= 0 (r, g, b per cell, x fastest).
void readRgbLattice(const JsonValue& value, const int resolution[3], const GridBounds& bounds,
                    std::optional<RgbGrid>& lattice, Rgb& uniform) {
    if (!value.json().is_object()) {
        uniform = value.rgb(0.0f);
        return;
    }
    const JsonObject object(value, {"values"});
    const JsonValue values = object.require("values");
    const uint64_t cells = uint64_t(resolution[0]) * uint64_t(resolution[1]) * uint64_t(resolution[2]);
    if (values.arraySize() != 3 * cells)
        values.failExpected(fmt::format("{} numbers (3 per cell, {} x {} x {} cells)", 3 * cells,
                                        resolution[0], resolution[1], resolution[2]));
    RgbGrid grid{resolution[0], resolution[1], resolution[2], bounds, {}};
    grid.values.reserve(cells);
    const std::vector<JsonValue> numbers = values.elements();
    for (size_t i = 0; i < cells; ++i)
        grid.values.emplace_back(numbers[3 * i].numberAtLeast(0.0f), numbers[3 * i + 1].numberAtLeast(0.0f),
                                 numbers[3 * i + 2].numberAtLeast(0.0f));
    lattice = std::move(grid);
}

MediumModel readRgbGrid(const JsonValue& value, const fs::path&) {
    RgbGridMedium medium;
    const JsonValue resolution = value.requiredMember("resolution");
    if (resolution.arraySize() != 3) resolution.failExpected("[nx, ny, nz]");
    int n[3];
    for (size_t i = 0; i < 3; ++i) n[i] = int(resolution.element(i).integer(1, limits::kMaxGridSide));
    if (auto v = value.member("bounds")) medium.bounds = readBounds(*v);
    if (!value.member("sigma_a") && !value.member("sigma_s"))
        value.fail("an rgb_grid needs sigma_a, sigma_s or both");
    if (auto v = value.member("sigma_a"))
        readRgbLattice(*v, n, medium.bounds, medium.sigmaA, medium.uniformSigmaA);
    if (auto v = value.member("sigma_s"))
        readRgbLattice(*v, n, medium.bounds, medium.sigmaS, medium.uniformSigmaS);
    if (auto v = value.member("emission"))
        readRgbLattice(*v, n, medium.bounds, medium.emission, medium.uniformEmission);
    if (auto v = value.member("scale")) medium.scale = v->numberAtLeast(0.0f);
    if (auto v = value.member("emission_scale")) medium.emissionScale = v->numberAtLeast(0.0f);
    if (auto v = value.member("g")) medium.phase.g = v->numberInRange(-0.99f, 0.99f);
    if (auto v = value.member("transform")) medium.toWorld = readTransform(*v);
    medium.buildMajorants();
    for (const Rgb& m : medium.majorants.sigmaMaj)
        if (!m.isFinite()) value.fail("sigma_a and sigma_s times scale do not fit a 32-bit float");
    return medium;
}

MediumModel readCloud(const JsonValue& value, const fs::path&) {
    const Coefficients c = readCoefficients(value);
    CloudMedium medium;
    medium.sigmaA = c.sigmaA;
    medium.sigmaS = c.sigmaS;
    medium.phase = c.phase;
    if (auto v = value.member("density")) medium.density = v->numberAtLeast(0.0f);
    if (auto v = value.member("wispiness")) medium.wispiness = v->numberAtLeast(0.0f);
    if (auto v = value.member("frequency")) medium.frequency = v->numberAtLeast(0.0f);
    if (auto v = value.member("bounds")) medium.bounds = readBounds(*v);
    if (auto v = value.member("transform")) medium.toWorld = readTransform(*v);
    medium.buildMajorants();
    return medium;
}

using MediumReader = MediumModel (*)(const JsonValue&, const fs::path&);

const std::array<TypeRow<MediumReader>, 4> kMediumTypes{{
    {"homogeneous", {"type", "sigma_a", "sigma_s", "scale", "g", "emission", "preset"}, readHomogeneous},
    {"grid",
     {"type", "sigma_a", "sigma_s", "scale", "g", "density", "bounds", "transform", "emission", "temperature",
      "temperature_offset", "temperature_scale", "emission_scale"},
     readGrid},
    {"rgb_grid",
     {"type", "resolution", "sigma_a", "sigma_s", "emission", "scale", "emission_scale", "g", "bounds",
      "transform"},
     readRgbGrid},
    {"cloud",
     {"type", "sigma_a", "sigma_s", "scale", "g", "density", "wispiness", "frequency", "bounds", "transform"},
     readCloud},
}};

}  // namespace

HomogeneousMedium readHomogeneousMedium(const JsonValue& value) {
    Coefficients c = readCoefficients(value);
    // A measured medium by name (media/scattering_presets.h), in mm^-1, times "scale".
    if (auto v = value.member("preset")) {
        if (value.member("sigma_a") || value.member("sigma_s"))
            v->fail("give either \"preset\" or \"sigma_a\" and \"sigma_s\"");
        std::vector<std::string_view> names;
        for (const ScatteringPreset& preset : kScatteringPresets) names.push_back(preset.name);
        const ScatteringPreset& preset = kScatteringPresets[v->choice(names)];
        const float scale = value.member("scale") ? value.member("scale")->number() : 1.0f;
        c.sigmaA = preset.absorption * scale;
        c.sigmaS = preset.reducedScattering * scale;
        if (!(c.sigmaA + c.sigmaS).isFinite())
            value.fail("the preset's coefficients times scale do not fit a 32-bit float");
    }
    HomogeneousMedium medium{c.sigmaA, c.sigmaS, Rgb(0.0f), c.phase};
    if (auto v = value.member("emission")) medium.emission = v->rgb(0.0f);
    return medium;
}

void readMedia(const JsonValue& section, const fs::path& folder, Scene& scene) {
    for (const auto& [name, value] : section.members()) {
        if (name.empty()) value.fail("a medium needs a name: \"\" stands for the vacuum");
        scene.media.push_back(findTypeRow<MediumReader>(value, kMediumTypes).read(value, folder));
        scene.mediumNames.push_back(name);
    }
}

uint32_t readMediumReference(const JsonValue& value, const std::vector<std::string>& names) {
    if (value.json().is_null()) return MediumInterface::kVacuum;
    if (value.string().empty()) return MediumInterface::kVacuum;
    return readNameReference(value, names, "medium", "media", "; \"\" is the vacuum");
}

MediumInterface readMediumInterface(const JsonValue& shape, const std::vector<std::string>& names) {
    MediumInterface media;
    if (auto v = shape.member("inside")) media.inside = readMediumReference(*v, names);
    if (auto v = shape.member("outside")) media.outside = readMediumReference(*v, names);
    return media;
}

}  // namespace penumbra
