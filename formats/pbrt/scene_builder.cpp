#include "formats/pbrt/scene_builder.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "core/input_file.h"
#include "core/input_limits.h"
#include "formats/pbrt/json_numbers.h"
#include "formats/pbrt/media.h"
#include "geometry/curves.h"
#include "textures/image_file.h"

namespace penumbra::pbrt {

namespace fs = std::filesystem;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegrees = 180.0 / kPi;

Matrix4d translation(Vec3d d) {
    Matrix4d m = Matrix4d::identity();
    m.m[0][3] = d.x, m.m[1][3] = d.y, m.m[2][3] = d.z;
    return m;
}

Matrix4d scaling(Vec3d s) {
    Matrix4d m = Matrix4d::identity();
    m.m[0][0] = s.x, m.m[1][1] = s.y, m.m[2][2] = s.z;
    return m;
}

// pbrt's Rotate: right-handed rotation by `degrees` about `axis` (Rodrigues).
Matrix4d rotation(double degrees, Vec3d axis) {
    const Vec3d a = normalize(axis);
    const double s = std::sin(degrees / kDegrees), c = std::cos(degrees / kDegrees);
    Matrix4d m = Matrix4d::identity();
    m.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
    m.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
    m.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
    m.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
    m.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
    m.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
    m.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
    m.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
    m.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
    return m;
}

// The 16 numbers of Transform / ConcatTransform are pbrt's matrix in column order.
Matrix4d fromColumns(const std::vector<double>& v) {
    Matrix4d m;
    for (int i = 0; i < 16; ++i) m.m[i % 4][i / 4] = v[size_t(i)];
    return m;
}

// A rigid motion key (scale, then rotate, then translate) of an affine matrix without shear;
// `sheared` is set when the matrix has shear, which such a key cannot hold.
Json motionKey(const Matrix4d& m, bool& sheared) {
    Vec3d c[3] = {{m.m[0][0], m.m[1][0], m.m[2][0]},
                  {m.m[0][1], m.m[1][1], m.m[2][1]},
                  {m.m[0][2], m.m[1][2], m.m[2][2]}};
    Vec3d scale{length(c[0]), length(c[1]), length(c[2])};
    if (m.determinant3() < 0) {  // a mirror: a negative x scale
        scale.x = -scale.x;
    }
    Vec3d r[3] = {c[0] * (1.0 / scale.x), c[1] * (1.0 / scale.y), c[2] * (1.0 / scale.z)};
    if (std::abs(dot(r[0], r[1])) > 1e-4 || std::abs(dot(r[0], r[2])) > 1e-4 ||
        std::abs(dot(r[1], r[2])) > 1e-4)
        sheared = true;
    // Rotation matrix (columns r) to a quaternion, then to axis and angle.
    const double trace = r[0].x + r[1].y + r[2].z;
    double w, x, y, z;
    if (trace > 0) {
        const double s = 0.5 / std::sqrt(trace + 1.0);
        w = 0.25 / s, x = (r[1].z - r[2].y) * s, y = (r[2].x - r[0].z) * s, z = (r[0].y - r[1].x) * s;
    } else if (r[0].x > r[1].y && r[0].x > r[2].z) {
        const double s = 2.0 * std::sqrt(1.0 + r[0].x - r[1].y - r[2].z);
        w = (r[1].z - r[2].y) / s, x = 0.25 * s, y = (r[1].x + r[0].y) / s, z = (r[2].x + r[0].z) / s;
    } else if (r[1].y > r[2].z) {
        const double s = 2.0 * std::sqrt(1.0 + r[1].y - r[0].x - r[2].z);
        w = (r[2].x - r[0].z) / s, x = (r[1].x + r[0].y) / s, y = 0.25 * s, z = (r[2].y + r[1].z) / s;
    } else {
        const double s = 2.0 * std::sqrt(1.0 + r[2].z - r[0].x - r[1].y);
        w = (r[0].y - r[1].x) / s, x = (r[2].x + r[0].z) / s, y = (r[2].y + r[1].z) / s, z = 0.25 * s;
    }
    const double sinHalf = std::sqrt(x * x + y * y + z * z);
    const double degrees = 2.0 * std::atan2(sinHalf, w) * kDegrees;
    const Vec3d axis = sinHalf > 1e-12 ? Vec3d{x / sinHalf, y / sinHalf, z / sinHalf} : Vec3d{0, 0, 1};
    return Json{{"scale", vec3Json(scale)},
                {"rotate", {{"axis", vec3Json(axis)}, {"degrees", degrees}}},
                {"translate", vec3Json({m.m[0][3], m.m[1][3], m.m[2][3]})}};
}

void requireNumberCount(const Parameter* p, size_t count) {
    if (p && p->numbers.size() != count)
        failAt(p->where, fmt::format("parameter \"{}\" takes {} numbers, found {}", p->declaration(), count,
                                     p->numbers.size()));
}

}  // namespace

SceneBuilder::SceneBuilder(fs::path mainFile, WarningLog& log)
    : mainFile_(std::move(mainFile)), folder_(mainFile_.parent_path()), log_(log) {
    scene_["materials"] = Json::object();
    scene_["shapes"] = Json::array();
    scene_["lights"] = Json::array();
    // pbrt-v4's defaults, where they differ from penumbra's.
    scene_["film"] = Json{{"resolution", {1280, 720}}, {"spp", 16}};
    scene_["integrator"] = Json{{"max_depth", 5}};
}

void SceneBuilder::requireWorld(const Directive& d, bool inWorld) const {
    if (inWorld && !inWorld_) failAt(d.where, fmt::format("{} is only allowed after WorldBegin", d.name));
    if (!inWorld && inWorld_) failAt(d.where, fmt::format("{} must come before WorldBegin", d.name));
}

void SceneBuilder::concat(const Matrix4d& t) {
    for (int i = 0; i < 2; ++i)
        if (state_.activeTransforms & (1u << i)) state_.ctm[size_t(i)] = state_.ctm[size_t(i)] * t;
}

void SceneBuilder::directive(Directive&& d) {
    const std::string& n = d.name;
    if (n == "Translate" || n == "Scale" || n == "Rotate" || n == "LookAt" || n == "Transform" ||
        n == "ConcatTransform" || n == "Identity" || n == "CoordinateSystem" || n == "CoordSysTransform" ||
        n == "ActiveTransform" || n == "TransformTimes") {
        transformDirective(d);
    } else if (n == "AttributeBegin" || n == "TransformBegin") {
        push(d, n == "AttributeBegin");
    } else if (n == "AttributeEnd" || n == "TransformEnd") {
        const bool attributes = n == "AttributeEnd";
        if (stack_.empty())
            failAt(d.where, fmt::format("{} without a matching {}", n,
                                        attributes ? "AttributeBegin" : "TransformBegin"));
        if (stack_.back().attributes != attributes)
            failAt(d.where, fmt::format("{} closes the {} at {}", n,
                                        stack_.back().attributes ? "AttributeBegin" : "TransformBegin",
                                        stack_.back().where.describe()));
        if (currentObject_ && stack_.size() == 1 && attributes)
            failAt(d.where, fmt::format("AttributeEnd closes the ObjectBegin \"{}\" at {} (use ObjectEnd)",
                                        currentObject_->first, currentObject_->second.describe()));
        if (attributes) {
            state_ = stack_.back().state;
        } else {
            state_.ctm = stack_.back().state.ctm;
            state_.activeTransforms = stack_.back().state.activeTransforms;
        }
        stack_.pop_back();
    } else if (n == "ReverseOrientation") {
        state_.reverseOrientation = !state_.reverseOrientation;
    } else if (n == "WorldBegin") {
        if (inWorld_) failAt(d.where, "a second WorldBegin");
        finishCamera(scene_);
        inWorld_ = true;
        state_.ctm = {Matrix4d::identity(), Matrix4d::identity()};
        state_.activeTransforms = 3;
        namedCoordinateSystems_["world"] = state_.ctm;
    } else if (n == "WorldEnd") {
        log_.warn(d.where, "WorldEnd is pbrt-v3 syntax; ignored");
    } else if (n == "Camera" || n == "Film" || n == "Sampler" || n == "PixelFilter" || n == "Integrator" ||
               n == "Accelerator" || n == "ColorSpace" || n == "Option") {
        optionDirective(d);
    } else if (n == "Material" || n == "MakeNamedMaterial" || n == "NamedMaterial" || n == "Texture") {
        materialDirective(d);
    } else if (n == "LightSource") {
        lightSource(d);
    } else if (n == "AreaLightSource") {
        areaLightSource(d);
    } else if (n == "ObjectBegin" || n == "ObjectEnd" || n == "ObjectInstance") {
        objectDirective(d);
    } else if (n == "Shape") {
        requireWorld(d, true);
        ShapeRecord shape{d.strings[0], std::move(d.parameters), state_, d.where};
        if (currentObject_) {
            objects_[currentObject_->first].push_back(std::move(shape));
        } else {
            addShape(shape, nullptr);
        }
    } else if (n == "MakeNamedMedium" || n == "MediumInterface") {
        mediumDirective(d);
    } else if (n == "Attribute") {
        d.parameters.markAllUsed();
        log_.warn(d.where,
                  "Attribute is not supported and was ignored (default attributes are not supported)");
    } else {
        failAt(d.where, fmt::format("directive '{}' is not handled", n));
    }
}

void SceneBuilder::push(const Directive& d, bool attributes) {
    if (stack_.size() >= size_t(limits::kMaxPbrtNesting))
        failAt(d.where,
               fmt::format(
                   "{} would open level {} of nesting: a pbrt scene nests AttributeBegin, TransformBegin and "
                   "ObjectBegin at most {} levels deep (docs/limits.md)",
                   d.name, stack_.size() + 1, limits::kMaxPbrtNesting));
    stack_.push_back({state_, attributes, d.where});
}

