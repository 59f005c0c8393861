#include "renderer/image_output.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"

namespace OCIO = OCIO_NAMESPACE;

namespace penumbra {

namespace {

SourceLocation fileLocation(const std::string& file) {
    SourceLocation where;
    where.file = file;
    return where;
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& message) {
    throw InputError(fileLocation(path.string()), message);
}

// "<folder>/<stem>.tmp-<pid><ext>": same folder (so the rename is atomic, never across file
// systems) and same extension (OIIO picks the format from it).
std::filesystem::path temporaryPathFor(const std::filesystem::path& path) {
    std::filesystem::path tmp = path;
    tmp.replace_filename(fmt::format("{}.tmp-{}{}", path.stem().string(), long(::getpid()),
                                     path.extension().string()));
    return tmp;
}

// Writes a file to `path` through a temporary file that is renamed over `path` once complete:
// `write` opens the temporary file (named in its argument) and writes it, returning false with
// `error` set on failure. On failure the temporary file is removed and an InputError naming
// `path` is thrown.
void writeAtomicallyWith(const std::filesystem::path& path, const char* what,
                         const std::function<bool(OIIO::ImageOutput&, const std::string&, std::string&)>& write) {
    std::error_code ec;
    const std::filesystem::path parent = path.parent_path();
    if (!parent.empty()) {
        std::filesystem::create_directories(parent, ec);
        if (ec) fail(path, fmt::format("cannot create folder '{}' for the {}: {}", parent.string(), what, ec.message()));
    }

    const std::filesystem::path tmp = temporaryPathFor(path);
    auto cleanupAndFail = [&](const std::string& message) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        fail(path, fmt::format("cannot write the {}: {}", what, message));
    };

    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) cleanupAndFail(OIIO::geterror());
    std::string error;
    if (!write(*out, tmp.string(), error)) {
        out->close();
        out.reset();
        cleanupAndFail(error);
    }
    if (!out->close()) cleanupAndFail(out->geterror());
    out.reset();

    std::filesystem::rename(tmp, path, ec);
    if (ec) cleanupAndFail(fmt::format("cannot rename '{}' to the destination: {}", tmp.string(), ec.message()));
}

// Writes `spec`-shaped `pixels` (packed, of type `pixelType`) to `path` atomically.
void writeAtomically(const std::filesystem::path& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc pixelType,
                     const void* pixels, const char* what) {
    writeAtomicallyWith(path, what, [&](OIIO::ImageOutput& out, const std::string& tmp, std::string& error) {
        if (!out.open(tmp, spec) || !out.write_image(pixelType, pixels)) {
            error = out.geterror();
            return false;
        }
        return true;
    });
}

std::string softwareName() { return std::string("penumbra ") + PENUMBRA_VERSION; }

// The OCIO config: $OCIO when set and non-empty, otherwise the shipped one. CreateFromEnv rather
// than GetCurrentConfig, because GetCurrentConfig caches the first config it loads and would
// ignore later changes of $OCIO within the process.
OCIO::ConstConfigRcPtr loadOcioConfig() {
    const char* env = std::getenv("OCIO");
    const bool fromEnv = env != nullptr && *env != '\0';
    const std::string configPath = fromEnv ? env : PENUMBRA_OCIO_CONFIG;
    try {
        return fromEnv ? OCIO::Config::CreateFromEnv() : OCIO::Config::CreateFromFile(configPath.c_str());
    } catch (const OCIO::Exception& e) {
        throw InputError(fileLocation(configPath),
                         fmt::format("cannot load the OpenColorIO config{}: {}", fromEnv ? " named by $OCIO" : "",
                                     e.what()));
    }
}

std::string joinQuoted(int count, const std::function<const char*(int)>& name) {
    std::string out;
    for (int i = 0; i < count; ++i) out += fmt::format("{}'{}'", i ? ", " : "", name(i));
    return out.empty() ? "none" : out;
}

