// One triangle of an emitting mesh (geometry/emission.h) as an area light: sampled uniformly by
// area. On a mesh with a cut-out (geometry/cut_out.h) a sampled point's radiance is multiplied by
// the coverage there: the expectation of the stochastic test that a ray hitting the point passes,
// so next-event estimation and hits agree (a hit, once kept, sees the full radiance).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "core/float_error.h"
#include "core/rgb.h"
#include "core/sampling.h"
#include "core/vec.h"
#include "geometry/cut_out.h"
#include "geometry/emission.h"
#include "geometry/surface_interaction.h"
#include "geometry/triangle.h"
#include "geometry/triangle_mesh.h"
#include "lights/light_bounds.h"
#include "lights/light_sample.h"

namespace penumbra {

struct TriangleLight {
    Vec3f p0, p1, p2;
    Vec3f normal;    // front normal (unit)
    float area = 0;  // 0 for a degenerate triangle, which has no power and is never chosen
    Rgb radiance;    // with a texture, its average (which sets the power)
    bool twoSided = false;
    const Texture* texture = nullptr;  // textured emission; its mesh keeps it alive
    const Texture* alpha = nullptr;    // the mesh's cut-out; its mesh keeps it alive
    Vec2f uv0, uv1, uv2;               // textured or cut out: the vertices' uvs

    // Triangle `t` of an emitting mesh.
    static TriangleLight fromMesh(const TriangleMesh& mesh, size_t t) {
        TriangleLight light;
        light.radiance = mesh.emission.radiance;
        light.twoSided = mesh.emission.twoSided;
        light.p0 = mesh.positions[mesh.indices[3 * t]];
        light.p1 = mesh.positions[mesh.indices[3 * t + 1]];
        light.p2 = mesh.positions[mesh.indices[3 * t + 2]];
        light.texture = mesh.emission.texture.get();
        light.alpha = mesh.alpha.get();
        if ((light.texture || light.alpha) && !mesh.uvs.empty()) {
            light.uv0 = mesh.uvs[mesh.indices[3 * t]];
            light.uv1 = mesh.uvs[mesh.indices[3 * t + 1]];
            light.uv2 = mesh.uvs[mesh.indices[3 * t + 2]];
        }
        const Vec3f n = cross(light.p1 - light.p0, light.p2 - light.p0);
        light.area = 0.5f * length(n);
        light.normal = light.area > 0.0f ? normalize(n) : Vec3f{0, 0, 1};
        return light;
    }

    static constexpr bool kIsDelta = false, kIsInfinite = false;

    static constexpr bool kPointIndependentOfReference = true;
    double power(double /*sceneRadius*/) const {
        return double(radiance.luminance()) * area * kPi * (twoSided ? 2 : 1);
    }
    LightBounds bounds(float power) const {
        LightBounds b;
        b.phi = power;
        b.center = (p0 + p1 + p2) / 3.0f;
        b.radius = std::sqrt(std::max(
            {lengthSquared(p0 - b.center), lengthSquared(p1 - b.center), lengthSquared(p2 - b.center)}));
        b.axis = normal;
        b.cosThetaO = 1.0f;  // one normal
        b.twoSided = twoSided;
        return b;
    }
    bool sample(Vec3f reference, Vec2f u, LightSample& ls) const {
        const TrianglePointSample s = sampleTriangle(p0, p1, p2, u);
        const Vec2f b = s.barycentrics;
        ls.point = s.point;
        ls.pointError = s.pointError;
        ls.lightNormal = normal;
        AreaSampleGeometry g;
        if (!connectAreaSample(reference, ls, g)) return false;
        Rgb emitted = radiance;
        if (texture || alpha) {
            const Vec2f uv = uv0 * (1.0f - b.x - b.y) + uv1 * b.x + uv2 * b.y;
            if (texture) emitted = emittedRadiance(*texture, uv);
            if (alpha) emitted *= std::clamp(cutOutCoverage(*alpha, uv), 0.0f, 1.0f);
        }
        ls.radiance = (g.cosAtLight > 0.0f || twoSided) ? emitted : Rgb(0.0f);
        // From the distance and cosine at hand; pdf() computes them again (the two differ by rounding).
        ls.pdf = areaToSolidAnglePdf(g.distanceSquared, std::abs(g.cosAtLight), area);
        return true;
    }
    float pdf(Vec3f reference, Vec3f point) const {
        const Vec3f toPoint = point - reference;
        const float distanceSquared = lengthSquared(toPoint);
        const float cosAtLight = std::abs(dot(normal, toPoint)) / std::sqrt(distanceSquared);
        return areaToSolidAnglePdf(distanceSquared, cosAtLight, area);
    }
    // Radiance leaving the hit `si` on it towards `towardsViewer`.
    Rgb emitted(const SurfaceInteraction& si, Vec3f towardsViewer) const {
        if (twoSided || dot(si.geometricNormal, towardsViewer) > 0.0f)
            return texture ? emittedRadiance(*texture, si.uv) : radiance;
        return Rgb(0.0f);
    }
};

}  // namespace penumbra
