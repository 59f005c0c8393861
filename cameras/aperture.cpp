#include "cameras/aperture.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.h"
#include "core/sampling.h"

namespace penumbra {

Aperture Aperture::polygon(int blades, float rotationDegrees) {
    Aperture aperture;
    aperture.blades_ = blades;
    const float rotation = rotationDegrees * kPi / 180.0f;
    for (int blade = 0; blade <= blades; ++blade) {
        const float angle = rotation + 2.0f * kPi * float(blade) / float(blades);
        aperture.bladeVertices_.push_back({std::cos(angle), std::sin(angle)});
    }
    return aperture;
}

Aperture Aperture::image(const ApertureImage& image) {
    Aperture aperture;
    aperture.image_ = image;
    aperture.distribution_ = PiecewiseConstant2D(image.values, size_t(image.width), size_t(image.height));
    if (aperture.distribution_.empty()) throw InputError("the aperture image lets no light through");
    return aperture;
}

Aperture Aperture::ofThinLens(const CameraParams& p) {
    if (!p.apertureImage.empty()) return image(p.apertureImage);
    if (p.apertureBlades >= 3) return polygon(p.apertureBlades, p.apertureRotationDegrees);
    return {};
}

Vec2f Aperture::sample(Vec2f u) const {
    if (blades_ < 3) {
        if (image_.empty()) return sampleUniformDiskConcentric(u);
        const Vec2f p = distribution_.sample(u);  // (column, row) in [0, 1)^2, row 0 at the top
        return {2.0f * p.x - 1.0f, 1.0f - 2.0f * p.y};
    }
    // Uniform on a regular polygon: the blade's triangle (centre, vertex i, vertex i + 1) is
    // picked by u.x, whose remainder is reused, so strata stay compact.
    const float scaled = u.x * float(blades_);
    const int blade = std::min(int(scaled), blades_ - 1);
    const Vec2f b = sampleUniformTriangle({scaled - float(blade), u.y});
    // The centre has weight 1 - b.x - b.y and is the origin.
    return bladeVertices_[size_t(blade)] * b.x + bladeVertices_[size_t(blade) + 1] * b.y;
}

float Aperture::transmission(Vec2f p) const {
    if (image_.empty()) {
        if (blades_ < 3) return p.x * p.x + p.y * p.y <= 1.0f ? 1.0f : 0.0f;
        // Inside the polygon: on the inner side of every edge.
        for (int i = 0; i < blades_; ++i) {
            const Vec2f a = bladeVertices_[size_t(i)], b = bladeVertices_[size_t(i) + 1];
            if ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) < 0.0f) return 0.0f;
        }
        return 1.0f;
    }
    if (!(std::abs(p.x) <= 1.0f && std::abs(p.y) <= 1.0f)) return 0.0f;
    // Texel centres at (i + 1/2) / width; bilinear between them, clamped at the border.
    const float x = 0.5f * (p.x + 1.0f) * float(image_.width) - 0.5f;
    const float y = 0.5f * (1.0f - p.y) * float(image_.height) - 0.5f;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float fx = x - float(x0), fy = y - float(y0);
    auto at = [&](int i, int j) {
        i = std::clamp(i, 0, image_.width - 1);
        j = std::clamp(j, 0, image_.height - 1);
        return image_.values[size_t(j) * size_t(image_.width) + size_t(i)];
    };
    return (1.0f - fy) * ((1.0f - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
           fy * ((1.0f - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
}

namespace {

constexpr int kBuiltinSide = 256;

// 1 inside the polygon (non-zero winding), 0 outside, at each texel centre of [-1, 1]^2 (+y up).
ApertureImage rasterizePolygon(const std::vector<Vec2f>& vertices) {
    ApertureImage image{kBuiltinSide, kBuiltinSide, std::vector<float>(size_t(kBuiltinSide) * kBuiltinSide)};
    for (int row = 0; row < kBuiltinSide; ++row)
        for (int column = 0; column < kBuiltinSide; ++column) {
            const Vec2f p{-1.0f + 2.0f * (float(column) + 0.5f) / kBuiltinSide,
                          1.0f - 2.0f * (float(row) + 0.5f) / kBuiltinSide};
            int winding = 0;
            for (size_t i = 0; i < vertices.size(); ++i) {
                const Vec2f a = vertices[i], b = vertices[(i + 1) % vertices.size()];
                const float side = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
                if (a.y <= p.y) {
                    if (b.y > p.y && side > 0.0f) ++winding;
                } else if (b.y <= p.y && side < 0.0f) {
                    --winding;
                }
            }
            image.values[size_t(row) * kBuiltinSide + size_t(column)] = winding != 0 ? 1.0f : 0.0f;
        }
    return image;
}

}  // namespace

std::optional<ApertureImage> builtinApertureImage(std::string_view name) {
    ApertureImage image;
    if (name == "gaussian") {
        // exp(-r^2) - exp(-1), zero beyond the unit circle (pbrt-v4's, sigma^2 = 1).
        image = {kBuiltinSide, kBuiltinSide, std::vector<float>(size_t(kBuiltinSide) * kBuiltinSide)};
        for (int row = 0; row < kBuiltinSide; ++row)
            for (int column = 0; column < kBuiltinSide; ++column) {
                const float x = -1.0f + 2.0f * (float(column) + 0.5f) / kBuiltinSide;
                const float y = 1.0f - 2.0f * (float(row) + 0.5f) / kBuiltinSide;
                image.values[size_t(row) * kBuiltinSide + size_t(column)] =
                    std::max(0.0f, std::exp(-(x * x + y * y)) - std::exp(-1.0f));
            }
    } else if (name == "square") {
        // The square of half the side, centred.
        image = rasterizePolygon({{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}});
    } else if (name == "pentagon") {
        // A regular pentagon with a vertex up, on the circle of radius 0.8.
        std::vector<Vec2f> vertices;
        for (int i = 0; i < 5; ++i) {
            const float angle = 0.5f * kPi - 2.0f * kPi * float(i) / 5.0f;
            vertices.push_back(Vec2f{std::cos(angle), std::sin(angle)} * 0.8f);
        }
        image = rasterizePolygon(vertices);
    } else if (name == "star") {
        // A five-pointed star: outer vertices on the unit circle, inner ones on the circle through
        // the crossings of its edges (radius cos 72 / cos 36).
        std::vector<Vec2f> vertices;
        const float inner = std::cos(0.4f * kPi) / std::cos(0.2f * kPi);
        for (int i = 9; i >= 0; --i) {
            const float r = (i & 1) ? 1.0f : inner;
            vertices.push_back(Vec2f{std::cos(kPi * float(i) / 5.0f), std::sin(kPi * float(i) / 5.0f)} * r);
        }
        image = rasterizePolygon(vertices);
    } else {
        return std::nullopt;
    }
    normalizeApertureImage(image);
    return image;
}

void normalizeApertureImage(ApertureImage& image) {
    double sum = 0.0;
    for (float& v : image.values) {
        if (!(v > 0.0f) || !std::isfinite(v)) v = 0.0f;
        sum += v;
    }
    if (!(sum > 0.0)) throw InputError("the aperture image lets no light through (every value is 0)");
    const double mean = sum / double(image.values.size());
    const float scale = float((kPi / 4.0) / mean);
    for (float& v : image.values) v *= scale;
}

}  // namespace penumbra
