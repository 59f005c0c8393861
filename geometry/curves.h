// Curves (hair, fur, grass): a set of cubic Bezier segments with a radius at each control point, as
// pbrt-v4's `curve` shape and Embree's curve geometries describe them, and the ray test our BVH
// uses and both backends' hits are recomputed with (geometry/surface_interaction.h).
//
// The surface is pbrt-v4's and Embree's "flat" curve: at each point of its centre line the curve
// is a segment of its width facing the ray, so a ray hits it where its distance to the centre line,
// seen along the ray, is at most the radius there. `Cylinder` curves are the same surface shaded
// with a normal turned across the width as a cylinder's would be; `Ribbon` curves have a normal of
// their own along the curve (interpolated between the two given at its ends), and a ray sees them
// as wide as their width times |cos| of that normal with the ray (pbrt-v4's approximation of an
// oriented ribbon).
//
// The ray test is our own: the segment is taken into the ray's space (the ray along +z from the
// origin), split in halves (de Casteljau) to a depth at which its pieces are straight within a
// twentieth of its narrowest width (pbrt-v4's bound from the control polygon's second
// differences), pieces whose boxes miss the ray culled; a piece hit is where the ray passes
// between the perpendiculars to the curve's tangents at its two ends, at the point of the piece
// nearest the ray (the chord's nearest point, refined by Newton's method on the curve).
// Embree tessellates its flat curves into ray-facing quads instead: the two tests agree but
// within a few hundredths of the width at a curve's silhouette (tools/crosscheck.h explains those).
// Like Embree's, our test sees no curve nearer to the ray's origin than twice its radius.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/frame.h"
#include "core/vec.h"
#include "geometry/medium_interface.h"

namespace penumbra {

enum class CurveType : uint8_t { Flat, Cylinder, Ribbon };

struct Curves {
    std::string name;
    CurveType type = CurveType::Flat;
    // Cubic Bezier segments, four control points each (B-splines are converted when read): their
    // positions and radii (half the width; the radius along a segment is the Bezier of its four).
    std::vector<Vec3f> points;
    std::vector<float> radii;
    // Per segment: the interval of its curve's parameter u it covers (shading's uv.x).
    std::vector<Vec2f> uRanges;
    // Ribbons only: the unit normals at each segment's start and end.
    std::vector<Vec3f> normals;
    uint32_t material = 0;
    MediumInterface media{};