std::string SceneBuilder::unusedName(const char* section, const std::string& wanted) const {
    const auto members = scene_.find(section);
    if (members == scene_.end()) return wanted;
    std::string name = wanted;
    for (int i = 2; members->contains(name); ++i) name = fmt::format("{}#{}", wanted, i);
    return name;
}

void SceneBuilder::transformDirective(const Directive& d) {
    const std::string& n = d.name;
    const auto& v = d.numbers;
    if (n == "Translate") {
        concat(translation({v[0], v[1], v[2]}));
    } else if (n == "Scale") {
        concat(scaling({v[0], v[1], v[2]}));
    } else if (n == "Rotate") {
        const Vec3d axis{v[1], v[2], v[3]};
        if (!(length(axis) > 0.0)) failAt(d.where, "Rotate needs a non-zero axis");
        concat(rotation(v[0], axis));
    } else if (n == "LookAt") {
        // pbrt's LookAt: a world-to-camera transform of a left-handed camera frame.
        const Vec3d eye{v[0], v[1], v[2]}, look{v[3], v[4], v[5]}, up{v[6], v[7], v[8]};
        if (!(length(look - eye) > 0.0))
            failAt(d.where, "LookAt: the eye and the point looked at are the same");
        const Vec3d dir = normalize(look - eye);
        if (!(length(up) > 0.0) || !(length(cross(normalize(up), dir)) > 1e-9))
            failAt(d.where, "LookAt: the up vector is zero or parallel to the viewing direction");
        const Vec3d right = normalize(cross(normalize(up), dir));
        const Vec3d newUp = cross(dir, right);
        Matrix4d worldFromCamera = Matrix4d::identity();
        for (int i = 0; i < 3; ++i) {
            worldFromCamera.m[i][0] = right[i];
            worldFromCamera.m[i][1] = newUp[i];
            worldFromCamera.m[i][2] = dir[i];
            worldFromCamera.m[i][3] = eye[i];
        }
        concat(*worldFromCamera.inverse());
    } else if (n == "Transform") {
        const Matrix4d m = fromColumns(v);
        for (int i = 0; i < 2; ++i)
            if (state_.activeTransforms & (1u << i)) state_.ctm[size_t(i)] = m;
    } else if (n == "ConcatTransform") {
        concat(fromColumns(v));
    } else if (n == "Identity") {
        for (int i = 0; i < 2; ++i)
            if (state_.activeTransforms & (1u << i)) state_.ctm[size_t(i)] = Matrix4d::identity();
    } else if (n == "CoordinateSystem") {
        namedCoordinateSystems_[d.strings[0]] = state_.ctm;
    } else if (n == "CoordSysTransform") {
        auto it = namedCoordinateSystems_.find(d.strings[0]);
        if (it == namedCoordinateSystems_.end()) {
            log_.warn(d.where, fmt::format("CoordSysTransform: unknown coordinate system \"{}\"; ignored",
                                           d.strings[0]));
            return;
        }
        for (int i = 0; i < 2; ++i)
            if (state_.activeTransforms & (1u << i)) state_.ctm[size_t(i)] = it->second[size_t(i)];
    } else if (n == "ActiveTransform") {
        const std::string& which = d.strings[0];
        if (which == "StartTime")
            state_.activeTransforms = 1;
        else if (which == "EndTime")
            state_.activeTransforms = 2;
        else if (which == "All")
            state_.activeTransforms = 3;
        else
            failAt(d.where,
                   fmt::format("ActiveTransform expects StartTime, EndTime or All, found '{}'", which));
    } else if (n == "TransformTimes") {
        if (!(v[1] >= v[0]))
            failAt(d.where, "TransformTimes: the end time must not be before the start time");
        transformTimes_[0] = v[0];
        transformTimes_[1] = v[1];
    }
}

void SceneBuilder::optionDirective(const Directive& d) {
    const std::string& n = d.name;
    const ParameterList& p = d.parameters;
    if (n != "Option" && n != "ColorSpace") requireWorld(d, false);
    if (n == "Camera") {
        camera_.cameraFromWorld = state_.ctm;
        camera_.params = p;
        camera_.type = d.strings[0];
        camera_.where = d.where;
        camera_.given = true;
        camera_.medium = state_.outsideMedium;
        camera_.mediumWhere = state_.mediumWhere;
        // pbrt-v4 names the camera's coordinate system "camera".
        std::array<Matrix4d, 2> worldFromCamera;
        for (size_t i = 0; i < 2; ++i) {
            const auto inverse = state_.ctm[i].inverse();
            if (!inverse) failAt(d.where, "the camera transform is singular (it has no inverse)");
            worldFromCamera[i] = *inverse;
        }
        namedCoordinateSystems_["camera"] = worldFromCamera;
        return;  // its parameters are read at WorldBegin, when the film is known
    }
    Json& film = scene_["film"];
    if (n == "Film") {
        if (d.strings[0] != "rgb" && d.strings[0] != "gbuffer" && d.strings[0] != "spectral")
            log_.warn(d.where,
                      fmt::format("Film \"{}\" is not supported: rendered as an rgb film", d.strings[0]));
        const int64_t w = p.getInt("xresolution").value_or(1280), h = p.getInt("yresolution").value_or(720);
        if (w < 1 || h < 1 || w > 65536 || h > 65536)
            failAt(d.where, fmt::format("Film: resolution {}x{} is outside 1 to 65536 pixels a side", w, h));
        filmWidth_ = int(w), filmHeight_ = int(h);
        if (auto diagonal = p.getFloat("diagonal")) {
            if (!(*diagonal > 0.0 && *diagonal <= 1e4))
                failAt(p.find("diagonal", {ParamType::Float})->where,
                       fmt::format("Film: diagonal must be > 0 and <= 10000 mm, found {}", *diagonal));
            filmDiagonalMm_ = *diagonal;
        }
        film["resolution"] = {w, h};
        origins_.push_back({"/film/resolution", d.where});
        // pbrt-v4's sensor: the imaging ratio exposure time x iso / 100 and a white balance; for a
        // measured camera response (not here) pbrt-v4 balances to 6500 K unless told otherwise.
        filmIso_ = p.getFloat("iso").value_or(100.0);
        if (!(filmIso_ > 0.0 && filmIso_ <= 1e7))
            failAt(p.find("iso", {ParamType::Float})->where,
                   fmt::format("Film: iso must be > 0 and at most 1e7, found {}", filmIso_));
        const std::string sensor = p.getString("sensor").value_or("cie1931");
        filmWhiteBalance_ = p.getFloat("whitebalance").value_or(sensor == "cie1931" ? 0.0 : 6500.0);
        if (!(filmWhiteBalance_ == 0.0 || (filmWhiteBalance_ >= 1000.0 && filmWhiteBalance_ <= 100000.0)))
            failAt(
                p.find("whitebalance", {ParamType::Float})->where,
                fmt::format("Film: whitebalance must be 0 or a temperature from 1000 to 100000 K, found {}",
                            filmWhiteBalance_));
        if (sensor != "cie1931")
            log_.warn(
                p.find("sensor", {ParamType::String})->where,
                fmt::format("Film sensor \"{}\": its measured response is not in penumbra; rendered with "
                            "the CIE 1931 observer, white-balanced to {} K",
                            sensor, filmWhiteBalance_));
        if (auto f = p.getString("filename"))
            log_.warn(
                p.find("filename", {ParamType::String})->where,
                fmt::format("Film filename \"{}\" is not used: penumbra writes the EXR that -o names", *f));
        if (const Parameter* crop = p.find("cropwindow", {ParamType::Float})) {
            requireNumberCount(crop, 4);
            const auto& c = crop->numbers;
            for (double v : c)
                if (!(v >= 0.0 && v <= 1.0))
                    failAt(crop->where,
                           fmt::format(
                               "Film cropwindow: expected fractions of the image from 0 to 1, found {}", v));
            // pbrt-v4 takes each pair in either order.
            const double x0 = std::min(c[0], c[1]), x1 = std::max(c[0], c[1]);
            const double y0 = std::min(c[2], c[3]), y1 = std::max(c[2], c[3]);
            if (!(x1 > x0 && y1 > y0)) failAt(crop->where, "Film cropwindow: the window has no area");
            film["crop_window"] = Json::array({x0, x1, y0, y1});
            origins_.push_back({"/film/crop_window", crop->where});
        }
    } else if (n == "Sampler") {
        const std::string& type = d.strings[0];
        int64_t spp = p.getInt("pixelsamples").value_or(16);
        if (type == "stratified") {
            const int64_t xs = p.getInt("xsamples").value_or(4), ys = p.getInt("ysamples").value_or(4);
            // Two negative counts would multiply to a positive one.
            if (xs < 1 || ys < 1)
                failAt(d.where, fmt::format("Sampler \"stratified\": expected xsamples and ysamples of at "
                                            "least 1, found {} and {}",
                                            xs, ys));
            spp = xs * ys;
            p.getBool("jitter");
        }
        if (spp < 1)
            failAt(d.where, fmt::format("Sampler: expected at least 1 sample per pixel, found {}", spp));
        film["spp"] = spp;
        origins_.push_back({"/film/spp", d.where});
        // pbrt-v4's seed is any int: a negative one stays distinct from every other seed.
        if (auto seed = p.getInt("seed")) scene_["render"]["seed"] = uint64_t(*seed);
        origins_.push_back({"/render", d.where});
        if (type == "independent") {
            scene_["render"]["sampler"] = "independent";
        } else if (type != "stratified") {
            p.getString("randomization");
            log_.warn(
                d.where,
                fmt::format("Sampler \"{}\" is rendered with penumbra's stratified sampler (the same image "
                            "in expectation, different noise)",
                            type));
        }
    } else if (n == "PixelFilter") {
        filterGiven_ = true;
        const std::string& type = d.strings[0];
        const double defaultRadius = type == "box"        ? 0.5
                                     : type == "gaussian" ? 1.5
                                     : type == "sinc"     ? 4.0
                                                          : 2.0;
        const double xr = p.getFloat("xradius").value_or(defaultRadius),
                     yr = p.getFloat("yradius").value_or(defaultRadius);
        if (xr != yr)
            log_.warn(d.where, fmt::format("PixelFilter: xradius {} and yradius {} differ; both use {}", xr,
                                           yr, std::max(xr, yr)));
        double radius = std::max(xr, yr);
        std::string kind = "tent";
        if (type == "box") {
            kind = "box";
        } else if (type == "gaussian") {
            // The tent with the Gaussian's standard deviation (a tent of radius r has r / sqrt(6)).
            const double sigma = p.getFloat("sigma").value_or(0.5);
            radius = std::min(radius, sigma * std::sqrt(6.0));
            log_.warn(
                d.where,
                fmt::format("PixelFilter \"gaussian\" is rendered as a tent of the same standard deviation "
                            "(radius {:.3g})",
                            radius));
        } else if (type != "triangle") {
            p.markAllUsed();
            log_.warn(d.where,
                      fmt::format("PixelFilter \"{}\" is rendered as a tent of radius {}", type, radius));
        }
        if (!(radius > 0.0)) failAt(d.where, "PixelFilter: the radius must be > 0");
        film["filter"] = Json{{"type", kind}, {"radius", radius}};
        origins_.push_back({"/film/filter", d.where});
    } else if (n == "Integrator") {
        const std::string& type = d.strings[0];
        const int64_t depth = p.getInt("maxdepth").value_or(5);
        if (depth < 0) failAt(d.where, fmt::format("Integrator: maxdepth must be >= 0, found {}", depth));
        scene_["integrator"]["max_depth"] = depth;
        origins_.push_back({"/integrator", d.where});
        if (const auto sampler = p.getString("lightsampler")) {
            if (*sampler == "power") {
                scene_["integrator"]["light_sampler"] = "power";
            } else if (*sampler != "bvh") {
                log_.warn(
                    d.where,
                    fmt::format("Integrator \"lightsampler\" \"{}\" is not supported: lights are chosen "
                                "by penumbra's default (\"bvh\")",
                                *sampler));
            }
        }
        if (const Parameter* r = p.find("regularize", {ParamType::Bool}))
            log_.warn(r->where, "Integrator \"regularize\" is not supported and was ignored");
        if (type != "path" && type != "volpath")
            log_.warn(d.where,
                      fmt::format(
                          "Integrator \"{}\" is rendered with penumbra's path tracer (next-event estimation "
                          "with MIS)",
                          type));
    } else if (n == "Accelerator") {
        p.markAllUsed();
        log_.warn(d.where, "Accelerator is ignored: penumbra chooses its own (--accel)");
    } else if (n == "ColorSpace") {
        if (d.strings[0] != "srgb")
            log_.warn(d.where,
                      fmt::format("ColorSpace \"{}\" is not supported: colours are read as sRGB (Rec.709)",
                                  d.strings[0]));
    } else if (n == "Option") {
        p.markAllUsed();
        for (const Parameter& option : p.parameters())
            log_.warn(option.where,
                      fmt::format("Option \"{}\" is not supported and was ignored", option.declaration()));
    }
    p.reportUnused(log_, fmt::format("{} \"{}\"", n, d.strings.empty() ? "" : d.strings[0]));
}

