// pbrt-v4's materials and textures mapped to penumbra's materials (scenes/README.md), as the JSON
// material objects of penumbra's scene format. The mapping of each type is stated in
// docs/pbrt-import.md. Textures are reduced to constants for now (penumbra's materials have no
// textures yet): each texture becomes the constant closest to it, with a warning saying which.
#pragma once

#include <map>
#include <optional>
#include <string>

#include "core/rgb.h"
#include "scenes/json_reader.h"
#include "scenes/pbrt/parameter_list.h"
#include "scenes/pbrt/warning_log.h"

namespace penumbra::pbrt {

// What an emitter's or a reflector's spectrum means (scenes/pbrt/spectrum.h): the two are
// converted to RGB differently.
enum class SpectrumUse : uint8_t { Reflectance, Emission, Unbounded };

// The textures defined so far, each as the constant standing for it.
class TextureTable {
public:
    // Texture "name" "float"|"spectrum" "class" params.
    void define(const std::string& name, const std::string& kind, const std::string& textureClass,
                const ParameterList& params, const SourceLocation& where, const std::filesystem::path& folder,
                WarningLog& log);
    std::optional<Rgb> spectrum(const std::string& name) const;
    std::optional<float> scalar(const std::string& name) const;

private:
    std::map<std::string, Rgb> spectrum_;
    std::map<std::string, float> float_;
};

// A colour parameter given as rgb, blackbody, spectrum, or a texture's name; `fallback` when
// absent. Throws InputError at the parameter for an unknown texture or named spectrum.
Rgb readColor(const ParameterList& params, std::string_view name, Rgb fallback, SpectrumUse use,
              const TextureTable& textures, WarningLog& log);
// A float parameter given as a float or a float texture's name.
double readScalar(const ParameterList& params, std::string_view name, double fallback, const TextureTable& textures);

// The average of an OpenEXR image's pixels, for image textures and image environment lights until
// penumbra reads images itself. Empty, with a warning, when the image cannot be read or is not
// an EXR file.
std::optional<Rgb> imageMean(const std::filesystem::path& file, bool srgbEncoded8Bit, const SourceLocation& where,
                             WarningLog& log);

// The penumbra material standing for a pbrt material of `type` with `params` (penumbra's JSON
// material object). "mix" is not handled here: the builder resolves it to one of its materials.
// Throws InputError at `where` for an unknown type.
Json mapMaterial(const std::string& type, const ParameterList& params, const TextureTable& textures,
                 const SourceLocation& where, WarningLog& log);

}  // namespace penumbra::pbrt
