// pbrt-v4's materials and textures mapped to penumbra's materials and texture objects
// (scenes/README.md), as the JSON of penumbra's scene format. The mapping of each type is stated
// in docs/pbrt-import.md.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "core/rgb.h"
#include "formats/pbrt/double_math.h"
#include "formats/pbrt/parameter_list.h"
#include "formats/pbrt/warning_log.h"
#include "scenes/json_reader.h"

namespace penumbra::pbrt {

// What an emitter's or a reflector's spectrum means (formats/pbrt/spectrum.h): the two are
// converted to RGB differently.
enum class SpectrumUse : uint8_t { Reflectance, Emission, Unbounded };

// The textures defined so far: each as penumbra's texture object where it has one (image,
// checkerboard), and as the constant standing for it where penumbra takes no texture.
class TextureTable {
public:
    struct Texture {
        Rgb constant;                // the value itself, or a stand-in for `object`
        std::optional<Json> object;  // penumbra's texture object (scenes/README.md, "Textures")
        std::string standIn;         // for `object`: what `constant` is, for warnings
    };
    // Texture "name" "float"|"spectrum" "class" params, defined where the current transform is
    // `worldFromTexture` (the space of the 3D textures and of a direction mix's direction).
    void define(const std::string& name, const std::string& kind, const std::string& textureClass,
                const ParameterList& params, const Matrix4d& worldFromTexture, const SourceLocation& where,
                WarningLog& log);
    const Texture* spectrum(const std::string& name) const;
    const Texture* scalar(const std::string& name) const;

private:
    std::map<std::string, Texture> spectrum_;
    std::map<std::string, Texture> float_;
};

// A colour parameter given as rgb, blackbody, spectrum, or a texture's name; `fallback` when
// absent. A texture penumbra cannot take here gives its stand-in constant, with a warning.
// Throws InputError at the parameter for an unknown texture or named spectrum.
Rgb readColor(const ParameterList& params, std::string_view name, Rgb fallback, SpectrumUse use,
              const TextureTable& textures, WarningLog& log);
// A float parameter given as a float or a float texture's name.
double readScalar(const ParameterList& params, std::string_view name, double fallback,
                  const TextureTable& textures, WarningLog& log);

// The penumbra material standing for a pbrt material of `type` with `params` (penumbra's JSON
// material object). "mix" is not handled here: the builder resolves it to one of its materials.
// Throws InputError at `where` for an unknown type.
Json mapMaterial(const std::string& type, const ParameterList& params, const TextureTable& textures,
                 const SourceLocation& where, WarningLog& log);

}  // namespace penumbra::pbrt