void SceneBuilder::finishCamera(Json& scene) {
    const ParameterList& p = camera_.params;
    const SourceLocation& where = camera_.where;
    const std::string& type = camera_.type;
    if (type != "perspective" && type != "orthographic" && type != "spherical" && type != "realistic") {
        p.markAllUsed();
        log_.warn(where,
                  fmt::format("Camera \"{}\" is not supported: rendered as a perspective camera", type));
    }
    std::array<Matrix4d, 2> worldFromCamera;
    for (size_t i = 0; i < 2; ++i) worldFromCamera[i] = *camera_.cameraFromWorld[i].inverse();

    // The frame penumbra's camera would build from eye, forward and up has its x axis to the
    // image's right: when pbrt's camera x axis points the other way, mirror the world.
    auto poseOf = [](const Matrix4d& w) {
        const Vec3d eye = w.applyPoint({0, 0, 0});
        const Vec3d forward = normalize(w.applyVector({0, 0, 1}));
        const Vec3d up = normalize(w.applyVector({0, 1, 0}));
        return std::array<Vec3d, 3>{eye, forward, up};
    };
    const auto pose = poseOf(worldFromCamera[0]);
    const Vec3d right = normalize(cross(pose[1], pose[2]));
    if (dot(worldFromCamera[0].applyVector({1, 0, 0}), right) < 0.0) {
        // Reflection across the plane through the eye with normal `right`: p - 2 (n.(p - eye)) n.
        Matrix4d g = Matrix4d::identity();
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) g.m[i][j] -= 2.0 * right[i] * right[j];
            g.m[i][3] = 2.0 * right[i] * dot(right, pose[0]);
        }
        mirror_ = g;
    }

    Json camera = Json::object();
    // pbrt-v4's spherical images in penumbra's camera frame (cameras/spherical.h): the
    // equirectangular one has its centre on the camera's -x and its columns reversed, the equal-area
    // one is penumbra's turned half round the up axis; the pose turns to match.
    auto viewOf = [&](const std::array<Vec3d, 3>& pz) {
        if (type != "spherical") return pz[1];
        if (p.getString("mapping").value_or("equalarea") == "equirectangular")
            return normalize(cross(pz[1], pz[2])) * -1.0;
        return pz[1] * -1.0;
    };
    auto addPose = [&](Json& target, const std::array<Vec3d, 3>& pz) {
        target["look_from"] = vec3Json(pz[0]);
        target["look_at"] = vec3Json(pz[0] + viewOf(pz));
        target["up"] = vec3Json(pz[2]);
    };
    addPose(camera, pose);

    if (type == "spherical") {
        camera["type"] = "spherical";
        const std::string mapping = p.getString("mapping").value_or("equalarea");
        if (mapping != "equalarea" && mapping != "equirectangular")
            failAt(p.find("mapping", {ParamType::String})->where,
                   fmt::format(
                       "Camera \"spherical\": mapping must be \"equalarea\" or \"equirectangular\", found "
                       "\"{}\"",
                       mapping));
        if (mapping == "equirectangular") {
            camera["mirror"] = true;
        } else {
            camera["mapping"] = "equal_area";
            if (filmWidth_ != filmHeight_)
                failAt(where,
                       fmt::format("Camera \"spherical\": an equal-area image is square; the film is {}x{}",
                                   filmWidth_, filmHeight_));
        }
        p.getFloat("lensradius");  // pbrt-v4 reads and ignores them
        p.getFloat("focaldistance");
        p.getFloat("frameaspectratio");
        p.find("screenwindow", {ParamType::Float});
    } else if (type == "realistic") {
        realisticCamera(camera);
    } else {
        projectiveCamera(camera);
    }
    const double open = p.getFloat("shutteropen").value_or(0.0),
                 close = p.getFloat("shutterclose").value_or(1.0);
    if (close < open) failAt(where, "Camera: shutterclose must not be before shutteropen");
    if (!(camera_.cameraFromWorld[0] == camera_.cameraFromWorld[1])) {
        Json second = Json::object();
        addPose(second, poseOf(worldFromCamera[1]));
        Json first = Json::object();
        addPose(first, pose);
        camera["motion"] = Json::array({first, second});
    }
    camera["shutter"] = Json::array({open, close});
    scene["camera"] = camera;
    // pbrt-v4 exposes the film for the shutter's time at the film's ISO (PixelSensor::Create).
    if (close - open != 1.0 || filmIso_ != 100.0 || filmWhiteBalance_ != 0.0) {
        Json sensor = Json::object();
        if (filmIso_ != 100.0) sensor["iso"] = filmIso_;
        if (close - open != 1.0) {
            if (close > open)
                sensor["exposure_time"] = close - open;
            else
                log_.warn(
                    where,
                    "Camera: the shutter never opens (shutterclose = shutteropen), which pbrt-v4 refuses; "
                    "rendered with an exposure time of 1");
        }
        if (filmWhiteBalance_ != 0.0) sensor["white_balance"] = filmWhiteBalance_;
        scene_["film"]["sensor"] = std::move(sensor);
    }
    if (camera_.given) origins_.push_back({"/camera", where});
    p.reportUnused(log_, fmt::format("Camera \"{}\"", camera_.type));
    if (!filterGiven_)
        log_.warn({mainFile_.string(), 0, 0, {}},
                  "no PixelFilter: pbrt-v4's default Gaussian filter is rendered as a tent of the same "
                  "standard deviation "
                  "(radius 1.22)");
    if (!filterGiven_) scene_["film"]["filter"] = Json{{"type", "tent"}, {"radius", 0.5 * std::sqrt(6.0)}};
}

