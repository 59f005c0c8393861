#include "cameras/camera.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/motion.h"
#include "core/sampling.h"

namespace penumbra {

ThinLensCamera::ThinLensCamera(const ThinLensCameraParams& p, int filmWidth, int filmHeight) {
    auto toWorld = Transform::lookAt(p.lookFrom, p.lookAt, p.up);
    if (!toWorld)
        throw InputError("camera: look_from, look_at and up must span a view (got a degenerate look-at)");
    if (!(p.verticalFovDegrees > 0.0f && p.verticalFovDegrees < 180.0f))
        throw InputError("camera: fov must lie in (0, 180) degrees");
    if (filmWidth <= 0 || filmHeight <= 0) throw InputError("camera: film resolution must be positive");
    cameraToWorld_ = *toWorld;
    pinholeOrigin_ = cameraToWorld_.applyPoint({0.0f, 0.0f, 0.0f});
    halfHeight_ = std::tan(0.5f * p.verticalFovDegrees * kPi / 180.0f);
    halfWidth_ = halfHeight_ * float(filmWidth) / float(filmHeight);
    invWidth_ = 1.0f / float(filmWidth);
    invHeight_ = 1.0f / float(filmHeight);
    if (!(p.apertureRadius >= 0.0f)) throw InputError("camera: the aperture radius must be >= 0");
    if (p.apertureBlades != 0 && p.apertureBlades < 3)
        throw InputError("camera: an aperture needs 0 or >= 3 blades");
    apertureRadius_ = p.apertureRadius;
    apertureBlades_ = p.apertureBlades;
    apertureRotation_ = p.apertureRotationDegrees * kPi / 180.0f;
    // The polygon's vertices, once: a camera ray takes the two of its blade, rather than making
    // them with two sincos calls a ray (bench/README.md, "Speed tricks").
    if (apertureBlades_ >= 3)
        for (int blade = 0; blade <= apertureBlades_; ++blade) {
            const float angle = apertureRotation_ + 2.0f * kPi * float(blade) / float(apertureBlades_);
            bladeVertices_.push_back({std::cos(angle), std::sin(angle)});
        }
    focusDistance_ = p.focusDistance > 0.0f ? p.focusDistance : length(p.lookAt - p.lookFrom);
    if (p.motion.size() == 1) throw InputError("camera: motion needs at least two poses");
    for (const CameraPose& pose : p.motion)
        if (!Transform::lookAt(pose.lookFrom, pose.lookAt, pose.up))
            throw InputError("camera: every motion pose must span a view (got a degenerate look-at)");
    motion_ = p.motion;
}

CameraFootprint ThinLensCamera::footprint(int samplesPerPixel) const {
    const Transform toWorld = cameraToWorld(0.0f);
    CameraFootprint f;
    f.origin = toWorld.applyPoint({0.0f, 0.0f, 0.0f});
    f.right = normalize(toWorld.applyVector({1.0f, 0.0f, 0.0f}));
    f.up = normalize(toWorld.applyVector({0.0f, 1.0f, 0.0f}));
    f.pixelSpacing = 2.0f * halfHeight_ * invHeight_;
    f.sampleScale = std::max(0.125f, 1.0f / std::sqrt(float(std::max(samplesPerPixel, 1))));
    return f;
}

Vec2f ThinLensCamera::sampleAperture(Vec2f u) const {
    if (apertureBlades_ < 3) return sampleUniformDiskConcentric(u);
    // Uniform on a regular polygon: the blade's triangle (centre, vertex i, vertex i + 1) is
    // picked by u.x, whose remainder is reused, so strata stay compact.
    const float scaled = u.x * float(apertureBlades_);
    const int blade = std::min(int(scaled), apertureBlades_ - 1);
    const Vec2f b = sampleUniformTriangle({scaled - float(blade), u.y});
    // The centre has weight 1 - b.x - b.y and is the origin.
    return bladeVertices_[size_t(blade)] * b.x + bladeVertices_[size_t(blade) + 1] * b.y;
}

Ray ThinLensCamera::generateRay(Vec2f filmPosition, Vec2f lensSample, float timeSample) const {
    // Point on the image plane at z = 1 in camera space (+x right, +y up, +z forward).
    const Vec3f onImagePlane{(2.0f * filmPosition.x * invWidth_ - 1.0f) * halfWidth_,
                             (1.0f - 2.0f * filmPosition.y * invHeight_) * halfHeight_, 1.0f};
    Vec3f origin{0.0f, 0.0f, 0.0f};
    Vec3f direction = onImagePlane;
    if (apertureRadius_ > 0.0f) {
        // Every ray through the lens converges on the focus plane where the pinhole ray meets it.
        const Vec2f lens = sampleAperture(lensSample) * apertureRadius_;
        const Vec3f focusPoint = onImagePlane * focusDistance_;
        origin = {lens.x, lens.y, 0.0f};
        direction = focusPoint - origin;
    }
    Ray ray;
    ray.time = timeSample;
    if (motion_.empty()) {
        ray.origin = apertureRadius_ > 0.0f ? cameraToWorld_.applyPoint(origin) : pinholeOrigin_;
        ray.direction = normalize(cameraToWorld_.applyVector(direction));
    } else {
        const Transform toWorld = cameraToWorld(ray.time);
        ray.origin = toWorld.applyPoint(origin);
        ray.direction = normalize(toWorld.applyVector(direction));
    }
    return ray;
}

Transform ThinLensCamera::cameraToWorld(float time) const {
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
