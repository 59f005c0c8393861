#include "cameras/lens_system.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/sampling.h"

namespace penumbra {

namespace {

// The number of film-radius intervals with an exit pupil bound of their own, and the candidate
// rays each bound is found from.
constexpr int kPupilIntervals = 64;
constexpr int kPupilCandidates = 1 << 16;

float airIfZero(float eta) { return eta == 0.0f ? 1.0f : eta; }

// Snell's law: the direction refracted from the incident direction `d` at a surface of normal `n`
// facing the incoming ray (dot(n, d) < 0), for eta = eta_incident / eta_transmitted; nullopt on
// total internal reflection.
std::optional<Vec3f> refract(Vec3f d, Vec3f n, float eta) {
    const Vec3f wi = -normalize(d);
    const float cosI = dot(n, wi);
    const float sin2T = eta * eta * std::max(0.0f, 1.0f - cosI * cosI);
    if (sin2T >= 1.0f) return std::nullopt;
    const float cosT = std::sqrt(1.0f - sin2T);
    return -wi * eta + n * (eta * cosI - cosT);
}

// The radical inverse of i in base 2 and 3: Halton points for the pupil search.
float radicalInverse(uint32_t i, uint32_t base) {
    const float invBase = 1.0f / float(base);
    float inverse = 0.0f, scale = invBase;
    for (; i > 0; i /= base, scale *= invBase) inverse += float(i % base) * scale;
    return inverse;
}

}  // namespace

LensSystemProjection::LensSystemProjection(const CameraParams& p, float focusDistance, int filmWidth,
                                           int filmHeight) {
    const LensSystemParams& lens = p.lensSystem;
    if (lens.surfaces.empty()) throw InputError("camera: the lens system has no surface");
    if (!(lens.mmPerSceneUnit > 0.0f)) throw InputError("camera: a scene unit's length in mm must be > 0");
    if (!(lens.filmDiagonalMm > 0.0f)) throw InputError("camera: the film diagonal must be > 0");
    const float unit = 1.0f / lens.mmPerSceneUnit;  // scene units per millimetre
    for (const LensSurface& s : lens.surfaces) {
        float diameter = s.apertureDiameter;
        if (s.curvatureRadius == 0.0f && lens.apertureDiameterMm > 0.0f)
            diameter = std::min(diameter, lens.apertureDiameterMm);  // the stop opens at most to its rim
        surfaces_.push_back(
            {s.curvatureRadius * unit, s.thickness * unit, airIfZero(s.eta), 0.5f * diameter * unit});
    }
    if (!p.apertureImage.empty()) {
        stopShape_ = Aperture::image(p.apertureImage);
        stopIsImage_ = true;
    }
    const float aspect = float(filmHeight) / float(filmWidth);
    const float diagonal = lens.filmDiagonalMm * unit;
    filmHalfWidth_ = 0.5f * std::sqrt(diagonal * diagonal / (1.0f + aspect * aspect));
    filmHalfHeight_ = aspect * filmHalfWidth_;
    filmHalfDiagonal_ = 0.5f * diagonal;
    invWidth_ = 1.0f / float(filmWidth);
    invHeight_ = 1.0f / float(filmHeight);
    pixelPitch_ = 2.0f * filmHalfHeight_ * invHeight_;

    // Focus: move the lens by delta so that the plane at `focusDistance` from the film images onto
    // it. With the principal planes P (front) and P' (rear) at distances a = D - P and b = P' from
    // the object and the film, the lens equation 1/(a - delta) + 1/(b + delta) = 1/f gives
    // delta^2 - (a - b) delta + (a + b) f - a b = 0, whose smaller root keeps the usual
    // configuration (the image a little beyond f); it needs a + b >= 4 f.
    const CardinalPoints c = cardinalPoints();
    const float f = c.focalLength();
    focalLength_ = f;
    if (!(f > 0.0f))
        throw InputError(fmt::format("camera: the lens system does not converge light (focal length {})", f));
    const double a = double(focusDistance) - double(c.frontPrincipalZ), b = double(c.rearPrincipalZ);
    const double discriminant = (a + b) * (a + b - 4.0 * double(f));
    if (!(discriminant >= 0.0))
        throw InputError(
            fmt::format("camera: the lens system cannot focus at {} scene units from the film (its focal "
                        "length is {} mm: "
                        "objects closer than about four focal lengths cannot be focused)",
                        focusDistance, f / unit));
    const double delta = 0.5 * ((a - b) - std::sqrt(discriminant));
    surfaces_.back().thickness += float(delta);
    if (!(surfaces_.back().thickness > 0.0f))
        throw InputError("camera: focusing the lens system would put the film inside the lens");

    // Each interval's bound is found on its own (the same bounds whatever the thread count).
    exitPupil_.resize(kPupilIntervals);
    tbb::parallel_for(0, kPupilIntervals, [&](int i) {
        exitPupil_[size_t(i)] = boundExitPupil(float(i) / kPupilIntervals * filmHalfDiagonal_,
                                               float(i + 1) / kPupilIntervals * filmHalfDiagonal_);
    });
    if (std::all_of(exitPupil_.begin(), exitPupil_.end(), [](const PupilBounds& b) { return b.empty(); }))
        throw InputError("camera: no ray from the film passes through the lens system");
}

float LensSystemProjection::frontZ() const {
    float z = 0.0f;
    for (const Surface& s : surfaces_) z += s.thickness;
    return z;
}

bool LensSystemProjection::intersect(size_t i, float vertexZ, Vec3f origin, Vec3f direction, Vec3f& hit,
                                     Vec3f& normal) const {
    const Surface& s = surfaces_[i];
    // The sphere through the vertex with its centre R behind it (towards the film for R > 0).
    const Vec3f centre{0.0f, 0.0f, vertexZ - s.curvatureRadius};
    const Vec3f o = origin - centre;
    const float A = dot(direction, direction), B = 2.0f * dot(direction, o),
                C = dot(o, o) - s.curvatureRadius * s.curvatureRadius;
    const float discriminant = B * B - 4.0f * A * C;
    if (!(discriminant >= 0.0f)) return false;
    // The numerically stable roots.
    const float q = -0.5f * (B + std::copysign(std::sqrt(discriminant), B));
    float t0 = q / A, t1 = C / q;
    if (t0 > t1) std::swap(t0, t1);
    // The surface is the cap around the vertex, on the vertex's side of the centre (+z of it for
    // R > 0): the ray meets that side first when it comes from it, its z direction and R's sign
    // differing.
    const bool nearer = (direction.z > 0.0f) != (s.curvatureRadius > 0.0f);
    const float t = nearer ? t0 : t1;
    if (!(t >= 0.0f)) return false;
    hit = origin + direction * t;
    normal = normalize(hit - centre);
    if (dot(normal, direction) > 0.0f) normal = -normal;
    return true;
}

std::optional<CameraSpaceRay> LensSystemProjection::trace(Vec3f origin, Vec3f direction,
                                                          bool fromFilm) const {
    const size_t n = surfaces_.size();
    float weight = 1.0f;
    // The vertex z of each surface, walked from the film (the last surface) or from the front.
    float vertexZ = fromFilm ? 0.0f : frontZ();
    for (size_t k = 0; k < n; ++k) {
        const size_t i = fromFilm ? n - 1 - k : k;
        const Surface& s = surfaces_[i];
        if (fromFilm) vertexZ += s.thickness;
        Vec3f hit, normal;
        const bool isStop = s.curvatureRadius == 0.0f;
        if (isStop) {
            const float t = (vertexZ - origin.z) / direction.z;
            if (!(t >= 0.0f)) return std::nullopt;
            hit = origin + direction * t;
        } else if (!intersect(i, vertexZ, origin, direction, hit, normal)) {
            return std::nullopt;
        }
        const float r2 = hit.x * hit.x + hit.y * hit.y;
        if (isStop && stopIsImage_) {
            // The stop's shape: only rays from the film see it (the focus search does not).
            if (fromFilm)
                weight = stopShape_.transmission({hit.x / s.apertureRadius, hit.y / s.apertureRadius});
            else if (!(r2 <= s.apertureRadius * s.apertureRadius))
                return std::nullopt;
            if (!(weight > 0.0f)) return std::nullopt;
        } else if (!(r2 <= s.apertureRadius * s.apertureRadius)) {
            return std::nullopt;
        }
        origin = hit;
        if (!isStop) {
            // The media on either side: behind the surface (film side) its own index, in front the
            // previous surface's (air before the first).
            const float behind = s.eta, inFront = i > 0 ? surfaces_[i - 1].eta : 1.0f;
            const auto refracted = refract(direction, normal, fromFilm ? behind / inFront : inFront / behind);
            if (!refracted) return std::nullopt;
            direction = *refracted;
        }
        if (!fromFilm) vertexZ -= s.thickness;
    }
    return CameraSpaceRay{origin, direction, weight};
}

std::optional<CameraSpaceRay> LensSystemProjection::traceFromFilm(Vec3f origin, Vec3f direction) const {
    return trace(origin, direction, true);
}

std::optional<CameraSpaceRay> LensSystemProjection::traceFromScene(Vec3f origin, Vec3f direction) const {
    return trace(origin, direction, false);
}

LensSystemProjection::CardinalPoints LensSystemProjection::cardinalPoints() const {
    // A ray parallel to the axis at height h: where the ray leaving the lens crosses the axis is
    // the focal point, where it (extended back) reaches height h the principal plane.
    const float h = 0.001f * filmHalfDiagonal_ * 2.0f;
    CardinalPoints c;
    auto crossings = [h](const CameraSpaceRay& out, float& principalZ, float& focalZ) {
        const float toAxis = -out.origin.x / out.direction.x;
        focalZ = out.origin.z + toAxis * out.direction.z;
        const float toHeight = (h - out.origin.x) / out.direction.x;
        principalZ = out.origin.z + toHeight * out.direction.z;
    };
    const auto fromScene = traceFromScene({h, 0.0f, frontZ() + 1.0f}, {0.0f, 0.0f, -1.0f});
    const auto fromFilm = traceFromFilm({h, 0.0f, -1.0f}, {0.0f, 0.0f, 1.0f});
    if (!fromScene || !fromFilm)
        throw InputError(
            "camera: a ray parallel to the axis does not pass the lens system (is its stop closed?)");
    crossings(*fromScene, c.rearPrincipalZ, c.rearFocalZ);
    crossings(*fromFilm, c.frontPrincipalZ, c.frontFocalZ);
    return c;
}

LensSystemProjection::PupilBounds LensSystemProjection::boundExitPupil(float r0, float r1) const {
    const float rear = surfaces_.back().apertureRadius * 1.5f;  // a square around the rear element
    constexpr float kHuge = std::numeric_limits<float>::max();
    PupilBounds bounds{{kHuge, kHuge}, {-kHuge, -kHuge}};
    bool found = false;
    for (int i = 0; i < kPupilCandidates; ++i) {
        const Vec3f film{r0 + (r1 - r0) * (float(i) + 0.5f) / kPupilCandidates, 0.0f, 0.0f};
        const Vec2f onRear{-rear + 2.0f * rear * radicalInverse(uint32_t(i), 2),
                           -rear + 2.0f * rear * radicalInverse(uint32_t(i), 3)};
        const bool inside = found && onRear.x >= bounds.lower.x && onRear.x <= bounds.upper.x &&
                            onRear.y >= bounds.lower.y && onRear.y <= bounds.upper.y;
        if (inside || !traceFromFilm(film, Vec3f{onRear.x, onRear.y, rearZ()} - film)) continue;
        bounds.lower = {std::min(bounds.lower.x, onRear.x), std::min(bounds.lower.y, onRear.y)};
        bounds.upper = {std::max(bounds.upper.x, onRear.x), std::max(bounds.upper.y, onRear.y)};
        found = true;
    }
    if (!found) return {};
    // Grown by two candidate spacings: the candidates sample the square, not its every point.
    const float margin = 2.0f * (2.0f * rear * std::sqrt(2.0f)) / std::sqrt(float(kPupilCandidates));
    bounds.lower = {bounds.lower.x - margin, bounds.lower.y - margin};
    bounds.upper = {bounds.upper.x + margin, bounds.upper.y + margin};
    return bounds;
}

CameraSpaceRay LensSystemProjection::generate(Vec2f filmPosition, Vec2f lensSample) const {
    constexpr CameraSpaceRay kBlocked{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f};
    // The film point: the image is inverted by the lens, so the raster's right is the film's left
    // and the raster's bottom the film's top.
    const Vec3f film{filmHalfWidth_ * (1.0f - 2.0f * filmPosition.x * invWidth_),
                     filmHalfHeight_ * (2.0f * filmPosition.y * invHeight_ - 1.0f), 0.0f};
    const float radius = std::sqrt(film.x * film.x + film.y * film.y);
    const int interval = std::min(kPupilIntervals - 1, int(radius / filmHalfDiagonal_ * kPupilIntervals));
    const PupilBounds& pupil = exitPupil_[size_t(interval)];
    if (pupil.empty()) return kBlocked;
    // A point of the bounds (found for film points on +x), turned to the film point's angle.
    const Vec2f p{pupil.lower.x + (pupil.upper.x - pupil.lower.x) * lensSample.x,
                  pupil.lower.y + (pupil.upper.y - pupil.lower.y) * lensSample.y};
    const float cosPhi = radius > 0.0f ? film.x / radius : 1.0f,
                sinPhi = radius > 0.0f ? film.y / radius : 0.0f;
    const Vec3f onRear{cosPhi * p.x - sinPhi * p.y, sinPhi * p.x + cosPhi * p.y, rearZ()};
    const Vec3f direction = onRear - film;
    const auto out = traceFromFilm(film, direction);
    if (!out) return kBlocked;
    // The film's measurement: radiance times cos^4 over the squared distance to the rear plane,
    // per unit pupil area (the density of the pupil point is 1 / area).
    const float cosTheta = normalize(direction).z;
    const float area = (pupil.upper.x - pupil.lower.x) * (pupil.upper.y - pupil.lower.y);
    const float weight =
        out->weight * (cosTheta * cosTheta) * (cosTheta * cosTheta) * area / (rearZ() * rearZ());
    return {out->origin, out->direction, weight};
}

}  // namespace penumbra
