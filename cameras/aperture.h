// The lens aperture's shape: where on the lens a ray leaves. A disk, a regular polygon of blades
// (the shape of out-of-focus highlights), or an image of the aperture's transmission (pbrt-v4's
// `aperture`: "gaussian", "square", "pentagon", "star" or a file), sampled in proportion to it.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "cameras/camera_params.h"
#include "core/piecewise_constant_2d.h"
#include "core/vec.h"

namespace penumbra {

class Aperture {
public:
    Aperture() = default;  // round
    // A regular polygon whose vertices lie on the unit circle, the first at `rotationDegrees`.
    static Aperture polygon(int blades, float rotationDegrees);
    // The image over [-1, 1]^2 (camera_params.h); throws InputError when it lets no light through.
    static Aperture image(const ApertureImage& image);
    // The thin lens's aperture a camera's parameters describe: its image, else its blades, else round.
    static Aperture ofThinLens(const CameraParams& params);

    // A point of the unit aperture (the disk, polygon or square [-1, 1]^2) from a uniform sample,
    // with density proportional to the transmission. Continuous and monotone in each coordinate of
    // u, so stratified samples stay stratified.
    Vec2f sample(Vec2f u) const;
    // The transmission at p in [-1, 1]^2: 1 inside a disk or polygon and 0 outside; an image's
    // bilinearly interpolated value (0 outside the square).
    float transmission(Vec2f p) const;
    bool isImage() const { return !image_.empty(); }

private:
    int blades_ = 0;
    // The polygon's vertices on the unit circle, the first repeated at the end: a ray takes the two
    // of its blade rather than making them with two sincos calls (bench/README.md, "Speed tricks").
    std::vector<Vec2f> bladeVertices_;
    ApertureImage image_;
    PiecewiseConstant2D distribution_;
};

// pbrt-v4's built-in aperture images (256 x 256, normalized): "gaussian", "square", "pentagon",
// "star"; nullopt for another name.
std::optional<ApertureImage> builtinApertureImage(std::string_view name);

// The image scaled so that its mean over [-1, 1]^2 is pi / 4, the round aperture's: the same light
// passes as through the round aperture of the same radius (pbrt-v4's normalization). Negative
// and non-finite values become 0. Throws InputError when nothing passes.
void normalizeApertureImage(ApertureImage& image);

}  // namespace penumbra
