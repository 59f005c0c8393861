// The camera: a pose (moving over the shutter or not) and one of the projections, which turns a
// film position and a lens sample into a weighted world-space ray. The projections are a closed
// set (std::variant), each in a header of its own: the thin-lens perspective (thin_lens.h), the
// orthographic (orthographic.h), the spherical (spherical.h), the fisheye (fisheye.h) and the lens
// system (lens_system.h).
#pragma once

#include <variant>
#include <vector>

#include "cameras/camera_params.h"
#include "cameras/camera_ray.h"
#include "cameras/fisheye.h"
#include "cameras/lens_system.h"
#include "cameras/orthographic.h"
#include "cameras/spherical.h"
#include "cameras/thin_lens.h"
#include "core/ray.h"
#include "core/transform.h"
#include "core/vec.h"
#include "textures/texture_footprint.h"

namespace penumbra {

using Projection = std::variant<ThinLensProjection, OrthographicProjection, SphericalProjection,
                                FisheyeProjection, LensSystemProjection>;

// A world-space camera ray and what it carries to the film: the radiance along the ray times
// `weight` (0: no light reaches the film along it; the ray need not be traced).
struct CameraRay {
    Ray ray;
    float weight = 1.0f;
};

class Camera {
public:
    // Parameters are validated by the scene loader; throws InputError on degenerate ones anyway.
    Camera(const CameraParams& params, int filmWidth, int filmHeight);

    // filmPosition in raster space: x to the right, y down, (0, 0) the top-left corner of the
    // image and (width, height) the bottom-right. lensSample and timeSample are uniform in [0, 1);
    // the ray's time is the shutter fraction timeSample.
    CameraRay generateRay(Vec2f filmPosition, Vec2f lensSample, float timeSample) const {
        // The thin lens inline, the other projections out of line: inlining them all into the
        // render loop made its body larger and the loop slower (bench/README.md, "Speed tricks").
        if (const auto* thinLens = std::get_if<ThinLensProjection>(&projection_))
            return toWorld(thinLens->generate(filmPosition, lensSample), timeSample);
        return generateOtherRay(filmPosition, lensSample, timeSample);
    }

    // Whether generateRay reads lensSample (a lens of non-zero aperture, a lens system): a sample
    // that is not read need not be drawn.
    bool usesLensSample() const { return usesLensSample_; }

    // The camera-to-world transform at a shutter fraction.
    Transform cameraToWorld(float time = 0.0f) const;
    // What a texture lookup's footprint needs of the camera (textures/texture_footprint.h), at
    // shutter open, for `samplesPerPixel` samples per pixel.
    CameraFootprint footprint(int samplesPerPixel) const;

private:
    CameraRay generateOtherRay(Vec2f filmPosition, Vec2f lensSample, float timeSample) const;
    CameraRay toWorld(const CameraSpaceRay& local, float timeSample) const {
        CameraRay out;
        out.weight = local.weight;
        Ray& ray = out.ray;
        ray.time = timeSample;
        if (motion_.empty()) {
            ray.origin = fromOrigin_ ? pinholeOrigin_ : cameraToWorld_.applyPoint(local.origin);
            ray.direction = normalize(cameraToWorld_.applyVector(local.direction));
        } else {
            const Transform toWorld = cameraToWorld(ray.time);
            ray.origin = toWorld.applyPoint(local.origin);
            ray.direction = normalize(toWorld.applyVector(local.direction));
        }
        return out;
    }

    Projection projection_;
    Transform cameraToWorld_;
    Vec3f pinholeOrigin_;      // cameraToWorld_ applied to the camera-space origin, once
    bool fromOrigin_ = false;  // every ray starts at the camera-space origin (a pinhole, spherical, fisheye)
    bool usesLensSample_ = false;
    std::vector<CameraPose> motion_;
};

}  // namespace penumbra
