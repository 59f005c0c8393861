// An emitting sphere (geometry/emission.h) as an area light: sampled by the solid angle it
// subtends (geometry/sphere.h).
#pragma once

#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "geometry/emission.h"
#include "geometry/sphere.h"
#include "geometry/surface_interaction.h"
#include "lights/light_bounds.h"
#include "lights/light_sample.h"

namespace penumbra {

struct SphereLight {
    Vec3f center;
    float radius = 0;
    Rgb radiance;  // with a texture, its average (which sets the power)
    bool twoSided = false;
    const Texture* texture =
        nullptr;  // textured emission over the sphere's (u, v); the sphere keeps it alive

    static SphereLight fromSphere(const Sphere& sphere) {
        return {sphere.center, sphere.radius, sphere.emission.radiance, sphere.emission.twoSided,
                sphere.emission.texture.get()};
    }

    static constexpr bool kIsDelta = false, kIsInfinite = false;

    static constexpr bool kPointIndependentOfReference = false;
    double power(double /*sceneRadius*/) const {
        const double area = 4.0 * kPi * double(radius) * radius;
        return double(radiance.luminance()) * area * kPi * (twoSided ? 2 : 1);
    }
    LightBounds bounds(float power) const {
        LightBounds b;
        b.phi = power;
        b.center = center;
        b.radius = radius;
        return b;
    }
    bool sample(Vec3f reference, Vec2f u, LightSample& ls) const {
        const SpherePointSample s = sampleSphereSeenFrom(center, radius, reference, u);
        ls.lightNormal = s.normal;
        ls.point = s.point;
        ls.pointError = s.pointError;
        AreaSampleGeometry g;
        if (!connectAreaSample(reference, ls, g)) return false;
        const Rgb emitted = texture ? emittedRadiance(*texture, sphereUv(ls.lightNormal)) : radiance;
        ls.radiance = (g.cosAtLight > 0.0f || twoSided) ? emitted : Rgb(0.0f);
        ls.pdf = pdf(reference, ls.point);
        return true;
    }
    float pdf(Vec3f reference, Vec3f point) const {
        return sphereSampleSolidAnglePdf(center, radius, reference, point);
    }
    Rgb emitted(const SurfaceInteraction& si, Vec3f towardsViewer) const {
        if (twoSided || dot(si.geometricNormal, towardsViewer) > 0.0f)
            return texture ? emittedRadiance(*texture, si.uv) : radiance;
        return Rgb(0.0f);
    }
};

}  // namespace penumbra
