// The subsurface material through the renderer (a dielectric boundary around a medium that the
// volumetric integrator walks: materials/subsurface_boundary.h, scenes/material_interior.h),
// against closed forms: the plane albedo of a semi-infinite medium with an index-matched boundary
// (Chandrasekhar's H-function), a white furnace with a refracting boundary, the exact interface's
// reflectance of a uniform sky, and walks cut short.
//
// Tolerances as in media_render_test.cpp: many pixels that estimate the same value independently;
// their mean within 5 standard errors of the exact value, the standard error from the pixels'
// spread. The H-function is solved to about 1e-7, far below the statistical tolerance (about 2e-3).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"
#include "tests/support/pixel_mean.h"
#include "tests/support/test_statistics.h"

namespace penumbra {
namespace {

using test::withinSigmas;
using testing::PixelMean;
using testing::renderedChannelMean;

// Gauss-Legendre nodes and weights on [0, 1] (Newton's method on the Legendre polynomial P_n).
void gaussLegendre(int n, std::vector<double>& nodes, std::vector<double>& weights) {
    nodes.assign(size_t(n), 0.0);
    weights.assign(size_t(n), 0.0);
    for (int i = 0; i < n; ++i) {
        double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), derivative = 0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1, p1 = x;  // P_0, P_1, then up to P_n by the recurrence
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            derivative = n * (x * p1 - p0) / (x * x - 1);
            const double step = p1 / derivative;
            x -= step;
            if (std::abs(step) < 1e-15) break;
        }
        nodes[size_t(i)] = 0.5 * (1 - x);
        weights[size_t(i)] = 1.0 / ((1 - x * x) * derivative * derivative);  // 2 / (...) on [-1, 1], halved
    }
}

// Chandrasekhar's H-function of isotropic scattering with single-scattering albedo `albedo`:
//   1 / H(mu) = 1 - (albedo / 2) mu integral over [0, 1] of H(mu') / (mu + mu') d mu',
// iterated to convergence at Gauss-Legendre nodes, then evaluated anywhere by the same formula.
class HFunction {
public:
    explicit HFunction(double albedo) : albedo_(albedo) {
        gaussLegendre(96, nodes_, weights_);
        values_.assign(nodes_.size(), 1.0);
        for (int iteration = 0; iteration < 2000; ++iteration) {
            std::vector<double> next(nodes_.size());
            double change = 0;
            for (size_t i = 0; i < nodes_.size(); ++i) {
                next[i] = (*this)(nodes_[i]);
                change = std::max(change, std::abs(next[i] - values_[i]));
            }
            values_ = next;
            if (change < 1e-13) break;
        }
    }
    double operator()(double mu) const {
        double integral = 0;
        for (size_t i = 0; i < nodes_.size(); ++i) integral += weights_[i] * values_[i] / (mu + nodes_[i]);
        return 1.0 / (1.0 - albedo_ / 2 * mu * integral);
    }
    // The zeroth moment, integral over [0, 1] of H.
    double moment0() const {
        double sum = 0;
        for (size_t i = 0; i < nodes_.size(); ++i) sum += weights_[i] * values_[i];
        return sum;
    }

private:
    double albedo_;
    std::vector<double> nodes_, weights_, values_;
};

// The plane albedo of a semi-infinite isotropically scattering medium with an index-matched
// boundary, lit from direction cosine mu: 1 - H(mu) sqrt(1 - albedo) (Chandrasekhar 1960,
// "Radiative Transfer", chapter IV). By reciprocity it is also the radiance seen along mu under a
// uniform sky of radiance 1.
double planeAlbedo(double albedo, double mu) { return 1.0 - HFunction(albedo)(mu) * std::sqrt(1.0 - albedo); }