uint8_t quantize8(float v) {
    if (!(v > 0.0f)) return 0;  // also maps NaN to 0
    if (v >= 1.0f) return 255;
    return uint8_t(std::lround(v * 255.0f));
}

// The EXR layout (docs/exr-layout.md). Version 1: the first layout with a "sums" part.
constexpr int kFilmLayoutVersion = 1;

const std::vector<std::string>& beautyChannels() {
    static const std::vector<std::string> names = {"R", "G", "B", "A", "albedo.R", "albedo.G", "albedo.B",
                                                   "N.X", "N.Y", "N.Z", "Z", "variance.R", "variance.G",
                                                   "variance.B"};
    return names;
}

// The exact sums of PixelSums in a fixed order, each stored as four UINT channels NAME.w0..w3
// (the 128-bit integer of an ExactSum, least significant word first), then "spp".
constexpr int kSumCount = 15;
const char* const kSumNames[kSumCount] = {"sum.R", "sum.G", "sum.B", "sumsq.R", "sumsq.G", "sumsq.B",
                                          "sum.weight", "sum.albedo.R", "sum.albedo.G", "sum.albedo.B",
                                          "sum.N.X", "sum.N.Y", "sum.N.Z", "sum.Z", "sum.hits"};

ExactSum& sumAt(PixelSums& p, int i) {
    if (i < 3) return p.radiance[i];
    if (i < 6) return p.radianceSquared[i - 3];
    if (i == 6) return p.weight;
    if (i < 10) return p.albedo[i - 7];
    if (i < 13) return p.normal[i - 10];
    return i == 13 ? p.depth : p.hitWeight;
}
const ExactSum& sumAt(const PixelSums& p, int i) { return sumAt(const_cast<PixelSums&>(p), i); }

const std::vector<std::string>& sumChannels() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (const char* sum : kSumNames)
            for (int w = 0; w < 4; ++w) n.push_back(fmt::format("{}.w{}", sum, w));
        n.push_back("spp");
        return n;
    }();
    return names;
}

std::string formatWindow(const PixelWindow& w) { return fmt::format("{},{},{},{}", w.x0, w.x1, w.y0, w.y1); }

}  // namespace

std::string hashFileContents(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, "cannot read the file to hash it");
    uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a, 64 bits
    char buffer[1 << 16];
    while (in) {
        in.read(buffer, sizeof buffer);
        for (std::streamsize i = 0; i < in.gcount(); ++i) {
            hash ^= uint8_t(buffer[i]);
            hash *= 0x100000001b3ull;
        }
    }
    if (in.bad()) fail(path, "cannot read the file to hash it");
    return fmt::format("fnv1a64:{:016x}", hash);
}