// pbrt-v4's perspective and orthographic cameras: a screen window, a thin lens.
void SceneBuilder::projectiveCamera(Json& camera) {
    const ParameterList& p = camera_.params;
    const SourceLocation& where = camera_.where;
    const bool orthographic = camera_.type == "orthographic";
    // fov is the shorter image axis's; penumbra's is the vertical one.
    const double fov = orthographic ? 90.0 : p.getFloat("fov").value_or(90.0);
    if (!(fov > 0.0 && fov < 180.0))
        failAt(where, fmt::format("Camera: fov must be between 0 and 180 degrees, found {}", fov));
    const double aspect = double(filmWidth_) / double(filmHeight_);
    double frame = aspect;
    if (auto f = p.getFloat("frameaspectratio")) {
        frame = *f;
        if (std::abs(frame - aspect) > 1e-3 * aspect)
            log_.warn(where,
                      fmt::format("Camera frameaspectratio {} differs from the film's {}: the film's is used",
                                  frame, aspect));
        frame = aspect;
    }
    double halfHeight = frame >= 1.0 ? 1.0 : 1.0 / frame;  // the screen window's, in units of tan(fov / 2)
    if (const Parameter* window = p.find("screenwindow", {ParamType::Float})) {
        requireNumberCount(window, 4);
        const auto& s = window->numbers;
        const bool centred =
            std::abs(s[0] + s[1]) <= 1e-6 * std::abs(s[1]) && std::abs(s[2] + s[3]) <= 1e-6 * std::abs(s[3]);
        const bool matching = s[3] > 0.0 && std::abs(s[1] / s[3] - aspect) <= 1e-3 * aspect;
        if (centred && matching)
            halfHeight = s[3];
        else
            log_.warn(window->where,
                      "Camera screenwindow that is off-centre or of another aspect ratio is not supported: "
                      "the default one is used");
    }
    if (orthographic) {
        // The screen window in scene units: its height is the image's.
        camera["type"] = "orthographic";
        camera["height"] = 2.0 * halfHeight;
    } else {
        camera["fov"] = 2.0 * std::atan(std::tan(fov / 2.0 / kDegrees) * halfHeight) * kDegrees;
    }
    const double lensRadius = p.getFloat("lensradius").value_or(0.0);
    const double focus = p.getFloat("focaldistance").value_or(1e6);
    if (lensRadius < 0.0) failAt(where, "Camera: lensradius must be >= 0");
    if (!(focus > 0.0)) failAt(where, "Camera: focaldistance must be > 0");
    if (lensRadius > 0.0) {
        camera["aperture_radius"] = lensRadius;
        camera["focus_distance"] = focus;
    }
}

// pbrt-v4's realistic camera: its lens file, stop diameter (mm), focus distance (m) and aperture
// shape, with the film's diagonal (mm); the scene is in metres.
void SceneBuilder::realisticCamera(Json& camera) {
    const ParameterList& p = camera_.params;
    const SourceLocation& where = camera_.where;
    camera["type"] = "lens_system";
    const Parameter* lensFile = p.find("lensfile", {ParamType::String});
    if (!lensFile || lensFile->strings.size() != 1 || lensFile->strings[0].empty())
        failAt(where, "Camera \"realistic\": give its lens description as \"string lensfile\"");
    auto existing = [&](const Parameter& parameter, const std::string& what) {
        const std::string& file = parameter.strings[0];
        const fs::path path = fs::path(file).is_absolute() ? fs::path(file) : folder_ / file;
        std::error_code error;
        if (!fs::is_regular_file(path, error))
            failAt(parameter.where, fmt::format("Camera \"realistic\": {} \"{}\" not found (looked for {})",
                                                what, file, path.string()));
        return path.string();
    };
    camera["lens_file"] = existing(*lensFile, "lens file");
    const double diameter = p.getFloat("aperturediameter").value_or(1.0);
    if (!(diameter > 0.0)) failAt(where, "Camera \"realistic\": aperturediameter must be > 0");
    camera["aperture_diameter"] = diameter;
    const double focus = p.getFloat("focusdistance").value_or(10.0);
    if (!(focus > 0.0)) failAt(where, "Camera \"realistic\": focusdistance must be > 0");
    camera["focus_distance"] = focus;
    camera["film_diagonal"] = filmDiagonalMm_;
    if (const Parameter* aperture = p.find("aperture", {ParamType::String})) {
        if (aperture->strings.size() != 1)
            failAt(aperture->where, "parameter \"string aperture\" takes one name");
        const std::string& name = aperture->strings[0];
        const bool builtin = name == "gaussian" || name == "square" || name == "pentagon" || name == "star";
        camera["aperture"] = builtin ? name : existing(*aperture, "aperture image");
    }
}

std::string SceneBuilder::materialOf(const ShapeRecord& shape) {
    if (!shape.state.material.empty()) return shape.state.material;
    if (defaultMaterial_.empty()) {
        defaultMaterial_ = unusedName("materials", "pbrt default (diffuse 0.5)");
        scene_["materials"][defaultMaterial_] = Json{{"type", "lambert"}, {"albedo", 0.5}};
    }
    return defaultMaterial_;
}

void SceneBuilder::materialDirective(const Directive& d) {
    requireWorld(d, true);
    const std::string& n = d.name;
    const ParameterList& p = d.parameters;
    if (n == "Texture") {
        textures_.define(d.strings[0], d.strings[1], d.strings[2], p, toWorld(state_.ctm[0]), d.where, log_);
        return;
    }
    if (n == "NamedMaterial") {
        auto it = namedMaterials_.find(d.strings[0]);
        if (it == namedMaterials_.end())
            failAt(d.where, fmt::format("NamedMaterial: no material named \"{}\"", d.strings[0]));
        state_.material = it->second;
        return;
    }
    std::string type, name;
    if (n == "Material") {
        type = d.strings[0];
        name = fmt::format("Material at {}", d.where.describe());
    } else {
        name = d.strings[0];
        if (namedMaterials_.count(name))
            failAt(d.where, fmt::format("MakeNamedMaterial: \"{}\" is defined twice", name));
        const auto t = p.getString("type");
        if (!t)
            failAt(d.where, fmt::format("MakeNamedMaterial \"{}\" needs a \"string type\" parameter", name));
        type = *t;
    }
    std::string jsonName = unusedName("materials", name);
    if (type == "mix") {
        // penumbra's mix: pbrt-v4's choice of one of the two per shading point.
        const Parameter* materials = p.find("materials", {ParamType::String});
        if (!materials || materials->strings.size() != 2)
            failAt(d.where, "mix needs \"string materials\" with two names");
        Json pair = Json::array();
        for (const std::string& member : materials->strings) {
            auto it = namedMaterials_.find(member);
            if (it == namedMaterials_.end())
                failAt(materials->where, fmt::format("mix: no material named \"{}\"", member));
            pair.push_back(it->second);
        }
        Json mix{{"type", "mix"}};
        mix["materials"] = std::move(pair);
        if (const Parameter* amount = p.find("amount", {ParamType::Float, ParamType::Texture})) {
            const TextureTable::Texture* texture =
                amount->type == ParamType::Texture && amount->strings.size() == 1
                    ? textures_.scalar(amount->strings[0])
                    : nullptr;
            if (texture && texture->object)
                mix["amount"] = *texture->object;
            else
                mix["amount"] = std::clamp(readScalar(p, "amount", 0.5, textures_, log_), 0.0, 1.0);
        }
        scene_["materials"][jsonName] = std::move(mix);
        origins_.push_back({"/materials/" + escapeJsonPointerToken(jsonName), d.where});
    } else {
        scene_["materials"][jsonName] = mapMaterial(type, p, textures_, d.where, log_);
        origins_.push_back({"/materials/" + escapeJsonPointerToken(jsonName), d.where});
    }
    p.reportUnused(log_, fmt::format("material \"{}\"", type));
    if (n == "Material")
        state_.material = jsonName;
    else
        namedMaterials_[name] = jsonName;
}

void SceneBuilder::areaLightSource(const Directive& d) {
    requireWorld(d, true);
    const ParameterList& p = d.parameters;
    if (d.strings[0] != "diffuse") {
        p.markAllUsed();
        log_.warn(
            d.where,
            fmt::format("AreaLightSource \"{}\" is not supported (only \"diffuse\"): the shapes do not emit",
                        d.strings[0]));
        state_.areaLight.reset();
        return;
    }
    Rgb radiance = readColor(p, "L", Rgb(1.0f), SpectrumUse::Emission, textures_, log_);
    radiance *= float(p.getFloat("scale").value_or(1.0));
    if (const Parameter* f = p.find("filename", {ParamType::String})) {
        log_.warn(f->where,
                  "image area lights are not supported: the light emits its L (times scale) instead");
    }
    if (const Parameter* power = p.find("power", {ParamType::Float}))
        log_.warn(power->where, "area light \"power\" is not supported: the light emits its L (times scale)");
    state_.areaLight = AreaLight{radiance, p.getBool("twosided").value_or(false), d.where};
    p.reportUnused(log_, "AreaLightSource \"diffuse\"");
}

