#include "textures/image_texture.h"

#include <fmt/format.h>

#include "textures/texture_plugin_loader.h"

namespace penumbra {

ImageTextureSource openImageTexture(const std::filesystem::path& path, int colorSpace,
                                    const SourceLocation& where) {
    ImageTextureSource source;
    try {
        source.plugin = &texturePlugin();
    } catch (const InputError& e) {
        throw InputError(where, e.message());
    }
    char error[1024] = "";
    PenumbraTextureInfo info{};
    if (!source.plugin->openTexture(path.c_str(), colorSpace, &source.handle, &info, error, sizeof error))
        throw InputError(where, fmt::format("cannot read the image {}: {}", path.string(), error));
    source.channels = info.channels;
    return source;
}

void throwIfTextureLookupsFailed() {
    if (!texturePluginLoaded()) return;
    char first[1024] = "";
    const unsigned long long failed = texturePlugin().takeLookupFailures(first, sizeof first);
    if (failed > 0)
        throw InputError(
            fmt::format("cannot read the image texture {} ({} lookup{} failed; the render stopped)", first,
                        failed, failed == 1 ? "" : "s"));
}

}  // namespace penumbra
