#include "formats/pbrt/media.h"

#include <fmt/format.h>

#include <cmath>

#include "core/input_limits.h"
#include "formats/pbrt/json_numbers.h"
#include "media/scattering_presets.h"

namespace penumbra::pbrt {

namespace {

// What both types share: the coefficients (pbrt-v4's defaults: 1 each), scale and g.
void mapCoefficients(const ParameterList& p, const TextureTable& textures, WarningLog& log, Json& medium) {
    medium["sigma_a"] = rgbJson(readColor(p, "sigma_a", Rgb(1.0f), SpectrumUse::Unbounded, textures, log));
    medium["sigma_s"] = rgbJson(readColor(p, "sigma_s", Rgb(1.0f), SpectrumUse::Unbounded, textures, log));
    if (auto scale = p.getFloat("scale")) {
        if (!(*scale >= 0.0 && std::isfinite(*scale)))
            failAt(p.find("scale", {ParamType::Float})->where, "\"float scale\" must be finite and >= 0");
        medium["scale"] = *scale;
    }
    if (auto g = p.getFloat("g")) {
        if (!(std::abs(*g) < 1.0))
            failAt(p.find("g", {ParamType::Float})->where, "\"float g\" must lie strictly between -1 and 1");
        // |g| = 1 is a delta distribution; penumbra's phase function takes |g| <= 0.99.
        medium["g"] = std::clamp(*g, -0.99, 0.99);
    }
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
        const std::vector<double> density = p.getFloats("density");
        if (density.empty()) failAt(where, "a uniformgrid medium needs \"float density\" values");
        int64_t n[3];
        const char* names[3] = {"nx", "ny", "nz"};
        for (int i = 0; i < 3; ++i) {
            n[i] = p.getInt(names[i]).value_or(1);
            if (n[i] < 1 || n[i] > limits::kMaxGridSide)
                failAt(p.find(names[i], {ParamType::Integer})->where,
                       fmt::format("\"integer {}\" must be from 1 to {} (docs/limits.md)", names[i],
                                   limits::kMaxGridSide));
        }
        if (uint64_t(density.size()) != uint64_t(n[0] * n[1] * n[2]))
            failAt(p.find("density", {ParamType::Float})->where,
                   fmt::format("{} density values; nx * ny * nz = {} x {} x {} = {} expected", density.size(),
                               n[0], n[1], n[2], n[0] * n[1] * n[2]));
        for (double d : density)
            if (!(d >= 0.0 && std::isfinite(d)))
                failAt(p.find("density", {ParamType::Float})->where,
                       "density values must be finite and >= 0");
        medium["density"] = Json{{"resolution", {n[0], n[1], n[2]}}, {"values", density}};
        const Vec3d p0 = p.getPoint3("p0").value_or(Vec3d{0, 0, 0}),
                    p1 = p.getPoint3("p1").value_or(Vec3d{1, 1, 1});
        medium["bounds"] = Json::array({Json::array({p0.x, p0.y, p0.z}), Json::array({p1.x, p1.y, p1.z})});
        if (!transform.is_null()) medium["transform"] = transform;
        for (const char* unsupported : {"temperature", "Le", "Lescale"})
            if (const Parameter* q = p.find(unsupported, {ParamType::Float, ParamType::Rgb,
                                                          ParamType::Spectrum, ParamType::Blackbody}))
                log.warn(q->where,
                         fmt::format("uniformgrid \"{}\" is not supported yet: the medium does not emit",
                                     unsupported));
        p.markAllUsed();
        return medium;
    }
    if (type == "nanovdb") {
        // pbrt-v4's NanoVDBMedium: the "density" grid of the file, where the file places it.
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
        medium["density"] = Json{{"file", file}, {"grid", "density"}};
        if (!transform.is_null()) medium["transform"] = transform;
        for (const char* unsupported :
             {"Le", "Lescale", "temperaturecutoff", "temperatureoffset", "temperaturescale"})
            if (const Parameter* q = p.find(unsupported, {ParamType::Float, ParamType::Rgb,
                                                          ParamType::Spectrum, ParamType::Blackbody}))
                log.warn(q->where,
                         fmt::format("nanovdb \"{}\" is not supported yet: the medium does not emit",
                                     unsupported));
        return medium;
    }
    if (type == "rgbgrid" || type == "cloud") {
        p.markAllUsed();
        log.warn(
            where,
            fmt::format("medium type \"{}\" is not supported yet: the medium is left out (vacuum)", type));
        return Json();
    }
    failAt(where, fmt::format("unknown medium type \"{}\" (pbrt-v4's are homogeneous, uniformgrid, rgbgrid, "
                              "cloud and nanovdb)",
                              type));
}

}  // namespace penumbra::pbrt