void SceneBuilder::lightSource(const Directive& d) {
    requireWorld(d, true);
    const std::string& type = d.strings[0];
    const ParameterList& p = d.parameters;
    const Matrix4d world = toWorld(state_.ctm[0]);
    const float scale = float(p.getFloat("scale").value_or(1.0));
    Json light;
    if (type == "point") {
        Rgb intensity = readColor(p, "I", Rgb(1.0f), SpectrumUse::Emission, textures_, log_) * scale;
        // pbrt-v4 scales by power / (4 pi) without dividing by the RGB's own luminance.
        if (auto power = p.getFloat("power"); power && *power > 0.0) intensity *= float(*power / (4.0 * kPi));
        const Vec3d from = p.getPoint3("from").value_or(Vec3d{0, 0, 0});
        light = Json{{"type", "point"},
                     {"position", vec3Json(world.applyPoint(from))},
                     {"intensity", rgbJson(intensity)}};
    } else if (type == "spot") {
        Rgb intensity = readColor(p, "I", Rgb(1.0f), SpectrumUse::Emission, textures_, log_) * scale;
        const Vec3d from = p.getPoint3("from").value_or(Vec3d{0, 0, 0}),
                    to = p.getPoint3("to").value_or(Vec3d{0, 0, 1});
        const double coneAngle = p.getFloat("coneangle").value_or(30.0),
                     coneDelta = p.getFloat("conedelta").value_or(5.0);
        if (!(coneAngle > 0.0 && coneAngle <= 180.0))
            failAt(d.where, "spot light: \"coneangle\" must be in (0, 180] degrees");
        if (!(coneDelta >= 0.0 && coneDelta <= coneAngle))
            failAt(d.where, "spot light: \"conedelta\" must be from 0 to \"coneangle\" degrees");
        // pbrt-v4's SpotLight::Create: power / (2 pi ((1 - cosStart) + (cosStart - cosEnd) / 2)),
        // without dividing by the RGB's own luminance (as for point lights).
        if (auto power = p.getFloat("power"); power && *power > 0.0) {
            const double cosEnd = std::cos(coneAngle * kPi / 180.0),
                         cosStart = std::cos((coneAngle - coneDelta) * kPi / 180.0);
            intensity *= float(*power / (2.0 * kPi * ((1.0 - cosStart) + (cosStart - cosEnd) / 2.0)));
        }
        const Vec3d direction = world.applyVector(to - from);
        if (!(length(direction) > 0.0)) failAt(d.where, "spot light: from and to must differ");
        light = Json{{"type", "spot"},
                     {"position", vec3Json(world.applyPoint(from))},
                     {"direction", vec3Json(normalize(direction))},
                     {"intensity", rgbJson(intensity)},
                     {"cone_angle", shortest(float(coneAngle))},
                     {"cone_delta", shortest(float(coneDelta))}};
    } else if (type == "distant") {
        Rgb irradiance = readColor(p, "L", Rgb(1.0f), SpectrumUse::Emission, textures_, log_) * scale;
        if (auto e = p.getFloat("illuminance"); e && *e > 0.0) irradiance *= float(*e);
        const Vec3d from = p.getPoint3("from").value_or(Vec3d{0, 0, 0}),
                    to = p.getPoint3("to").value_or(Vec3d{0, 0, 1});
        const Vec3d direction = world.applyVector(to - from);
        if (!(length(direction) > 0.0)) failAt(d.where, "distant light: from and to must differ");
        light = Json{{"type", "directional"},
                     {"direction", vec3Json(normalize(direction))},
                     {"irradiance", rgbJson(irradiance)}};
    } else if (type == "goniometric") {
        // pbrt-v4's GoniometricLight::Create: its image is looked up with the direction in the
        // light's space after a swap of y and z, so the image's pole (the nadir of penumbra's
        // profile frame) is the light's +y and its horizontal angle 0 the light's +x.
        const Parameter* filename = p.find("filename", {ParamType::String});
        if (!filename || filename->strings.size() != 1 || filename->strings[0].empty())
            failAt(d.where, "LightSource \"goniometric\": give its image as \"string filename\"");
        const std::string& file = filename->strings[0];
        const fs::path path = fs::path(file).is_absolute() ? fs::path(file) : folder_ / file;
        std::error_code error;
        if (!fs::is_regular_file(path, error))
            failAt(filename->where,
                   fmt::format("LightSource \"goniometric\": image \"{}\" not found (looked for {})", file,
                               path.string()));
        Rgb intensity = readColor(p, "I", Rgb(1.0f), SpectrumUse::Emission, textures_, log_) * scale;
        const std::optional<double> power = p.getFloat("power");
        const Vec3d nadir = world.applyVector(Vec3d{0, 1, 0}), front = world.applyVector(Vec3d{1, 0, 0});
        if (!(length(nadir) > 0.0) || !(length(cross(front, nadir)) > 1e-6 * length(front) * length(nadir)))
            failAt(d.where, "goniometric light: its transform must not collapse the light's axes");
        light = Json{{"type", "goniometric"},
                     {"position", vec3Json(world.applyPoint(Vec3d{0, 0, 0}))},
                     {"file", file},
                     {"nadir", vec3Json(normalize(nadir))},
                     {"front", vec3Json(normalize(front))},
                     {"scale", rgbJson(intensity)}};
        // pbrt-v4 divides by the image's flux, 4 pi times its mean: the loader knows it (the key's
        // meaning is pbrt-v4's), so the image is read once.
        if (power && *power > 0.0) light["power"] = *power;
    } else if (type == "infinite") {
        if (const Parameter* f = p.find("filename", {ParamType::String})) {
            if (const Parameter* l = p.find("L", {ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody}))
                failAt(l->where,
                       "LightSource \"infinite\": give either \"L\" or \"filename\", not both (as pbrt-v4)");
            imageEnvironment(*f, scale, d.where);
        } else {
            Rgb radiance = readColor(p, "L", Rgb(1.0f), SpectrumUse::Emission, textures_, log_) * scale;
            if (auto e = p.getFloat("illuminance"); e && *e > 0.0)
                radiance *= float(*e / kPi);  // a uniform sky of radiance L gives the illuminance pi L
            addBackground(radiance, d.where);
        }
        p.reportUnused(log_, "LightSource \"infinite\"");
        return;
    } else {
        p.markAllUsed();
        log_.warn(d.where, fmt::format("LightSource \"{}\" is not supported and was left out", type));
        return;
    }
    origins_.push_back({fmt::format("/lights/{}", scene_["lights"].size()), d.where});
    scene_["lights"].push_back(light);
    p.reportUnused(log_, fmt::format("LightSource \"{}\"", type));
}

void SceneBuilder::addBackground(Rgb radiance, const SourceLocation& where) {
    if (scene_.contains("environment")) {
        log_.warn(
            where,
            "a constant infinite light besides an image one is left out (penumbra has one environment)");
        return;
    }
    Rgb background = radiance;
    if (scene_.contains("background")) {
        const Json& b = scene_["background"];
        background += Rgb(b[0].get<float>(), b[1].get<float>(), b[2].get<float>());
    }
    scene_["background"] = rgbJson(background);
}

void SceneBuilder::imageEnvironment(const Parameter& filename, float scale, const SourceLocation& where) {
    if (filename.strings.size() != 1)
        failAt(filename.where, "parameter \"string filename\" takes one file name");
    const std::string& file = filename.strings[0];
    const fs::path path = fs::path(file).is_absolute() ? fs::path(file) : folder_ / file;
    std::error_code error;
    if (!fs::is_regular_file(path, error))
        failAt(filename.where, fmt::format("LightSource \"infinite\": image \"{}\" not found (looked for {})",
                                           file, path.string()));
    const LinearRgbImage image = readLinearRgbImage(path, filename.where);
    // Square: pbrt-v4's own maps (the only ones it takes), equal-area octahedral; otherwise
    // latitude-longitude (pbrt-v3's maps).
    const bool equalArea = image.width == image.height;
    if (scene_.contains("environment")) {
        log_.warn(where, "a second image infinite light is left out (penumbra has one environment)");
        return;
    }
    if (scene_.contains("background")) {
        log_.warn(
            where,
            "constant infinite lights besides an image one are left out (penumbra has one environment)");
        scene_.erase("background");
    }
    // pbrt's direction in the light's space is R times penumbra's in its light frame:
    // - latitude-longitude (pbrt-v3's, and pbrt-v4 imgtool makeequiarea's input): column
    //   u = phi / 2 pi with phi = atan2(y, x), row v = theta / pi from +z (top row). penumbra's is
    //   (sin theta sin phi, cos theta, -sin theta cos phi) with +y up, so R: x -> y, y -> z, z -> -x
    //   (a reflection);
    // - equal-area: pbrt-v4's EqualAreaSquareToSphere gives (a, b, c) with c the pole; penumbra's
    //   map is the same square with (a, c, -b), so R: x -> x, y -> z, z -> -y (a rotation).
    // The light's transform (and the world's mirror) follow; what is left is a rotation, and a
    // reflection of the image when the whole has a negative determinant.
    Matrix4d r = Matrix4d::identity();
    if (equalArea)
        r.m[1][1] = 0, r.m[1][2] = -1, r.m[2][1] = 1, r.m[2][2] = 0;
    else
        r.m[0][0] = 0, r.m[0][2] = -1, r.m[1][0] = 1, r.m[1][1] = 0, r.m[2][1] = 1, r.m[2][2] = 0;
    Matrix4d m = toWorld(state_.ctm[0]) * r;
    for (int i = 0; i < 3; ++i) m.m[i][3] = 0.0;  // directions: no translation
    Vec3d c[3];
    double lengths[3];
    for (int j = 0; j < 3; ++j) {
        c[j] = Vec3d{m.m[0][j], m.m[1][j], m.m[2][j]};
        lengths[j] = length(c[j]);
        c[j] = normalize(c[j]);
    }
    const bool uniform = std::abs(lengths[0] - lengths[1]) <= 1e-4 * lengths[0] &&
                         std::abs(lengths[0] - lengths[2]) <= 1e-4 * lengths[0];
    if (!uniform || std::abs(dot(c[0], c[1])) > 1e-4 || std::abs(dot(c[0], c[2])) > 1e-4 ||
        std::abs(dot(c[1], c[2])) > 1e-4)
        failAt(
            where,
            "LightSource \"infinite\": the transform of an image light must rotate (and may mirror and scale "
            "uniformly), not shear or scale unevenly");
    const bool mirrored = m.determinant3() < 0.0;
    if (mirrored) c[0] = c[0] * -1.0;  // penumbra's "mirror" reflects the light's x before the rotation
    Matrix4d rotation = Matrix4d::identity();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) rotation.m[i][j] = c[j][i];
    bool sheared = false;
    const Json key = motionKey(rotation, sheared);
    Json environment{{"type", "image"}, {"file", file}, {"scale", shortest(scale)}};
    if (equalArea) environment["mapping"] = "equal_area";
    if (key["rotate"]["degrees"].get<double>() != 0.0) environment["rotate"] = key["rotate"];
    if (mirrored) environment["mirror"] = true;
    origins_.push_back({"/environment", where});
    scene_["environment"] = std::move(environment);
}

void SceneBuilder::objectDirective(const Directive& d) {
    requireWorld(d, true);
    if (d.name == "ObjectBegin") {
        if (currentObject_)
            failAt(d.where, fmt::format("ObjectBegin inside the definition of \"{}\" (started at {})",
                                        currentObject_->first, currentObject_->second.describe()));
        if (objects_.count(d.strings[0]))
            failAt(d.where, fmt::format("ObjectBegin: object \"{}\" is defined twice", d.strings[0]));
        push(d, true);  // ObjectBegin opens attributes, as in pbrt-v4
        currentObject_ = {d.strings[0], d.where};
        objects_[d.strings[0]];
    } else if (d.name == "ObjectEnd") {
        if (!currentObject_) failAt(d.where, "ObjectEnd without a matching ObjectBegin");
        if (stack_.empty() || stack_.back().where.line != currentObject_->second.line ||
            stack_.back().where.file != currentObject_->second.file)
            failAt(d.where, fmt::format("ObjectEnd while the AttributeBegin at {} is open",
                                        stack_.back().where.describe()));
        state_ = stack_.back().state;
        stack_.pop_back();
        currentObject_.reset();
    } else {
        if (currentObject_) failAt(d.where, "ObjectInstance inside an object definition");
        auto it = objects_.find(d.strings[0]);
        if (it == objects_.end())
            failAt(d.where, fmt::format("ObjectInstance: no object named \"{}\"", d.strings[0]));
        instantiate(it->first, state_.ctm, d.where);
    }
}