void writeExr(const Film& film, const RenderMetadata& metadata, const std::filesystem::path& path) {
    const PixelWindow full{0, film.width(), 0, film.height()};
    const PixelWindow window = metadata.crop.value_or(full);
    if (window.x0 < 0 || window.y0 < 0 || window.x1 > film.width() || window.y1 > film.height() ||
        window.width() <= 0 || window.height() <= 0)
        fail(path, fmt::format("cannot write the EXR image: the crop window {} does not lie inside the {}x{} image",
                               formatWindow(window), film.width(), film.height()));

    // Part 0, "beauty": what viewers and compositors read; it carries the metadata.
    const std::vector<std::string>& beautyNames = beautyChannels();
    OIIO::ImageSpec beauty(window.width(), window.height(), int(beautyNames.size()), OIIO::TypeDesc::FLOAT);
    beauty.x = window.x0;
    beauty.y = window.y0;
    beauty.full_x = 0;
    beauty.full_y = 0;
    beauty.full_width = film.width();
    beauty.full_height = film.height();
    beauty.channelnames = beautyNames;
    beauty.alpha_channel = 3;
    beauty.z_channel = 10;
    beauty.attribute("oiio:subimagename", "beauty");
    beauty.attribute("compression", "zip");
    beauty.attribute("Software", softwareName());
    beauty.attribute("penumbra:film", kFilmLayoutVersion);
    beauty.attribute("penumbra:spp", metadata.samplesPerPixel);
    // EXR has no 64-bit integer attribute; a decimal string keeps every seed exact.
    beauty.attribute("penumbra:seed", std::to_string(metadata.seed));
    beauty.attribute("penumbra:sampler", metadata.sampler);
    beauty.attribute("penumbra:accel", metadata.accelerator);
    beauty.attribute("penumbra:scene", metadata.sceneFile);
    beauty.attribute("penumbra:sceneHash", metadata.sceneHash);
    beauty.attribute("penumbra:renderTime", OIIO::TypeDesc::DOUBLE, &metadata.renderSeconds);
    beauty.attribute("penumbra:version", metadata.version);
    beauty.attribute("penumbra:resolution", fmt::format("{}x{}", film.width(), film.height()));
    beauty.attribute("penumbra:samples", fmt::format("{}:{}", metadata.firstSample, metadata.endSample));
    beauty.attribute("penumbra:crop", formatWindow(window));

    // Part 1, "sums": the film itself, losslessly.
    const std::vector<std::string>& sumNames = sumChannels();
    OIIO::ImageSpec sums = beauty;
    sums.nchannels = int(sumNames.size());
    sums.channelnames = sumNames;
    sums.set_format(OIIO::TypeDesc::UINT32);
    sums.channelformats.clear();
    sums.alpha_channel = -1;
    sums.z_channel = -1;
    sums.attribute("oiio:subimagename", "sums");
    // Lossless at any level; level 1 deflates the low words of the sums, which are noise that
    // no level compresses much, markedly faster than the default level at the same size (within 1%).
    sums.attribute("compression", "zip:1");

    const size_t pixelCount = size_t(window.width()) * window.height();
    std::vector<float> beautyPixels(pixelCount * beautyNames.size());
    std::vector<uint32_t> sumWords(pixelCount * sumNames.size());
    size_t i = 0;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x, ++i) {
            const PixelSums& p = film.at(x, y);
            const Rgb mean = p.mean(), albedo = p.meanAlbedo(), variance = p.varianceOfMean();
            const Vec3f normal = p.meanNormal();
            const float values[] = {mean.r,   mean.g,   mean.b,   p.sampleCount > 0 ? 1.0f : 0.0f,
                                    albedo.r, albedo.g, albedo.b, normal.x,
                                    normal.y, normal.z, p.meanDepth(), variance.r,
                                    variance.g, variance.b};
            std::copy(std::begin(values), std::end(values), beautyPixels.begin() + i * beautyNames.size());
            uint32_t* words = sumWords.data() + i * sumNames.size();
            for (int s = 0; s < kSumCount; ++s) sumAt(p, s).toWords(words + 4 * s);
            words[4 * kSumCount] = p.sampleCount;
        }

    writeAtomicallyWith(path, "EXR image", [&](OIIO::ImageOutput& out, const std::string& tmp, std::string& error) {
        if (!out.supports("multiimage")) {
            error = "the EXR writer does not support multi-part files";
            return false;
        }
        const OIIO::ImageSpec specs[2] = {beauty, sums};
        if (!out.open(tmp, 2, specs) || !out.write_image(OIIO::TypeDesc::FLOAT, beautyPixels.data()) ||
            !out.open(tmp, sums, OIIO::ImageOutput::AppendSubimage) ||
            !out.write_image(OIIO::TypeDesc::UINT32, sumWords.data())) {
            error = out.geterror();
            return false;
        }
        return true;
    });
}

namespace {

int parseIntStrict(const std::string& text, bool& ok) {
    size_t used = 0;
    long long value = 0;
    try {
        value = std::stoll(text, &used);
    } catch (const std::exception&) {
        ok = false;
        return 0;
    }
    if (used != text.size() || value < INT32_MIN || value > INT32_MAX) ok = false;
    return int(value);
}

}  // namespace

