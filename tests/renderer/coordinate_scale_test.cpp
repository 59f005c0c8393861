// The Cornell box scaled by factors from 1e-6 to 1e7 renders the same image, with either backend:
// ray offsets and intersection tests whose error bounds follow the coordinates' magnitude leave no
// bias at any scale (no light leaking through self-intersections, no paths lost to them).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "film/film.h"
#include "renderer/render.h"
#include "scenes/scene_loader.h"

namespace penumbra {
namespace {

// Every length in the scene times `factor`: the image of a scene of emitters given by radiance and
// a pinhole camera does not change.
void scaleScene(Scene& scene, float factor) {
    for (TriangleMesh& mesh : scene.meshes)
        for (Vec3f& p : mesh.positions) p = p * factor;
    for (Sphere& sphere : scene.spheres) {
        sphere.center = sphere.center * factor;
        sphere.radius *= factor;
    }
    scene.camera.lookFrom = scene.camera.lookFrom * factor;
    scene.camera.lookAt = scene.camera.lookAt * factor;
    scene.camera.focusDistance *= factor;
}

struct ImageMean {
    std::array<double, 3> mean{}, variance{};  // per channel: the image's mean and its variance
};

// The image mean is the average of the pixels' means; pixels are independent, so its variance is
// the sum of the pixels' variances of the mean over the pixel count squared.
ImageMean imageMean(const Film& film) {
    ImageMean m;
    const double n = double(film.width()) * film.height();
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            const Rgb mean = film.at(x, y).mean(), variance = film.at(x, y).varianceOfMean();
            for (int c = 0; c < 3; ++c) {
                m.mean[c] += mean[c] / n;
                m.variance[c] += variance[c] / (n * n);
            }
        }
    return m;
}

ImageMean renderAtScale(float factor, AcceleratorKind accelerator) {
    Scene scene = loadScene(std::filesystem::path(PENUMBRA_SOURCE_DIR) / "scenes" / "cornell-box.json");
    scene.film.width = 64;
    scene.film.height = 64;
    scene.film.samplesPerPixel = 256;
    scene.integrator.maxDepth = 8;
    // The light out of view, lower: the pixels on its edge would dominate the variance.
    scene.camera.lookFrom.y -= 0.4f;
    scene.camera.lookAt.y -= 0.4f;
    scaleScene(scene, factor);
    RenderOptions options;
    options.accelerator = accelerator;
    Film film(scene.film.width, scene.film.height);
    render(scene, options, film);
    return imageMean(film);
}

// Each scale's mean against scale 1's, per channel, within 5 standard errors of their difference:
// sqrt(var_s + var_1), as for independent renders. The renders share their random numbers, so the
// true spread of the difference is smaller and 5 such sigma never fail by chance; a systematic
// bias (self-intersections darken, light leaking through offsets brightens) of a few tenths of a
// percent or more does fail.
TEST(CoordinateScale, CornellBoxMeanIsTheSameAtEveryScaleWithEitherBackend) {
    for (AcceleratorKind accelerator : {AcceleratorKind::Embree, AcceleratorKind::Bvh}) {
        const ImageMean reference = renderAtScale(1.0f, accelerator);
        for (float factor : {1e-6f, 1e-4f, 1e-2f, 1e2f, 1e5f, 1e7f}) {
            const ImageMean scaled = renderAtScale(factor, accelerator);
            std::printf("scale %g %s ratio to scale 1 (r, g, b):", double(factor),
                        acceleratorKindName(accelerator).data());
            for (int c = 0; c < 3; ++c)
                std::printf(" %.5f +- %.5f", scaled.mean[c] / reference.mean[c],
                            std::sqrt(scaled.variance[c] + reference.variance[c]) / reference.mean[c]);
            std::printf("\n");
            for (int c = 0; c < 3; ++c) {
                const double sigma = std::sqrt(scaled.variance[c] + reference.variance[c]);
                const double difference = scaled.mean[c] - reference.mean[c];
                EXPECT_LE(std::abs(difference), 5.0 * sigma)
                    << "scale " << factor << " " << acceleratorKindName(accelerator) << " channel " << c
                    << ": ratio " << scaled.mean[c] / reference.mean[c] << ", " << difference / sigma
                    << " sigma";
            }
        }
    }
}

}  // namespace
}  // namespace penumbra
