// Equiangular sampling (core/equiangular.h): its density is a density (integrates to 1 over the
// segment, finite or not, by Simpson's rule with the substitution t = delta + h tan(theta) for the
// infinite one), proportional to 1 / (distance to the point)^2, and sample() is its inverse CDF:
// the fraction of a fine quadrature of pdf below sample(u) is u.
#include "core/equiangular.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace penumbra {
namespace {

double integrate(const EquiangularDistance& e, double a, double b, int steps = 1 << 14) {
    const double h = (b - a) / steps;
    double sum = e.pdf(float(a)) + e.pdf(float(b));
    for (int i = 1; i < steps; ++i) sum += e.pdf(float(a + i * h)) * (i % 2 ? 4 : 2);
    return sum * h / 3;
}

TEST(Equiangular, TheDensityIntegratesToOneAndFallsAsTheInverseSquare) {
    const Vec3f origin{0.0f, 0.0f, 0.0f}, direction{0.0f, 0.0f, 1.0f}, point{0.7f, -0.2f, 3.0f};
    const EquiangularDistance finite(origin, direction, 5.0f, point);
    ASSERT_TRUE(finite.valid());
    EXPECT_NEAR(integrate(finite, 0.0, 5.0), 1.0, 1e-5);
    const double h2 = 0.7 * 0.7 + 0.2 * 0.2;
    for (float t : {0.0f, 1.0f, 3.0f, 4.5f})
        EXPECT_NEAR(finite.pdf(t) * (h2 + (t - 3.0) * (t - 3.0)), finite.pdf(3.0f) * h2, 1e-5);
    // The infinite ray: the tail beyond 1000 carries h / ((thetaB - thetaA) * 1000) of the mass.
    const EquiangularDistance infinite(origin, direction, std::numeric_limits<float>::infinity(), point);
    ASSERT_TRUE(infinite.valid());
    EXPECT_NEAR(integrate(infinite, 0.0, 1000.0, 1 << 20), 1.0, 1e-3);
}

TEST(Equiangular, SamplingIsTheInverseOfTheDistribution) {
    const Vec3f origin{1.0f, 2.0f, 0.0f}, direction = normalize(Vec3f{1.0f, 1.0f, 1.0f}),
                                          point{3.0f, 2.5f, 1.0f};
    const float tEnd = 6.0f;
    const EquiangularDistance e(origin, direction, tEnd, point);
    for (float u : {0.01f, 0.2f, 0.5f, 0.77f, 0.99f}) {
        const float t = e.sample(u);
        ASSERT_GE(t, 0.0f);
        ASSERT_LE(t, tEnd);
        EXPECT_NEAR(integrate(e, 0.0, t), u, 1e-4) << u;
    }
}

TEST(Equiangular, APointOnTheRaysLineHasNoDensity) {
    const EquiangularDistance e({0, 0, 0}, {0, 0, 1}, 10.0f, {0, 0, 4});
    EXPECT_FALSE(e.valid());
    EXPECT_EQ(e.pdf(4.0f), 0.0f);
}

}  // namespace
}  // namespace penumbra
