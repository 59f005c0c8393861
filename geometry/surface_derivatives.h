// The partial derivatives dp/du and dp/dv of a surface at a shading point, for the footprint of a
// texture lookup (textures/texture_footprint.h). Computed only where a texture needs them.
#pragma once

#include <array>
#include <cmath>

#include "core/frame.h"
#include "core/sampling.h"
#include "geometry/scene_geometry.h"
#include "geometry/surface_interaction.h"

namespace penumbra {

struct SurfaceDerivatives {
    Vec3f dpdu, dpdv;
};

// World-space derivatives at `si` (found by a ray at shutter fraction `time`). A triangle's come
// from its vertices' uvs (pbrt-v4's Triangle::InteractionFromIntersection; a mesh without uvs has
// none and gets the normal's frame); a sphere's from its (phi / 2 pi, theta / pi) parameterisation.
inline SurfaceDerivatives surfaceDerivatives(const SceneGeometry& scene, const SurfaceInteraction& si,
                                             float time) {
    const Frame fallback = Frame::fromNormal(si.geometricNormal);
    SurfaceDerivatives d{fallback.s, fallback.t};
    const ShapeRef shape = si.shape;
    Transform toWorld;
    bool moves = false;
    if (shape.kind == ShapeKind::Curves) {
        // Along the curve (its tangent, at the curve's speed in its u) and across it (pbrt-v4's
        // dpdv of a flat curve: the width).
        const Curves& curves = scene.curves[shape.index];
        const Vec2f range = curves.uRanges[shape.primitive];
        const float segmentU = detail::curveSegmentU(curves, shape.primitive, si.uv.x);
        const float speed = length(curve::bezierDerivative(curves.controlPoints(shape.primitive), segmentU));
        const Vec3f tangent = curveTangent(scene, si);
        d.dpdu = tangent * (range.y > range.x ? speed / (range.y - range.x) : speed);
        d.dpdv = cross(si.geometricNormal, tangent) *
                 (2.0f * curve::bezier(curves.controlRadii(shape.primitive), segmentU));
        return d;
    }
    if (shape.kind == ShapeKind::BilinearPatches) {
        // The patch's own derivatives at its (u, v), taken to the texture's uv by the inverse of the
        // uvs' Jacobian when the patch has uvs (pbrt-v4's).
        const BilinearPatches& patches = scene.patches[shape.index];
        const std::array<Vec3f, 4> p = patches.cornerPositions(shape.primitive);
        Vec2f uv = si.uv;
        Vec2f q[4];
        if (!patches.uvs.empty()) {
            for (int k = 0; k < 4; ++k) q[k] = patches.uvs[patches.indices[4 * size_t(shape.primitive) + k]];
            uv = bilinear::inverse(q, si.uv);
        }
        d.dpdu = bilinear::dpdu(p.data(), uv.y);
        d.dpdv = bilinear::dpdv(p.data(), uv.x);
        if (!patches.uvs.empty()) {
            const Vec2f dqdu = bilinear::lerp(uv.y, q[1] - q[0], q[3] - q[2]),
                        dqdv = bilinear::lerp(uv.x, q[2] - q[0], q[3] - q[1]);
            const float determinant = dqdu.x * dqdv.y - dqdu.y * dqdv.x;
            if (!(std::abs(determinant) > 1e-12f)) return d;
            // [dp/ds dp/dt] = [dp/du dp/dv] J^-1, J = [dq/du dq/dv].
            const Vec3f dpdu = d.dpdu, dpdv = d.dpdv;
            d.dpdu = (dpdu * dqdv.y - dpdv * dqdu.y) / determinant;
            d.dpdv = (dpdv * dqdu.x - dpdu * dqdv.x) / determinant;
        }
        return d;
    }
    if (shape.kind == ShapeKind::Mesh) {
        const TriangleMesh& mesh = scene.meshes[shape.index];
        if (mesh.uvs.empty()) return d;
        const uint32_t* index = &mesh.indices[3 * size_t(shape.primitive)];
        const Vec3f p0 = detail::vertexAt(mesh, index[0], time), p1 = detail::vertexAt(mesh, index[1], time),
                    p2 = detail::vertexAt(mesh, index[2], time);
        const Vec2f duv02 = mesh.uvs[index[0]] - mesh.uvs[index[2]],
                    duv12 = mesh.uvs[index[1]] - mesh.uvs[index[2]];
        const Vec3f dp02 = p0 - p2, dp12 = p1 - p2;
        const float determinant = duv02.x * duv12.y - duv02.y * duv12.x;
        if (!(std::abs(determinant) > 1e-12f)) return d;
        const float inverse = 1.0f / determinant;
        d.dpdu = (dp02 * duv12.y - dp12 * duv02.y) * inverse;
        d.dpdv = (dp12 * duv02.x - dp02 * duv12.x) * inverse;
        moves = mesh.motion.moves();
        if (moves) toWorld = mesh.motion.at(time);
    } else {
        const Sphere& sphere = scene.spheres[shape.index];
        moves = sphere.motion.moves();
        if (moves) toWorld = sphere.motion.at(time);
        // The outward normal in the sphere's own space: (sin t cos p, sin t sin p, cos t).
        const Vec3f n =
            moves ? normalize(toWorld.inverse().applyNormal(si.geometricNormal)) : si.geometricNormal;
        const float r = sphere.radius;
        const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - n.z * n.z));
        if (!(sinTheta > 1e-6f)) return d;
        const float cosPhi = n.x / sinTheta, sinPhi = n.y / sinTheta;
        d.dpdu = Vec3f{-n.y, n.x, 0.0f} * (2.0f * kPi * r);
        d.dpdv = Vec3f{n.z * cosPhi, n.z * sinPhi, -sinTheta} * (kPi * r);
    }
    if (moves) {
        d.dpdu = toWorld.applyVector(d.dpdu);
        d.dpdv = toWorld.applyVector(d.dpdv);
    }
    return d;
}

}  // namespace penumbra
