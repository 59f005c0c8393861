// penumbra_texture_plugin: the OpenImageIO side of textures/texture_plugin.h. Built as a module
// and loaded the first time a scene names an image, so that the penumbra executable does not link
// OpenImageIO.
#include "textures/texture_plugin.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace {

int failWith(const std::string& message, char* error, size_t errorSize) {
    if (errorSize > 0) {
        const size_t n = std::min(message.size(), errorSize - 1);
        std::memcpy(error, message.data(), n);
        error[n] = '\0';
    }
    return 0;
}

// Integer formats hold display-encoded values (PNG, JPEG, 8-bit TIFF); float formats linear ones.
bool isSrgb(const OIIO::ImageSpec& spec, int colorSpace) {
    if (colorSpace != PENUMBRA_COLOR_AUTO) return colorSpace == PENUMBRA_COLOR_SRGB;
    if (spec.format.is_floating_point()) return false;
    const std::string declared = spec.get_string_attribute("oiio:ColorSpace");
    return !OIIO::Strutil::iequals(declared, "linear") && !OIIO::Strutil::iequals(declared, "scene_linear");
}

// The file's pixels as linear floats (sRGB-encoded ones decoded with OpenImageIO's built-in sRGB ->
// linear conversion).
bool readLinear(const char* path, bool srgb, OIIO::ImageBuf& result, std::string& failure) {
    OIIO::ImageBuf source(path);
    OIIO::ImageBuf floats;
    if (!source.read(0, 0, true, OIIO::TypeDesc::FLOAT) || !floats.copy(source, OIIO::TypeDesc::FLOAT)) {
        failure = source.geterror().empty() ? floats.geterror() : source.geterror();
        return false;
    }
    if (!srgb) {
        result = std::move(floats);
        return true;
    }
    // Alpha, when there is one, stays linear (colorconvert's unpremult = false, alpha untouched).
    if (!OIIO::ImageBufAlgo::colorconvert(result, floats, "sRGB", "linear", false)) {
        failure = result.geterror();
        return false;
    }
    return true;
}

// Removes the "penumbra-textures-<pid>-XXXXXX" folders in `temporary` that a killed process left
// (its destructor never ran): those whose process is gone and that were not modified in the last
// minute (the temporary folder may be shared with another machine, whose process numbers mean
// nothing here).
void removeFoldersOfKilledProcesses(const std::filesystem::path& temporary) {
    const std::string prefix = "penumbra-textures-";
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(temporary, ec)) {
        const std::string name = entry.path().filename().string();
        if (!name.starts_with(prefix) || !entry.is_directory(ec)) continue;
        const size_t end = name.find('-', prefix.size());
        const std::string digits = name.substr(prefix.size(), end == std::string::npos ? 0 : end - prefix.size());
        if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) continue;
        const pid_t pid = pid_t(std::stol(digits));
        if (pid == ::getpid() || ::kill(pid, 0) == 0 || errno == EPERM) continue;
        std::error_code ignored;
        const auto modified = std::filesystem::last_write_time(entry.path(), ignored);
        if (ignored || std::filesystem::file_time_type::clock::now() - modified < std::chrono::minutes(1)) continue;
        std::filesystem::remove_all(entry.path(), ignored);
    }
}

// The one TextureSystem of the process, the sRGB images it has converted, and the temporary
// folder that holds those conversions (removed at exit; after a kill, by the next process that
// converts one).
class Textures {
public:
    Textures() {
        system_ = OIIO::TextureSystem::create(false);
        system_->attribute("automip", 1);         // plain images get MIP levels built in memory
        system_->attribute("max_memory_MB", 2048.0f);
        system_->attribute("deduplicate", 1);
    }
    // The TextureSystem is not destroyed: this runs at process exit, which frees it anyway, and
    // OpenImageIO 2.4's TextureSystem::destroy deletes it through a type of another size (a
    // new-delete mismatch that AddressSanitizer reports inside the library).
    ~Textures() {
        if (!folder_.empty()) {
            std::error_code ec;
            std::filesystem::remove_all(folder_, ec);
        }
    }
    OIIO::TextureSystem& system() { return *system_; }

    // The file the TextureSystem reads for `path`: the file itself, or its linearised conversion.
    bool fileFor(const char* path, bool srgb, std::string& file, std::string& failure) {
        if (!srgb) {
            file = path;
            return true;
        }
        std::lock_guard lock(mutex_);
        const auto found = converted_.find(path);
        if (found != converted_.end()) {
            file = found->second;
            return true;
        }
        OIIO::ImageBuf linear;
        if (!readLinear(path, true, linear, failure)) return false;
        if (folder_.empty()) {
            const std::filesystem::path temporary = std::filesystem::temp_directory_path();
            removeFoldersOfKilledProcesses(temporary);
            std::string pattern = (temporary / ("penumbra-textures-" + std::to_string(::getpid()) + "-XXXXXX")).string();
            if (!::mkdtemp(pattern.data())) {
                failure = std::string("cannot create a temporary folder for converted textures: ") + std::strerror(errno);
                return false;
            }
            folder_ = pattern;
        }
        file = folder_ + "/" + std::to_string(converted_.size()) + ".exr";
        // Half floats keep 11 significant bits, more than the 8 of the source; tiled and MIP-mapped as maketx makes them.
        OIIO::ImageSpec config;
        config.format = OIIO::TypeDesc::HALF;
        config.tile_width = config.tile_height = 64;
        config.attribute("maketx:filtername", "box");
        if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, linear, file, config)) {
            failure = "cannot build the linearised texture: " + OIIO::geterror();
            return false;
        }
        converted_.emplace(path, file);
        return true;
    }