FilmFile readFilmExr(const std::filesystem::path& path) {
    const std::string name = path.string();
    const char* notOurs = "is not a film written by penumbra (render or merge)";
    if (!std::filesystem::is_regular_file(path)) fail(path, "no such file");
    auto in = OIIO::ImageInput::open(name);
    if (!in) fail(path, fmt::format("cannot read the image: {}", OIIO::geterror()));
    if (std::string(in->format_name()) != "openexr") fail(path, fmt::format("{}: it is not an OpenEXR file", notOurs));

    const OIIO::ImageSpec beauty = in->spec(0, 0);
    if (!beauty.find_attribute("penumbra:film"))
        fail(path, fmt::format("{}: it has no penumbra:film attribute", notOurs));
    const int layout = beauty.get_int_attribute("penumbra:film");
    if (layout != kFilmLayoutVersion)
        fail(path, fmt::format("film layout version {} is not supported (this penumbra reads version {})", layout,
                               kFilmLayoutVersion));

    FilmFile result{Film(beauty.full_width, beauty.full_height), {}};
    RenderMetadata& m = result.metadata;
    m.samplesPerPixel = beauty.get_int_attribute("penumbra:spp");
    m.sampler = beauty.get_string_attribute("penumbra:sampler");
    m.accelerator = beauty.get_string_attribute("penumbra:accel");
    m.sceneFile = beauty.get_string_attribute("penumbra:scene");
    m.sceneHash = beauty.get_string_attribute("penumbra:sceneHash");
    m.version = beauty.get_string_attribute("penumbra:version");
    beauty.getattribute("penumbra:renderTime", OIIO::TypeDesc::DOUBLE, &m.renderSeconds);

    const std::string seed = beauty.get_string_attribute("penumbra:seed");
    bool ok = !seed.empty() && seed.find_first_not_of("0123456789") == std::string::npos;
    try {
        if (ok) m.seed = std::stoull(seed);
    } catch (const std::exception&) {
        ok = false;
    }
    if (!ok) fail(path, fmt::format("malformed penumbra:seed '{}'", seed));

    const std::string samples = beauty.get_string_attribute("penumbra:samples");
    const size_t colon = samples.find(':');
    ok = colon != std::string::npos;
    const int first = ok ? parseIntStrict(samples.substr(0, colon), ok) : 0;
    const int end = ok ? parseIntStrict(samples.substr(colon + 1), ok) : 0;
    if (!ok || first < 0 || end < first) fail(path, fmt::format("malformed penumbra:samples '{}'", samples));
    m.firstSample = uint32_t(first);
    m.endSample = uint32_t(end);

    if (beauty.full_x != 0 || beauty.full_y != 0 || beauty.full_width <= 0 || beauty.full_height <= 0 ||
        beauty.get_string_attribute("penumbra:resolution") !=
            fmt::format("{}x{}", beauty.full_width, beauty.full_height))
        fail(path, "the display window does not match penumbra:resolution");
    const PixelWindow window{beauty.x, beauty.x + beauty.width, beauty.y, beauty.y + beauty.height};
    if (window.x0 < 0 || window.y0 < 0 || window.x1 > beauty.full_width || window.y1 > beauty.full_height ||
        beauty.get_string_attribute("penumbra:crop") != formatWindow(window))
        fail(path, "the data window does not match penumbra:crop");
    if (window != PixelWindow{0, beauty.full_width, 0, beauty.full_height}) m.crop = window;

    if (!in->seek_subimage(1, 0)) fail(path, fmt::format("{}: it has no \"sums\" part", notOurs));
    const OIIO::ImageSpec sums = in->spec(1, 0);
    if (sums.x != beauty.x || sums.y != beauty.y || sums.width != beauty.width || sums.height != beauty.height)
        fail(path, "the \"sums\" part's data window differs from the beauty's");
    const std::vector<std::string>& names = sumChannels();
    std::vector<int> channelOf(names.size());
    for (size_t c = 0; c < names.size(); ++c) {
        channelOf[c] = sums.channelindex(names[c]);
        if (channelOf[c] < 0) fail(path, fmt::format("the \"sums\" part has no channel '{}'", names[c]));
        if (sums.channelformat(channelOf[c]) != OIIO::TypeDesc::UINT32)
            fail(path, fmt::format("channel '{}' of the \"sums\" part is not UINT", names[c]));
    }
    std::vector<uint32_t> words(size_t(sums.width) * sums.height * sums.nchannels);
    if (!in->read_image(1, 0, 0, sums.nchannels, OIIO::TypeDesc::UINT32, words.data()))
        fail(path, fmt::format("cannot read the \"sums\" part: {}", in->geterror()));

    size_t i = 0;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x, ++i) {
            const uint32_t* px = words.data() + i * sums.nchannels;
            PixelSums& p = result.film.at(x, y);
            for (int s = 0; s < kSumCount; ++s) {
                const uint32_t w[4] = {px[channelOf[4 * s]], px[channelOf[4 * s + 1]], px[channelOf[4 * s + 2]],
                                       px[channelOf[4 * s + 3]]};
                sumAt(p, s) = ExactSum::fromWords(w);
            }
            p.sampleCount = px[channelOf[4 * kSumCount]];
        }
    return result;
}

