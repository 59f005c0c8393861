#include "formats/pbrt/media.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/input_limits.h"
#include "formats/pbrt/json_numbers.h"
#include "media/nanovdb_grid.h"
#include "media/scattering_presets.h"

namespace penumbra::pbrt {

namespace {

// A float parameter that must be finite and >= 0, as `key` of the JSON medium if given.
void mapNonNegative(const ParameterList& p, const char* name, const char* key, Json& medium) {
    if (auto v = p.getFloat(name)) {
        if (!(*v >= 0.0 && std::isfinite(*v)))
            failAt(p.find(name, {ParamType::Float})->where,
                   fmt::format("\"float {}\" must be finite and >= 0", name));
        medium[key] = *v;
    }
}

void mapPhase(const ParameterList& p, Json& medium) {
    if (auto g = p.getFloat("g")) {
        if (!(std::abs(*g) < 1.0))
            failAt(p.find("g", {ParamType::Float})->where, "\"float g\" must lie strictly between -1 and 1");
        // |g| = 1 is a delta distribution; penumbra's phase function takes |g| <= 0.99.
        medium["g"] = std::clamp(*g, -0.99, 0.99);
    }
}

// What the spectral types share: the coefficients (pbrt-v4's defaults: 1 each), scale and g.
void mapCoefficients(const ParameterList& p, const TextureTable& textures, WarningLog& log, Json& medium) {
    medium["sigma_a"] = rgbJson(readColor(p, "sigma_a", Rgb(1.0f), SpectrumUse::Unbounded, textures, log));
    medium["sigma_s"] = rgbJson(readColor(p, "sigma_s", Rgb(1.0f), SpectrumUse::Unbounded, textures, log));
    mapNonNegative(p, "scale", "scale", medium);
    mapPhase(p, medium);
}

// nx, ny, nz (pbrt-v4's defaults 1), checked.
std::array<int64_t, 3> readResolution(const ParameterList& p) {
    std::array<int64_t, 3> n{};
    const char* names[3] = {"nx", "ny", "nz"};
    for (int i = 0; i < 3; ++i) {
        n[size_t(i)] = p.getInt(names[i]).value_or(1);
        if (n[size_t(i)] < 1 || n[size_t(i)] > limits::kMaxGridSide)
            failAt(p.find(names[i], {ParamType::Integer})->where,
                   fmt::format("\"integer {}\" must be from 1 to {} (docs/limits.md)", names[i],
                               limits::kMaxGridSide));
    }
    return n;
}

// The values of a per-cell parameter: `perCell` numbers for each of the n[0] * n[1] * n[2] cells,
// finite and >= 0.
void checkCells(const Parameter& q, const std::array<int64_t, 3>& n, size_t perCell) {
    const uint64_t cells = uint64_t(n[0] * n[1] * n[2]);
    if (uint64_t(q.numbers.size()) != cells * perCell)
        failAt(q.where, fmt::format("{} values for \"{}\"; nx * ny * nz = {} x {} x {} = {} {}expected",
                                    q.numbers.size() / perCell, q.name, n[0], n[1], n[2], cells,
                                    perCell == 3 ? "colours " : ""));
    for (double v : q.numbers)
        if (!(v >= 0.0 && std::isfinite(v)))
            failAt(q.where, fmt::format("\"{}\" values must be finite and >= 0", q.name));
}

// The JSON format's lattice of a per-cell parameter, {"resolution": [nx, ny, nz], "values": [...]},
// checked before anything is built (an error thrown inside a braced JSON initializer would leave
// it half made).
Json latticeJson(const Parameter& q, const std::array<int64_t, 3>& n) {
    checkCells(q, n, 1);
    Json lattice = Json::object();
    lattice["resolution"] = Json::array({n[0], n[1], n[2]});
    lattice["values"] = q.numbers;
    return lattice;
}

// An rgb_grid's lattice of a per-cell colour parameter, {"values": [r, g, b, ...]}, checked first.
Json rgbLatticeJson(const Parameter& q, const std::array<int64_t, 3>& n) {
    checkCells(q, n, 3);
    Json lattice = Json::object();
    lattice["values"] = q.numbers;
    return lattice;
}

Json boundsJson(const ParameterList& p) {
    const Vec3d p0 = p.getPoint3("p0").value_or(Vec3d{0, 0, 0}),
                p1 = p.getPoint3("p1").value_or(Vec3d{1, 1, 1});
    return Json::array({Json::array({p0.x, p0.y, p0.z}), Json::array({p1.x, p1.y, p1.z})});
}

// pbrt-v4's temperatureoffset (or its older name temperaturecutoff) and temperaturescale.
void mapTemperatureTransform(const ParameterList& p, Json& medium) {
    const std::optional<double> offset =
        p.getFloat("temperatureoffset") ? p.getFloat("temperatureoffset") : p.getFloat("temperaturecutoff");
    if (offset) medium["temperature_offset"] = *offset;
    mapNonNegative(p, "temperaturescale", "temperature_scale", medium);
}

}  // namespace

Json mapMedium(const ParameterList& p, const Json& transform, const std::filesystem::path& folder,
               const TextureTable& textures, const SourceLocation& where, WarningLog& log) {
    const std::string type = p.getString("type").value_or("");
    Json medium = Json::object();
    if (type == "homogeneous") {
        medium["type"] = "homogeneous";
        mapCoefficients(p, textures, log, medium);
        // pbrt-v4 takes a preset it knows over sigma_a and sigma_s, and warns of one it does not.
        if (const Parameter* preset = p.find("preset", {ParamType::String})) {
            const std::string& name = preset->strings.at(0);
            if (findScatteringPreset(name)) {
                medium.erase("sigma_a");
                medium.erase("sigma_s");
                medium["preset"] = name;
            } else {
                log.warn(preset->where,
                         fmt::format("medium preset \"{}\" is unknown: sigma_a and sigma_s are used "
                                     "instead (as pbrt-v4 does)",
                                     name));
            }
        }
        const Rgb emission = readColor(p, "Le", Rgb(0.0f), SpectrumUse::Emission, textures, log) *
                             float(p.getFloat("Lescale").value_or(1.0));
        if (!emission.isBlack()) medium["emission"] = rgbJson(emission);
        // A homogeneous medium fills space: its transform changes nothing.
        return medium;
    }
    if (type == "uniformgrid") {
        medium["type"] = "grid";
        mapCoefficients(p, textures, log, medium);
        const Parameter* density = p.find("density", {ParamType::Float});
        if (!density || density->numbers.empty())
            failAt(where, "a uniformgrid medium needs \"float density\" values");
        const std::array<int64_t, 3> n = readResolution(p);
        medium["density"] = latticeJson(*density, n);
        medium["bounds"] = boundsJson(p);
        if (!transform.is_null()) medium["transform"] = transform;
        // Emission: a temperature grid (a blackbody) or a radiance "Le", times "Lescale".
        const Parameter* temperature = p.find("temperature", {ParamType::Float});
        const Parameter* le = p.find("Le", {ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody});
        if (temperature && le)
            failAt(le->where, "give either \"Le\" or \"temperature\" (as pbrt-v4 requires)");
        if (temperature) medium["temperature"] = latticeJson(*temperature, n);
        if (le) {
            const Rgb emission = readColor(p, "Le", Rgb(0.0f), SpectrumUse::Emission, textures, log);
            if (!emission.isBlack()) medium["emission"] = rgbJson(emission);
        }
        if (medium.contains("temperature") || medium.contains("emission")) {
            mapTemperatureTransform(p, medium);
            // Without "Lescale", pbrt-v4 scales the emission by a lattice of one cell of value 1:
            // by its SampledGrid's convention that is 1 at the box's centre, falling linearly to 1/8
            // at its corners. The same lattice here gives the same image.
            const Parameter* scale = p.find("Lescale", {ParamType::Float});
            medium["emission_scale"] =
                scale ? latticeJson(*scale, n) : Json{{"resolution", {1, 1, 1}}, {"values", {1.0}}};
        }
        p.markAllUsed();
        return medium;
    }
    if (type == "nanovdb") {
        // pbrt-v4's NanoVDBMedium: the file's "density" grid (or "gridname"), and its "temperature"
        // grid (or "temperaturename") if the file has one, emitting as a blackbody times "Lescale".
        medium["type"] = "grid";
        mapCoefficients(p, textures, log, medium);
        const Parameter* filename = p.find("filename", {ParamType::String});
        if (!filename || filename->strings.size() != 1 || filename->strings[0].empty())
            failAt(where, "a nanovdb medium needs its file as \"string filename\"");
        const std::string& file = filename->strings[0];
        const std::filesystem::path path =
            std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : folder / file;
        std::error_code error;
        if (!std::filesystem::is_regular_file(path, error))
            failAt(filename->where,
                   fmt::format("nanovdb medium: \"{}\" not found (looked for {})", file, path.string()));
        medium["density"] = Json{{"file", file}, {"grid", p.getString("gridname").value_or("density")}};
        const std::string temperatureName = p.getString("temperaturename").value_or("temperature");
        const std::vector<std::string> grids = readNanoVdbGridNames(path);
        if (std::find(grids.begin(), grids.end(), temperatureName) != grids.end()) {
            medium["temperature"] = Json{{"file", file}, {"grid", temperatureName}};
            mapTemperatureTransform(p, medium);
            mapNonNegative(p, "Lescale", "emission_scale", medium);
        }
        if (!transform.is_null()) medium["transform"] = transform;
        p.markAllUsed();
        return medium;
    }
    if (type == "rgbgrid") {
        // pbrt-v4's RGBGridMedium: RGB lattices of sigma_a, sigma_s (each 1 where not given) and Le
        // (which needs sigma_a), over the box p0-p1, times "scale" and "Lescale".
        medium["type"] = "rgb_grid";
        const std::array<int64_t, 3> n = readResolution(p);
        medium["resolution"] = {n[0], n[1], n[2]};
        const Parameter* sigmaA = p.find("sigma_a", {ParamType::Rgb});
        const Parameter* sigmaS = p.find("sigma_s", {ParamType::Rgb});
        const Parameter* le = p.find("Le", {ParamType::Rgb});
        if (!sigmaA && !sigmaS)
            failAt(where, "an rgbgrid medium needs \"rgb sigma_a\", \"rgb sigma_s\" or both");
        if (le && !sigmaA)
            failAt(le->where, "an rgbgrid medium with \"Le\" needs \"rgb sigma_a\" (as pbrt-v4 requires)");
        medium["sigma_a"] = sigmaA ? rgbLatticeJson(*sigmaA, n) : Json::array({1, 1, 1});
        medium["sigma_s"] = sigmaS ? rgbLatticeJson(*sigmaS, n) : Json::array({1, 1, 1});
        if (le) medium["emission"] = rgbLatticeJson(*le, n);
        mapNonNegative(p, "scale", "scale", medium);
        mapNonNegative(p, "Lescale", "emission_scale", medium);
        mapPhase(p, medium);
        medium["bounds"] = boundsJson(p);
        if (!transform.is_null()) medium["transform"] = transform;
        p.markAllUsed();
        return medium;
    }
    if (type == "cloud") {
        // pbrt-v4's CloudMedium: procedural noise in the box p0-p1.
        medium["type"] = "cloud";
        mapCoefficients(p, textures, log, medium);
        mapNonNegative(p, "density", "density", medium);
        mapNonNegative(p, "wispiness", "wispiness", medium);
        mapNonNegative(p, "frequency", "frequency", medium);
        medium["bounds"] = boundsJson(p);
        if (!transform.is_null()) medium["transform"] = transform;
        p.markAllUsed();
        return medium;
    }
    failAt(where, fmt::format("unknown medium type \"{}\" (pbrt-v4's are homogeneous, uniformgrid, rgbgrid, "
                              "cloud and nanovdb)",
                              type));
}

}  // namespace penumbra::pbrt
