// The film's sensor response (cameras/sensor_response.h), pbrt-v4's PixelSensor with the CIE 1931
// observer: the imaging ratio exposure time x ISO / 100 multiplies the radiance exactly; the
// daylight chromaticities against the CIE's published D50, D65 and D75 (CIE 015:2004, table T.3)
// and the Planckian locus; a white balance takes its temperature's white to penumbra's white;
// and a render with a sensor is the render without it, times the ratio, bit for bit.
#include "cameras/sensor_response.h"

#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "core/colorimetry.h"
#include "scenes/scene_loader.h"
#include "tests/support/render_scene.h"

namespace penumbra {
namespace {

TEST(SensorResponse, TheImagingRatioMultipliesTheRadiance) {
    const SensorResponse sensor = SensorResponse::make(400.0f, 0.5f, 0.0f);
    EXPECT_EQ(sensor.imagingRatio(), 2.0f);
    EXPECT_EQ(sensor.apply(Rgb(0.3f, 1.7f, 12.5f)), Rgb(0.6f, 3.4f, 25.0f));
    EXPECT_EQ(SensorResponse::make(100.0f, 1.0f, 0.0f).apply(Rgb(0.1f, 0.2f, 0.3f)), Rgb(0.1f, 0.2f, 0.3f));
}

TEST(SensorResponse, DaylightChromaticitiesAreTheCiesIlluminants) {
    // Nominal temperatures: the CIE's D50, D65 and D75 are defined at 5003, 6504 and 7504 K, the
    // nominal ones times 1.4388 / 1.4380.
    const struct {
        double kelvin, x, y;
    } kIlluminants[] = {{5000, 0.34567, 0.35850}, {6500, 0.31271, 0.32902}, {7500, 0.29902, 0.31485}};
    for (const auto& d : kIlluminants) {
        const auto xy = daylightChromaticity(d.kelvin);
        EXPECT_NEAR(xy[0], d.x, 2e-4) << d.kelvin;
        EXPECT_NEAR(xy[1], d.y, 2e-4) << d.kelvin;
    }
    // Below 4000 K a blackbody: the Planckian locus at 3000 K is (0.4369, 0.4041) and at 2000 K
    // (0.5267, 0.4133) (Wyszecki and Stiles, table 1(3.11)); Kim et al.'s cubics hold them
    // within 5e-4.
    for (const auto& [kelvin, x, y] :
         {std::tuple{3000.0, 0.4369, 0.4041}, std::tuple{2000.0, 0.5267, 0.4133}}) {
        const auto warm = daylightChromaticity(kelvin * 1.4380 / 1.4388);
        EXPECT_NEAR(warm[0], x, 5e-4) << kelvin;
        EXPECT_NEAR(warm[1], y, 5e-4) << kelvin;
    }
}

TEST(SensorResponse, AWhiteBalanceMakesItsTemperaturesWhiteWhite) {
    for (const float kelvin : {2700.0f, 4500.0f, 6500.0f, 10000.0f}) {
        const SensorResponse sensor = SensorResponse::make(100.0f, 1.0f, kelvin);
        const auto xy = daylightChromaticity(kelvin);
        const Rgb white = xyzToLinearSrgb({xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]});
        const Rgb balanced = sensor.apply(white);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(balanced[c], 1.0, 2e-4) << kelvin << " channel " << c;
    }
    // D65 is penumbra's white: its balance changes (almost) nothing.
    const SensorResponse d65 = SensorResponse::make(100.0f, 1.0f, 6500.0f);
    for (int row = 0; row < 3; ++row)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(d65.rows[row][c], row == c ? 1.0 : 0.0, 1e-3);
}

TEST(SensorResponse, ARenderWithASensorIsScaledBitForBit) {
    const std::string common = R"("film": {"resolution": [24, 16], "spp": 4)";
    const std::string rest = R"(},
        "camera": {"look_from": [0, 0, 4], "look_at": [0, 0, 0], "fov": 40},
        "lights": [{"type": "point", "position": [1, 2, 3], "intensity": 20}],
        "background": 0.2,
        "materials": {"m": {"type": "lambert", "albedo": [0.7, 0.4, 0.2]}},
        "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})";
    const Scene plain = parseScene("{" + common + rest, "plain.json");
    const Scene exposed = parseScene(
        "{" + common + R"(, "sensor": {"iso": 800, "exposure_time": 0.25})" + rest, "exposed.json");
    ASSERT_TRUE(exposed.film.sensor);
    const Film a = testing::renderScene(plain), b = testing::renderScene(exposed);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 24; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(b.at(x, y).mean()[c], 2.0f * a.at(x, y).mean()[c]) << x << " " << y << " " << c;
}

}  // namespace
}  // namespace penumbra
