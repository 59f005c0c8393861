#include "geometry/curves.h"

#include "core/check.h"

namespace penumbra {

size_t curveSegmentCount(size_t pointCount, CurveBasis basis) {
    if (pointCount < 4) return 0;
    if (basis == CurveBasis::BSpline) return pointCount - 3;
    return (pointCount - 1) % 3 == 0 ? (pointCount - 1) / 3 : 0;
}

std::vector<float> linearCurveRadii(size_t pointCount, CurveBasis basis, float width0, float width1) {
    const size_t segments = curveSegmentCount(pointCount, basis);
    std::vector<float> radii(pointCount, 0.5f * width0);
    if (segments == 0) return radii;
    for (size_t j = 0; j < pointCount; ++j) {
        // In units of segments: a Bezier point j sits at j / 3; a B-spline's at j - 1 (its
        // segment i starts at the average of points i, i + 1, i + 2, centred on i + 1).
        const double abscissa = basis == CurveBasis::Bezier ? double(j) / 3.0 : double(j) - 1.0;
        const double u = abscissa / double(segments);
        radii[j] = float(0.5 * ((1.0 - u) * width0 + u * width1));
    }
    return radii;
}

namespace {

struct Piece {
    Vec3f p[4];
    float r[4];
    float u0, u1;
};

void appendPiece(Curves& curves, const Piece& piece, Vec3f n0, Vec3f n1, int depth, bool ribbon) {
    if (depth > 0) {
        Piece left, right;
        curve::split(piece.p, left.p, right.p);
        curve::split(piece.r, left.r, right.r);
        const float uMid = 0.5f * (piece.u0 + piece.u1);
        left.u0 = piece.u0, left.u1 = uMid, right.u0 = uMid, right.u1 = piece.u1;
        const Vec3f nMid = ribbon ? curve::ribbonNormal(n0, n1, 0.5f) : Vec3f{};
        appendPiece(curves, left, n0, nMid, depth - 1, ribbon);
        appendPiece(curves, right, nMid, n1, depth - 1, ribbon);
        return;
    }
    curves.points.insert(curves.points.end(), piece.p, piece.p + 4);
    curves.radii.insert(curves.radii.end(), piece.r, piece.r + 4);
    curves.uRanges.push_back({piece.u0, piece.u1});
    if (ribbon) curves.normals.insert(curves.normals.end(), {n0, n1});
}

}  // namespace

void appendCurve(Curves& curves, std::span<const Vec3f> points, std::span<const float> radii,
                 CurveBasis basis, std::span<const Vec3f> normals, int splitDepth) {
    const size_t segments = curveSegmentCount(points.size(), basis);
    const bool ribbon = curves.type == CurveType::Ribbon;
    PENUMBRA_CHECK(segments > 0 && radii.size() == points.size(),
                   "a curve has whole segments and a radius a point");
    PENUMBRA_CHECK(!ribbon || normals.size() == segments + 1, "a ribbon has a normal a segment boundary");
    for (size_t i = 0; i < segments; ++i) {
        Piece piece;
        const size_t first = basis == CurveBasis::Bezier ? 3 * i : i;
        if (basis == CurveBasis::Bezier) {
            for (int k = 0; k < 4; ++k) piece.p[k] = points[first + k], piece.r[k] = radii[first + k];
        } else {
            curve::bsplineToBezier(&points[first], piece.p);
            curve::bsplineToBezier(&radii[first], piece.r);
        }
        piece.u0 = float(i) / float(segments);
        piece.u1 = float(i + 1) / float(segments);
        appendPiece(curves, piece, ribbon ? normals[i] : Vec3f{}, ribbon ? normals[i + 1] : Vec3f{},
                    splitDepth, ribbon);
    }
}

}  // namespace penumbra
