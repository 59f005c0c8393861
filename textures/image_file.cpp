#include "textures/image_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/input_limits.h"
#include "textures/exr_header_check.h"
#include "textures/texture_plugin_loader.h"

namespace penumbra {

namespace {

bool isExr(const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    return extension == ".exr";
}

void checkSize(int64_t width, int64_t height, const std::filesystem::path& path,
               const SourceLocation& where) {
    if (width <= 0 || height <= 0 || width * height > limits::kMaxImageTexels)
        throw InputError(where, fmt::format("{}: an image of {} x {} texels (at most {} in all)",
                                            path.string(), width, height, limits::kMaxImageTexels));
}

LinearRgbImage readExr(const std::filesystem::path& path, const SourceLocation& where) {
    // The headers first, by OpenEXR's C core, before the C++ reader allocates what they declare.
    const std::string problem = exrHeaderProblem(path.c_str(), limits::kMaxImageTexels);
    if (!problem.empty())
        throw InputError(where, fmt::format("{}: cannot read the OpenEXR image: {}", path.string(), problem));
    try {
        Imf::InputFile file(path.c_str());
        const Imath::Box2i window = file.header().dataWindow();
        const int64_t width = int64_t(window.max.x) - window.min.x + 1,
                      height = int64_t(window.max.y) - window.min.y + 1;
        checkSize(width, height, path, where);
        const Imf::ChannelList& channels = file.header().channels();
        // R, G, B; a luminance-only image (Y) is grey.
        const bool grey = !channels.findChannel("R") && channels.findChannel("Y");
        // A strip of rows at a time, appended to room reserved (and not yet touched) for all of
        // them, so that memory grows only with what decodes: a file that declares the limit and
        // holds nothing fails on its first strip.
        LinearRgbImage image;
        image.width = int(width);
        image.height = int(height);
        image.texels.reserve(size_t(width * height));
        const int64_t stripRows = std::min<int64_t>(64, height);
        std::vector<Rgb> strip(size_t(width * stripRows));
        const char* names[3] = {"R", "G", "B"};
        for (int64_t y = window.min.y; y <= window.max.y; y += stripRows) {
            const int64_t rows = std::min<int64_t>(stripRows, int64_t(window.max.y) - y + 1);
            Imf::FrameBuffer buffer;
            char* base = reinterpret_cast<char*>(strip.data()) -
                         (int64_t(window.min.x) + y * width) * int64_t(sizeof(Rgb));
            for (int c = 0; c < 3; ++c)
                buffer.insert(grey ? "Y" : names[c],
                              Imf::Slice(Imf::FLOAT, base + c * sizeof(float), sizeof(Rgb),
                                         sizeof(Rgb) * size_t(width), 1, 1, 0.0));
            file.setFrameBuffer(buffer);
            file.readPixels(int(y), int(y + rows - 1));
            image.texels.insert(image.texels.end(), strip.begin(), strip.begin() + rows * width);
        }
        return image;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {  // OpenEXR throws Iex exceptions
        throw InputError(where,
                         fmt::format("{}: cannot read the OpenEXR image: {}", path.string(), e.what()));
    }
}

// An environment map's texels are radiance: finite and not negative. Anything else (a NaN, an
// infinity, a negative value from a corrupt or mistaken file) is refused rather than taken as
// black, naming the first such texel (x from the left, y from the top).
void checkRadiance(const LinearRgbImage& image, const std::filesystem::path& path,
                   const SourceLocation& where) {
    for (size_t i = 0; i < image.texels.size(); ++i) {
        const Rgb& texel = image.texels[i];
        for (int c = 0; c < 3; ++c) {
            if (std::isfinite(texel[c]) && texel[c] >= 0.0f) continue;
            size_t bad = 0;
            for (const Rgb& t : image.texels)
                for (int k = 0; k < 3; ++k) bad += !(std::isfinite(t[k]) && t[k] >= 0.0f);
            throw InputError(
                where, fmt::format("{}: texel ({}, {}) has {} = {}: radiance must be finite and not "
                                   "negative ({} such values in the image)",
                                   path.string(), i % size_t(image.width), i / size_t(image.width), "RGB"[c],
                                   texel[c], bad));
        }
    }
}

LinearRgbImage readPluginImage(const std::filesystem::path& path, const SourceLocation& where) {
    const PenumbraTexturePlugin& plugin = texturePlugin();
    char error[1024] = "";
    int width = 0, height = 0;
    if (!plugin.probeImage(path.c_str(), limits::kMaxImageTexels, &width, &height, error, sizeof error))
        throw InputError(where, fmt::format("{}: cannot read the image: {}", path.string(), error));
    checkSize(width, height, path, where);
    // Room reserved, not touched: it fills as the plugin hands over strips that decoded.
    LinearRgbImage image;
    image.width = width;
    image.height = height;
    image.texels.reserve(size_t(width) * size_t(height));
    auto append = [](void* user, const float* rgb, int rows) {
        auto& texels = static_cast<LinearRgbImage*>(user)->texels;
        const size_t count = size_t(static_cast<LinearRgbImage*>(user)->width) * size_t(rows);
        for (size_t i = 0; i < count; ++i) texels.push_back(Rgb(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]));
    };
    if (!plugin.readLinearRgb(path.c_str(), width, height, append, &image, error, sizeof error))
        throw InputError(where, fmt::format("{}: cannot read the image: {}", path.string(), error));
    if (image.texels.size() != size_t(width) * size_t(height))
        throw InputError(where, fmt::format("{}: cannot read the image: fewer rows than its header declares",
                                            path.string()));
    return image;
}

}  // namespace

LinearRgbImage readLinearRgbImage(const std::filesystem::path& path, const SourceLocation& where) {
    LinearRgbImage image = isExr(path) ? readExr(path, where) : readPluginImage(path, where);
    checkRadiance(image, path, where);
    return image;
}

}  // namespace penumbra