    size_t segmentCount() const { return points.size() / 4; }
    const Vec3f* controlPoints(size_t segment) const { return &points[4 * segment]; }
    const float* controlRadii(size_t segment) const { return &radii[4 * segment]; }
};

// How a curve's control points make its segments: cubic Bezier (3 n + 1 points for n segments, the
// last point of one segment the first of the next) or uniform cubic B-spline (n + 3 points).
enum class CurveBasis : uint8_t { Bezier, BSpline };

// The number of segments of a curve of `pointCount` control points; 0 when the count does not make
// whole segments (fewer than 4, or a Bezier count not 3 n + 1).
size_t curveSegmentCount(size_t pointCount, CurveBasis basis);

// Appends one curve to `curves`: control `points` with a radius each (a B-spline's converted to
// Bezier segments, the same curve), each segment then halved `splitDepth` times (pbrt-v4's
// `splitdepth`: shorter segments box more tightly), covering u in [0, 1] along the curve. Ribbons
// take a unit normal at each segment boundary (segments + 1), interpolated along the curve.
// Requires curveSegmentCount(points.size(), basis) > 0 and radii.size() == points.size().
void appendCurve(Curves& curves, std::span<const Vec3f> points, std::span<const float> radii,
                 CurveBasis basis, std::span<const Vec3f> normals, int splitDepth);

// The control radii that give a curve of `pointCount` points a width varying linearly from width0
// at its start to width1 at its end, as pbrt-v4's `width0`/`width1` (each control point's at its
// Greville abscissa, where a linear function's control values lie).
std::vector<float> linearCurveRadii(size_t pointCount, CurveBasis basis, float width0, float width1);

// Where a ray met a curve segment: t along the ray, u in [0, 1] along the segment, and v across
// its width, the distance from the centre line over the radius, signed by side (as Embree reports
// flat curves: -1 and 1 are the two edges; a ribbon's are at -|cos| and |cos| of its normal with
// the ray).
struct CurveHit {
    float t = 0.0f, u = 0.0f, v = 0.0f;
};

namespace curve {

template <typename T>
T bezier(const T c[4], float u) {
    const float s = 1.0f - u;
    return c[0] * (s * s * s) + c[1] * (3.0f * s * s * u) + c[2] * (3.0f * s * u * u) + c[3] * (u * u * u);
}
template <typename T>
T bezierDerivative(const T c[4], float u) {
    const float s = 1.0f - u;
    return (c[1] - c[0]) * (3.0f * s * s) + (c[2] - c[1]) * (6.0f * s * u) + (c[3] - c[2]) * (3.0f * u * u);
}
// Splits a Bezier segment at its middle into `left` (u in [0, 1/2]) and `right` (de Casteljau).
template <typename T>
void split(const T c[4], T left[4], T right[4]) {
    const T m01 = (c[0] + c[1]) * 0.5f, m12 = (c[1] + c[2]) * 0.5f, m23 = (c[2] + c[3]) * 0.5f;
    const T m012 = (m01 + m12) * 0.5f, m123 = (m12 + m23) * 0.5f, mid = (m012 + m123) * 0.5f;
    left[0] = c[0], left[1] = m01, left[2] = m012, left[3] = mid;
    right[0] = mid, right[1] = m123, right[2] = m23, right[3] = c[3];
}

// The cubic B-spline segment on control points b0..b3 as a Bezier segment (the same curve).
template <typename T>
void bsplineToBezier(const T b[4], T out[4]) {
    out[0] = (b[0] + b[1] * 4.0f + b[2]) * (1.0f / 6.0f);
    out[1] = (b[1] * 4.0f + b[2] * 2.0f) * (1.0f / 6.0f);
    out[2] = (b[1] * 2.0f + b[2] * 4.0f) * (1.0f / 6.0f);
    out[3] = (b[1] + b[2] * 4.0f + b[3]) * (1.0f / 6.0f);
}

// The unit normal of a ribbon at `u` along a segment: the spherical interpolation of its two.
inline Vec3f ribbonNormal(Vec3f n0, Vec3f n1, float u) {
    const float cosAngle = std::clamp(dot(n0, n1), -1.0f, 1.0f);
    const float angle = std::acos(cosAngle);
    if (angle < 1e-4f) return normalize(n0 * (1.0f - u) + n1 * u);
    const float s = std::sin(angle);
    return normalize(n0 * (std::sin((1.0f - u) * angle) / s) + n1 * (std::sin(u * angle) / s));
}

// How many times the segment is halved before its pieces count as straight: pbrt-v4's bound, the
// depth at which the pieces' second differences fall below a twentieth of the width, but of the
// segment's narrowest width rather than its widest (a tapered hair's tip would be straight only
// within several of its widths), at most 10.
inline int splitDepth(const Vec3f c[4], float minRadius) {
    float l0 = 0.0f;
    for (int i = 0; i < 2; ++i) {
        const Vec3f d = abs(c[i] - c[i + 1] * 2.0f + c[i + 2]);
        l0 = std::max(l0, std::max(d.x, std::max(d.y, d.z)));
    }
    const float eps = std::max(minRadius * 2.0f * 0.05f, 1e-30f);
    const float ratio = 1.41421356f * 6.0f * l0 / (8.0f * eps);
    if (!(ratio > 1.0f)) return 0;
    return std::clamp(int(std::log2(std::min(ratio, 1e12f))) / 2, 0, 10);
}

// The parameter of a piece's point nearest the ray (the origin of the xy plane), from `w` on: two
// Newton steps on d/dw |B(w).xy|^2 / 2 = B.xy . B'.xy = 0, kept in [0, 1]. The chord's parameter
// alone is off along the curve by the piece's uneven speed, which at a tapered tip can exceed the
// radius there.
inline float nearestParameter(const Vec3f p[4], float w) {
    for (int step = 0; step < 2; ++step) {
        const Vec3f b = bezier(p, w), d1 = bezierDerivative(p, w);
        const float s = 1.0f - w;
        const Vec3f d2 = (p[2] - p[1] * 2.0f + p[0]) * (6.0f * s) + (p[3] - p[2] * 2.0f + p[1]) * (6.0f * w);
        const float f = b.x * d1.x + b.y * d1.y;
        const float slope = d1.x * d1.x + d1.y * d1.y + b.x * d2.x + b.y * d2.y;
        if (!(slope > 0.0f)) break;
        w = std::clamp(w - f / slope, 0.0f, 1.0f);
    }
    return w;
}

struct RaySpaceSegment {
    Vec3f p[4];    // control points in ray space: the ray along +z from the origin, unit length
    float r[4];    // control radii
    Vec3f n0, n1;  // ribbons: the end normals in ray space
    float u0, u1;  // the interval of the whole segment's u this piece covers
};

struct Search {
    bool ribbon = false;
    float zNear = 0.0f, zFar = 0.0f;  // the ray's interval, in ray-space z
    bool found = false;
    CurveHit hit;
    float z = 0.0f;
};

// The two halves of a piece (de Casteljau at its middle), as both the recursion and the descent to
// a piece of a segment (intersectCurveSegment) take them, so that they get the same bits.
inline void halves(const RaySpaceSegment& s, RaySpaceSegment& left, RaySpaceSegment& right) {
    split(s.p, left.p, right.p);
    split(s.r, left.r, right.r);
    const float uMid = 0.5f * (s.u0 + s.u1);
    left.n0 = right.n0 = s.n0, left.n1 = right.n1 = s.n1;
    left.u0 = s.u0, left.u1 = uMid, right.u0 = uMid, right.u1 = s.u1;
}

inline void intersectPiece(const RaySpaceSegment& s, int depth, Search& search) {
    // Cull by the piece's box, widened by its largest radius (a Bezier lies in its control hull).
    const float rMax = std::max(std::max(s.r[0], s.r[1]), std::max(s.r[2], s.r[3]));
    Vec3f lo = s.p[0], hi = s.p[0];
    for (int i = 1; i < 4; ++i) lo = min(lo, s.p[i]), hi = max(hi, s.p[i]);
    if (lo.x - rMax > 0.0f || hi.x + rMax < 0.0f || lo.y - rMax > 0.0f || hi.y + rMax < 0.0f) return;
    if (hi.z + rMax < search.zNear || lo.z - rMax > (search.found ? search.z : search.zFar)) return;
    if (depth > 0) {
        RaySpaceSegment left, right;
        halves(s, left, right);
        intersectPiece(left, depth - 1, search);
        intersectPiece(right, depth - 1, search);
        return;
    }
    // The ray must pass between the perpendiculars to the tangents at the piece's two ends (the
    // same tangents its neighbours see, so that adjacent pieces neither overlap nor leave a gap).
    const auto dot2 = [](Vec2f a, Vec2f b) { return a.x * b.x + a.y * b.y; };
    const Vec2f p0{s.p[0].x, s.p[0].y}, p1{s.p[1].x, s.p[1].y}, p2{s.p[2].x, s.p[2].y},
        p3{s.p[3].x, s.p[3].y};
    if (dot2(Vec2f{-p0.x, -p0.y}, p1 - p0) < 0.0f) return;
    if (dot2(Vec2f{-p3.x, -p3.y}, p2 - p3) < 0.0f) return;
    // The piece's point nearest the ray: along its chord, then refined on the curve.
    const Vec2f chord = p3 - p0;
    const float chordLength2 = dot2(chord, chord);
    const float w = nearestParameter(
        s.p, chordLength2 > 0.0f ? std::clamp(-dot2(p0, chord) / chordLength2, 0.0f, 1.0f) : 0.0f);
    const Vec3f point = bezier(s.p, w);
    const float distance2 = point.x * point.x + point.y * point.y;
    const float radius = bezier(s.r, w);
    const float u = s.u0 + (s.u1 - s.u0) * w;
    const float seenRadius = search.ribbon ? radius * std::abs(ribbonNormal(s.n0, s.n1, u).z) : radius;
    if (!(distance2 <= seenRadius * seenRadius) || !(radius > 0.0f)) return;
    // Nearer than twice the radius to the origin the ray starts within the curve's reach, where a
    // surface facing it is not defined: no hit there, as Embree's flat curves (it also keeps a ray
    // leaving a fiber from meeting that fiber again).
    if (!(point.z > 2.0f * radius)) return;
    if (point.z < search.zNear || point.z > (search.found ? search.z : search.zFar)) return;
    // The side of the centre line the ray passes on gives v's sign.
    const Vec3f tangent = bezierDerivative(s.p, w);
    const float side = tangent.x * point.y - tangent.y * point.x;
    const float v = std::sqrt(distance2) / radius;
    search.found = true;
    search.z = point.z;
    search.hit.u = u;
    search.hit.v = side >= 0.0f ? v : -v;
}

}  // namespace curve

// A dyadic piece of a segment, u in [index / 2^level, (index + 1) / 2^level]: what our BVH boxes
// (a long, bent segment's box is mostly empty; its pieces' are tighter).
struct CurvePiece {
    uint32_t level = 0, index = 0;
};

// The ray test of segment `segment` of `curves` for the ray origin + t direction, t in
// [tnear, tfar] (the direction need not be unit: t is in its units); the nearest hit. With a
// `piece`, only the hits within it, found by the whole segment's test: its halving is followed
// down to the piece, so the piece's leaves are the whole test's bit for bit, and the nearest hit
// over all pieces is the whole test's.
inline bool intersectCurveSegment(const Curves& curves, size_t segment, Vec3f origin, Vec3f direction,
                                  float tnear, float tfar, CurveHit& hit, CurvePiece piece = {}) {
    const float directionLength = length(direction);
    if (!(directionLength > 0.0f)) return false;
    const Frame frame = Frame::fromNormal(direction / directionLength);
    curve::RaySpaceSegment s;
    const Vec3f* c = curves.controlPoints(segment);
    const float* r = curves.controlRadii(segment);
    float rMin = r[0];
    for (int i = 0; i < 4; ++i) {
        s.p[i] = frame.toLocal(c[i] - origin);
        s.r[i] = r[i];
        rMin = std::min(rMin, r[i]);
    }
    curve::Search search;
    if (curves.type == CurveType::Ribbon) {
        search.ribbon = true;
        s.n0 = frame.toLocal(curves.normals[2 * segment]);
        s.n1 = frame.toLocal(curves.normals[2 * segment + 1]);
    }
    s.u0 = 0.0f, s.u1 = 1.0f;
    search.zNear = tnear * directionLength;
    search.zFar = tfar * directionLength;
    const int depth = curve::splitDepth(s.p, rMin);
    int level = int(piece.level);
    uint32_t index = piece.index;
    if (depth < level) {
        // The whole test's leaves span several pieces: the first piece of a leaf tests it.
        const int above = level - depth;
        if ((index & ((1u << above) - 1u)) != 0) return false;
        index >>= above;
        level = depth;
    }
    for (int k = level - 1; k >= 0; --k) {
        curve::RaySpaceSegment left, right;
        curve::halves(s, left, right);
        s = ((index >> k) & 1u) != 0 ? right : left;
    }
    curve::intersectPiece(s, depth - level, search);
    if (!search.found) return false;
    hit = search.hit;
    hit.t = search.z / directionLength;
    return true;
}

}  // namespace penumbra