void writeDisplayImage(const Film& film, const std::filesystem::path& path, const std::string& display,
                       const std::string& view) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    if (extension != ".png" && extension != ".jpg" && extension != ".jpeg")
        fail(path, fmt::format("unsupported display image format '{}' (expected .png, .jpg or .jpeg)", extension));

    const OCIO::ConstConfigRcPtr config = loadOcioConfig();

    const std::string displayName = display.empty() ? config->getDefaultDisplay() : display;
    bool displayKnown = false;
    for (int i = 0; i < config->getNumDisplays(); ++i) displayKnown |= displayName == config->getDisplay(i);
    if (!displayKnown)
        throw InputError(fmt::format("unknown OpenColorIO display '{}'; available displays: {}", displayName,
                                     joinQuoted(config->getNumDisplays(), [&](int i) { return config->getDisplay(i); })));

    const std::string viewName = view.empty() ? config->getDefaultView(displayName.c_str()) : view;
    bool viewKnown = false;
    const int numViews = config->getNumViews(displayName.c_str());
    for (int i = 0; i < numViews; ++i) viewKnown |= viewName == config->getView(displayName.c_str(), i);
    if (!viewKnown)
        throw InputError(fmt::format("unknown OpenColorIO view '{}' of display '{}'; available views: {}", viewName,
                                     displayName,
                                     joinQuoted(numViews, [&](int i) { return config->getView(displayName.c_str(), i); })));

    std::vector<float> rgb = film.meanRgb();
    try {
        const auto processor = config->getProcessor(OCIO::ROLE_SCENE_LINEAR, displayName.c_str(), viewName.c_str(),
                                                    OCIO::TRANSFORM_DIR_FORWARD);
        if (!rgb.empty()) {
            OCIO::PackedImageDesc image(rgb.data(), film.width(), film.height(), 3);
            processor->getDefaultCPUProcessor()->apply(image);
        }
    } catch (const OCIO::Exception& e) {
        fail(path, fmt::format("OpenColorIO cannot convert scene_linear to display '{}', view '{}': {}", displayName,
                               viewName, e.what()));
    }

    std::vector<uint8_t> pixels(rgb.size());
    std::transform(rgb.begin(), rgb.end(), pixels.begin(), quantize8);

    OIIO::ImageSpec spec(film.width(), film.height(), 3, OIIO::TypeDesc::UINT8);
    spec.attribute("Software", softwareName());
    if (extension != ".png") spec.attribute("Compression", "jpeg:95");
    writeAtomically(path, spec, OIIO::TypeDesc::UINT8, pixels.data(), "display image");
}

}  // namespace penumbra