// The solver's check: the H-function's zeroth moment is 2 (1 - sqrt(1 - albedo)) / albedo.
TEST(Subsurface, TheHFunctionSolverMeetsItsMomentIdentity) {
    for (double albedo : {0.5, 0.8, 0.95, 0.999}) {
        const HFunction h(albedo);
        EXPECT_NEAR(h.moment0(), 2 * (1 - std::sqrt(1 - albedo)) / albedo, 1e-7) << albedo;
    }
}

// A box from `lo` to `hi` as a triangle mesh with outward faces, in a JSON scene's "shapes".
std::string boxJson(Vec3f lo, Vec3f hi, const std::string& material) {
    std::ostringstream json;
    json << R"({"type": "triangle_mesh", "positions": [)";
    for (int v = 0; v < 8; ++v)
        json << (v ? ", [" : "[") << (v & 1 ? hi.x : lo.x) << ", " << (v & 2 ? hi.y : lo.y) << ", "
             << (v & 4 ? hi.z : lo.z) << "]";
    // Vertex v = x + 2 y + 4 z; each face's two triangles counter-clockwise seen from outside.
    json << R"(], "indices": [0, 2, 3, 0, 3, 1,  4, 5, 7, 4, 7, 6,  0, 1, 5, 0, 5, 4,  2, 6, 7, 2, 7, 3,  )"
         << R"(0, 4, 6, 0, 6, 2,  1, 3, 7, 1, 7, 5], "material": ")" << material << R"("})";
    return json.str();
}

// A camera whose every pixel sees the same ray, from `from` towards `to`, in a JSON scene.
std::string narrowCameraJson(Vec3f from, Vec3f to) {
    std::ostringstream json;
    json << R"("camera": {"look_from": [)" << from.x << ", " << from.y << ", " << from.z
         << R"(], "look_at": [)" << to.x << ", " << to.y << ", " << to.z << R"(], "fov": 0.005})";
    return json.str();
}

// A semi-infinite medium (a box 1000 mean free paths deep and 2000 wide) of a subsurface material
// with eta 1, whose three channels scatter with albedos 0.5, 0.8 and 0.95, under a uniform sky:
// seen along cosines 1 and 0.5 from the normal, each channel is its plane albedo.
TEST(Subsurface, ASemiInfiniteMediumReflectsItsPlaneAlbedo) {
    const double albedo[3] = {0.5, 0.8, 0.95};
    for (double mu : {1.0, 0.5}) {
        const Vec3f target{0.1f, 0.2f, 0.0f};
        const float sinTheta = float(std::sqrt(1 - mu * mu));
        const Vec3f from = target + Vec3f{0.0f, -sinTheta, float(mu)} * 5.0f;
        const Scene scene = parseScene(R"({
            "film": {"resolution": [16, 16], "spp": 512, "filter": {"type": "box"}},
            "integrator": {"max_depth": 8},
            "background": 1,
            )" + narrowCameraJson(from, target) +
                                           R"(,
            "materials": {"slab": {"type": "subsurface", "eta": 1,
                                   "sigma_a": [0.5, 0.2, 0.05], "sigma_s": [0.5, 0.8, 0.95]}},
            "shapes": [)" + boxJson({-1000, -1000, -1000}, {1000, 1000, 0}, "slab") +
                                           "]}",
                                       "slab.json");
        for (int c = 0; c < 3; ++c) {
            const PixelMean m = renderedChannelMean(scene, c);
            EXPECT_TRUE(withinSigmas(m.mean, planeAlbedo(albedo[c], mu), m.standardError))
                << "mu " << mu << ", channel " << c;
        }
    }
}

