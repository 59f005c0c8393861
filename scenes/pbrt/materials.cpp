#include "scenes/pbrt/materials.h"

#include <OpenEXR/ImfRgbaFile.h>
#include <OpenEXR/ImfArray.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scenes/pbrt/spectrum.h"

namespace penumbra::pbrt {

namespace fs = std::filesystem;

namespace {

double shortest(float v) { return std::stod(fmt::format("{}", v)); }  // as in scene_builder.cpp
Json rgbJson(Rgb c) { return Json::array({shortest(c.r), shortest(c.g), shortest(c.b)}); }

Rgb clamp01(Rgb c, const Parameter* p, WarningLog& log, std::string_view what) {
    const Rgb clamped{std::clamp(c.r, 0.0f, 1.0f), std::clamp(c.g, 0.0f, 1.0f), std::clamp(c.b, 0.0f, 1.0f)};
    if (p && (clamped.r != c.r || clamped.g != c.g || clamped.b != c.b))
        log.warn(p->where, fmt::format("{} outside [0, 1] clamped to it", what));
    return clamped;
}

// pbrt-v4's roughness parameters: "roughness", or "uroughness" and "vroughness"; remapped to the
// microfacet alpha with pbrt-v4's RoughnessToAlpha (sqrt) unless "remaproughness" is false.
// Returns {alpha along u, alpha along v}.
std::pair<double, double> readAlpha(const ParameterList& params, const TextureTable& textures) {
    const double r = readScalar(params, "roughness", 0.0, textures);
    double u = readScalar(params, "uroughness", r, textures);
    double v = readScalar(params, "vroughness", r, textures);
    const bool remap = params.getBool("remaproughness").value_or(true);
    if (remap) {
        u = std::sqrt(std::max(u, 0.0));
        v = std::sqrt(std::max(v, 0.0));
    }
    return {u, v};
}

// Adds "alpha" when the surface is rough (penumbra renders alpha below 0.001 with the smooth model).
void addAlpha(Json& material, std::pair<double, double> alpha) {
    if (alpha.first <= 0.0 && alpha.second <= 0.0) return;
    const auto bounded = [](double a) { return std::clamp(a, 1e-4, 4.0); };
    if (alpha.first == alpha.second) material["alpha"] = bounded(alpha.first);
    else material["alpha"] = Json::array({bounded(alpha.first), bounded(alpha.second)});
}

// An index of refraction given as a float, a spectrum or a texture: its value (the spectrum's
// green channel, near 550 nm; dispersion is not rendered).
double readEta(const ParameterList& params, const TextureTable& textures, WarningLog& log) {
    const Parameter* p = params.find("eta", {ParamType::Float, ParamType::Spectrum, ParamType::Rgb, ParamType::Texture});
    if (!p) return 1.5;
    if (p->type == ParamType::Float) return p->numbers.at(0);
    const Rgb eta = readColor(params, "eta", Rgb(1.5f), SpectrumUse::Unbounded, textures, log);
    if (eta.r != eta.g || eta.g != eta.b)
        log.warn(p->where, "a spectrally varying index of refraction is rendered with its value at 550 nm (no dispersion)");
    return eta.g;
}

}  // namespace

Rgb readColor(const ParameterList& params, std::string_view name, Rgb fallback, SpectrumUse use,
              const TextureTable& textures, WarningLog& log) {
    const Parameter* p = params.find(name, {ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody,
                                            ParamType::Texture, ParamType::Float});
    if (!p) return fallback;
    switch (p->type) {
        case ParamType::Rgb:
            if (p->numbers.size() != 3)
                failAt(p->where, fmt::format("parameter \"{}\" takes one colour (3 numbers), found {} numbers",
                                             p->declaration(), p->numbers.size()));
            if (use != SpectrumUse::Unbounded)
                for (double v : p->numbers)
                    if (v < 0.0) failAt(p->where, fmt::format("parameter \"{}\" must not be negative", p->declaration()));
            return {float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2])};
        case ParamType::Float:
            if (p->numbers.size() != 1) failAt(p->where, fmt::format("parameter \"{}\" takes one value", p->declaration()));
            return Rgb(float(p->numbers[0]));
        case ParamType::Blackbody:
            if (p->numbers.empty() || !(p->numbers[0] > 0.0))
                failAt(p->where, fmt::format("parameter \"{}\" needs a temperature in kelvin > 0", p->declaration()));
            if (use == SpectrumUse::Reflectance)
                failAt(p->where, fmt::format("parameter \"{}\": a blackbody is an emission spectrum, not a reflectance",
                                             p->declaration()));
            return blackbodyRgb(p->numbers[0]);
        case ParamType::Spectrum: {
            if (!p->strings.empty()) {
                if (auto named = namedSpectrumRgb(p->strings[0])) return *named;
                failAt(p->where, fmt::format("parameter \"{}\": unknown named spectrum \"{}\" (penumbra knows the "
                                             "metal-{{Cu,Au,Ag,Al}}-{{eta,k}}, glass-{{BK7,BAF10,FK51A,LASF9,F5}}, "
                                             "stdillum-D65 and stdillum-A spectra; spectrum files are not read)",
                                             p->declaration(), p->strings[0]));
            }
            for (size_t i = 2; i < p->numbers.size(); i += 2)
                if (!(p->numbers[i] > p->numbers[i - 2]))
                    failAt(p->where, fmt::format("parameter \"{}\": wavelengths must increase", p->declaration()));
            return use == SpectrumUse::Emission ? emissionSpectrumRgb(p->numbers) : reflectanceSpectrumRgb(p->numbers);
        }
        case ParamType::Texture: {
            if (p->strings.size() != 1) failAt(p->where, fmt::format("parameter \"{}\" takes one texture name", p->declaration()));
            if (auto t = textures.spectrum(p->strings[0])) return *t;
            if (auto t = textures.scalar(p->strings[0])) return Rgb(*t);
            failAt(p->where, fmt::format("parameter \"{}\": unknown texture \"{}\"", p->declaration(), p->strings[0]));
        }
        default: break;
    }
    return fallback;
}

