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
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "core/input_limits.h"
#include "textures/exr_header_check.h"

namespace {

// OpenImageIO's messages, one a line, joined with "; ".
void copyText(const std::string& text, char* to, size_t size) {
    if (size == 0) return;
    std::string joined;
    for (char c : text) {
        if (c == '\n')
            joined += "; ";
        else  // bytes of a corrupt file are not printed raw
            joined += ((unsigned char)c < 0x20 || c == 0x7f) ? '?' : c;
    }
    while (joined.ends_with("; ")) joined.resize(joined.size() - 2);
    const size_t n = std::min(joined.size(), size - 1);
    std::memcpy(to, joined.data(), n);
    to[n] = '\0';
}

int failWith(const std::string& message, char* error, size_t errorSize) {
    copyText(message, error, errorSize);
    return 0;
}

// The format of an image by its first bytes (its magic number), of the formats penumbra reads:
// OpenEXR, PNG, JPEG, TIFF (and .tx), Radiance HDR, PFM and Truevision TGA (the last two for the
// scenes of pbrt-v4 and Tungsten, which use them), as OpenImageIO names them; null for any other.
// OpenImageIO has readers for some 30 formats and tries each on a file its name does not match;
// the others are less hardened (its BMP reader crashed on an 822-byte file, its WebP reader decoded
// 24 bytes as 7897 x 14457 texels; found by fuzzing), so no file reaches them.
const char* formatByContents(const char* path) {
    unsigned char magic[18] = {};
    std::FILE* file = std::fopen(path, "rb");
    if (!file) return nullptr;
    const size_t n = std::fread(magic, 1, sizeof magic, file);
    std::fclose(file);
    const auto starts = [&](const char* bytes, size_t size) {
        return n >= size && std::memcmp(magic, bytes, size) == 0;
    };
    if (starts("\x76\x2f\x31\x01", 4)) return "openexr";
    if (starts("\x89PNG\r\n\x1a\n", 8)) return "png";
    if (starts("\xff\xd8\xff", 3)) return "jpeg";
    if (starts("II*\0", 4) || starts("MM\0*", 4) || starts("II+\0", 4) || starts("MM\0+", 4)) return "tiff";
    if (starts("#?RADIANCE", 10) || starts("#?RGBE", 6)) return "hdr";
    // Portable float map: "PF" (colour) or "Pf" (grey), then a line break.
    if ((starts("PF", 2) || starts("Pf", 2)) && n >= 3 && (magic[2] == '\n' || magic[2] == '\r'))
        return "pnm";
    // TGA has no magic number: a file named .tga whose 18-byte header holds a colour-map type, an
    // image type and a pixel depth that TGA defines.
    const std::string_view name(path);
    const bool namedTga = name.size() >= 4 &&
                          (name.substr(name.size() - 4) == ".tga" || name.substr(name.size() - 4) == ".TGA");
    const auto isOneOf = [](unsigned char value, std::initializer_list<unsigned char> values) {
        return std::find(values.begin(), values.end(), value) != values.end();
    };
    if (namedTga && n == 18 && magic[1] <= 1 && isOneOf(magic[2], {1, 2, 3, 9, 10, 11}) &&
        isOneOf(magic[16], {8, 15, 16, 24, 32}))
        return "targa";
    return nullptr;
}

// What is wrong with the size an image declares, from its header only (nothing of its pixels is
// read or allocated yet): every MIP level of the first subimage (the one looked up) within
// `maxTexels`, its tiles too, within the limits on channels and values, a flat 2D image. An OpenEXR
// file's headers are parsed by OpenEXR's C core before OpenImageIO opens it (exr_header_check.h).
std::string declaredSizeProblem(const char* path, int64_t maxTexels) {
    const char* format = formatByContents(path);
    if (!format)
        return "not an image in one of the formats penumbra reads (OpenEXR, PNG, JPEG, TIFF, Radiance HDR, "
               "PFM, TGA), "
               "by its "
               "first bytes";
    if (penumbra::startsLikeExr(path)) {
        const std::string problem = penumbra::exrHeaderProblem(path, maxTexels);
        if (!problem.empty()) return problem;
    }
    auto in = OIIO::ImageInput::open(path);
    if (!in) return OIIO::geterror();
    if (in->format_name() != std::string_view(format))
        return std::string("its first bytes are of ") + format + ", yet OpenImageIO read it as " +
               in->format_name();
    constexpr int kMaxLevels = 32;  // a 65536-texel side has 17
    for (int level = 0; level < kMaxLevels && in->seek_subimage(0, level); ++level) {
        const OIIO::ImageSpec& spec = in->spec();
        const std::string where = level == 0 ? "" : " (MIP level " + std::to_string(level) + ")";
        if (spec.deep) return "deep data is not read as an image";
        if (spec.depth > 1)
            return "a volume of depth " + std::to_string(spec.depth) + " is not read as an image";
        if (spec.width <= 0 || spec.height <= 0) return "an empty image" + where;
        // OpenImageIO reads (and converts) 256 rows at a time whatever the height: a 4-row BMP
        // 7 million texels wide made it allocate 5.4 GB (found by fuzzing).
        if (spec.width > penumbra::limits::kMaxImageSide || spec.height > penumbra::limits::kMaxImageSide)
            return std::to_string(spec.width) + " x " + std::to_string(spec.height) + " texels" + where +
                   "; at most " + std::to_string(penumbra::limits::kMaxImageSide) + " a side are read";
        const int64_t texels = int64_t(spec.width) * int64_t(spec.height);
        if (texels > maxTexels)
            return std::to_string(spec.width) + " x " + std::to_string(spec.height) + " texels" + where +
                   "; at most " + std::to_string(maxTexels) + " are read";
        // The TextureSystem spans texture coordinates, and builds MIP levels, over the display
        // window: an 8 x 4 EXR whose display window was 889 million texels wide took 22 GB and
        // 2.5 minutes (found by fuzzing). It is held to the same limits.
        if (spec.full_width > penumbra::limits::kMaxImageSide ||
            spec.full_height > penumbra::limits::kMaxImageSide ||
            int64_t(spec.full_width) * int64_t(spec.full_height) > maxTexels)
            return "a display window of " + std::to_string(spec.full_width) + " x " +
                   std::to_string(spec.full_height) + " texels" + where + "; at most " +
                   std::to_string(maxTexels) + " texels and " +
                   std::to_string(penumbra::limits::kMaxImageSide) + " a side are read";
        if (int64_t(spec.tile_width) * int64_t(spec.tile_height) * int64_t(std::max(spec.tile_depth, 1)) >
            maxTexels)
            return "tiles of " + std::to_string(spec.tile_width) + " x " + std::to_string(spec.tile_height) +
                   " texels" + where + "; at most " + std::to_string(maxTexels) + " are read";
        const int64_t maxValues = penumbra::limits::kMaxValuesPerTexel * maxTexels;
        if (spec.nchannels < 1 || spec.nchannels > penumbra::limits::kMaxImageChannels ||
            texels * spec.nchannels > maxValues)
            return std::to_string(spec.nchannels) + " channels of " + std::to_string(spec.width) + " x " +
                   std::to_string(spec.height) + " texels" + where + "; at most " +
                   std::to_string(maxValues) + " values (texels x channels) are read";
    }
    return "";
}

// Integer formats hold display-encoded values (PNG, JPEG, 8-bit TIFF); float formats linear ones.
bool isSrgb(const OIIO::ImageSpec& spec, int colorSpace) {
    if (colorSpace != PENUMBRA_COLOR_AUTO) return colorSpace == PENUMBRA_COLOR_SRGB;
    if (spec.format.is_floating_point()) return false;
    const std::string declared = spec.get_string_attribute("oiio:ColorSpace");
    return !OIIO::Strutil::iequals(declared, "linear") && !OIIO::Strutil::iequals(declared, "scene_linear");
}

// The file's pixels linearised (sRGB-encoded ones decoded with OpenImageIO's built-in sRGB ->
// linear conversion) into half floats, the precision the linearised texture keeps: one copy of
// the image in the file's own format, converted texel by texel into the other.
// Read with an ImageInput of its own, not ImageBuf(path): that keeps the file's header in
// OpenImageIO's shared ImageCache, and a file rewritten under the same name was then read into a
// buffer of the old size (a heap overflow; found by fuzzing).
bool readLinearised(const char* path, OIIO::ImageBuf& result, std::string& failure) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        failure = OIIO::geterror();
        return false;
    }
    OIIO::ImageSpec spec = in->spec();
    spec.channelformats.clear();  // one format for every channel, as read_image converts them
    OIIO::ImageBuf source(spec);
    if (!in->read_image(0, 0, 0, spec.nchannels, spec.format, source.localpixels())) {
        failure = in->geterror();
        return false;
    }
    spec.set_format(OIIO::TypeDesc::HALF);
    result.reset(spec);
    // Alpha, when there is one, stays linear (colorconvert's unpremult = false, alpha untouched).
    if (!OIIO::ImageBufAlgo::colorconvert(result, source, "sRGB", "linear", false)) {
        failure = result.geterror();
        return false;
    }
    return true;
}

