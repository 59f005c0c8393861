// A material parameter's value over a surface: a constant, a procedural checkerboard, an image
// looked up through OpenImageIO's TextureSystem (textures/texture_plugin.h), or one of pbrt-v4's
// procedural and composite textures (textures/procedural_texture.h). Colours are linear RGB; a
// scalar parameter (roughness) reads the first channel.
//
// Coordinates: a texture is looked up at the surface's (u, v) (geometry/surface_interaction.h:
// mesh uvs, a quad's corners, a sphere's (phi / 2 pi, theta / pi)), or at the (s, t) a spherical,
// cylindrical or planar mapping gives the point (textures/texture_mapping.h), then scaled and offset:
// (s, t) * uvScale + uvOffset. Images put t = 0 at their bottom row (OBJ's and pbrt's convention),
// so the image row coordinate is 1 - t.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "core/rgb.h"
#include "core/vec.h"
#include "textures/texture_footprint.h"
#include "textures/texture_mapping.h"
#include "textures/texture_plugin.h"

namespace penumbra {

enum class TextureKind : uint8_t { Constant, Checkerboard, Image, Procedural };

struct ProceduralTexture;

// How an image is sampled (texture_plugin.h's PenumbraTextureWrap and PenumbraTextureFilter).
enum class TextureWrap : uint8_t { Repeat, Clamp, Black, Mirror };
enum class TextureFilter : uint8_t { Closest, Bilinear, Trilinear, Anisotropic };

struct ImageTextureSource {
    const PenumbraTexturePlugin* plugin = nullptr;
    void* handle = nullptr;  // the plugin's handle of the opened file
    int channels = 3;        // of the file
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    TextureFilter filter = TextureFilter::Trilinear;
};

class Texture {
public:
    Texture() = default;
    static Texture constant(Rgb value) {
        Texture t;
        t.a_ = value;
        return t;
    }
    // Squares of side 1 / frequency in (u, v): colour `a` where floor(u f) + floor(v f) is even, `b`
    // where it is odd. Point-sampled: the pixel filter does the anti-aliasing.
    static Texture checkerboard(Rgb a, Rgb b) {
        Texture t;
        t.kind_ = TextureKind::Checkerboard;
        t.a_ = a;
        t.b_ = b;
        return t;
    }
    // `scale` multiplies the looked-up colour; `invert` then takes it from 1 (at least 0), as
    // pbrt-v4's imagemap `invert`.
    static Texture image(const ImageTextureSource& source, Rgb scale, bool invert = false) {
        Texture t;
        t.kind_ = TextureKind::Image;
        t.image_ = source;
        t.a_ = scale;
        t.invert_ = invert;
        return t;
    }
    // pbrt-v4's procedural and composite textures (textures/procedural_texture.h).
    static Texture procedural(std::shared_ptr<const ProceduralTexture> procedural);
    Texture& mapUv(Vec2f scale, Vec2f offset) {
        uvScale_ = scale;
        uvOffset_ = offset;
        return *this;
    }
    // Coordinates from the point instead of (u, v) (not TextureMappingKind::Uv): the texture is
    // then spatial.
    Texture& setMapping(const TextureMapping& mapping) {
        mapping_ = std::make_shared<const TextureMapping>(mapping);
        spatial_ = true;
        return *this;
    }

    TextureKind kind() const { return kind_; }
    // Whether a lookup needs a footprint (a filter that chooses a MIP level).
    bool needsFootprint() const {
        if (kind_ == TextureKind::Procedural) return proceduralNeedsFootprint_;
        return kind_ == TextureKind::Image &&
               (image_.filter == TextureFilter::Trilinear || image_.filter == TextureFilter::Anisotropic);
    }
    // Whether a lookup needs the point and normal (TextureQuery::p, n), not only (u, v): then it
    // can shade a material but not be a cut-out's or an emitter's (looked up at (u, v) alone).
    bool isSpatial() const { return spatial_; }

    Rgb evaluate(const TextureQuery& query) const {
        if (kind_ == TextureKind::Constant) return a_;
        const TextureCoordinates c = coordinates(query);
        if (kind_ == TextureKind::Checkerboard) {
            const int64_t parity = int64_t(std::floor(c.st.x)) + int64_t(std::floor(c.st.y));
            return (parity & 1) == 0 ? a_ : b_;
        }
        if (kind_ == TextureKind::Procedural) [[unlikely]]
            return evaluateProcedural(query, c.st);
        return lookupImage(c);
    }

    // The query's coordinates (mapped, then scaled and offset) and their derivatives.
    TextureCoordinates coordinates(const TextureQuery& query) const {
        TextureCoordinates c =
            mapping_ ? mapping_->map(query)
                     : TextureCoordinates{query.uv, query.dudx, query.dudy, query.dvdx, query.dvdy};
        c.st = {c.st.x * uvScale_.x + uvOffset_.x, c.st.y * uvScale_.y + uvOffset_.y};
        c.dsdx *= uvScale_.x;
        c.dsdy *= uvScale_.x;
        c.dtdx *= uvScale_.y;
        c.dtdy *= uvScale_.y;
        return c;
    }

    // The texture read as a surface's coverage (a cut-out's alpha, geometry/cut_out.h): an image's
    // alpha channel when it has one (two channels: grey and alpha; four: RGBA), as pbrt-v4 reads a
    // float image texture of four channels, else its first channel; a constant's or a
    // checkerboard's first channel. An image's value is multiplied by its scale's first channel.
    float coverage(const TextureQuery& query) const {
        if (kind_ == TextureKind::Image && (image_.channels == 2 || image_.channels == 4))
            return lookupAlpha(query);
        return evaluate(query).r;
    }

private:
    Rgb lookupImage(const TextureCoordinates& c) const;
    Rgb evaluateProcedural(const TextureQuery& query, Vec2f uv) const;
    float lookupAlpha(const TextureQuery& query) const;

    TextureKind kind_ = TextureKind::Constant;
    Rgb a_, b_;  // the constant or the image's scale; the checkerboard's two colours
    Vec2f uvScale_{1.0f, 1.0f}, uvOffset_{0.0f, 0.0f};
    std::shared_ptr<const TextureMapping> mapping_;  // null: (u, v)
    ImageTextureSource image_;
    std::shared_ptr<const ProceduralTexture> procedural_;
    bool invert_ = false;                    // an image's `invert`
    bool proceduralNeedsFootprint_ = false;  // an input's needsFootprint()
    bool spatial_ = false;                   // isSpatial()
};

}  // namespace penumbra