std::string SceneBuilder::copyReason(const ShapeRecord& shape) const {
    if (shape.type == "sphere") return "spheres (penumbra's prototypes are meshes)";
    if (shape.type == "curve") return "curves (penumbra's prototypes are meshes)";
    if (shape.type == "bilinearmesh") return "bilinear patches (penumbra's prototypes are triangle meshes)";
    if (shape.state.areaLight && !shape.state.areaLight->radiance.isBlack())
        return "area lights (instances do not emit)";
    if (!(shape.state.ctm[0] == shape.state.ctm[1])) return "shapes that move inside the object definition";
    return {};
}

int64_t SceneBuilder::placementCost(const std::string& object) const {
    int64_t cost = 0;
    for (const ShapeRecord& shape : objects_.at(object)) {
        int64_t triangles = 1;
        const bool mesh = shape.type == "trianglemesh" || shape.type == "bilinearmesh";
        if (mesh && !copyReason(shape).empty())
            for (const Parameter& q : shape.params.parameters())
                if (q.name == "indices")
                    triangles = std::max<int64_t>(
                        1, int64_t(q.numbers.size()) / (shape.type == "trianglemesh" ? 3 : 2));
        cost += triangles;
    }
    return cost;
}

void SceneBuilder::instantiate(const std::string& object, const std::array<Matrix4d, 2>& worldFromInstance,
                               const SourceLocation& where) {
    // Checked before anything is placed: a few lines could otherwise place millions of shapes.
    const int64_t cost = placementCost(object);
    const int64_t allowed = std::max<int64_t>(
        limits::kMinPbrtPlacedShapes, int64_t(textBytes_ / uint64_t(limits::kPbrtTextBytesPerPlacedShape)));
    if (placedShapes_ + cost > allowed)
        failAt(where,
               fmt::format(
                   "ObjectInstance \"{}\" would bring the shapes placed by object instances to {} (it places "
                   "{}): "
                   "a pbrt scene of {} of text places at most {}, one per {} bytes of text and at least {} "
                   "(docs/limits.md)",
                   object, placedShapes_ + cost, cost, describeBytes(textBytes_), allowed,
                   limits::kPbrtTextBytesPerPlacedShape, limits::kMinPbrtPlacedShapes));
    placedShapes_ += cost;
    const std::vector<ShapeRecord>& shapes = objects_.at(object);
    auto [names, first] = prototypes_.try_emplace(object);
    for (size_t i = 0; i < shapes.size(); ++i) {
        const ShapeRecord& shape = shapes[i];
        if (first) {
            // The prototype: the shape in the object's space (its own transform baked in).
            std::string name;
            if (copyReason(shape).empty()) {
                if (std::optional<Json> geometry =
                        shapeGeometry(shape, shape.state.ctm[0].determinant3() < 0.0)) {
                    name = unusedName("prototypes",
                                      shapes.size() == 1 ? object : fmt::format("{}/{}", object, i));
                    if (!(shape.state.ctm[0] == Matrix4d::identity()))
                        (*geometry)["transform"] =
                            Json::array({Json{{"matrix", matrixJson(shape.state.ctm[0])}}});
                    origins_.push_back({"/prototypes/" + escapeJsonPointerToken(name), shape.where});
                    scene_["prototypes"][name] = std::move(*geometry);
                }
            }
            names->second.push_back(name);
        }
        const std::string& prototype = names->second[i];
        if (prototype.empty()) {
            if (const std::string reason = copyReason(shape); !reason.empty())
                log_.warn(where, fmt::format("object instances of {} are placed as copies", reason));
            addShape(shape, &worldFromInstance);
            continue;
        }
        Json instance{{"type", "instance"}, {"prototype", prototype}, {"material", materialOf(shape)}};
        addMediumInterface(instance, shape.state);
        addPlacement(instance, worldFromInstance, where);
        origins_.push_back({fmt::format("/shapes/{}", scene_["shapes"].size()), where});
        scene_["shapes"].push_back(std::move(instance));
    }
}

void SceneBuilder::mediumDirective(const Directive& d) {
    if (d.name == "MediumInterface") {
        state_.insideMedium = d.strings[0];
        state_.outsideMedium = d.strings.size() > 1 ? d.strings[1] : d.strings[0];
        state_.mediumWhere = d.where;
        return;
    }
    // MakeNamedMedium "name" params, placed by the current transform.
    const std::string& name = d.strings[0];
    if (namedMedia_.contains(name)) failAt(d.where, fmt::format("medium \"{}\" is defined twice", name));
    const Matrix4d world = toWorld(state_.ctm[0]);
    const Json transform =
        world == Matrix4d::identity() ? Json() : Json::array({Json{{"matrix", matrixJson(world)}}});
    Json medium = mapMedium(d.parameters, transform, folder_, textures_, d.where, log_);
    d.parameters.reportUnused(log_, fmt::format("MakeNamedMedium \"{}\"", name));
    if (medium.is_null()) {
        namedMedia_[name] = "";  // left out, with a warning: the vacuum
        return;
    }
    const std::string jsonName = unusedName("media", name);
    scene_["media"][jsonName] = std::move(medium);
    namedMedia_[name] = jsonName;
}

std::string SceneBuilder::mediumOf(const std::string& name, const SourceLocation& where) {
    if (name.empty()) return "";
    usedMedia_.try_emplace(name, where);
    const auto found = namedMedia_.find(name);
    // Defined later in the file, or never (checked by finish()): the name as it is.
    return found == namedMedia_.end() ? name : found->second;
}

void SceneBuilder::addMediumInterface(Json& shape, const GraphicsState& state) {
    if (state.insideMedium == state.outsideMedium) return;
    shape["inside"] = mediumOf(state.insideMedium, state.mediumWhere);
    shape["outside"] = mediumOf(state.outsideMedium, state.mediumWhere);
}

void SceneBuilder::addPlacement(Json& shape, const std::array<Matrix4d, 2>& ctm,
                                const SourceLocation& where) {
    if (ctm[0] == ctm[1]) {
        const Matrix4d world = toWorld(ctm[0]);
        if (!(world == Matrix4d::identity()))
            shape["transform"] = Json::array({Json{{"matrix", matrixJson(world)}}});
        return;
    }
    bool sheared = false;
    shape["motion"] =
        Json{{"transforms",
              Json::array({motionKey(toWorld(ctm[0]), sheared), motionKey(toWorld(ctm[1]), sheared)})}};
    if (sheared) log_.warn(where, "a moving transform with shear is rendered without the shear");
    const Json& shutter = scene_["camera"]["shutter"];
    if (shutter[0].get<double>() != transformTimes_[0] || shutter[1].get<double>() != transformTimes_[1])
        log_.warn(
            where,
            "TransformTimes differ from the camera's shutter: penumbra spreads motion keys over the shutter");
}

