#include "textures/image_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>

#include <fmt/format.h>

#include <cstdint>
#include <limits>

#include "core/input_limits.h"
#include "textures/texture_plugin_loader.h"

namespace penumbra {

namespace {

bool isExr(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    return extension == ".exr";
}

void checkSize(int64_t width, int64_t height, const std::filesystem::path& path, const SourceLocation& where) {
    if (width <= 0 || height <= 0 || width * height > limits::kMaxImageTexels)
        throw InputError(where, fmt::format("{}: an image of {} x {} texels (at most {} in all)", path.string(), width,
                                            height, limits::kMaxImageTexels));
}

LinearRgbImage readExr(const std::filesystem::path& path, const SourceLocation& where) {
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        const int64_t width = int64_t(window.max.x) - window.min.x + 1, height = int64_t(window.max.y) - window.min.y + 1;
        checkSize(width, height, path, where);
        const Imf::ChannelList& channels = file.header().channels();
        // R, G, B; a luminance-only image (Y) is grey.
        const bool grey = !channels.findChannel("R") && channels.findChannel("Y");
        LinearRgbImage image;
        image.width = int(width);
        image.height = int(height);
        image.texels.assign(size_t(width * height), Rgb(0.0f));
        Imf::FrameBuffer buffer;
        char* base = reinterpret_cast<char*>(image.texels.data()) -
                     (int64_t(window.min.x) + int64_t(window.min.y) * width) * int64_t(sizeof(Rgb));
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            buffer.insert(grey ? "Y" : names[c],
                          Imf::Slice(Imf::FLOAT, base + c * sizeof(float), sizeof(Rgb), sizeof(Rgb) * size_t(width), 1, 1, 0.0));
        file.setFrameBuffer(buffer);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {  // OpenEXR throws Iex exceptions
        throw InputError(where, fmt::format("{}: cannot read the OpenEXR image: {}", path.string(), e.what()));
    }
}

}  // namespace

LinearRgbImage readLinearRgbImage(const std::filesystem::path& path, const SourceLocation& where) {
    if (isExr(path)) return readExr(path, where);
    const PenumbraTexturePlugin& plugin = texturePlugin();
    char error[1024] = "";
    int width = 0, height = 0;
    if (!plugin.readImageSize(path.c_str(), &width, &height, error, sizeof error))
        throw InputError(where, fmt::format("{}: {}", path.string(), error));
    checkSize(width, height, path, where);
    LinearRgbImage image;
    image.width = width;
    image.height = height;
    image.texels.resize(size_t(width) * size_t(height));
    if (!plugin.readLinearRgb(path.c_str(), reinterpret_cast<float*>(image.texels.data()), error, sizeof error))
        throw InputError(where, fmt::format("{}: {}", path.string(), error));
    return image;
}

}  // namespace penumbra
