#include "cameras/camera.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/motion.h"

namespace penumbra {

namespace {

Projection makeProjection(const CameraParams& p, int filmWidth, int filmHeight) {
    if (filmWidth <= 0 || filmHeight <= 0) throw InputError("camera: film resolution must be positive");
    const float focusDistance = p.focusDistance > 0.0f ? p.focusDistance : length(p.lookAt - p.lookFrom);
    switch (p.projection) {
        case CameraProjection::Perspective:
            return ThinLensProjection(p, focusDistance, filmWidth, filmHeight);
        case CameraProjection::Orthographic:
            return OrthographicProjection(p, focusDistance, filmWidth, filmHeight);
        case CameraProjection::Spherical:
            if (p.sphericalMapping == SphericalMapping::EqualArea && filmWidth != filmHeight)
                throw InputError(
                    fmt::format("camera: an equal-area spherical image is square; the film is {}x{}",
                                filmWidth, filmHeight));
            return SphericalProjection(p, filmWidth, filmHeight);
        case CameraProjection::Fisheye:
            return FisheyeProjection(p, filmWidth, filmHeight);
        case CameraProjection::LensSystem:
            // pbrt-v4's default focus distance when none is given: 10 (metres).
            return LensSystemProjection(p, p.focusDistance > 0.0f ? p.focusDistance : 10.0f, filmWidth,
                                        filmHeight);
    }
    throw InputError("camera: unknown projection");
}

}  // namespace

Camera::Camera(const CameraParams& p, int filmWidth, int filmHeight)
    : projection_(makeProjection(p, filmWidth, filmHeight)) {
    auto toWorld = Transform::lookAt(p.lookFrom, p.lookAt, p.up);
    if (!toWorld)
        throw InputError("camera: look_from, look_at and up must span a view (got a degenerate look-at)");
    cameraToWorld_ = *toWorld;
    pinholeOrigin_ = cameraToWorld_.applyPoint({0.0f, 0.0f, 0.0f});
    if (!(p.apertureRadius >= 0.0f)) throw InputError("camera: the aperture radius must be >= 0");
    if (p.apertureBlades != 0 && p.apertureBlades < 3)
        throw InputError("camera: an aperture needs 0 or >= 3 blades");
    usesLensSample_ =
        std::visit([](const auto& projection) { return projection.usesLensSample(); }, projection_);
    const bool throughLens = std::holds_alternative<OrthographicProjection>(projection_) ||
                             std::holds_alternative<LensSystemProjection>(projection_);
    fromOrigin_ = !usesLensSample_ && !throughLens;
    if (p.motion.size() == 1) throw InputError("camera: motion needs at least two poses");
    for (const CameraPose& pose : p.motion)
        if (!Transform::lookAt(pose.lookFrom, pose.lookAt, pose.up))
            throw InputError("camera: every motion pose must span a view (got a degenerate look-at)");
    motion_ = p.motion;
}

CameraRay Camera::generateOtherRay(Vec2f filmPosition, Vec2f lensSample, float timeSample) const {
    const CameraSpaceRay local = std::visit(
        [&](const auto& projection) { return projection.generate(filmPosition, lensSample); }, projection_);
    return toWorld(local, timeSample);
}

CameraFootprint Camera::footprint(int samplesPerPixel) const {
    const Transform toWorld = cameraToWorld(0.0f);
    CameraFootprint f;
    f.origin = toWorld.applyPoint({0.0f, 0.0f, 0.0f});
    f.right = normalize(toWorld.applyVector({1.0f, 0.0f, 0.0f}));
    f.up = normalize(toWorld.applyVector({0.0f, 1.0f, 0.0f}));
    f.pixelSpacing =
        std::visit([](const auto& projection) { return projection.pixelSpacing(); }, projection_);
    // Parallel rays: the neighbouring pixel's ray is displaced, not turned.
    if (std::holds_alternative<OrthographicProjection>(projection_))
        f.parallelDirection = normalize(toWorld.applyVector({0.0f, 0.0f, 1.0f}));
    f.sampleScale = std::max(0.125f, 1.0f / std::sqrt(float(std::max(samplesPerPixel, 1))));
    return f;
}

Transform Camera::cameraToWorld(float time) const {
    if (motion_.empty()) return cameraToWorld_;
    const KeySegment s = locateKeySegment(motion_.size(), time);
    const CameraPose& a = motion_[s.first];
    const CameraPose& b = motion_[s.first + 1];
    const float t = s.fraction;
    auto lerp = [t](Vec3f x, Vec3f y) { return x * (1.0f - t) + y * t; };
    // Poses were validated one by one; an in-between pose can still degenerate (e.g. up flipping
    // through the view direction), in which case the nearer key's pose is used.
    const auto between =
        Transform::lookAt(lerp(a.lookFrom, b.lookFrom), lerp(a.lookAt, b.lookAt), lerp(a.up, b.up));
    if (between) return *between;
    const CameraPose& nearest = t < 0.5f ? a : b;
    return *Transform::lookAt(nearest.lookFrom, nearest.lookAt, nearest.up);
}

}  // namespace penumbra