// The diffuse exit keeps the exact interface's internal reflection (its Fresnel reflectance, for
// the direction the walk arrives in) and changes only the direction light leaves in, so what a
// slab reflects of a uniform sky is what the exact interface reflects: a dielectric (eta 1.33)
// around the same medium (sigma_t 1, albedos 0.5, 0.9 and 0.99), rendered by the same volumetric
// path tracer with the walk's events counted as bounces (max_depth 1024 cuts almost none). The two
// means within 5 standard errors of their difference.
TEST(Subsurface, ASlabReflectsWhatTheExactInterfaceReflectsOfAUniformSky) {
    const std::string camera = narrowCameraJson({0.1f, 0.2f, 5.0f}, {0.1f, 0.2f, 0.0f});
    const std::string box = boxJson({-1000, -1000, -1000}, {1000, 1000, 0}, "slab");
    const std::string common = R"("film": {"resolution": [16, 16], "spp": 256, "filter": {"type": "box"}},
        "integrator": {"max_depth": 1024}, "background": 1, )" +
                               camera + ", ";
    const Scene subsurface =
        parseScene("{" + common + R"("materials": {"slab": {"type": "subsurface", "eta": 1.33,
        "sigma_a": [0.5, 0.1, 0.01], "sigma_s": [0.5, 0.9, 0.99]}}, "shapes": [)" +
                       box + "]}",
                   "subsurface.json");
    std::string exactBox = box;
    exactBox.insert(exactBox.size() - 1, R"(, "inside": "medium")");
    const Scene exact = parseScene("{" + common +
                                       R"("materials": {"slab": {"type": "dielectric", "eta": 1.33}},
        "media": {"medium": {"type": "homogeneous", "sigma_a": [0.5, 0.1, 0.01], "sigma_s": [0.5, 0.9, 0.99]}},
        "shapes": [)" + exactBox + "]}",
                                   "exact.json");
    for (int c = 0; c < 3; ++c) {
        const PixelMean a = renderedChannelMean(subsurface, c), b = renderedChannelMean(exact, c);
        EXPECT_TRUE(withinSigmas(a.mean - b.mean, 0.0, std::hypot(a.standardError, b.standardError)))
            << "channel " << c << ": " << a.mean << " against " << b.mean;
    }
}

// A white furnace through a refracting boundary: a sphere of a subsurface material that absorbs
// nothing (eta 1.5, chromatic and anisotropic scattering) under a uniform sky of 1. What the
// interface reflects is 1 - what enters, and all that enters leaves (diffusely, times eta^2 for
// the 1 / eta^2 refraction in took), so every pixel is 1. max_depth 1: the entry is the path's
// one bounce, and the walk and its exit count apart.
TEST(Subsurface, ANonAbsorbingSphereIsAWhiteFurnace) {
    for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        const Scene scene = parseScene(R"({
            "film": {"resolution": [24, 24], "spp": 256, "filter": {"type": "box"}},
            "integrator": {"max_depth": 1},
            "background": 1,
            "camera": {"look_from": [0, 0, 4], "look_at": [0, 0, 0], "fov": 25},
            "materials": {"milk": {"type": "subsurface", "eta": 1.5, "g": 0.5,
                                   "sigma_a": 0, "sigma_s": [1, 2, 3]}},
            "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "milk"}]})",
                                       "furnace.json");
        for (int c = 0; c < 3; ++c) {
            const PixelMean m = renderedChannelMean(scene, c, accelerator);
            EXPECT_TRUE(withinSigmas(m.mean, 1.0, m.standardError)) << "channel " << c;
        }
    }
}

// A walk that would need some 10^8 steps to cross the sphere (optical radius 10^4, nothing
// absorbed) ends at kMaxWalkVertices, as absorbed: without the bound this render would not end.
// Walks that enter near the surface mostly leave within a few steps (the number of steps to leave
// a half-space has a tail falling as n^-1/2), so the image stays near the furnace's 1, below it by
// the walks cut short: a few percent (measured 0.95 at 1024 steps).
TEST(Subsurface, AWalkThatWouldNotEndIsCutShort) {
    const Scene scene = parseScene(R"({
        "film": {"resolution": [16, 16], "spp": 16, "filter": {"type": "box"}},
        "background": 1,
        "camera": {"look_from": [0, 0, 4], "look_at": [0, 0, 0], "fov": 10},
        "materials": {"dense": {"type": "subsurface", "eta": 1.5, "sigma_a": 0, "sigma_s": 10000}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "dense"}]})",
                                   "dense.json");
    const PixelMean m = renderedChannelMean(scene, 1);
    EXPECT_GT(m.mean, 0.85);
    EXPECT_LT(m.mean + 5 * m.standardError, 1.0);
}

