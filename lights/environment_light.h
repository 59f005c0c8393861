// Light arriving from infinitely far away in every direction that leaves the scene: a constant
// radiance (the scene's "background") or an image, rotated and scaled. Rays that escape see it;
// next-event estimation samples it, the image in proportion to its luminance times the solid
// angle of each texel (a piecewise-constant 2D distribution over the texels, as pbrt-v4's
// ImageInfiniteLight and Mitsuba's envmap do), the constant case uniformly over the sphere.
//
// The image's parameterisations, in the light's own frame (before its rotation), +y up; image
// coordinates (s, t) in [0, 1)^2, s along a row, t down the rows (top row first):
// - Equirectangular (latitude-longitude): s is the azimuth phi = 2 pi s, t the polar angle
//   theta = pi t from +y; the direction is (sin theta sin phi, cos theta, -sin theta cos phi), so
//   the image's left edge (and its right edge) looks along -z, its centre along +z (Mitsuba's
//   convention). A texel covers (2 pi / width) (pi / height) sin(theta) of solid angle.
// - Equal-area octahedral (Clarberg 2008, "Fast equal-area mapping of the (hemi)sphere using
//   SIMD"; pbrt-v4's environment maps): a square whose centre looks up (+y) and whose edges and
//   corners look down; Clarberg's (a, b, c) for (s, t), c towards the pole, is the direction
//   (a, c, -b). Every texel covers the same solid angle, 4 pi / (width height).
// Lookups take the nearest texel: the radiance is then exactly the piecewise-constant function
// the sampling distribution is built from.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "core/piecewise_constant_2d.h"
#include "core/rgb.h"
#include "core/sampling.h"
#include "core/transform.h"
#include "core/vec.h"
#include "lights/light_bounds.h"
#include "lights/light_sample.h"

namespace penumbra {

enum class EnvironmentMapping { Equirectangular, EqualArea };

// Linear RGB texels, rows top to bottom, and how they cover the sphere.
struct EnvironmentImage {
    int width = 0, height = 0;
    std::vector<Rgb> texels;
    EnvironmentMapping mapping = EnvironmentMapping::Equirectangular;
    Rgb at(int x, int y) const { return texels[size_t(y) * size_t(width) + size_t(x)]; }
};

struct EnvironmentSample {
    Vec3f direction;  // unit, world space, towards the environment
    Rgb radiance;     // arriving along -direction
    float pdf;        // solid-angle density
};

class EnvironmentLight {
public:
    EnvironmentLight() = default;  // black: no environment
    static EnvironmentLight constant(Rgb radiance);
    // `image` scaled by `scale` (per channel), turned by `rotation` (a rotation: world = rotation *
    // light frame). Negative and non-finite texels count as black.
    static EnvironmentLight fromImage(EnvironmentImage image, Rgb scale, const Transform& rotation);

    bool isBlack() const { return black_; }
    bool hasImage() const { return image_ != nullptr; }
    // The constant radiance (without an image), or the image's scale.
    Rgb constantRadiance() const { return radiance_; }
    const EnvironmentImage* image() const { return image_ ? &image_->image : nullptr; }

    // Radiance arriving along -direction (`direction` need not be unit).
    Rgb radiance(Vec3f direction) const {
        if (!image_) return radiance_;
        return lookup(direction);
    }
    // A direction for next-event estimation (u in [0, 1)^2); none where the density is zero.
    std::optional<EnvironmentSample> sample(Vec2f u) const;
    // The solid-angle density with which sample() produces the unit direction `direction`.
    float pdf(Vec3f direction) const;
    // The radiance averaged over the sphere of directions, (1 / 4 pi) * integral of L: the
    // constant itself for a constant environment. Its luminance sets the light's power.
    Rgb average() const;

    // The image coordinates (s, t) in [0, 1)^2 of a unit direction in the light's own frame, and back.
    static Vec2f directionToImage(Vec3f local,
                                  EnvironmentMapping mapping = EnvironmentMapping::Equirectangular);
    static Vec3f imageToDirection(Vec2f st, EnvironmentMapping mapping = EnvironmentMapping::Equirectangular);

private:
    struct ImageData {
        EnvironmentImage image;
        PiecewiseConstant2D distribution;  // luminance * sin(theta) per texel
        Rgb average;
    };
    Rgb lookup(Vec3f direction) const;

    bool black_ = true;
    Rgb radiance_{0.0f, 0.0f, 0.0f};
    std::shared_ptr<const ImageData> image_;  // shared: scenes are copied, their images need not be
    Transform rotation_;                      // light frame -> world
};

// The environment as one light of the set (lights/light.h): it shares the map, which is large.
struct EnvironmentEmitter {
    std::shared_ptr<const EnvironmentLight> environment;

    static constexpr bool kIsDelta = false, kIsInfinite = true;

    static constexpr bool kPointIndependentOfReference = false;
    // Power through a disk the size of the scene, from every direction (pbrt-v4's estimate), with
    // the radiance averaged over the sphere.
    double power(double sceneRadius) const {
        return 4.0 * kPi * kPi * sceneRadius * sceneRadius * double(environment->average().luminance());
    }
    LightBounds bounds(float /*power*/) const { return {}; }  // infinite: chosen by its power share
    bool sample(Vec3f /*reference*/, Vec2f u, LightSample& ls) const {
        const std::optional<EnvironmentSample> es = environment->sample(u);
        if (!es) return false;
        ls.direction = es->direction;
        ls.distance = std::numeric_limits<float>::infinity();
        ls.radiance = es->radiance;
        ls.pdf = es->pdf;
        ls.isDelta = false;
        return true;
    }
    // For an infinite light the second argument is the direction towards it.
    float pdf(Vec3f /*reference*/, Vec3f direction) const { return environment->pdf(direction); }
};

}  // namespace penumbra