double readScalar(const ParameterList& params, std::string_view name, double fallback, const TextureTable& textures) {
    const Parameter* p = params.find(name, {ParamType::Float, ParamType::Texture});
    if (!p) return fallback;
    if (p->type == ParamType::Float) {
        if (p->numbers.size() != 1) failAt(p->where, fmt::format("parameter \"{}\" takes one value", p->declaration()));
        return p->numbers[0];
    }
    if (p->strings.size() != 1) failAt(p->where, fmt::format("parameter \"{}\" takes one texture name", p->declaration()));
    if (auto t = textures.scalar(p->strings[0])) return *t;
    failAt(p->where, fmt::format("parameter \"{}\": unknown float texture \"{}\"", p->declaration(), p->strings[0]));
}

std::optional<Rgb> imageMean(const fs::path& file, bool srgbEncoded8Bit, const SourceLocation& where, WarningLog& log) {
    (void)srgbEncoded8Bit;  // for the 8-bit formats, once penumbra reads them (OpenEXR is linear)
    std::error_code error;
    if (!fs::is_regular_file(file, error)) {
        log.warn(where, fmt::format("image \"{}\" not found", file.string()));
        return std::nullopt;
    }
    // OpenEXR only: the program links no other image library (OpenImageIO is loaded for the
    // display image alone), and pbrt-v4's environment maps are EXR files.
    if (file.extension() != ".exr") {
        log.warn(where, fmt::format("image \"{}\" is not an EXR file, which is all penumbra reads here", file.string()));
        return std::nullopt;
    }
    try {
        Imf::RgbaInputFile input(file.string().c_str());
        const Imath::Box2i window = input.dataWindow();
        const int width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
        if (width <= 0 || height <= 0 || uint64_t(width) * uint64_t(height) > (uint64_t(1) << 28)) return std::nullopt;
        std::vector<Imf::Rgba> row(static_cast<size_t>(width));
        double sum[3] = {0, 0, 0};
        for (int y = window.min.y; y <= window.max.y; ++y) {
            input.setFrameBuffer(row.data() - window.min.x - ptrdiff_t(y) * width, 1, size_t(width));
            input.readPixels(y, y);
            for (const Imf::Rgba& p : row) {
                const float c[3] = {float(p.r), float(p.g), float(p.b)};
                for (int i = 0; i < 3; ++i) sum[i] += std::isfinite(c[i]) ? c[i] : 0.0;
            }
        }
        const double n = double(width) * double(height);
        return Rgb(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n));
    } catch (const std::exception& e) {
        log.warn(where, fmt::format("image \"{}\" could not be read: {}", file.string(), e.what()));
        return std::nullopt;
    }
}