// Textured coefficients are taken where a walk enters (pbrt-v4 evaluates its BSSRDF's there):
// the semi-infinite medium above, its sigma_a and sigma_s checkerboards in the plane (squares of
// side 1) giving albedo 0.5 on one kind of square and 0.95 on the other. Seen at a point in each
// kind, every channel is the plane albedo of that square's albedo, though the walks wander
// across squares (the coefficients stay those of the entry).
TEST(Subsurface, TexturedCoefficientsAreTakenWhereTheWalkEnters) {
    const std::string box = boxJson({-1000, -1000, -1000}, {1000, 1000, 0}, "slab");
    for (const auto& [target, albedo] :
         {std::pair{Vec3f{0.5f, 0.5f, 0.0f}, 0.5}, std::pair{Vec3f{1.5f, 0.5f, 0.0f}, 0.95}}) {
        const Scene scene = parseScene(R"({
            "film": {"resolution": [16, 16], "spp": 512, "filter": {"type": "box"}},
            "integrator": {"max_depth": 8},
            "background": 1,
            )" + narrowCameraJson(target + Vec3f{0.0f, 0.0f, 5.0f}, target) +
                                           R"(,
            "materials": {"slab": {"type": "subsurface", "eta": 1,
                "sigma_a": {"type": "checkerboard", "colors": [0.5, 0.05], "mapping": {"type": "planar"}},
                "sigma_s": {"type": "checkerboard", "colors": [0.5, 0.95], "mapping": {"type": "planar"}}}},
            "shapes": [)" + box + "]}",
                                       "slab.json");
        const PixelMean m = renderedChannelMean(scene, 1);
        EXPECT_TRUE(withinSigmas(m.mean, planeAlbedo(albedo, 1.0), m.standardError)) << "albedo " << albedo;
    }
}

// A textured reflectance (and mean free path) renders as the constant one at each point: a slab
// under a rough boundary (eta 1.33) whose reflectance checkerboard holds 0.3 on the square seen
// and 0.8 on the others, against the same slab of constant reflectance 0.3 (the two means within 5
// standard errors of their difference).
TEST(Subsurface, ATexturedReflectanceIsTheConstantOneWhereTheWalkEnters) {
    const std::string box = boxJson({-1000, -1000, -1000}, {1000, 1000, 0}, "slab");
    auto slab = [&](const std::string& reflectance, const std::string& mfp) {
        return parseScene(R"({
            "film": {"resolution": [16, 16], "spp": 256, "filter": {"type": "box"}},
            "integrator": {"max_depth": 8},
            "background": 1,
            )" + narrowCameraJson({0.5f, 0.5f, 5.0f}, {0.5f, 0.5f, 0.0f}) +
                              R"(,
            "materials": {"slab": {"type": "subsurface", "eta": 1.33, "roughness": 0.3,
                "reflectance": )" +
                              reflectance + R"(, "mfp": )" + mfp + R"(}},
            "shapes": [)" + box +
                              "]}",
                          "slab.json");
    };
    const Scene textured =
        slab(R"({"type": "checkerboard", "colors": [0.3, 0.8], "mapping": {"type": "planar"}})",
             R"({"type": "checkerboard", "colors": [0.5, 4], "mapping": {"type": "planar"}})");
    const Scene constant = slab("0.3", "0.5");
    const PixelMean a = renderedChannelMean(textured, 0), b = renderedChannelMean(constant, 0);
    EXPECT_TRUE(withinSigmas(a.mean - b.mean, 0.0, std::hypot(a.standardError, b.standardError)))
        << a.mean << " against " << b.mean;
}

}  // namespace
}  // namespace penumbra
