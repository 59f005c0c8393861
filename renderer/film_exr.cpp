// The film's EXR (docs/exr-layout.md), written and read with OpenEXR directly: linking OpenEXR
// costs a process a few milliseconds at start-up, OpenImageIO about 0.4 s.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/ImfTestFile.h>

#include <algorithm>
#include <cstdint>
#include <thread>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.h"
#include "renderer/atomic_file.h"
#include "renderer/image_output.h"

namespace penumbra {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& message) {
    SourceLocation where;
    where.file = path.string();
    throw InputError(where, message);
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

Imath::Box2i boxOf(const PixelWindow& w) { return Imath::Box2i({w.x0, w.y0}, {w.x1 - 1, w.y1 - 1}); }
PixelWindow windowOf(const Imath::Box2i& b) { return PixelWindow{b.min.x, b.max.x + 1, b.min.y, b.max.y + 1}; }

// A frame buffer over interleaved pixels of `names.size()` channels of `type`, covering `box`.
template <class T>
Imf::FrameBuffer interleaved(Imf::PixelType type, T* pixels, const std::vector<std::string>& names,
                             const Imath::Box2i& box) {
    const size_t xStride = sizeof(T) * names.size();
    const size_t yStride = xStride * size_t(box.max.x - box.min.x + 1);
    Imf::FrameBuffer buffer;
    for (size_t c = 0; c < names.size(); ++c)
        buffer.insert(names[c], Imf::Slice::Make(type, pixels + c, box, xStride, yStride));
    return buffer;
}

// Attributes read as OpenImageIO read them before: a missing one (or one of another type) is the
// type's empty value, which the checks below then refuse where it matters.
std::string stringAttribute(const Imf::Header& header, const char* name) {
    const auto* a = header.findTypedAttribute<Imf::StringAttribute>(name);
    return a ? a->value() : std::string();
}
int intAttribute(const Imf::Header& header, const char* name) {
    const auto* a = header.findTypedAttribute<Imf::IntAttribute>(name);
    return a ? a->value() : 0;
}

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

const char* const kNotOurs = "is not a film written by penumbra (render or merge)";

FilmFile readFilm(const std::filesystem::path& path, Imf::MultiPartInputFile& file) {
    const Imf::Header& beauty = file.header(0);
    if (!beauty.findTypedAttribute<Imf::IntAttribute>("penumbra:film"))
        fail(path, fmt::format("{}: it has no penumbra:film attribute", kNotOurs));
    const int layout = intAttribute(beauty, "penumbra:film");
    if (layout != kFilmLayoutVersion)
        fail(path, fmt::format("film layout version {} is not supported (this penumbra reads version {})", layout,
                               kFilmLayoutVersion));

    const Imath::Box2i display = beauty.displayWindow();
    const int fullWidth = display.max.x - display.min.x + 1, fullHeight = display.max.y - display.min.y + 1;
    if (display.min.x != 0 || display.min.y != 0 || fullWidth <= 0 || fullHeight <= 0 ||
        stringAttribute(beauty, "penumbra:resolution") != fmt::format("{}x{}", fullWidth, fullHeight))
        fail(path, "the display window does not match penumbra:resolution");

    FilmFile result{Film(fullWidth, fullHeight), {}};
    RenderMetadata& m = result.metadata;
    m.samplesPerPixel = intAttribute(beauty, "penumbra:spp");
    m.sampler = stringAttribute(beauty, "penumbra:sampler");
    m.accelerator = stringAttribute(beauty, "penumbra:accel");
    m.sceneFile = stringAttribute(beauty, "penumbra:scene");
    m.sceneHash = stringAttribute(beauty, "penumbra:sceneHash");
    m.version = stringAttribute(beauty, "penumbra:version");
    if (const auto* time = beauty.findTypedAttribute<Imf::DoubleAttribute>("penumbra:renderTime"))
        m.renderSeconds = time->value();

    const std::string seed = stringAttribute(beauty, "penumbra:seed");
    bool ok = !seed.empty() && seed.find_first_not_of("0123456789") == std::string::npos;
    try {
        if (ok) m.seed = std::stoull(seed);
    } catch (const std::exception&) {
        ok = false;
    }
    if (!ok) fail(path, fmt::format("malformed penumbra:seed '{}'", seed));

    const std::string samples = stringAttribute(beauty, "penumbra:samples");
    const size_t colon = samples.find(':');
    ok = colon != std::string::npos;
    const int first = ok ? parseIntStrict(samples.substr(0, colon), ok) : 0;
    const int end = ok ? parseIntStrict(samples.substr(colon + 1), ok) : 0;
    if (!ok || first < 0 || end < first) fail(path, fmt::format("malformed penumbra:samples '{}'", samples));
    m.firstSample = uint32_t(first);
    m.endSample = uint32_t(end);

    const Imath::Box2i data = beauty.dataWindow();
    const PixelWindow window = windowOf(data);
    if (window.x0 < 0 || window.y0 < 0 || window.x1 > fullWidth || window.y1 > fullHeight ||
        stringAttribute(beauty, "penumbra:crop") != formatWindow(window))
        fail(path, "the data window does not match penumbra:crop");
    if (window != PixelWindow{0, fullWidth, 0, fullHeight}) m.crop = window;

    int sumsPart = -1;
    for (int p = 0; p < file.parts(); ++p)
        if (file.header(p).hasName() && file.header(p).name() == "sums") sumsPart = p;
    if (sumsPart < 0) fail(path, fmt::format("{}: it has no \"sums\" part", kNotOurs));
    const Imf::Header& sums = file.header(sumsPart);
    if (sums.dataWindow() != data) fail(path, "the \"sums\" part's data window differs from the beauty's");
    const std::vector<std::string>& names = sumChannels();
    for (const std::string& name : names) {
        const Imf::Channel* channel = sums.channels().findChannel(name);
        if (!channel) fail(path, fmt::format("the \"sums\" part has no channel '{}'", name));
        if (channel->type != Imf::UINT) fail(path, fmt::format("channel '{}' of the \"sums\" part is not UINT", name));
    }
    std::vector<uint32_t> words(size_t(window.width()) * window.height() * names.size());
    try {
        Imf::InputPart part(file, sumsPart);
        part.setFrameBuffer(interleaved(Imf::UINT, words.data(), names, data));
        part.readPixels(data.min.y, data.max.y);
    } catch (const std::exception& e) {
        fail(path, fmt::format("cannot read the \"sums\" part: {}", e.what()));
    }

    size_t i = 0;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x, ++i) {
            const uint32_t* px = words.data() + i * names.size();
            PixelSums& p = result.film.at(x, y);
            for (int s = 0; s < kSumCount; ++s) sumAt(p, s) = ExactSum::fromWords(px + 4 * s);
            p.sampleCount = px[4 * kSumCount];
        }
    return result;
}