// Removes this user's "penumbra-textures-<pid>-XXXXXX" folders in `temporary` that a killed process left
// (its destructor never ran): those whose process is gone and that were not modified in the last
// minute (the temporary folder may be shared with another machine, whose process numbers mean
// nothing here).
void removeFoldersOfKilledProcesses(const std::filesystem::path& temporary) {
    const std::string prefix = "penumbra-textures-";
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(temporary, ec)) {
        const std::string name = entry.path().filename().string();
        // This user's own folders only, never one reached through a link.
        struct stat info;
        if (!name.starts_with(prefix) || ::lstat(entry.path().c_str(), &info) != 0 ||
            !S_ISDIR(info.st_mode) || info.st_uid != ::geteuid())
            continue;
        const size_t end = name.find('-', prefix.size());
        const std::string digits =
            name.substr(prefix.size(), end == std::string::npos ? 0 : end - prefix.size());
        if (digits.empty() || digits.size() > 9 ||
            digits.find_first_not_of("0123456789") != std::string::npos)
            continue;
        const pid_t pid = pid_t(std::stol(digits));
        if (pid == ::getpid() || ::kill(pid, 0) == 0 || errno == EPERM) continue;
        std::error_code ignored;
        const auto modified = std::filesystem::last_write_time(entry.path(), ignored);
        if (ignored || std::filesystem::file_time_type::clock::now() - modified < std::chrono::minutes(1))
            continue;
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
        system_->attribute("automip", 1);  // plain images get MIP levels built in memory
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
        if (!readLinearised(path, linear, failure)) return false;
        if (folder_.empty()) {
            const std::filesystem::path temporary = std::filesystem::temp_directory_path();
            removeFoldersOfKilledProcesses(temporary);
            std::string pattern =
                (temporary / ("penumbra-textures-" + std::to_string(::getpid()) + "-XXXXXX")).string();
            if (!::mkdtemp(pattern.data())) {
                failure = std::string("cannot create a temporary folder for converted textures: ") +
                          std::strerror(errno);
                return false;
            }
            folder_ = pattern;
        }
        // One name per source file, kept when it is forgotten: a file rewritten and opened again
        // reuses its name, so the TextureSystem's table of files does not grow.
        const size_t index = conversionNames_.emplace(path, conversionNames_.size()).first->second;
        file = folder_ + "/" + std::to_string(index) + ".exr";
        // Half floats keep 11 significant bits, more than the 8 of the source. Tiled, so that the
        // TextureSystem reads it tile by tile; its MIP levels are built on demand from the tiles of
        // the level above ("automip"), as for any image without them. make_texture, which writes
        // them at once, took 1.8 GB beside the 8192 x 8192 RGBA image it was given.
        linear.set_write_format(OIIO::TypeDesc::HALF);
        linear.set_write_tiles(64, 64);
        if (!linear.write(file)) {
            failure = "cannot write the linearised texture: " + linear.geterror();
            return false;
        }
        converted_.emplace(path, file);
        return true;
    }

    // The file a handle was opened from, for the message of a failed lookup.
    void name(void* handle, const char* path) {
        std::lock_guard lock(mutex_);
        names_[handle] = path;
    }
    void recordFailure(void* handle, const std::string& message) {
        if (failures_++ > 0) return;  // the first is the one reported
        std::lock_guard lock(mutex_);
        const auto found = names_.find(handle);
        firstFailure_ = (found != names_.end() ? found->second : std::string("an image texture")) + ": " +
                        (message.empty() ? "a lookup failed" : message);
    }
    unsigned long long takeFailures(std::string& first) {
        std::lock_guard lock(mutex_);
        first = firstFailure_;
        firstFailure_.clear();
        return failures_.exchange(0);
    }

    void forget(const char* path) {
        std::lock_guard lock(mutex_);
        const auto found = converted_.find(path);
        if (found != converted_.end()) {
            system_->invalidate(OIIO::ustring(found->second), true);
            std::error_code ec;
            std::filesystem::remove(found->second, ec);
            converted_.erase(found);
        }
        system_->invalidate(OIIO::ustring(path), true);
    }