void SceneBuilder::addCurve(const ShapeRecord& record, const std::array<Matrix4d, 2>& ctm) {
    const ParameterList& p = record.params;
    const SourceLocation& where = record.where;
    std::vector<Vec3d> points = p.getPoint3s("P");
    const std::string basis = p.getString("basis").value_or("bezier");
    if (basis != "bezier" && basis != "bspline")
        failAt(where, fmt::format("curve: basis \"{}\" is not bezier or bspline", basis));
    const int64_t degree = p.getInt("degree").value_or(3);
    if (degree != 2 && degree != 3)
        failAt(where, fmt::format("curve: degree must be 2 or 3, found {}", degree));
    const std::string type = p.getString("type").value_or("flat");
    if (type != "flat" && type != "cylinder" && type != "ribbon")
        failAt(where, fmt::format("curve: type \"{}\" is not flat, cylinder or ribbon", type));
    // Quadratic curves as the cubic Bezier curves they are (degree elevation; a quadratic
    // B-spline's segment first as its quadratic Bezier segment).
    const bool bezier = basis == "bezier";
    const size_t n = points.size();
    const size_t segments =
        degree == 3 ? curveSegmentCount(n, bezier ? CurveBasis::Bezier : CurveBasis::BSpline)
                    : (bezier ? ((n - 1) % 2 == 0 && n >= 3 ? (n - 1) / 2 : 0) : (n >= 3 ? n - 2 : 0));
    if (segments == 0)
        failAt(where,
               fmt::format("curve: {} control points do not make whole segments of a degree {} {} curve", n,
                           degree, basis));
    std::string jsonBasis = basis;
    if (degree == 2) {
        std::vector<Vec3d> cubic{};
        for (size_t i = 0; i < segments; ++i) {
            Vec3d q0 = points[bezier ? 2 * i : i], q1 = points[bezier ? 2 * i + 1 : i + 1],
                  q2 = points[bezier ? 2 * i + 2 : i + 2];
            if (!bezier) q0 = (q0 + q1) * 0.5, q2 = (q1 + q2) * 0.5;
            if (i == 0) cubic.push_back(q0);
            cubic.insert(cubic.end(), {q0 + (q1 - q0) * (2.0 / 3.0), q2 + (q1 - q2) * (2.0 / 3.0), q2});
        }
        points = std::move(cubic);
        jsonBasis = "bezier";
    }
    const double width = p.getFloat("width").value_or(1.0);
    const double width0 = p.getFloat("width0").value_or(width), width1 = p.getFloat("width1").value_or(width);
    if (!(width0 >= 0.0 && width1 >= 0.0)) failAt(where, "curve: widths must not be negative");
    std::vector<Vec3d> normals = type == "ribbon" ? p.getNormals("N") : std::vector<Vec3d>{};
    if (type == "ribbon" && normals.size() != segments + 1)
        failAt(
            where,
            fmt::format("curve: a ribbon needs a normal \"N\" at each of its {} segment boundaries, found {}",
                        segments + 1, normals.size()));
    p.markAllUsed();  // "splitdepth" among them: penumbra's test subdivides adaptively (geometry/curves.h)
    if (!(ctm[0] == ctm[1]))
        log_.warn(where, "moving curves are not supported: rendered where they are at the shutter's opening");
    // Into the world: points as points, normals by the inverse transpose, widths by the
    // transform's mean scale (pbrt-v4 keeps a curve in its own space, where its width is given).
    const Matrix4d world = toWorld(ctm[0]);
    const double scale = std::cbrt(std::abs(world.determinant3()));
    Json shape;
    shape["type"] = "curves";
    shape["material"] = materialOf(record);
    addMediumInterface(shape, record.state);
    if (type != "flat") shape["curve_type"] = type;
    if (jsonBasis != "bezier") shape["basis"] = jsonBasis;
    Json newPoints = Json::array();
    for (const Vec3d& q : points) newPoints.push_back(vec3Json(world.applyPoint(q)));
    Json newNormals = Json::array();
    if (!normals.empty()) {
        // Normals by the inverse transpose.
        const std::optional<Matrix4d> inverse = world.inverse();
        if (!inverse) failAt(where, "curve: a ribbon's transform is singular: its normals have no direction");
        const Matrix4d normalMatrix = inverse->transposed();
        for (const Vec3d& normal : normals) newNormals.push_back(vec3Json(normalMatrix.applyVector(normal)));
    }
    const Json widthPair = Json::array({width0 * scale, width1 * scale});
    if (record.state.areaLight && !record.state.areaLight->radiance.isBlack())
        log_.warn(where, "curves do not emit in penumbra: the area light on this curve is left out");
    if (lastCurves_ && *lastCurves_ + 1 == scene_["shapes"].size()) {
        Json& last = scene_["shapes"][*lastCurves_];
        bool same = true;
        for (const char* key : {"material", "inside", "outside", "curve_type", "basis"})
            same = same && last.value(key, Json()) == shape.value(key, Json());
        if (same) {
            for (Json& q : newPoints) last["points"].push_back(std::move(q));
            for (Json& q : newNormals) last["normals"].push_back(std::move(q));
            last["curve_sizes"].push_back(points.size());
            last["curve_widths"].push_back(widthPair);
            return;
        }
    }
    shape["points"] = std::move(newPoints);
    if (type == "ribbon") shape["normals"] = std::move(newNormals);
    shape["curve_sizes"] = Json::array({points.size()});
    shape["curve_widths"] = Json::array({widthPair});
    lastCurves_ = scene_["shapes"].size();
    origins_.push_back({fmt::format("/shapes/{}", scene_["shapes"].size()), where});
    scene_["shapes"].push_back(std::move(shape));
}

void SceneBuilder::addShape(const ShapeRecord& record, const std::array<Matrix4d, 2>* worldFromInstance) {
    std::array<Matrix4d, 2> ctm = record.state.ctm;
    if (worldFromInstance)
        for (size_t i = 0; i < 2; ++i) ctm[i] = (*worldFromInstance)[i] * ctm[i];
    if (record.type == "curve") {
        addCurve(record, ctm);
        return;
    }
    // Bilinear patches are penumbra's own shape where they neither emit nor move (nor have a cut-out,
    // which our patch test has not): two triangles each otherwise.
    const bool emits = record.state.areaLight && !record.state.areaLight->radiance.isBlack();
    const Parameter* alpha = record.params.find("alpha", {ParamType::Float, ParamType::Texture});
    const bool exactPatches =
        record.type == "bilinearmesh" && !emits && ctm[0] == ctm[1] && !(alpha && cutOutAlpha(*alpha));
    std::optional<Json> geometry = shapeGeometry(record, ctm[0].determinant3() < 0.0, exactPatches);
    if (!geometry) return;
    Json& shape = *geometry;
    shape["material"] = materialOf(record);
    addMediumInterface(shape, record.state);
    if (const auto& light = record.state.areaLight; light && !light->radiance.isBlack())
        shape["emission"] = Json{{"radiance", rgbJson(light->radiance)}, {"two_sided", light->twoSided}};
    addPlacement(shape, ctm, record.where);
    origins_.push_back({fmt::format("/shapes/{}", scene_["shapes"].size()), record.where});
    scene_["shapes"].push_back(std::move(shape));
}

namespace {

// A mesh's "positions", "normals" (each non-zero) and "uvs" in penumbra's shape object.
void addMeshVertices(Json& shape, const std::vector<Vec3d>& positions, const std::vector<Vec3d>& normals,
                     const std::vector<Vec2d>& uvs, const std::string& type, const ParameterList& p) {
    Json jp = Json::array();
    jp.get_ref<Json::array_t&>().reserve(positions.size());
    for (const Vec3d& v : positions) jp.push_back(vec3Json(v));
    shape["positions"] = std::move(jp);
    if (!normals.empty()) {
        Json jn = Json::array();
        for (const Vec3d& v : normals) {
            if (!(length(v) > 0.0))
                failAt(p.find("N", {ParamType::Normal})->where, fmt::format("{}: a normal is zero", type));
            jn.push_back(vec3Json(v));
        }
        shape["normals"] = std::move(jn);
    }
    if (!uvs.empty()) {
        Json ju = Json::array();
        for (const Vec2d& v : uvs) ju.push_back(Json::array({v.x, v.y}));
        shape["uvs"] = std::move(ju);
    }
}

// Whether every patch (four indices each) lies in a plane, to a millionth of its size: then its two
// triangles are the same surface.
bool patchesAreFlat(const std::vector<Vec3d>& positions, const std::vector<int64_t>& indices) {
    for (size_t i = 0; i + 3 < indices.size(); i += 4) {
        const Vec3d p00 = positions[size_t(indices[i])], p10 = positions[size_t(indices[i + 1])],
                    p01 = positions[size_t(indices[i + 2])], p11 = positions[size_t(indices[i + 3])];
        const Vec3d normal = cross(p10 - p00, p01 - p00);
        const double size = std::max({length(p10 - p00), length(p01 - p00), length(p11 - p00)});
        if (std::abs(dot(p11 - p00, normal)) > 1e-6 * size * length(normal)) return false;
    }
    return true;
}

}  // namespace

