#include "formats/pbrt/materials.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/input_limits.h"
#include "formats/pbrt/json_numbers.h"
#include "formats/pbrt/spectrum.h"
#include "media/scattering_presets.h"

namespace penumbra::pbrt {

namespace fs = std::filesystem;

namespace {

Rgb clamp01(Rgb c, const Parameter* p, WarningLog& log, std::string_view what) {
    const Rgb clamped{std::clamp(c.r, 0.0f, 1.0f), std::clamp(c.g, 0.0f, 1.0f), std::clamp(c.b, 0.0f, 1.0f)};
    if (p && (clamped.r != c.r || clamped.g != c.g || clamped.b != c.b))
        log.warn(p->where, fmt::format("{} outside [0, 1] clamped to it", what));
    return clamped;
}

// pbrt-v4's roughness parameters: "roughness", or "uroughness" and "vroughness"; remapped to the
// microfacet alpha with pbrt-v4's RoughnessToAlpha (sqrt) unless "remaproughness" is false.
// Returns {alpha along u, alpha along v}.
std::pair<double, double> readAlpha(const ParameterList& params, const TextureTable& textures,
                                    WarningLog& log, const std::string& prefix = "") {
    const double r = readScalar(params, prefix + "roughness", 0.0, textures, log);
    double u = readScalar(params, prefix + "uroughness", r, textures, log);
    double v = readScalar(params, prefix + "vroughness", r, textures, log);
    // A negative roughness has no alpha (pbrt-v4 would take its square root): not a smooth surface.
    for (const char* name : {"roughness", "uroughness", "vroughness"})
        if (const Parameter* p = params.find(prefix + name, {ParamType::Float, ParamType::Texture});
            p && !p->numbers.empty() && p->numbers[0] < 0.0)
            failAt(p->where,
                   fmt::format("parameter \"{}\" must be >= 0, found {}", p->declaration(), p->numbers[0]));
    const bool remap = params.getBool("remaproughness").value_or(true);
    if (remap) {
        u = std::sqrt(std::max(u, 0.0));
        v = std::sqrt(std::max(v, 0.0));
    }
    return {u, v};
}

// A roughness penumbra textures as pbrt-v4 does: `prefix`roughness naming a float texture that has a
// texture object, or uroughness and vroughness (each defaulting to roughness) of which one or both
// do: that object, or [u, v] with a number (clamped to [0, 1]) for an axis that is constant. Empty
// when no texture is involved (readAlpha then reads the constants) or one has no object.
std::optional<Json> texturedRoughness(const ParameterList& params, const TextureTable& textures,
                                      const std::string& prefix = "") {
    auto objectOf = [&](const std::string& name) -> std::optional<Json> {
        const Parameter* p = params.find(name, {ParamType::Float, ParamType::Texture});
        if (!p || p->type != ParamType::Texture || p->strings.size() != 1) return std::nullopt;
        const TextureTable::Texture* t = textures.scalar(p->strings[0]);
        return t ? t->object : std::nullopt;
    };
    const bool anisotropic = params.has(prefix + "uroughness") || params.has(prefix + "vroughness");
    if (!anisotropic) return objectOf(prefix + "roughness");
    // One axis: its texture's object, or its number; nothing for a texture without an object.
    auto axis = [&](const std::string& name) -> std::optional<Json> {
        const std::string source = params.has(prefix + name) ? prefix + name : prefix + "roughness";
        if (std::optional<Json> object = objectOf(source)) return object;
        const Parameter* p = params.find(source, {ParamType::Float, ParamType::Texture});
        if (!p) return Json(0.0);
        if (p->type == ParamType::Float && !p->numbers.empty())
            return Json(std::clamp(p->numbers[0], 0.0, 1.0));
        return std::nullopt;
    };
    const std::optional<Json> u = axis("uroughness"), v = axis("vroughness");
    if (!u || !v || (!u->is_object() && !v->is_object())) return std::nullopt;
    if (*u == *v) return u;
    return Json::array({*u, *v});
}

// Writes a textured roughness with pbrt-v4's mapping (alpha = sqrt(r) unless `remaproughness
// false`), and returns true; false when the roughness is not a texture penumbra takes.
bool addTexturedRoughness(Json& material, const ParameterList& params, const TextureTable& textures,
                          const std::string& prefix = "") {
    std::optional<Json> roughness = texturedRoughness(params, textures, prefix);
    if (!roughness) return false;
    material["roughness"] = std::move(*roughness);
    material["roughness_mapping"] = params.getBool("remaproughness").value_or(true) ? "sqrt" : "identity";
    for (const char* name : {"roughness", "uroughness", "vroughness"})
        params.find(prefix + name, {ParamType::Float, ParamType::Texture});  // read: not unused
    return true;
}

// Adds "alpha" when the surface is rough (penumbra renders alpha below 0.001 with the smooth model).
void addAlpha(Json& material, std::pair<double, double> alpha) {
    if (alpha.first <= 0.0 && alpha.second <= 0.0) return;
    const auto bounded = [](double a) { return std::clamp(a, 1e-4, 4.0); };
    if (alpha.first == alpha.second)
        material["alpha"] = bounded(alpha.first);
    else
        material["alpha"] = Json::array({bounded(alpha.first), bounded(alpha.second)});
}

// An index of refraction given as a float, a spectrum or a texture: its value (the spectrum's
// green channel, near 550 nm; dispersion is not rendered).
double readEta(const ParameterList& params, const TextureTable& textures, WarningLog& log,
               const std::string& name = "eta") {
    const Parameter* p =
        params.find(name, {ParamType::Float, ParamType::Spectrum, ParamType::Rgb, ParamType::Texture});
    if (!p) return 1.5;
    if (p->type == ParamType::Float) return p->numbers.at(0);
    const Rgb eta = readColor(params, name, Rgb(1.5f), SpectrumUse::Unbounded, textures, log);
    if (eta.r != eta.g || eta.g != eta.b)
        log.warn(
            p->where,
            "a spectrally varying index of refraction is rendered with its value at 550 nm (no dispersion)");
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
                failAt(p->where,
                       fmt::format("parameter \"{}\" takes one colour (3 numbers), found {} numbers",
                                   p->declaration(), p->numbers.size()));
            if (use != SpectrumUse::Unbounded)
                for (double v : p->numbers)
                    if (v < 0.0)
                        failAt(p->where,
                               fmt::format("parameter \"{}\" must not be negative", p->declaration()));
            return {float(p->numbers[0]), float(p->numbers[1]), float(p->numbers[2])};
        case ParamType::Float:
            if (p->numbers.size() != 1)
                failAt(p->where, fmt::format("parameter \"{}\" takes one value", p->declaration()));
            return Rgb(float(p->numbers[0]));
        case ParamType::Blackbody:
            if (p->numbers.empty() || !(p->numbers[0] > 0.0))
                failAt(p->where,
                       fmt::format("parameter \"{}\" needs a temperature in kelvin > 0", p->declaration()));
            if (use == SpectrumUse::Reflectance)
                failAt(p->where,
                       fmt::format("parameter \"{}\": a blackbody is an emission spectrum, not a reflectance",
                                   p->declaration()));
            return blackbodyRgb(p->numbers[0]);
        case ParamType::Spectrum: {
            if (!p->strings.empty()) {
                if (auto named = namedSpectrumRgb(p->strings[0])) return *named;
                failAt(p->where,  // the parser reads any other name as a file
                       fmt::format("parameter \"{}\": unknown named spectrum \"{}\"", p->declaration(),
                                   p->strings[0]));
            }
            for (size_t i = 2; i < p->numbers.size(); i += 2)
                if (!(p->numbers[i] > p->numbers[i - 2]))
                    failAt(p->where,
                           fmt::format("parameter \"{}\": wavelengths must increase", p->declaration()));
            return use == SpectrumUse::Emission ? emissionSpectrumRgb(p->numbers)
                                                : reflectanceSpectrumRgb(p->numbers);
        }
        case ParamType::Texture: {
            if (p->strings.size() != 1)
                failAt(p->where, fmt::format("parameter \"{}\" takes one texture name", p->declaration()));
            const TextureTable::Texture* t = textures.spectrum(p->strings[0]);
            if (!t) t = textures.scalar(p->strings[0]);
            if (!t)
                failAt(p->where, fmt::format("parameter \"{}\": unknown texture \"{}\"", p->declaration(),
                                             p->strings[0]));
            if (t->object)
                log.warn(p->where, fmt::format("a texture where penumbra takes none (parameter \"{}\"): {}",
                                               p->declaration(), t->standIn));
            return t->constant;
        }
        default:
            break;
    }
    return fallback;
}

double readScalar(const ParameterList& params, std::string_view name, double fallback,
                  const TextureTable& textures, WarningLog& log) {
    const Parameter* p = params.find(name, {ParamType::Float, ParamType::Texture});
    if (!p) return fallback;
    if (p->type == ParamType::Float) {
        if (p->numbers.size() != 1)
            failAt(p->where, fmt::format("parameter \"{}\" takes one value", p->declaration()));
        return p->numbers[0];
    }
    if (p->strings.size() != 1)
        failAt(p->where, fmt::format("parameter \"{}\" takes one texture name", p->declaration()));
    const TextureTable::Texture* t = textures.scalar(p->strings[0]);
    if (!t)
        failAt(p->where, fmt::format("parameter \"{}\": unknown float texture \"{}\"", p->declaration(),
                                     p->strings[0]));
    if (t->object)
        log.warn(p->where, fmt::format("a texture where penumbra takes none (parameter \"{}\"): {}",
                                       p->declaration(), t->standIn));
    return t->constant.r;
}

namespace {

// pbrt-v4's 2D texture mappings (TextureMapping2D::Create): "uv" (st = (uscale u + udelta, vscale v +
// vdelta)), and "spherical", "cylindrical" and "planar" (v1, v2, udelta, vdelta) of the point in the
// texture's space (the CTM at the Texture directive), which take no uscale or vscale (nor udelta or
// vdelta but planar), as pbrt-v4's.
void addUvMapping(Json& texture, const ParameterList& params, const Matrix4d& worldFromTexture) {
    const std::string mapping = params.getString("mapping").value_or("uv");
    const double us = params.getFloat("uscale").value_or(1.0), vs = params.getFloat("vscale").value_or(1.0);
    const double ud = params.getFloat("udelta").value_or(0.0), vd = params.getFloat("vdelta").value_or(0.0);
    const std::optional<Vec3d> v1 = params.getPoint3("v1"), v2 = params.getPoint3("v2");
    if (mapping == "uv") {
        if (us != 1.0 || vs != 1.0) texture["uv_scale"] = Json::array({us, vs});
        if (ud != 0.0 || vd != 0.0) texture["uv_offset"] = Json::array({ud, vd});
        return;
    }
    if (mapping != "spherical" && mapping != "cylindrical" && mapping != "planar")
        failAt(params.find("mapping", {ParamType::String})->where,
               fmt::format("unknown texture mapping \"{}\" (expected uv, spherical, cylindrical or planar)",
                           mapping));
    Json object{{"type", mapping}};
    if (!(worldFromTexture == Matrix4d::identity()))
        object["transform"] = Json::array({Json{{"matrix", matrixJson(worldFromTexture)}}});
    if (mapping == "planar") {
        // pbrt-v4's defaults: v1 (1, 0, 0), v2 (0, 1, 0).
        object["v1"] = vec3Json(v1.value_or(Vec3d{1.0, 0.0, 0.0}));
        object["v2"] = vec3Json(v2.value_or(Vec3d{0.0, 1.0, 0.0}));
        if (ud != 0.0 || vd != 0.0) texture["uv_offset"] = Json::array({ud, vd});
    }
    texture["mapping"] = std::move(object);
}

// A texture object scaled by a constant factor: an image's "scale" (unless it is inverted after
// its scale), a checkerboard's colours, or else a "scale" texture of it.
Json scaled(Json texture, float s) {
    if (texture["type"] == "image" && !texture.value("invert", false)) {
        Rgb old(1.0f);
        if (const auto it = texture.find("scale"); it != texture.end())
            old = it->is_array() ? Rgb((*it)[0].get<float>(), (*it)[1].get<float>(), (*it)[2].get<float>())
                                 : Rgb(it->get<float>());
        const Rgb product = old * s;
        texture["scale"] =
            product.r == product.g && product.g == product.b ? Json(shortest(product.r)) : rgbJson(product);
    } else if (texture["type"] == "checkerboard") {
        for (Json& c : texture["colors"]) {
            const Rgb v = c.is_array() ? Rgb(c[0].get<float>(), c[1].get<float>(), c[2].get<float>())
                                       : Rgb(c.get<float>());
            c = rgbJson(v * s);
        }
    } else {
        return Json{{"type", "scale"}, {"texture", std::move(texture)}, {"scale", shortest(s)}};
    }
    return texture;
}

// A texture object's size: its values (numbers, strings, ...) and the levels of textures in it
// (objects with a "type"). Counting stops once past `maxValues`.
struct TextureSize {
    size_t values = 0;
    int levels = 0;
};
void measureTexture(const Json& json, int level, size_t maxValues, TextureSize& size) {
    if (size.values > maxValues) return;
    if (json.is_object()) {
        if (json.contains("type")) size.levels = std::max(size.levels, ++level);
        for (const auto& [key, value] : json.items()) measureTexture(value, level, maxValues, size);
    } else if (json.is_array()) {
        for (const Json& value : json) measureTexture(value, level, maxValues, size);
    } else {
        ++size.values;
    }
}

// Textures built from textures copy their inputs, so a file whose every Texture line names the one
// before twice would double its texture at each line: a texture object is bounded in depth as the
// JSON reader bounds it (an input of an input ... 16 deep) and in size.
void checkTextureSize(const Json& object, const std::string& name, const SourceLocation& where) {
    TextureSize size;
    measureTexture(object, 0, limits::kMaxPbrtTextureValues, size);
    if (size.levels > 17 || size.values > limits::kMaxPbrtTextureValues)
        failAt(where,
               fmt::format("texture \"{}\": textures of textures nest at most 16 deep and hold at most {} "
                           "values in all (docs/limits.md)",
                           name, limits::kMaxPbrtTextureValues));
}

}  // namespace

void TextureTable::define(const std::string& name, const std::string& kind, const std::string& textureClass,
                          const ParameterList& params, const Matrix4d& worldFromTexture,
                          const SourceLocation& where, WarningLog& log) {
    const bool isFloat = kind == "float";
    if (!isFloat && kind != "spectrum")
        failAt(where, fmt::format("texture \"{}\": expected the type \"float\" or \"spectrum\", found \"{}\"",
                                  name, kind));
    // A texture parameter: a constant, or another texture of the same kind.
    auto input = [&](std::string_view param, Rgb fallback) -> Texture {
        const Parameter* p = params.find(
            param, isFloat ? std::initializer_list<ParamType>{ParamType::Float, ParamType::Texture}
                           : std::initializer_list<ParamType>{ParamType::Rgb, ParamType::Spectrum,
                                                              ParamType::Blackbody, ParamType::Texture,
                                                              ParamType::Float});
        if (p && p->type == ParamType::Texture && p->strings.size() == 1) {
            const Texture* t = isFloat ? scalar(p->strings[0]) : spectrum(p->strings[0]);
            if (!t)
                failAt(p->where, fmt::format("parameter \"{}\": unknown {} texture \"{}\"", p->declaration(),
                                             kind, p->strings[0]));
            return *t;
        }
        if (isFloat) return {Rgb(float(readScalar(params, param, fallback.r, *this, log))), std::nullopt, {}};
        return {readColor(params, param, fallback, SpectrumUse::Reflectance, *this, log), std::nullopt, {}};
    };
    // A float input (a scale's factor, a mix's amount): a number, or a float texture.
    auto floatInput = [&](std::string_view param, double fallback) -> Texture {
        const Parameter* p = params.find(param, {ParamType::Float, ParamType::Texture});
        if (p && p->type == ParamType::Texture) {
            const Texture* t = p->strings.size() == 1 ? scalar(p->strings[0]) : nullptr;
            if (!t)
                failAt(p->where, fmt::format("parameter \"{}\": unknown float texture", p->declaration()));
            return *t;
        }
        return {Rgb(float(readScalar(params, param, fallback, *this, log))), std::nullopt, {}};
    };
    // An input as penumbra's JSON: its texture object, or its constant.
    auto json = [](const Texture& t, bool scalar) -> Json {
        if (t.object) return *t.object;
        return scalar ? Json(shortest(t.constant.r)) : rgbJson(t.constant);
    };
    // The space of 3D textures: the transform current at the definition.
    auto addTransform = [&](Json& object) {
        if (!(worldFromTexture == Matrix4d::identity()))
            object["transform"] = Json::array({Json{{"matrix", matrixJson(worldFromTexture)}}});
    };
    Texture texture{Rgb(0.5f), std::nullopt, {}};
    if (textureClass == "constant") {
        texture = input("value", Rgb(1.0f));
    } else if (textureClass == "scale") {
        const Texture tex = input("tex", Rgb(1.0f));
        const Texture factor = floatInput("scale", 1.0);
        texture.constant = tex.constant * factor.constant.r;
        if (tex.object && !factor.object) {
            texture.object = scaled(*tex.object, factor.constant.r);
            texture.standIn = tex.standIn;
        } else if (factor.object) {
            texture.object =
                Json{{"type", "scale"}, {"texture", json(tex, isFloat)}, {"scale", json(factor, true)}};
            texture.standIn = "the product of its inputs' stand-ins";
        }
    } else if (textureClass == "mix" || textureClass == "directionmix") {
        const Texture a = input("tex1", Rgb(0.0f)), b = input("tex2", Rgb(1.0f));
        if (textureClass == "mix") {
            const Texture amount = floatInput("amount", 0.5);
            const float amt = amount.constant.r;
            texture.constant = a.constant * (1.0f - amt) + b.constant * amt;
            if (a.object || b.object || amount.object)
                texture.object = Json{{"type", "mix"},
                                      {"textures", Json::array({json(a, isFloat), json(b, isFloat)})},
                                      {"amount", json(amount, true)}};
        } else {
            // pbrt-v4 takes the direction into render space by the transform at the definition.
            const Vec3d dir = params.getPoint3("dir").value_or(Vec3d{0.0, 1.0, 0.0});
            const Vec3d world = worldFromTexture.applyVector(dir);
            if (!(length(world) > 0.0) || !std::isfinite(length(world)))
                failAt(params.find("dir", {ParamType::Vector3, ParamType::Point3})->where,
                       "directionmix: \"dir\" must be a non-zero vector");
            texture.constant = (a.constant + b.constant) * 0.5f;
            texture.object = Json{{"type", "direction_mix"},
                                  {"textures", Json::array({json(a, isFloat), json(b, isFloat)})},
                                  {"direction", vec3Json(normalize(world))}};
        }
        texture.standIn = "the mix of its inputs' stand-ins";
    } else if (textureClass == "checkerboard") {
        const Texture a = input("tex1", Rgb(1.0f)), b = input("tex2", Rgb(0.0f));
        texture.constant = (a.constant + b.constant) * 0.5f;
        texture.standIn = "the mean of the checkerboard's two values";
        const int64_t dimension = params.getInt("dimension").value_or(2);
        if (dimension == 3) {
            Json object{{"type", "checkerboard_3d"},
                        {"colors", Json::array({json(a, isFloat), json(b, isFloat)})}};
            addTransform(object);
            texture.object = std::move(object);
        } else if (dimension != 2 || a.object || b.object) {
            log.warn(where, dimension != 2
                                ? fmt::format("checkerboard \"dimension\" {}: the mean of its two values "
                                              "instead (2 and 3 are checkerboards)",
                                              dimension)
                                : "checkerboards of textures are not supported: the mean of their two "
                                  "stand-ins instead");
        } else {
            Json object{{"type", "checkerboard"}};
            object["colors"] = isFloat ? Json::array({shortest(a.constant.r), shortest(b.constant.r)})
                                       : Json::array({rgbJson(a.constant), rgbJson(b.constant)});
            addUvMapping(object, params, worldFromTexture);
            texture.object = std::move(object);
        }
    } else if (textureClass == "dots") {
        const Texture inside = input("inside", Rgb(1.0f)), outside = input("outside", Rgb(0.0f));
        texture.constant = (inside.constant + outside.constant) * 0.5f;
        texture.standIn = "the mean of its two values";
        Json object{{"type", "dots"}, {"inside", json(inside, isFloat)}, {"outside", json(outside, isFloat)}};
        addUvMapping(object, params, worldFromTexture);
        texture.object = std::move(object);
    } else if (textureClass == "bilerp") {
        Json values = Json::array();
        Rgb sum(0.0f);
        for (const auto& [name, fallback] : {std::pair{"v00", 0.0f}, std::pair{"v10", 0.0f},
                                             std::pair{"v01", 1.0f}, std::pair{"v11", 1.0f}}) {
            const Rgb v = isFloat
                              ? Rgb(float(params.getFloat(name).value_or(fallback)))
                              : readColor(params, name, Rgb(fallback), SpectrumUse::Reflectance, *this, log);
            values.push_back(isFloat ? Json(shortest(v.r)) : rgbJson(v));
            sum = sum + v;
        }
        texture.constant = sum * 0.25f;
        texture.standIn = "the mean of its four values";
        Json object{{"type", "bilerp"}, {"values", std::move(values)}};
        addUvMapping(object, params, worldFromTexture);
        texture.object = std::move(object);
    } else if (textureClass == "fbm" || textureClass == "wrinkled" || textureClass == "windy" ||
               textureClass == "marble") {
        Json object{{"type", textureClass}};
        if (textureClass != "windy") {
            if (auto octaves = params.getInt("octaves"))
                object["octaves"] = std::clamp<int64_t>(*octaves, 1, 32);
            if (auto omega = params.getFloat("roughness")) object["roughness"] = std::clamp(*omega, 0.0, 1.0);
        }
        if (textureClass == "marble") {
            if (auto scale = params.getFloat("scale")) object["scale"] = std::clamp(*scale, 0.0, 1e6);
            if (auto variation = params.getFloat("variation"))
                object["variation"] = std::clamp(*variation, 0.0, 1e6);
        }
        addTransform(object);
        // Noise averages about 0 (fbm, windy), a turbulence about half its octaves' weights, and
        // marble is grey: stand-ins for where penumbra takes no texture.
        texture.constant =
            textureClass == "marble" ? Rgb(0.87f) : Rgb(textureClass == "wrinkled" ? 0.5f : 0.0f);
        texture.standIn = "a constant near its mean";
        texture.object = std::move(object);
    } else if (textureClass == "imagemap") {
        const std::optional<std::string> file = params.getString("filename");
        if (!file || file->empty()) failAt(where, "imagemap needs a \"string filename\"");
        Json object{{"type", "image"}, {"file", *file}};
        const std::string wrap = params.getString("wrap").value_or("repeat");
        if (wrap == "black" || wrap == "clamp")
            object["wrap"] = wrap;
        else if (wrap != "repeat")
            log.warn(where,
                     fmt::format("texture wrap mode \"{}\" is not supported: \"repeat\" instead", wrap));
        const std::string filter = params.getString("filter").value_or("bilinear");
        static const std::map<std::string, std::string> kFilters{{"point", "closest"},
                                                                 {"bilinear", "bilinear"},
                                                                 {"trilinear", "trilinear"},
                                                                 {"ewa", "anisotropic"}};
        if (auto f = kFilters.find(filter); f != kFilters.end())
            object["filter"] = f->second;
        else {
            log.warn(where, fmt::format("texture filter \"{}\" is not supported: bilinear instead", filter));
            object["filter"] = "bilinear";
        }
        params.getFloat("maxanisotropy");
        if (auto encoding = params.getString("encoding")) {
            if (*encoding == "sRGB")
                object["color_space"] = "srgb";
            else if (*encoding == "linear")
                object["color_space"] = "linear";
            else
                log.warn(
                    where,
                    fmt::format(
                        "texture encoding \"{}\" is not supported: the file's own (sRGB for 8-bit images)",
                        *encoding));
        }
        const double scale = params.getFloat("scale").value_or(1.0);
        if (scale != 1.0) object["scale"] = scale;
        if (params.getBool("invert").value_or(false)) object["invert"] = true;
        addUvMapping(object, params, worldFromTexture);
        texture = {Rgb(0.5f), std::move(object), "the constant 0.5 instead of the image"};
    } else {
        params.markAllUsed();
        log.warn(where, fmt::format("texture class \"{}\" is not supported: replaced by the constant 0.5",
                                    textureClass));
    }
    params.reportUnused(log, fmt::format("Texture \"{}\"", textureClass));
    if (texture.object) checkTextureSize(*texture.object, name, where);
    if (isFloat) texture.constant = Rgb(texture.constant.r);
    (isFloat ? float_ : spectrum_)[name] = std::move(texture);
}

const TextureTable::Texture* TextureTable::spectrum(const std::string& name) const {
    auto it = spectrum_.find(name);
    return it == spectrum_.end() ? nullptr : &it->second;
}

const TextureTable::Texture* TextureTable::scalar(const std::string& name) const {
    auto it = float_.find(name);
    return it == float_.end() ? nullptr : &it->second;
}

namespace {

// pbrt-v4's SubsurfaceMaterial as penumbra's "subsurface": the same dielectric boundary (eta
// 1.33 and the roughness keys) and the same four ways of giving the interior (by "name", sigma_a
// and sigma_s, reflectance and mfp, or pbrt-v4's defaults), times "scale"; penumbra renders its
// transport by a random walk where pbrt-v4 uses its photon beam diffusion profile. Textured
// coefficients are read at their constant value (with a warning): a homogeneous medium has one.
// The texture object a spectrum parameter names, if it names one that has one.
std::optional<Json> spectrumTextureObject(const ParameterList& params, const TextureTable& textures,
                                          std::string_view name) {
    const Parameter* p = params.find(name, {ParamType::Rgb, ParamType::Spectrum, ParamType::Texture,
                                            ParamType::Float, ParamType::Blackbody});
    if (p && p->type == ParamType::Texture && p->strings.size() == 1)
        if (const TextureTable::Texture* t = textures.spectrum(p->strings[0]); t && t->object)
            return *t->object;
    return std::nullopt;
}

void subsurfaceMaterial(Json& m, const ParameterList& params, const TextureTable& textures, WarningLog& log,
                        const SourceLocation& where) {
    m["type"] = "subsurface";
    m["eta"] = params.has("eta") ? readEta(params, textures, log) : 1.33;
    double g = params.getFloat("g").value_or(0.0);
    if (const std::optional<double> scale = params.getFloat("scale")) {
        if (!(*scale > 0.0) || !std::isfinite(*scale))
            failAt(params.find("scale", {ParamType::Float})->where,
                   fmt::format("parameter \"float scale\" of a subsurface material must be > 0, found {}",
                               *scale));
        m["scale"] = *scale;
    }
    // A coefficient's texture object: the walk takes its value where it enters (pbrt-v4 evaluates
    // its BSSRDF's coefficients there).
    auto textureObject = [&](const char* parameter) {
        return spectrumTextureObject(params, textures, parameter);
    };
    const std::string name = params.getString("name").value_or("");
    const bool hasSigmaA = params.has("sigma_a"), hasSigmaS = params.has("sigma_s");
    if (!name.empty()) {
        const auto preset = std::find_if(kScatteringPresets.begin(), kScatteringPresets.end(),
                                         [&](const ScatteringPreset& p) { return p.name == name; });
        if (preset == kScatteringPresets.end())
            failAt(params.find("name", {ParamType::String})->where,
                   fmt::format("unknown measured medium \"{}\" (known: the names of pbrt-v4's "
                               "GetMediumScatteringProperties, e.g. Skin1, Marble, Ketchup)",
                               name));
        m["preset"] = name;
        if (g != 0.0)
            log.warn(where, "\"g\" is ignored with named scattering coefficients (they are reduced: g is 0)");
        g = 0.0;
    } else if (hasSigmaA || hasSigmaS) {
        if (hasSigmaA != hasSigmaS)
            failAt(where, fmt::format("a subsurface material with \"{}\" needs \"{}\" too",
                                      hasSigmaA ? "sigma_a" : "sigma_s", hasSigmaA ? "sigma_s" : "sigma_a"));
        for (const char* coefficient : {"sigma_a", "sigma_s"}) {
            if (std::optional<Json> object = textureObject(coefficient)) {
                m[coefficient] = *object;
                continue;
            }
            const Rgb c = readColor(params, coefficient, Rgb(0.0f), SpectrumUse::Unbounded, textures, log);
            m[coefficient] = rgbJson({std::max(c.r, 0.0f), std::max(c.g, 0.0f), std::max(c.b, 0.0f)});
        }
    } else if (params.has("reflectance")) {
        if (std::optional<Json> object = textureObject("reflectance"))
            m["reflectance"] = *object;
        else
            m["reflectance"] = rgbJson(
                clamp01(readColor(params, "reflectance", Rgb(1.0f), SpectrumUse::Reflectance, textures, log),
                        nullptr, log, ""));
        if (std::optional<Json> object = textureObject("mfp")) {
            m["mfp"] = *object;
            params.find("mfp", {ParamType::Texture});  // read: not unused
        } else {
            const Rgb mfp = readColor(params, "mfp", Rgb(1.0f), SpectrumUse::Unbounded, textures, log);
            if (!(mfp.minComponent() > 0.0f) || !mfp.isFinite())
                failAt(params
                           .find("mfp",
                                 {ParamType::Rgb, ParamType::Spectrum, ParamType::Float, ParamType::Texture})
                           ->where,
                       "parameter \"mfp\" (the mean free path) must be > 0 and finite in every channel");
            m["mfp"] = rgbJson(mfp);
        }
    }
    if (g != 0.0) m["g"] = std::clamp(g, -0.99, 0.99);
    if (addTexturedRoughness(m, params, textures)) return;
    addAlpha(m, readAlpha(params, textures, log));
}

}  // namespace

Json mapMaterial(const std::string& type, const ParameterList& params, const TextureTable& textures,
                 const SourceLocation& where, WarningLog& log) {
    auto reflectance = [&](std::string_view name, Rgb fallback) {
        const Rgb c = readColor(params, name, fallback, SpectrumUse::Reflectance, textures, log);
        return clamp01(c,
                       params.find(name, {ParamType::Rgb, ParamType::Spectrum, ParamType::Texture,
                                          ParamType::Float, ParamType::Blackbody}),
                       log, "a reflectance");
    };
    auto textureObject = [&](std::string_view name) { return spectrumTextureObject(params, textures, name); };
    // A reflectance that penumbra may texture: the texture object itself when it is one.
    auto texturable = [&](std::string_view name, Rgb fallback) -> Json {
        if (std::optional<Json> object = textureObject(name)) return *object;
        return rgbJson(reflectance(name, fallback));
    };
    // A conductor's index: pbrt-v4's artist-friendly `reflectance` (eta 1, k from the reflectance
    // at normal incidence: penumbra's conductor "reflectance", a colour or a texture), or eta and
    // k, each a constant or (pbrt-v4's spectrum textures) the texture, clamped where it is read.
    auto conductorJson = [&](const std::string& prefix, const std::string& reflectanceName) {
        Json c = Json::object();
        if (params.has(reflectanceName)) {
            c["reflectance"] = texturable(reflectanceName, Rgb(0.5f));
            return c;
        }
        if (std::optional<Json> object = textureObject(prefix + "eta")) {
            c["eta"] = *object;
        } else {
            const Rgb eta = readColor(params, prefix + "eta", *namedSpectrumRgb("metal-Cu-eta"),
                                      SpectrumUse::Unbounded, textures, log);
            c["eta"] = rgbJson({std::max(eta.r, 1e-4f), std::max(eta.g, 1e-4f), std::max(eta.b, 1e-4f)});
        }
        if (std::optional<Json> object = textureObject(prefix + "k")) {
            c["k"] = *object;
        } else {
            const Rgb k = readColor(params, prefix + "k", *namedSpectrumRgb("metal-Cu-k"),
                                    SpectrumUse::Unbounded, textures, log);
            c["k"] = rgbJson({std::max(k.r, 0.0f), std::max(k.g, 0.0f), std::max(k.b, 0.0f)});
        }
        return c;
    };
    // The slab and walk of pbrt-v4's layered materials: thickness 0.01 (a float texture's object
    // where it has one), albedo black, g 0, maxdepth 10, nsamples 1 (the others written only where a
    // file changes them).
    auto addLayeredSlab = [&](Json& material) {
        const Parameter* thickness = params.find("thickness", {ParamType::Float, ParamType::Texture});
        const TextureTable::Texture* texture =
            thickness && thickness->type == ParamType::Texture && thickness->strings.size() == 1
                ? textures.scalar(thickness->strings[0])
                : nullptr;
        if (texture && texture->object)
            material["thickness"] = *texture->object;
        else
            material["thickness"] = std::max(readScalar(params, "thickness", 0.01, textures, log), 0.0);
        if (params.has("albedo")) {
            Json albedo = texturable("albedo", Rgb(0.0f));
            if (!albedo.is_object())
                albedo = rgbJson(
                    clamp01(readColor(params, "albedo", Rgb(0.0f), SpectrumUse::Reflectance, textures, log),
                            nullptr, log, ""));
            material["medium_albedo"] = std::move(albedo);
        }
        if (params.has("g"))
            material["g"] = std::clamp(readScalar(params, "g", 0.0, textures, log), -0.999, 0.999);
        if (const std::optional<int64_t> depth = params.getInt("maxdepth"))
            material["max_depth"] = std::clamp<int64_t>(*depth, 1, 1000);
        if (const std::optional<int64_t> n = params.getInt("nsamples"))
            material["samples"] = std::clamp<int64_t>(*n, 1, 256);
    };
    Json m = Json::object();
    if (type == "diffuse") {
        m["type"] = "lambert";
        m["albedo"] = texturable("reflectance", Rgb(0.5f));
    } else if (type == "coateddiffuse") {
        // pbrt-v4's LayeredBxDF (materials/layered_bsdf.h), as pbrt-v4 renders it.
        m["type"] = "coated_diffuse";
        m["model"] = "layered";
        m["albedo"] = texturable("reflectance", Rgb(0.5f));
        m["eta"] = readEta(params, textures, log);
        if (!addTexturedRoughness(m, params, textures)) addAlpha(m, readAlpha(params, textures, log));
        addLayeredSlab(m);
    } else if (type == "dielectric") {
        m["type"] = "dielectric";
        m["eta"] = readEta(params, textures, log);
        if (addTexturedRoughness(m, params, textures)) {
            m["type"] = "rough_dielectric";
        } else {
            const auto alpha = readAlpha(params, textures, log);
            if (alpha.first > 0.0 || alpha.second > 0.0) m["type"] = "rough_dielectric";
            addAlpha(m, alpha);
        }
    } else if (type == "thindielectric") {
        m["type"] = "thin_dielectric";
        m["eta"] = readEta(params, textures, log);
    } else if (type == "coatedconductor") {
        // pbrt-v4's LayeredBxDF over its conductor (materials/layered_bsdf.h).
        m["type"] = "coated_conductor";
        m["eta"] = readEta(params, textures, log, "interface.eta");
        if (!addTexturedRoughness(m, params, textures, "interface."))
            addAlpha(m, readAlpha(params, textures, log, "interface."));
        Json conductor = conductorJson("conductor.", "reflectance");
        if (!addTexturedRoughness(conductor, params, textures, "conductor."))
            addAlpha(conductor, readAlpha(params, textures, log, "conductor."));
        m["conductor"] = std::move(conductor);
        addLayeredSlab(m);
    } else if (type == "conductor") {
        m = conductorJson("", "reflectance");
        if (addTexturedRoughness(m, params, textures)) {
            m["type"] = "rough_conductor";
        } else {
            const auto alpha = readAlpha(params, textures, log);
            m["type"] = alpha.first > 0.0 || alpha.second > 0.0 ? "rough_conductor" : "conductor";
            addAlpha(m, alpha);
        }
    } else if (type == "interface" || type == "" || type == "none") {
        // pbrt-v4 gives all three no BSDF: the boundary of a participating medium.
        m["type"] = "interface";
    } else if (type == "diffusetransmission") {
        // pbrt-v4 multiplies both by `scale` and clamps them to [0, 1].
        m["type"] = "diffuse_transmission";
        const double scale = params.getFloat("scale").value_or(1.0);
        auto scaledColor = [&](std::string_view name) -> Json {
            Json value = texturable(name, Rgb(0.25f));
            if (value.is_object()) return scale == 1.0 ? value : scaled(std::move(value), float(scale));
            const Rgb c = readColor(params, name, Rgb(0.25f), SpectrumUse::Reflectance, textures, log);
            return rgbJson(clamp01(c * float(scale), nullptr, log, ""));  // silently, as pbrt-v4
        };
        m["reflectance"] = scaledColor("reflectance");
        m["transmittance"] = scaledColor("transmittance");
    } else if (type == "hair") {
        // pbrt-v4's HairMaterial: sigma_a, else reflectance, else the melanins (eumelanin 1.3 when
        // none is given); textures of them are read at their constant value.
        m["type"] = "hair";
        // A float, or a float texture at its constant value.
        const auto scalar = [&](const char* name, double fallback) {
            if (const std::optional<double> value = params.getFloat(name)) return *value;
            return double(
                readColor(params, name, Rgb(float(fallback)), SpectrumUse::Unbounded, textures, log).g);
        };
        if (params.find("sigma_a",
                        {ParamType::Rgb, ParamType::Spectrum, ParamType::Float, ParamType::Texture}))
            m["sigma_a"] =
                rgbJson(readColor(params, "sigma_a", Rgb(0.0f), SpectrumUse::Unbounded, textures, log));
        else if (params.find("reflectance",
                             {ParamType::Rgb, ParamType::Spectrum, ParamType::Float, ParamType::Texture}))
            m["color"] = rgbJson(
                clamp01(readColor(params, "reflectance", Rgb(0.5f), SpectrumUse::Reflectance, textures, log),
                        nullptr, log, ""));
        else if (params.find("eumelanin", {ParamType::Float, ParamType::Texture}) ||
                 params.find("pheomelanin", {ParamType::Float, ParamType::Texture})) {
            m["eumelanin"] = std::max(0.0, scalar("eumelanin", 0.0));
            m["pheomelanin"] = std::max(0.0, scalar("pheomelanin", 0.0));
        }
        for (const auto& [name, fallback] : {std::pair{"eta", 1.55}, std::pair{"beta_m", 0.3},
                                             std::pair{"beta_n", 0.3}, std::pair{"alpha", 2.0}})
            if (const double value = scalar(name, fallback); value != fallback) m[name] = value;
        if (m.contains("beta_m")) m["beta_m"] = std::clamp(m["beta_m"].get<double>(), 0.0, 1.0);
        if (m.contains("beta_n")) m["beta_n"] = std::clamp(m["beta_n"].get<double>(), 0.0, 1.0);
        params.markAllUsed();
    } else if (type == "subsurface") {
        subsurfaceMaterial(m, params, textures, log, where);
    } else if (type == "measured") {
        // pbrt-v4's MeasuredMaterial: a BRDF of the RGL database, its .bsdf file found relative to
        // the scene file when the scene loads (materials/measured_bsdf.h).
        const std::optional<std::string> file = params.getString("filename");
        if (!file || file->empty())
            failAt(where, "a measured material needs its .bsdf file as \"string filename\"");
        m["type"] = "measured";
        m["filename"] = *file;
    } else {
        failAt(where,
               fmt::format("unknown material type \"{}\" (expected diffuse, coateddiffuse, coatedconductor, "
                           "conductor, dielectric, thindielectric, diffusetransmission, interface, measured, "
                           "hair, subsurface or mix)",
                           type));
    }
    // pbrt-v4's bump map (a float texture of heights) and normal map (an image of linear
    // tangent-space normals), which every material but interface takes.
    if (m.value("type", "") != "interface") {
        if (const Parameter* p = params.find("displacement", {ParamType::Float, ParamType::Texture})) {
            if (p->type == ParamType::Texture && p->strings.size() == 1) {
                const TextureTable::Texture* t = textures.scalar(p->strings[0]);
                if (!t)
                    failAt(p->where, fmt::format("parameter \"{}\": unknown float texture \"{}\"",
                                                 p->declaration(), p->strings[0]));
                if (t->object) m["bump"] = *t->object;  // a constant height turns nothing
            }
        }
        if (const std::optional<std::string> file = params.getString("normalmap"); file && !file->empty())
            m["normal_map"] =
                Json{{"type", "image"}, {"file", *file}, {"color_space", "linear"}, {"filter", "bilinear"}};
    }
    return m;
}

}  // namespace penumbra::pbrt
