// Image textures through the texture plugin (textures/texture_plugin.h): opening one, its header
// checked against the limits first, and the lookups that failed while rendering. A texture that
// cannot be read stops the render with its file named: a truncated or corrupt file is found only
// when its tiles are read, and its lookups would otherwise be black without a word.
#pragma once

#include <filesystem>

#include "core/error.h"
#include "textures/texture.h"

namespace penumbra {

// Opens the image at `path` (colorSpace: PenumbraColorSpace) with the default wrap and filter.
// Throws InputError at `where` (the scene key that names the file) when the plugin cannot be
// loaded or the image cannot be opened: unreadable header, too many texels or channels.
ImageTextureSource openImageTexture(const std::filesystem::path& path, int colorSpace,
                                    const SourceLocation& where);

// Throws InputError naming the first failed lookup's file and OpenImageIO's message when any lookup
// failed since the last call (the count starts again from zero). Does nothing when no scene has
// loaded the plugin.
void throwIfTextureLookupsFailed();

}  // namespace penumbra