private:
    OIIO::TextureSystem* system_;
    std::mutex mutex_;
    std::map<std::string, std::string> converted_;
    std::map<std::string, size_t> conversionNames_;
    std::string folder_;
    std::map<void*, std::string> names_;
    std::atomic<unsigned long long> failures_{0};
    std::string firstFailure_;
};

Textures& textures() {
    static Textures instance;
    return instance;
}

int openTexture(const char* path, int colorSpace, void** handle, PenumbraTextureInfo* info, char* error,
                size_t errorSize) {
    try {
        const std::string problem = declaredSizeProblem(path, penumbra::limits::kMaxTextureTexels);
        if (!problem.empty()) return failWith(problem, error, errorSize);
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
        textures().name(h, path);
        *handle = h;
        *info = PenumbraTextureInfo{spec.width, spec.height, spec.nchannels, srgb ? 1 : 0};
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

OIIO::TextureOpt::Wrap wrapOf(int wrap) {
    switch (wrap) {
        case PENUMBRA_WRAP_CLAMP:
            return OIIO::TextureOpt::WrapClamp;
        case PENUMBRA_WRAP_BLACK:
            return OIIO::TextureOpt::WrapBlack;
        case PENUMBRA_WRAP_MIRROR:
            return OIIO::TextureOpt::WrapMirror;
        default:
            return OIIO::TextureOpt::WrapPeriodic;
    }
}

void lookup(void* handle, int wrapS, int wrapT, int filter, float s, float t, float dsdx, float dtdx,
            float dsdy, float dtdy, int channels, float* result) {
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
                        options, s, t, dsdx, dtdx, dsdy, dtdy, channels, result)) {
        std::fill(result, result + channels, 0.0f);
        textures().recordFailure(handle, system.geterror());
    }
}