void TextureTable::define(const std::string& name, const std::string& kind, const std::string& textureClass,
                          const ParameterList& params, const SourceLocation& where, const fs::path& folder,
                          WarningLog& log) {
    const bool isFloat = kind == "float";
    if (!isFloat && kind != "spectrum")
        failAt(where, fmt::format("texture \"{}\": expected the type \"float\" or \"spectrum\", found \"{}\"", name, kind));
    const SpectrumUse use = SpectrumUse::Reflectance;
    // A texture parameter that is itself a constant or another texture's name.
    auto color = [&](std::string_view param, Rgb fallback) {
        if (isFloat) return Rgb(float(readScalar(params, param, fallback.r, *this)));
        return readColor(params, param, fallback, use, *this, log);
    };
    Rgb value(0.5f);
    if (textureClass == "constant") {
        value = color("value", Rgb(1.0f));
    } else if (textureClass == "scale") {
        value = color("tex", Rgb(1.0f)) * float(readScalar(params, "scale", 1.0, *this));
    } else if (textureClass == "mix") {
        const float amount = float(readScalar(params, "amount", 0.5, *this));
        value = color("tex1", Rgb(0.0f)) * (1.0f - amount) + color("tex2", Rgb(1.0f)) * amount;
    } else if (textureClass == "checkerboard") {
        value = (color("tex1", Rgb(1.0f)) + color("tex2", Rgb(0.0f))) * 0.5f;
        log.warn(where, "checkerboard textures are not supported yet: replaced by the mean of its two textures");
    } else if (textureClass == "imagemap") {
        const std::string file = params.getString("filename").value_or("");
        const std::string encoding = params.getString("encoding").value_or("sRGB");
        const float scale = float(params.getFloat("scale").value_or(1.0));
        const bool invert = params.getBool("invert").value_or(false);
        const fs::path path = fs::path(file).is_absolute() ? fs::path(file) : folder / file;
        const std::optional<Rgb> mean = imageMean(path, encoding == "sRGB", where, log);
        value = mean.value_or(Rgb(0.5f)) * scale;
        if (invert) value = Rgb(1.0f) - value;
        if (isFloat) value = Rgb(value.average());
        log.warn(where, mean ? "image textures are not supported yet: replaced by the image's mean colour"
                             : "image textures are not supported yet: replaced by the constant 0.5");
    } else {
        params.markAllUsed();
        log.warn(where, fmt::format("texture class \"{}\" is not supported: replaced by the constant 0.5", textureClass));
    }
    params.reportUnused(log, fmt::format("Texture \"{}\"", textureClass));
    if (isFloat) float_[name] = value.r;
    else spectrum_[name] = value;
}

std::optional<Rgb> TextureTable::spectrum(const std::string& name) const {
    auto it = spectrum_.find(name);
    if (it == spectrum_.end()) return std::nullopt;
    return it->second;
}

std::optional<float> TextureTable::scalar(const std::string& name) const {
    auto it = float_.find(name);
    if (it == float_.end()) return std::nullopt;
    return it->second;
}