// OpenEXR compresses and decompresses blocks of lines on its own global thread pool, which has no
// threads until it is given some (then a file's blocks are spread over them).
int exrThreads() {
    static const int threads = [] {
        const int n = int(std::max(1u, std::thread::hardware_concurrency()));
        Imf::setGlobalThreadCount(n);
        return n;
    }();
    return threads;
}

}  // namespace

void writeExr(const Film& film, const RenderMetadata& metadata, const std::filesystem::path& path) {
    const PixelWindow full{0, film.width(), 0, film.height()};
    const PixelWindow window = metadata.crop.value_or(full);
    if (window.x0 < 0 || window.y0 < 0 || window.x1 > film.width() || window.y1 > film.height() ||
        window.width() <= 0 || window.height() <= 0)
        fail(path, fmt::format("cannot write the EXR image: the crop window {} does not lie inside the {}x{} image",
                               formatWindow(window), film.width(), film.height()));
    const Imath::Box2i data = boxOf(window);

    // Part 0, "beauty": what viewers and compositors read; it carries the metadata.
    Imf::Header beauty(boxOf(full), data);
    beauty.compression() = Imf::ZIP_COMPRESSION;
    beauty.insert("Software", Imf::StringAttribute(penumbraSoftwareName()));
    beauty.insert("penumbra:film", Imf::IntAttribute(kFilmLayoutVersion));
    beauty.insert("penumbra:spp", Imf::IntAttribute(metadata.samplesPerPixel));
    // EXR has no 64-bit integer attribute; a decimal string keeps every seed exact.
    beauty.insert("penumbra:seed", Imf::StringAttribute(std::to_string(metadata.seed)));
    beauty.insert("penumbra:sampler", Imf::StringAttribute(metadata.sampler));
    beauty.insert("penumbra:accel", Imf::StringAttribute(metadata.accelerator));
    beauty.insert("penumbra:scene", Imf::StringAttribute(metadata.sceneFile));
    beauty.insert("penumbra:sceneHash", Imf::StringAttribute(metadata.sceneHash));
    beauty.insert("penumbra:renderTime", Imf::DoubleAttribute(metadata.renderSeconds));
    beauty.insert("penumbra:version", Imf::StringAttribute(metadata.version));
    beauty.insert("penumbra:resolution", Imf::StringAttribute(fmt::format("{}x{}", film.width(), film.height())));
    beauty.insert("penumbra:samples",
                  Imf::StringAttribute(fmt::format("{}:{}", metadata.firstSample, metadata.endSample)));
    beauty.insert("penumbra:crop", Imf::StringAttribute(formatWindow(window)));

    // Part 1, "sums": the film itself, losslessly, with the same windows and metadata.
    Imf::Header sums = beauty;
    sums.setName("sums");
    sums.setType(Imf::SCANLINEIMAGE);
    // Lossless at any level; level 1 deflates the low words of the sums, which are noise that
    // no level compresses much, markedly faster than the default level at the same size (within 1%).
    sums.zipCompressionLevel() = 1;
    beauty.setName("beauty");
    beauty.setType(Imf::SCANLINEIMAGE);

    const std::vector<std::string>& beautyNames = beautyChannels();
    const std::vector<std::string>& sumNames = sumChannels();
    for (const std::string& name : beautyNames) beauty.channels().insert(name, Imf::Channel(Imf::FLOAT));
    for (const std::string& name : sumNames) sums.channels().insert(name, Imf::Channel(Imf::UINT));

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

    writeFileAtomically(path, "EXR image", [&](const std::string& tmp, std::string& error) {
        try {
            const Imf::Header headers[2] = {beauty, sums};
            // Compressed on every core; the bytes do not depend on the thread count, since each
            // block of lines is compressed on its own.
            Imf::MultiPartOutputFile file(tmp.c_str(), headers, 2, false, exrThreads());
            Imf::OutputPart beautyPart(file, 0);
            beautyPart.setFrameBuffer(interleaved(Imf::FLOAT, beautyPixels.data(), beautyNames, data));
            beautyPart.writePixels(window.height());
            Imf::OutputPart sumsPart(file, 1);
            sumsPart.setFrameBuffer(interleaved(Imf::UINT, sumWords.data(), sumNames, data));
            sumsPart.writePixels(window.height());
            return true;
        } catch (const std::exception& e) {  // OpenEXR throws Iex exceptions
            error = e.what();
            return false;
        }
    });
}

bool isPenumbraFilm(const std::filesystem::path& path) {
    try {
        if (!Imf::isOpenExrFile(path.c_str())) return false;
        Imf::MultiPartInputFile file(path.c_str());
        return file.header(0).find("penumbra:film") != file.header(0).end();
    } catch (const std::exception&) {
        return false;
    }
}

FilmFile readFilmExr(const std::filesystem::path& path) {
    if (!std::filesystem::is_regular_file(path)) fail(path, "no such file");
    if (!Imf::isOpenExrFile(path.c_str())) fail(path, fmt::format("{}: it is not an OpenEXR file", kNotOurs));
    try {
        Imf::MultiPartInputFile file(path.c_str(), exrThreads());
        return readFilm(path, file);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {  // OpenEXR throws Iex exceptions
        fail(path, fmt::format("cannot read the image: {}", e.what()));
    }
}

}  // namespace penumbra