private:
    OIIO::TextureSystem* system_;
    std::mutex mutex_;
    std::map<std::string, std::string> converted_;
    std::string folder_;
};

Textures& textures() {
    static Textures instance;
    return instance;
}

int openTexture(const char* path, int colorSpace, void** handle, PenumbraTextureInfo* info, char* error,
                size_t errorSize) {
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) return failWith(OIIO::geterror(), error, errorSize);
        const OIIO::ImageSpec spec = in->spec();
        in->close();
        const bool srgb = isSrgb(spec, colorSpace);
        std::string file, failure;
        if (!textures().fileFor(path, srgb, file, failure)) return failWith(failure, error, errorSize);
        OIIO::TextureSystem& system = textures().system();
        OIIO::TextureSystem::TextureHandle* h = system.get_texture_handle(OIIO::ustring(file));
        if (!h || !system.good(h)) return failWith(system.geterror(), error, errorSize);
        *handle = h;
        *info = PenumbraTextureInfo{spec.width, spec.height, spec.nchannels, srgb ? 1 : 0};
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

OIIO::TextureOpt::Wrap wrapOf(int wrap) {
    switch (wrap) {
        case PENUMBRA_WRAP_CLAMP: return OIIO::TextureOpt::WrapClamp;
        case PENUMBRA_WRAP_BLACK: return OIIO::TextureOpt::WrapBlack;
        case PENUMBRA_WRAP_MIRROR: return OIIO::TextureOpt::WrapMirror;
        default: return OIIO::TextureOpt::WrapPeriodic;
    }
}

void lookup(void* handle, int wrapS, int wrapT, int filter, float s, float t, float dsdx, float dtdx, float dsdy,
            float dtdy, int channels, float* result) {
    OIIO::TextureOpt options;
    options.swrap = wrapOf(wrapS);
    options.twrap = wrapOf(wrapT);
    switch (filter) {
        case PENUMBRA_FILTER_CLOSEST:
            options.mipmode = OIIO::TextureOpt::MipModeNoMIP;
            options.interpmode = OIIO::TextureOpt::InterpClosest;
            break;
        case PENUMBRA_FILTER_BILINEAR:
            options.mipmode = OIIO::TextureOpt::MipModeNoMIP;
            options.interpmode = OIIO::TextureOpt::InterpBilinear;
            break;
        case PENUMBRA_FILTER_TRILINEAR:
            options.mipmode = OIIO::TextureOpt::MipModeTrilinear;
            options.interpmode = OIIO::TextureOpt::InterpBilinear;
            break;
        default:
            options.mipmode = OIIO::TextureOpt::MipModeAniso;
            options.interpmode = OIIO::TextureOpt::InterpBilinear;
            break;
    }
    OIIO::TextureSystem& system = textures().system();
    if (!system.texture(static_cast<OIIO::TextureSystem::TextureHandle*>(handle), system.get_perthread_info(),
                        options, s, t, dsdx, dtdx, dsdy, dtdy, channels, result))
        std::fill(result, result + channels, 0.0f);
}

int readImageSize(const char* path, int* width, int* height, char* error, size_t errorSize) {
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) return failWith(OIIO::geterror(), error, errorSize);
        *width = in->spec().width;
        *height = in->spec().height;
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

int readLinearRgb(const char* path, float* rgb, char* error, size_t errorSize) {
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) return failWith(OIIO::geterror(), error, errorSize);
        const OIIO::ImageSpec spec = in->spec();
        in->close();
        OIIO::ImageBuf linear;
        std::string failure;
        if (!readLinear(path, isSrgb(spec, PENUMBRA_COLOR_AUTO), linear, failure))
            return failWith(failure, error, errorSize);
        const int n = linear.nchannels();
        std::vector<float> pixels(size_t(spec.width) * size_t(spec.height) * size_t(n));
        if (!linear.get_pixels(linear.roi(), OIIO::TypeDesc::FLOAT, pixels.data()))
            return failWith(linear.geterror(), error, errorSize);
        for (size_t p = 0; p < size_t(spec.width) * size_t(spec.height); ++p)
            for (int c = 0; c < 3; ++c) rgb[3 * p + c] = pixels[p * size_t(n) + size_t(n >= 3 ? c : 0)];
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

void statistics(int level, char* text, size_t textSize) {
    const std::string stats = textures().system().getstats(level, true);
    failWith(stats, text, textSize);
}

void counters(unsigned long long* lookups, unsigned long long* files, unsigned long long* bytesRead,
              unsigned long long* peakCacheBytes) {
    OIIO::TextureSystem& system = textures().system();
    long long queries = 0, read = 0, memory = 0;
    int unique = 0;
    system.getattribute("stat:texture_queries", OIIO::TypeDesc::INT64, &queries);
    system.getattribute("stat:unique_files", OIIO::TypeDesc::INT, &unique);
    system.getattribute("stat:bytes_read", OIIO::TypeDesc::INT64, &read);
    system.getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &memory);
    *lookups = (unsigned long long)queries;
    *files = (unsigned long long)unique;
    *bytesRead = (unsigned long long)read;
    *peakCacheBytes = (unsigned long long)memory;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) const PenumbraTexturePlugin* penumbra_texture_plugin() {
    static const PenumbraTexturePlugin plugin{kPenumbraTexturePluginVersion, openTexture, lookup, readImageSize,
                                              readLinearRgb, statistics, counters};
    return &plugin;
}
