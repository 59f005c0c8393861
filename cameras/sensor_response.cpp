#include "cameras/sensor_response.h"

#include "core/colorimetry.h"

namespace penumbra {

SensorResponse SensorResponse::make(float iso, float exposureTime, float whiteBalance) {
    SensorResponse s;
    s.iso = iso;
    s.exposureTime = exposureTime;
    s.whiteBalance = whiteBalance;
    const double ratio = double(exposureTime) * double(iso) / 100.0;
    for (int row = 0; row < 3; ++row) s.rows[row] = Rgb(0.0f);
    if (!(whiteBalance > 0.0f)) {
        for (int i = 0; i < 3; ++i)
            (i == 0 ? s.rows[0].r : i == 1 ? s.rows[1].g : s.rows[2].b) = float(ratio);
        return s;
    }
    // linear sRGB -> XYZ -> balanced XYZ -> linear sRGB, column by column.
    const std::array<Xyz, 3> balance = whiteBalanceXyz(daylightChromaticity(whiteBalance), kD65Chromaticity);
    for (int column = 0; column < 3; ++column) {
        const Xyz xyz = linearSrgbToXyz(
            Rgb(column == 0 ? 1.0f : 0.0f, column == 1 ? 1.0f : 0.0f, column == 2 ? 1.0f : 0.0f));
        Xyz balanced{};
        for (int i = 0; i < 3; ++i)
            balanced[i] = balance[i][0] * xyz[0] + balance[i][1] * xyz[1] + balance[i][2] * xyz[2];
        const Rgb out = xyzToLinearSrgb(balanced);
        for (int row = 0; row < 3; ++row) {
            Rgb& r = s.rows[row];
            (column == 0 ? r.r : column == 1 ? r.g : r.b) = float(double(out[row]) * ratio);
        }
    }
    return s;
}

}  // namespace penumbra