int probeImage(const char* path, long long maxTexels, int* width, int* height, char* error,
               size_t errorSize) {
    try {
        const std::string problem = declaredSizeProblem(path, maxTexels);
        if (!problem.empty()) return failWith(problem, error, errorSize);
        auto in = OIIO::ImageInput::open(path);
        if (!in) return failWith(OIIO::geterror(), error, errorSize);
        *width = in->spec().width;
        *height = in->spec().height;
        return 1;
    } catch (const std::exception& e) {
        return failWith(e.what(), error, errorSize);
    }
}

int readLinearRgb(const char* path, int width, int height,
                  void (*strip)(void* user, const float* rgb, int rows), void* user, char* error,
                  size_t errorSize) {
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) return failWith(OIIO::geterror(), error, errorSize);
        const OIIO::ImageSpec spec = in->spec();
        if (spec.width != width || spec.height != height || spec.nchannels < 1 ||
            spec.nchannels > penumbra::limits::kMaxImageChannels ||
            int64_t(width) * height * spec.nchannels >
                penumbra::limits::kMaxValuesPerTexel * penumbra::limits::kMaxImageTexels)
            return failWith("the file changed while it was read", error, errorSize);
        const bool srgb = isSrgb(spec, PENUMBRA_COLOR_AUTO);
        const int n = spec.nchannels;
        // A strip of rows at a time: beyond the result, memory for one strip (and what the
        // format's reader keeps). A tiled image by rows of tiles: OpenImageIO 2.4's read_scanlines
        // divides by zero on a tiled TIFF (SIGFPE; found by fuzzing).
        const bool tiled = spec.tile_width > 0 && spec.tile_height > 0;
        const int stripRows = std::min(tiled ? spec.tile_height : 64, height);
        std::vector<float> values(size_t(width) * size_t(stripRows) * size_t(n));
        std::vector<float> rgb(size_t(width) * size_t(stripRows) * 3);
        for (int y = 0; y < height; y += stripRows) {
            const int rows = std::min(stripRows, height - y);
            const int top = spec.y + y;
            const bool read = tiled ? in->read_tiles(0, 0, spec.x, spec.x + width, top, top + rows, spec.z,
                                                     spec.z + 1, 0, n, OIIO::TypeDesc::FLOAT, values.data())
                                    : in->read_scanlines(0, 0, top, top + rows, spec.z, 0, n,
                                                         OIIO::TypeDesc::FLOAT, values.data());
            if (!read) return failWith(in->geterror(), error, errorSize);
            if (srgb) {
                // Alpha, when there is one, stays linear (as openTexture() converts).
                OIIO::ImageBuf view(OIIO::ImageSpec(width, rows, n, OIIO::TypeDesc::FLOAT), values.data());
                if (!OIIO::ImageBufAlgo::colorconvert(view, view, "sRGB", "linear", false))
                    return failWith(view.geterror(), error, errorSize);
            }
            for (size_t p = 0; p < size_t(width) * size_t(rows); ++p)
                for (int c = 0; c < 3; ++c)
                    rgb[3 * p + size_t(c)] = values[p * size_t(n) + size_t(n >= 3 ? c : 0)];
            strip(user, rgb.data(), rows);
        }
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

unsigned long long takeLookupFailures(char* first, size_t firstSize) {
    std::string text;
    const unsigned long long count = textures().takeFailures(text);
    copyText(text, first, firstSize);
    return count;
}

void forget(const char* path) { textures().forget(path); }

}  // namespace

extern "C" __attribute__((visibility("default"))) const PenumbraTexturePlugin* penumbra_texture_plugin() {
    static const PenumbraTexturePlugin plugin{kPenumbraTexturePluginVersion,
                                              openTexture,
                                              lookup,
                                              probeImage,
                                              readLinearRgb,
                                              statistics,
                                              counters,
                                              takeLookupFailures,
                                              forget};
    return &plugin;
}
