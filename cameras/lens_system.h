// A camera that traces rays through a real lens design (Kolb, Mitchell and Hanrahan 1995, as
// pbrt-v4's RealisticCamera): spherical surfaces and a plane aperture stop from a lens file
// (cameras/lens_file.h), the film behind them at the distance that focuses the lens on
// `focusDistance` (the thick-lens approximation from traced cardinal points), rays aimed at the
// exit pupil's bounds precomputed per film radius, and pbrt-v4's radiometry: a ray's weight is
// cos^4(theta) times the pupil's area over the squared film-to-rear-lens distance, so vignetting and
// exposure are physical. Everything is in camera space: +z towards the scene, the film's centre at
// the origin, the lens in front of it.
#pragma once

#include <optional>
#include <vector>

#include "cameras/aperture.h"
#include "cameras/camera_params.h"
#include "cameras/camera_ray.h"

namespace penumbra {

class LensSystemProjection {
public:
    // `focusDistance`: from the film to the plane in focus, in scene units. Throws InputError when
    // the lens cannot focus there, lets no light through, or has no surface.
    LensSystemProjection(const CameraParams& params, float focusDistance, int filmWidth, int filmHeight);

    CameraSpaceRay generate(Vec2f filmPosition, Vec2f lensSample) const;
    bool usesLensSample() const { return true; }
    // The angle between neighbouring pixels at the image centre (radians): pixel pitch over focal
    // length.
    float pixelSpacing() const { return pixelPitch_ / focalLength_; }

    // A ray from the film side through every surface to the scene (or from the scene to the film
    // side): the ray leaving the last surface, weighted by the stop's transmission; nullopt when a
    // surface's rim or the stop blocks it, or it is totally reflected.
    std::optional<CameraSpaceRay> traceFromFilm(Vec3f origin, Vec3f direction) const;
    std::optional<CameraSpaceRay> traceFromScene(Vec3f origin, Vec3f direction) const;

    // The thick-lens approximation (camera-space z of the principal planes and focal points, from a
    // ray parallel to the axis at a small height traced each way).
    struct CardinalPoints {
        float rearPrincipalZ = 0.0f, rearFocalZ = 0.0f;    // of light arriving from the scene
        float frontPrincipalZ = 0.0f, frontFocalZ = 0.0f;  // of light arriving from the film
        float focalLength() const { return rearPrincipalZ - rearFocalZ; }
    };
    CardinalPoints cardinalPoints() const;
    // The z of the rear surface's vertex (the film-to-lens distance, as focused) and of the front's.
    float rearZ() const { return surfaces_.back().thickness; }
    float frontZ() const;
    float filmHalfDiagonal() const { return filmHalfDiagonal_; }

private:
    struct Surface {
        float curvatureRadius;  // signed; 0: the aperture stop
        float thickness;        // to the next surface (the last: to the film)
        float eta;              // behind the surface (film side); air is 1
        float apertureRadius;
    };
    struct PupilBounds {
        Vec2f lower{0.0f, 0.0f}, upper{0.0f, 0.0f};
        bool empty() const { return !(upper.x > lower.x && upper.y > lower.y); }
    };

    // Where the ray meets surface i (camera space), and the surface's normal facing the ray.
    bool intersect(size_t i, float vertexZ, Vec3f origin, Vec3f direction, Vec3f& hit, Vec3f& normal) const;
    std::optional<CameraSpaceRay> trace(Vec3f origin, Vec3f direction, bool fromFilm) const;
    // The bounds, on the plane of the rear vertex, of the points through which rays from film
    // points at distance [r0, r1] along +x pass the whole lens.
    PupilBounds boundExitPupil(float r0, float r1) const;

    std::vector<Surface> surfaces_;
    Aperture stopShape_;  // round unless an aperture image is given
    bool stopIsImage_ = false;
    std::vector<PupilBounds> exitPupil_;  // per film radius interval, over [0, filmHalfDiagonal_)
    float filmHalfWidth_ = 0.0f, filmHalfHeight_ = 0.0f, filmHalfDiagonal_ = 0.0f;
    float invWidth_ = 1.0f, invHeight_ = 1.0f;
    float pixelPitch_ = 0.0f, focalLength_ = 1.0f;
};

}  // namespace penumbra
