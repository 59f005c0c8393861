#include "textures/exr_header_check.h"

#include <OpenEXR/openexr.h>

#include <cstdio>

#include "core/input_limits.h"

namespace penumbra {

bool startsLikeExr(const char* path) {
    unsigned char magic[4] = {};
    std::FILE* file = std::fopen(path, "rb");
    if (!file) return false;
    const size_t n = std::fread(magic, 1, sizeof magic, file);
    std::fclose(file);
    return n == 4 && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01;
}

namespace {

// The first error the core reports (its own message, with the attribute's name).
void keepFirstError(exr_const_context_t context, exr_result_t code, const char* message) {
    void* user = nullptr;
    if (exr_get_user_data(context, &user) == EXR_ERR_SUCCESS && user &&
        static_cast<std::string*>(user)->empty())
        *static_cast<std::string*>(user) = message ? message : exr_get_error_code_as_string(code);
}

std::string partProblem(exr_const_context_t context, int part, int64_t maxTexels, int64_t& chunks) {
    const std::string which = part == 0 ? "" : " (part " + std::to_string(part) + ")";
    exr_storage_t storage = EXR_STORAGE_SCANLINE;
    exr_attr_box2i_t window{};
    const exr_attr_chlist_t* channels = nullptr;
    int32_t count = 0;
    if (exr_get_storage(context, part, &storage) != EXR_ERR_SUCCESS ||
        exr_get_data_window(context, part, &window) != EXR_ERR_SUCCESS ||
        exr_get_channels(context, part, &channels) != EXR_ERR_SUCCESS || !channels ||
        exr_get_chunk_count(context, part, &count) != EXR_ERR_SUCCESS)
        return "incomplete header" + which;
    if (storage == EXR_STORAGE_DEEP_SCANLINE || storage == EXR_STORAGE_DEEP_TILED)
        return "deep data" + which + " is not read as an image";
    const int64_t width = int64_t(window.max.x) - window.min.x + 1,
                  height = int64_t(window.max.y) - window.min.y + 1;
    if (width * height > maxTexels)
        return std::to_string(width) + " x " + std::to_string(height) + " texels" + which + "; at most " +
               std::to_string(maxTexels) + " are read";
    if (channels->num_channels > limits::kMaxImageChannels ||
        width * height * channels->num_channels > limits::kMaxValuesPerTexel * maxTexels)
        return std::to_string(channels->num_channels) + " channels of " + std::to_string(width) + " x " +
               std::to_string(height) + " texels" + which + "; at most " +
               std::to_string(limits::kMaxValuesPerTexel * maxTexels) +
               " values (texels x channels) are read";
    if (storage == EXR_STORAGE_TILED) {
        uint32_t tileWidth = 0, tileHeight = 0;
        exr_tile_level_mode_t levels{};
        exr_tile_round_mode_t round{};
        if (exr_get_tile_descriptor(context, part, &tileWidth, &tileHeight, &levels, &round) !=
            EXR_ERR_SUCCESS)
            return "incomplete tile description" + which;
        if (int64_t(tileWidth) * int64_t(tileHeight) > maxTexels)
            return "tiles of " + std::to_string(tileWidth) + " x " + std::to_string(tileHeight) + " texels" +
                   which + "; at most " + std::to_string(maxTexels) + " are read";
    }
    chunks += count;
    if (chunks > limits::kMaxExrChunks)
        return std::to_string(chunks) + " chunks (scanline blocks or tiles); at most " +
               std::to_string(limits::kMaxExrChunks) + " are read";
    return "";
}

}  // namespace

std::string exrHeaderProblem(const char* path, int64_t maxTexels) {
    std::string reason;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &reason;
    init.error_handler_fn = keepFirstError;
    init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER;  // otherwise it reports errors and goes on
    init.max_image_width = init.max_image_height = limits::kMaxImageSide;
    init.max_tile_width = init.max_tile_height = limits::kMaxImageSide;
    exr_context_t context = nullptr;
    const exr_result_t result = exr_start_read(&context, path, &init);
    if (result == EXR_ERR_SUCCESS) {
        int parts = 0;
        int64_t chunks = 0;
        if (exr_get_count(context, &parts) != EXR_ERR_SUCCESS) reason = "no parts";
        for (int part = 0; part < parts && reason.empty(); ++part)
            reason = partProblem(context, part, maxTexels, chunks);
    } else if (reason.empty()) {
        reason = exr_get_error_code_as_string(result);
    }
    exr_finish(&context);
    for (char& c : reason)
        if (c < 0x20 || c > 0x7e) c = '?';  // names from a corrupt header are not printed raw
    return reason;
}

}  // namespace penumbra