std::optional<Json> SceneBuilder::shapeGeometry(const ShapeRecord& record, bool swaps, bool exactPatches) {
    const ParameterList& p = record.params;
    const SourceLocation& where = record.where;
    const std::string& type = record.type;
    const bool reverse = record.state.reverseOrientation;
    Json shape = Json::object();

    if (type == "trianglemesh" || type == "bilinearmesh" || type == "loopsubdiv") {
        const bool bilinear = type == "bilinearmesh";
        const std::vector<Vec3d> positions = p.getPoint3s("P");
        if (positions.empty()) failAt(where, fmt::format("{} needs vertex positions (\"point3 P\")", type));
        std::vector<int64_t> indices = p.getInts("indices");
        const size_t corners = bilinear ? 4 : 3;
        if (indices.empty()) {
            if (positions.size() != corners)
                failAt(where, fmt::format("{} needs \"integer indices\" unless it has exactly {} vertices",
                                          type, corners));
            for (size_t i = 0; i < corners; ++i) indices.push_back(int64_t(i));
        }
        const Parameter* indexParam = p.find("indices", {ParamType::Integer});
        const SourceLocation& indexPlace = indexParam ? indexParam->where : where;
        if (indices.size() % corners != 0)
            failAt(indexPlace, fmt::format("{}: the number of indices ({}) is not a multiple of {}", type,
                                           indices.size(), corners));
        for (int64_t i : indices)
            if (i < 0 || uint64_t(i) >= positions.size())
                failAt(indexPlace,
                       fmt::format("{}: index {} is out of range: the mesh has {} vertices (counting from 0)",
                                   type, i, positions.size()));
        const std::vector<Vec3d> normals = p.getNormals("N");
        if (!normals.empty() && normals.size() != positions.size())
            failAt(p.find("N", {ParamType::Normal})->where,
                   fmt::format("{}: {} normals for {} vertices (one per vertex expected)", type,
                               normals.size(), positions.size()));
        const std::vector<Vec2d> uvs = p.getPoint2s(p.has("uv") ? "uv" : "st");
        if (!uvs.empty() && uvs.size() != positions.size())
            failAt(where, fmt::format("{}: {} uvs for {} vertices (one per vertex expected)", type,
                                      uvs.size(), positions.size()));
        if (bilinear && exactPatches) {
            shape["type"] = "bilinear_mesh";
            addMeshVertices(shape, positions, normals, uvs, type, p);
            shape["indices"] = indices;
            if (reverse) shape["reverse_orientation"] = true;
            p.reportUnused(log_, fmt::format("Shape \"{}\"", type));
            return shape;
        }
        // Triangles: a bilinear patch (p00, p10, p01, p11) becomes (p00, p10, p11) and (p00, p11, p01).
        std::vector<int64_t> triangles;
        if (bilinear) {
            for (size_t i = 0; i < indices.size(); i += 4)
                triangles.insert(triangles.end(), {indices[i], indices[i + 1], indices[i + 3], indices[i],
                                                   indices[i + 3], indices[i + 2]});
            if (!patchesAreFlat(positions, indices))
                log_.warn(where,
                          "bilinear patches that emit, move or have an alpha are rendered as two triangles "
                          "each (exact for flat patches, and these are not flat)");
        } else {
            triangles = std::move(indices);
        }
        // The front of each triangle is where pbrt-v4's surface normal points: the winding's side,
        // turned to the side of the mesh's normals when it has them, and reversed by ReverseOrientation.
        size_t turned = 0;
        for (size_t t = 0; t < triangles.size(); t += 3) {
            const Vec3d p0 = positions[size_t(triangles[t])], p1 = positions[size_t(triangles[t + 1])],
                        p2 = positions[size_t(triangles[t + 2])];
            const Vec3d front = cross(p1 - p0, p2 - p0);
            bool flip = reverse;
            if (!normals.empty()) {
                const Vec3d n = normals[size_t(triangles[t])] + normals[size_t(triangles[t + 1])] +
                                normals[size_t(triangles[t + 2])];
                flip = (dot(front, n) < 0.0) != reverse;
            }
            if (flip) {
                std::swap(triangles[t + 1], triangles[t + 2]);
                ++turned;
            }
        }
        shape["type"] = "triangle_mesh";
        if (type == "loopsubdiv") {
            // The triangles are the control mesh, refined at load (geometry/loop_subdivision.h).
            const int64_t levels = p.getInt("levels").value_or(3);
            if (levels < 0 || levels > 16)
                failAt(p.find("levels", {ParamType::Integer})->where,
                       fmt::format("loopsubdiv: \"levels\" must be from 0 to 16, found {}", levels));
            shape["subdivision"] = Json{{"scheme", "loop"}, {"levels", levels}};
        }
        addMeshVertices(shape, positions, normals, uvs, type, p);
        shape["indices"] = triangles;
        p.find("S", {ParamType::Vector3});
        if (const Parameter* s = p.find("S", {ParamType::Vector3}))
            log_.warn(s->where, "mesh tangents (\"S\") are not used");
        if (const Parameter* f = p.find("faceIndices", {ParamType::Integer}))
            log_.warn(f->where, "mesh \"faceIndices\" are not used");
    } else if (type == "plymesh") {
        const auto file = p.getString("filename");
        if (!file || file->empty()) failAt(where, "plymesh needs a \"string filename\"");
        const fs::path path = fs::path(*file).is_absolute() ? fs::path(*file) : folder_ / *file;
        std::error_code error;
        if (!fs::exists(path, error))
            failAt(p.find("filename", {ParamType::String})->where,
                   fmt::format("plymesh: mesh file \"{}\" not found (looked for {})", *file, path.string()));
        shape["type"] = "mesh_file";
        shape["file"] = *file;
        // pbrt-v4 faces each triangle to the file's normals where it has them, and turns both
        // under ReverseOrientation.
        shape["front"] = reverse ? "reversed_normals" : "normals";
        if (p.has("displacement")) log_.warn(where, "plymesh displacement is not supported");
        p.markAllUsed();
    } else if (type == "sphere") {
        const double radius = p.getFloat("radius").value_or(1.0);
        if (!(radius > 0.0)) failAt(where, fmt::format("sphere: the radius must be > 0, found {}", radius));
        // As pbrt-v4: the heights clamped to the sphere and taken in either order, phimax to [0, 360].
        double zmin = std::clamp(p.getFloat("zmin").value_or(-radius), -radius, radius);
        double zmax = std::clamp(p.getFloat("zmax").value_or(radius), -radius, radius);
        if (zmin > zmax) std::swap(zmin, zmax);
        const double phimax = std::clamp(p.getFloat("phimax").value_or(360.0), 0.0, 360.0);
        if (!(zmax > zmin) || !(phimax > 0.0))
            failAt(where, "sphere: zmin, zmax and phimax leave nothing of it");
        if (reverse != swaps)
            log_.warn(where,
                      "a sphere whose normals face inward (ReverseOrientation or a mirroring transform) is "
                      "rendered "
                      "facing outward");
        shape["type"] = "sphere";
        shape["center"] = Json::array({0.0, 0.0, 0.0});
        shape["radius"] = radius;
        // A partial sphere is made of triangles (as an ellipsoid is, which a non-uniform transform
        // makes of any sphere), its azimuth from +x counter-clockwise about +z as pbrt-v4's.
        if (zmin > -radius) shape["z_min"] = zmin;
        if (zmax < radius) shape["z_max"] = zmax;
        if (phimax < 360.0) shape["phi_max"] = phimax;
    } else if (type == "disk" || type == "cylinder") {
        const bool disk = type == "disk";
        const double radius = p.getFloat("radius").value_or(1.0);
        if (!(radius > 0.0)) failAt(where, fmt::format("{}: the radius must be > 0, found {}", type, radius));
        // pbrt-v4 clamps phimax to [0, 360]; none of it is no shape.
        const double phimax = std::clamp(p.getFloat("phimax").value_or(360.0), 0.0, 360.0);
        if (!(phimax > 0.0)) failAt(where, fmt::format("{}: phimax must be above 0 degrees", type));
        // pbrt's disk faces +z and its cylinder outward, both flipped by ReverseOrientation and by a
        // mirroring transform (pbrt-v4 flips the normals of quadrics then).
        const bool flipped = reverse != swaps;
        if (disk) {
            const double height = p.getFloat("height").value_or(0.0);
            const double inner = p.getFloat("innerradius").value_or(0.0);
            if (!(inner >= 0.0 && inner < radius))
                failAt(where,
                       fmt::format("disk: the inner radius must be from 0 to below the radius ({}), found {}",
                                   radius, inner));
            shape["type"] = "disk";
            shape["center"] = Json::array({0.0, 0.0, height});
            shape["normal"] = Json::array({0.0, 0.0, flipped ? -1.0 : 1.0});
            shape["radius"] = radius;
            if (inner > 0.0) shape["inner_radius"] = inner;
        } else {
            double zmin = p.getFloat("zmin").value_or(-1.0), zmax = p.getFloat("zmax").value_or(1.0);
            if (zmin > zmax) std::swap(zmin, zmax);  // as pbrt-v4
            if (!(zmax > zmin)) failAt(where, "cylinder: zmin and zmax are equal: it has no height");
            shape["type"] = "cylinder";
            shape["base"] = Json::array({0.0, 0.0, zmin});
            shape["axis"] = Json::array({0.0, 0.0, zmax - zmin});
            shape["radius"] = radius;
            if (flipped) shape["front"] = "inside";
        }
        if (phimax < 360.0) {
            shape["phi_max"] = phimax;
            // pbrt-v4 sweeps phi counter-clockwise about +z from +x; a disk facing -z sweeps about -z,
            // so it starts where pbrt-v4's sweep ends.
            const double end = phimax / kDegrees;
            shape["start_direction"] = disk && flipped ? Json::array({std::cos(end), std::sin(end), 0.0})
                                                       : Json::array({1.0, 0.0, 0.0});
        }
    } else {
        p.markAllUsed();
        log_.warn(where, fmt::format("Shape \"{}\" is not supported and was left out", type));
        return std::nullopt;
    }
    if (const Parameter* alpha = p.find("alpha", {ParamType::Float, ParamType::Texture}))
        if (std::optional<Json> value = cutOutAlpha(*alpha)) shape["alpha"] = std::move(*value);
    p.reportUnused(log_, fmt::format("Shape \"{}\"", type));
    return shape;
}

namespace {

// Removes the texture mappings of the point (spherical, cylindrical, planar) from a texture object
// and the textures in it; whether there was one. A cut-out is looked up at (u, v) alone.
bool dropPointMappings(Json& texture) {
    bool dropped = false;
    if (texture.is_object()) {
        dropped = texture.erase("mapping") > 0;
        for (auto& [key, value] : texture.items()) dropped = dropPointMappings(value) || dropped;
    } else if (texture.is_array()) {
        for (Json& value : texture) dropped = dropPointMappings(value) || dropped;
    }
    return dropped;
}

}  // namespace

std::optional<Json> SceneBuilder::cutOutAlpha(const Parameter& alpha) const {
    if (alpha.type == ParamType::Float) {
        if (alpha.numbers.size() != 1)
            failAt(alpha.where, fmt::format("parameter \"{}\" takes one value", alpha.declaration()));
        // pbrt-v4 leaves the test out at 1 or more and never keeps a hit at 0 or less.
        if (!(alpha.numbers[0] < 1.0)) return std::nullopt;
        return Json(std::max(alpha.numbers[0], 0.0));
    }
    if (alpha.strings.size() != 1)
        failAt(alpha.where, fmt::format("parameter \"{}\" takes one texture name", alpha.declaration()));
    const TextureTable::Texture* texture = textures_.scalar(alpha.strings[0]);
    if (!texture)
        failAt(alpha.where, fmt::format("parameter \"{}\": unknown float texture \"{}\"", alpha.declaration(),
                                        alpha.strings[0]));
    if (texture->object) {
        Json object = *texture->object;
        if (dropPointMappings(object))
            log_.warn(alpha.where,
                      "an alpha texture is looked up at the surface's (u, v): its spherical, "
                      "cylindrical or planar mapping is not used");
        return object;
    }
    const double constant = std::clamp(double(texture->constant.r), 0.0, 1.0);
    if (constant == 1.0) return std::nullopt;
    return Json(constant);
}

Json SceneBuilder::finish() {
    if (currentObject_)
        failAt(currentObject_->second,
               fmt::format("ObjectBegin \"{}\" is never closed by ObjectEnd", currentObject_->first));
    if (!stack_.empty())
        failAt(stack_.back().where,
               fmt::format("{} is never closed",
                           stack_.back().attributes ? "AttributeBegin" : "TransformBegin"));
    if (!inWorld_) finishCamera(scene_);
    if (!camera_.medium.empty()) {
        const std::string medium = mediumOf(camera_.medium, camera_.mediumWhere);
        if (!medium.empty()) scene_["camera"]["medium"] = medium;
    }
    for (const auto& [name, where] : usedMedia_)
        if (!namedMedia_.contains(name))
            failAt(where, fmt::format("medium \"{}\" is not defined (MakeNamedMedium)", name));
    return std::move(scene_);
}

}  // namespace penumbra::pbrt