Json mapMaterial(const std::string& type, const ParameterList& params, const TextureTable& textures,
                 const SourceLocation& where, WarningLog& log) {
    auto reflectance = [&](std::string_view name, Rgb fallback) {
        const Rgb c = readColor(params, name, fallback, SpectrumUse::Reflectance, textures, log);
        return clamp01(c, params.find(name, {ParamType::Rgb, ParamType::Spectrum, ParamType::Texture, ParamType::Float,
                                             ParamType::Blackbody}),
                       log, "a reflectance");
    };
    Json m = Json::object();
    if (type == "diffuse") {
        m["type"] = "lambert";
        m["albedo"] = rgbJson(reflectance("reflectance", Rgb(0.5f)));
    } else if (type == "coateddiffuse") {
        m["type"] = "coated_diffuse";
        m["albedo"] = rgbJson(reflectance("reflectance", Rgb(0.5f)));
        m["eta"] = readEta(params, textures, log);
        addAlpha(m, readAlpha(params, textures));
    } else if (type == "dielectric") {
        m["type"] = "dielectric";
        m["eta"] = readEta(params, textures, log);
        const auto alpha = readAlpha(params, textures);
        if (alpha.first > 0.0 || alpha.second > 0.0) m["type"] = "rough_dielectric";
        addAlpha(m, alpha);
    } else if (type == "thindielectric") {
        m["type"] = "thin_dielectric";
        m["eta"] = readEta(params, textures, log);
    } else if (type == "conductor" || type == "coatedconductor") {
        const std::string prefix = type == "coatedconductor" ? "conductor." : "";
        Rgb eta, k;
        if (params.has(prefix + "reflectance")) {
            // pbrt-v4's artist-friendly conductor: eta = 1 and k = 2 sqrt(r) / sqrt(1 - r) give
            // the reflectance r at normal incidence.
            const Rgb r = reflectance(prefix + "reflectance", Rgb(0.5f));
            eta = Rgb(1.0f);
            for (int c = 0; c < 3; ++c) {
                const float rc = std::min(r[c], 0.9999f);
                (c == 0 ? k.r : c == 1 ? k.g : k.b) = 2.0f * std::sqrt(rc) / std::sqrt(1.0f - rc);
            }
        } else {
            eta = readColor(params, prefix + "eta", *namedSpectrumRgb("metal-Cu-eta"), SpectrumUse::Unbounded, textures, log);
            k = readColor(params, prefix + "k", *namedSpectrumRgb("metal-Cu-k"), SpectrumUse::Unbounded, textures, log);
        }
        m["eta"] = rgbJson({std::max(eta.r, 1e-4f), std::max(eta.g, 1e-4f), std::max(eta.b, 1e-4f)});
        m["k"] = rgbJson({std::max(k.r, 0.0f), std::max(k.g, 0.0f), std::max(k.b, 0.0f)});
        const auto alpha = type == "coatedconductor"
                               ? std::pair{readScalar(params, "conductor.roughness", 0.0, textures),
                                           readScalar(params, "conductor.roughness", 0.0, textures)}
                               : readAlpha(params, textures);
        m["type"] = alpha.first > 0.0 || alpha.second > 0.0 ? "rough_conductor" : "conductor";
        addAlpha(m, alpha);
        if (type == "coatedconductor")
            log.warn(where, "coatedconductor is rendered as its conductor alone (the coating is left out)");
    } else if (type == "interface" || type == "" || type == "none") {
        // An invisible boundary (of a participating medium): a thin dielectric of index 1 lets
        // every ray through unchanged.
        m["type"] = "thin_dielectric";
        m["eta"] = 1.0;
        if (type == "interface") log.warn(where, "interface material: rendered as an invisible surface (participating media are not supported)");
    } else if (type == "diffusetransmission") {
        m["type"] = "lambert";
        m["albedo"] = rgbJson(reflectance("reflectance", Rgb(0.25f)));
        log.warn(where, "diffusetransmission is rendered as its diffuse reflection alone (no transmission)");
    } else if (type == "measured" || type == "hair" || type == "subsurface") {
        params.markAllUsed();
        m["type"] = "lambert";
        m["albedo"] = 0.5;
        log.warn(where, fmt::format("material \"{}\" is not supported: rendered as grey diffuse (0.5)", type));
    } else {
        failAt(where, fmt::format("unknown material type \"{}\" (expected diffuse, coateddiffuse, coatedconductor, "
                                  "conductor, dielectric, thindielectric, diffusetransmission, interface, measured, "
                                  "hair, subsurface or mix)",
                                  type));
    }
    return m;
}

}  // namespace penumbra::pbrt
