// make_sky: writes a procedural sky with a sun as an equirectangular OpenEXR image, in the
// orientation of lights/environment_light.h (+y up, the image centre looking along +z). The
// example scenes' environment map (scenes/textures/sky.exr) is its output with the defaults:
//
//   make_sky OUTPUT.exr [WIDTH [SUN_ELEVATION_DEGREES [SUN_AZIMUTH_DEGREES]]]
//
// The sky is a simple analytic model, not a physical one: a blue zenith fading to a pale horizon,
// a glow around the sun (forward scattering), a dark ground, and the sun itself as a disk of
// 1.5 degrees radius (five times the real one, so that it covers several texels) whose radiance
// makes it give about four times the sky's irradiance on a surface facing it.
#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

namespace {

constexpr double kPi = std::numbers::pi;

struct Color {
    double r, g, b;
};

Color mix(Color a, Color b, double t) {
    return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

// Radiance arriving from unit direction (x, y, z), y up; `sun` is the unit direction to the sun.
Color skyRadiance(double x, double y, double z, const double sun[3]) {
    const double cosSun = std::clamp(x * sun[0] + y * sun[1] + z * sun[2], -1.0, 1.0);
    const double angle = std::acos(cosSun);
    const double sunRadius = 1.5 * kPi / 180.0;
    if (angle < sunRadius) return {3000.0, 2800.0, 2500.0};
    if (y < 0.0) {
        // The ground: dark, a little lighter towards the horizon.
        const double t = std::min(1.0, -y * 4.0);
        return mix({0.30, 0.28, 0.25}, {0.12, 0.11, 0.10}, t);
    }
    const Color zenith{0.25, 0.45, 1.0}, horizon{0.85, 0.9, 1.0};
    Color c = mix(horizon, zenith, std::pow(y, 0.5));
    const double glow = 6.0 * std::exp(-angle / 0.12) + 0.6 * std::exp(-angle / 0.6);
    c.r += glow * 1.0;
    c.g += glow * 0.9;
    c.b += glow * 0.7;
    return c;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argc > 5) {
        std::fprintf(stderr,
                     "usage: make_sky OUTPUT.exr [WIDTH [SUN_ELEVATION_DEGREES [SUN_AZIMUTH_DEGREES]]]\n");
        return 2;
    }
    const int width = argc > 2 ? std::atoi(argv[2]) : 512;
    const double elevation = (argc > 3 ? std::atof(argv[3]) : 35.0) * kPi / 180.0;
    const double azimuth = (argc > 4 ? std::atof(argv[4]) : 200.0) * kPi / 180.0;
    if (width < 4 || width > 16384 || width % 2 != 0) {
        std::fprintf(stderr, "make_sky: the width must be an even number in [4, 16384]\n");
        return 2;
    }
    const int height = width / 2;
    // The image's (phi, theta) map to (sin t sin p, cos t, -sin t cos p).
    const double sun[3] = {std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                           -std::cos(elevation) * std::cos(azimuth)};
    // Each texel is the mean of 4 x 4 sub-samples, so that the sun's disk is antialiased.
    std::vector<float> pixels(size_t(width) * height * 3);
    const int n = 4;
    for (int row = 0; row < height; ++row)
        for (int column = 0; column < width; ++column) {
            Color sum{0, 0, 0};
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const double phi = 2.0 * kPi * (column + (i + 0.5) / n) / width;
                    const double theta = kPi * (row + (j + 0.5) / n) / height;
                    const Color c = skyRadiance(std::sin(theta) * std::sin(phi), std::cos(theta),
                                                -std::sin(theta) * std::cos(phi), sun);
                    sum.r += c.r;
                    sum.g += c.g;
                    sum.b += c.b;
                }
            float* p = &pixels[(size_t(row) * width + column) * 3];
            p[0] = float(sum.r / (n * n));
            p[1] = float(sum.g / (n * n));
            p[2] = float(sum.b / (n * n));
        }
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        const char* names[3] = {"R", "G", "B"};
        for (const char* name : names) header.channels().insert(name, Imf::Channel(Imf::HALF));
        Imf::OutputFile file(argv[1], header);
        // Half floats: 11 significant bits are plenty for a sky, and the file stays small.
        std::vector<Imath::half> halves(pixels.begin(), pixels.end());
        Imf::FrameBuffer buffer;
        for (int c = 0; c < 3; ++c)
            buffer.insert(names[c],
                          Imf::Slice(Imf::HALF, reinterpret_cast<char*>(halves.data() + c),
                                     3 * sizeof(Imath::half), 3 * sizeof(Imath::half) * size_t(width)));
        file.setFrameBuffer(buffer);
        file.writePixels(height);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "make_sky: %s: %s\n", argv[1], e.what());
        return 1;
    }
    return 0;
}
