// The film's EXR (docs/exr-layout.md), written and read with OpenEXR directly: linking OpenEXR
// costs a process far less at start-up than OpenImageIO (bench/README.md, "Speed tricks").
#include "film/film_exr.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/openexr.h>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/error.h"
#include "core/huge_page_allocator.h"
#include "core/input_file.h"
#include "core/input_limits.h"
#include "core/system_memory.h"
#include "film/adaptive_film.h"
#include "film/atomic_file.h"
#include "film/checked_file.h"
#include "film/film_checksum.h"
#include "film/version.h"

namespace penumbra {

namespace {

// The EXR layout (docs/exr-layout.md). Version 1: every sum as four words in part "sums".
// Version 2: high words that only repeat the sign are left out, and the words are
// spread over part "sums" (ZIP) and part "sums.noise" (RLE) by how they compress. Version 3
// (written): version 2 with the checksum penumbra:checksum in part "sums". Version 4 (written for
// adaptive renders): version 3 with penumbra:adaptive, whose pixels hold sample counts of their own.
constexpr int kFilmLayoutVersion = 4;
constexpr int kFirstLayoutWithChecksum = 3;
constexpr int kNonAdaptiveLayoutVersion = 3;
constexpr int kFirstAdaptiveLayout = 4;
const char* const kAdaptiveAttribute = "penumbra:adaptive";
const char* const kChecksumAttribute = "penumbra:checksum";
const char* const kSumsPart = "sums";
const char* const kNoisePart = "sums.noise";
// Present (as "beauty") only in files written with FilmContents::Beauty.
const char* const kContentsAttribute = "penumbra:contents";

const std::vector<std::string>& beautyChannels() {
    static const std::vector<std::string> names = {
        "R",   "G",   "B",   "A", "albedo.R",   "albedo.G",   "albedo.B",
        "N.X", "N.Y", "N.Z", "Z", "variance.R", "variance.G", "variance.B"};
    return names;
}

// The exact sums of PixelSums in a fixed order, each as UINT channels NAME.w0..w3 (the 128-bit
// integer of an ExactSum, least significant word first), then "spp".
constexpr int kSumCount = PixelSums::kSumCount;
const char* const kSumNames[kSumCount] = {
    "sum.R",        "sum.G",        "sum.B",   "sumsq.R", "sumsq.G", "sumsq.B", "sum.weight", "sum.albedo.R",
    "sum.albedo.G", "sum.albedo.B", "sum.N.X", "sum.N.Y", "sum.N.Z", "sum.Z",   "sum.hits"};

// Every word of every sum (channel 4 * sum + word), then "spp": the channels of layout version 1,
// and the order of the in-memory words of both versions.
constexpr int kSppChannel = 4 * kSumCount;
constexpr size_t kWordsPerPixel = 4 * kSumCount + 1;
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

// The word that sign-extends `word` (all zeros or all ones).
uint32_t signWord(uint32_t word) { return (word >> 31) ? ~0u : 0u; }

// How many low words hold the sum: the words above them repeat the sign of the highest one.
int wordsNeeded(const uint32_t words[4]) {
    int n = 4;
    while (n > 1 && words[n - 1] == signWord(words[n - 2])) --n;
    return n;
}

std::string formatWindow(const PixelWindow& w) { return fmt::format("{},{},{},{}", w.x0, w.x1, w.y0, w.y1); }

Imath::Box2i boxOf(const PixelWindow& w) { return Imath::Box2i({w.x0, w.y0}, {w.x1 - 1, w.y1 - 1}); }
PixelWindow windowOf(const Imath::Box2i& b) {
    return PixelWindow{b.min.x, b.max.x + 1, b.min.y, b.max.y + 1};
}

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

// Scanlines in one chunk of a part with this compression (OpenEXR's blocks of lines).
int linesPerChunk(Imf::Compression compression) {
    switch (compression) {
        case Imf::ZIP_COMPRESSION:
        case Imf::PXR24_COMPRESSION:
            return 16;
        case Imf::PIZ_COMPRESSION:
        case Imf::B44_COMPRESSION:
        case Imf::B44A_COMPRESSION:
        case Imf::DWAA_COMPRESSION:
            return 32;
        case Imf::DWAB_COMPRESSION:
            return 256;
        default:
            return 1;  // none, RLE, ZIPS
    }
}

// Every chunk of lines takes at least 20 bytes (its offset, part number, first line and size),
// so a file shorter than that for the rows its windows declare is truncated or lies about its
// size: refused before a film of that size is allocated.
void checkFileHoldsItsRows(const std::filesystem::path& path, Imf::MultiPartInputFile& file) {
    double minimumBytes = 0;
    for (int p = 0; p < file.parts(); ++p) {
        const Imf::Header& h = file.header(p);
        const double rows = double(h.dataWindow().max.y) - double(h.dataWindow().min.y) + 1;
        minimumBytes += std::ceil(rows / linesPerChunk(h.compression())) * 20;
    }
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec && double(size) < minimumBytes)
        throwFileError(
            path, fmt::format("the file is {} bytes, too small for the rows its windows declare (at least "
                              "{:.0f} bytes): it is truncated or its header is corrupt",
                              size, minimumBytes));
}

// OpenEXR 3.1's C++ reader allocates what a header attribute declares before reading it, and
// reads some attribute types by their contents rather than their declared size: a 4 KB file made it
// allocate and clear 1.8 GB. Its C core (OpenEXRCore) parses headers checking every declared size
// against the file's, so the headers are parsed by it first and a file it refuses is not handed on.
void checkHeadersWithOpenExrCore(const std::filesystem::path& path) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    std::string reason;
    init.user_data = &reason;
    init.error_handler_fn = [](exr_const_context_t context, exr_result_t code, const char* message) {
        void* user = nullptr;
        if (exr_get_user_data(context, &user) == EXR_ERR_SUCCESS && user &&
            static_cast<std::string*>(user)->empty())
            *static_cast<std::string*>(user) = message ? message : exr_get_error_code_as_string(code);
    };
    init.flags = EXR_CONTEXT_FLAG_STRICT_HEADER;  // otherwise it reports errors and goes on
    init.max_image_width = init.max_image_height = limits::kMaxImageSide;
    exr_context_t context = nullptr;
    const exr_result_t result = exr_start_read(&context, path.c_str(), &init);
    exr_finish(&context);
    if (result == EXR_ERR_SUCCESS) return;
    if (reason.empty()) reason = exr_get_error_code_as_string(result);
    for (char& c : reason)
        if (c < 0x20 || c > 0x7e) c = '?';  // names from a corrupt header are not printed raw
    throwFileError(path, "cannot read the image: " + reason);
}

// The attributes of the beauty part that say which samples the film holds, as the checksum covers
// them (docs/exr-layout.md); an adaptive film's penumbra:adaptive last.
std::string checksummedMetadata(const Imf::Header& beauty) {
    std::string text =
        fmt::format("{}|{}|{}|{}|{}|{}|{}|{}", stringAttribute(beauty, "penumbra:resolution"),
                    stringAttribute(beauty, "penumbra:crop"), stringAttribute(beauty, "penumbra:samples"),
                    intAttribute(beauty, "penumbra:spp"), stringAttribute(beauty, "penumbra:seed"),
                    stringAttribute(beauty, "penumbra:sampler"), stringAttribute(beauty, "penumbra:accel"),
                    stringAttribute(beauty, "penumbra:sceneHash"));
    if (intAttribute(beauty, "penumbra:film") >= kFirstAdaptiveLayout) {
        text += '|';  // appended in two steps: GCC 12 warns (-Wrestrict) of "|" + a temporary string
        text += stringAttribute(beauty, kAdaptiveAttribute);
    }
    return text;
}

// A sum at or beyond 2^126 units in magnitude is more than 2^32 samples can add (each adds less
// than 2^94 units): only a corrupt or crafted file holds one, and adding to it could overflow.
bool sumInRange(const ExactSum& sum) {
    uint32_t w[4];
    sum.toWords(w);
    const uint32_t top = w[3] >> 30;  // bits 127 and 126: equal (00 or 11) below 2^126
    return top == 0 || top == 3;
}

// The metadata and full size of the film in `file`, from its first header alone; `layout` is
// set to the film layout version.
FilmHeader readHeader(const std::filesystem::path& path, Imf::MultiPartInputFile& file, int& layout) {
    const Imf::Header& beauty = file.header(0);
    if (!beauty.findTypedAttribute<Imf::IntAttribute>("penumbra:film"))
        throwFileError(path, fmt::format("{}: it has no penumbra:film attribute", kNotOurs));
    layout = intAttribute(beauty, "penumbra:film");
    if (layout < 1 || layout > kFilmLayoutVersion)
        throwFileError(
            path,
            fmt::format("film layout version {} is not supported (this penumbra reads versions 1 to {})",
                        layout, kFilmLayoutVersion));

    if (beauty.find(kContentsAttribute) != beauty.end())
        throwFileError(
            path,
            "it holds the image and its AOVs only (written with --film beauty), not the film's sums: "
            "it cannot be resumed or merged (write films with --film full, the default)");

    const Imath::Box2i display = beauty.displayWindow();
    const int fullWidth = display.max.x - display.min.x + 1, fullHeight = display.max.y - display.min.y + 1;
    if (display.min.x != 0 || display.min.y != 0 || fullWidth <= 0 || fullHeight <= 0 ||
        stringAttribute(beauty, "penumbra:resolution") != fmt::format("{}x{}", fullWidth, fullHeight))
        throwFileError(path, "the display window does not match penumbra:resolution");

    if (fullWidth > limits::kMaxImageSide || fullHeight > limits::kMaxImageSide)
        throwFileError(path, fmt::format("the image is {}x{}; penumbra's limit is {} pixels a side",
                                         fullWidth, fullHeight, limits::kMaxImageSide));

    RenderMetadata m;
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
    if (!ok) throwFileError(path, fmt::format("malformed penumbra:seed '{}'", seed));

    const std::string samples = stringAttribute(beauty, "penumbra:samples");
    const size_t colon = samples.find(':');
    ok = colon != std::string::npos;
    const int first = ok ? parseIntStrict(samples.substr(0, colon), ok) : 0;
    const int end = ok ? parseIntStrict(samples.substr(colon + 1), ok) : 0;
    if (!ok || first < 0 || end < first)
        throwFileError(path, fmt::format("malformed penumbra:samples '{}'", samples));
    m.firstSample = uint32_t(first);
    m.endSample = uint32_t(end);

    const Imath::Box2i data = beauty.dataWindow();
    const PixelWindow window = windowOf(data);
    if (window.x0 < 0 || window.y0 < 0 || window.x1 > fullWidth || window.y1 > fullHeight ||
        stringAttribute(beauty, "penumbra:crop") != formatWindow(window))
        throwFileError(path, "the data window does not match penumbra:crop");
    if (window != PixelWindow{0, fullWidth, 0, fullHeight}) m.crop = window;
    if (layout >= kFirstAdaptiveLayout) {
        const std::string adaptive = stringAttribute(beauty, kAdaptiveAttribute);
        m.adaptive = parseAdaptiveAttribute(adaptive);
        if (!m.adaptive)
            throwFileError(
                path, fmt::format("malformed {} '{}' (expected [absolute:]THRESHOLD:MIN_SPP, 0 < THRESHOLD "
                                  "<= {:g} ({:g} absolute), MIN_SPP >= {})",
                                  kAdaptiveAttribute, adaptive, AdaptiveSettings::kMaxThreshold,
                                  AdaptiveSettings::kMaxAbsoluteThreshold, AdaptiveSettings::kMinMinSamples));
    }
    return FilmHeader{m, fullWidth, fullHeight};
}

FilmFile readFilm(const std::filesystem::path& path, Imf::MultiPartInputFile& file) {
    int layout = 0;
    const FilmHeader header = readHeader(path, file, layout);
    const RenderMetadata& m = header.metadata;
    const int fullWidth = header.width, fullHeight = header.height;
    const Imf::Header& beauty = file.header(0);
    const Imath::Box2i data = beauty.dataWindow();
    const PixelWindow window = windowOf(data);

    // The parts that hold sum words: "sums" (every version) and "sums.noise" (versions 2 and 3).
    std::vector<int> sumParts;
    for (int p = 0; p < file.parts(); ++p) {
        const Imf::Header& h = file.header(p);
        if (h.hasName() && (h.name() == kSumsPart || (layout >= 2 && h.name() == kNoisePart))) {
            if (h.dataWindow() != data)
                throwFileError(
                    path, fmt::format("the \"{}\" part's data window differs from the beauty's", h.name()));
            sumParts.push_back(p);
        }
    }
    if (std::none_of(sumParts.begin(), sumParts.end(),
                     [&](int p) { return file.header(p).name() == kSumsPart; }))
        throwFileError(path, fmt::format("{}: it has no \"sums\" part", kNotOurs));

    // Where each word is stored: a part, and its index among the channels read from that part.
    // Version 1 stores every word; versions 2 and 3 leave out those they can restore (see writeExr).
    const std::vector<std::string>& names = sumChannels();
    struct Source {
        int part = -1;
        size_t index = 0;
    };
    std::vector<Source> source(kWordsPerPixel);
    std::vector<std::vector<std::string>> namesOf(file.parts());
    for (int c = 0; c < int(kWordsPerPixel); ++c)
        for (int p : sumParts)
            if (const Imf::Channel* channel = file.header(p).channels().findChannel(names[c])) {
                if (channel->type != Imf::UINT)
                    throwFileError(path, fmt::format("channel '{}' of the \"{}\" part is not UINT", names[c],
                                                     file.header(p).name()));
                if (source[c].part < 0) {
                    source[c] = {p, namesOf[p].size()};
                    namesOf[p].push_back(names[c]);
                }
            }
    for (int c = 0; c < int(kWordsPerPixel); ++c)
        if (source[c].part < 0 && (layout == 1 || c == kSppChannel))
            throwFileError(path, fmt::format("the \"sums\" part has no channel '{}'", names[c]));

    // The sizes the headers declare, against the file and the memory, before they are allocated.
    checkFileHoldsItsRows(path, file);
    const size_t pixelCount = size_t(window.width()) * window.height();
    size_t wordsRead = 0;
    for (int p : sumParts) wordsRead += namesOf[p].size();
    requireMemory(
        double(fullWidth) * fullHeight * double(Film::bytesPerPixel() + Film::kOutputBytesPerPixel) +
            double(pixelCount) * double(wordsRead) * sizeof(uint32_t),
        fmt::format("{}: reading its {}x{} film", path.string(), fullWidth, fullHeight));
    FilmFile result{Film(fullWidth, fullHeight), m};

    std::vector<std::optional<HugePageBuffer<uint32_t>>> buffers(file.parts());
    for (int p : sumParts) {
        if (namesOf[p].empty()) continue;
        buffers[p].emplace(pixelCount * namesOf[p].size());
        try {
            Imf::InputPart part(file, p);
            part.setFrameBuffer(interleaved(Imf::UINT, buffers[p]->get(), namesOf[p], data));
            part.readPixels(data.min.y, data.max.y);
        } catch (const std::exception& e) {
            throwFileError(path,
                           fmt::format("cannot read the \"{}\" part: {}", file.header(p).name(), e.what()));
        }
    }
    auto word = [&](int c, size_t pixel) {
        const Source& from = source[c];
        return buffers[from.part]->get()[pixel * namesOf[from.part].size() + from.index];
    };
    int highest[kSumCount];  // per sum, its highest stored word (-1: none)
    for (int s = 0; s < kSumCount; ++s) {
        highest[s] = -1;
        for (int w = 0; w < 4; ++w)
            if (source[4 * s + w].part >= 0) highest[s] = w;
    }

    size_t i = 0;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x, ++i) {
            PixelSums p;
            for (int s = 0; s < kSumCount; ++s) {
                // A word left out is 0 below the highest stored one, and its sign extension above.
                uint32_t words[4] = {};
                for (int w = 0; w <= highest[s]; ++w)
                    if (source[4 * s + w].part >= 0) words[w] = word(4 * s + w, i);
                const uint32_t sign = highest[s] >= 0 ? signWord(words[highest[s]]) : 0u;
                for (int w = highest[s] + 1; w < 4; ++w) words[w] = sign;
                p.sum(s) = ExactSum::fromWords(words);
            }
            p.sampleCount = word(kSppChannel, i);
            for (int s = 0; s < kSumCount; ++s)
                if (!sumInRange(p.sum(s)))
                    throwFileError(path, fmt::format("pixel ({}, {}): {} is beyond what 2^32 samples can add "
                                                     "(2^78 in magnitude); the file is corrupt",
                                                     x, y, kSumNames[s]));
            result.film.set(x, y, p);
        }

    const Imf::Header& sumsHeader = file.header(*std::find_if(
        sumParts.begin(), sumParts.end(), [&](int p) { return file.header(p).name() == kSumsPart; }));
    const auto* stored = sumsHeader.findTypedAttribute<Imf::StringAttribute>(kChecksumAttribute);
    if (layout >= kFirstLayoutWithChecksum) {
        if (!stored)
            throwFileError(path,
                           fmt::format("the \"sums\" part has no {} attribute, which film layout {} requires",
                                       kChecksumAttribute, layout));
        const std::string computed =
            formatFilmChecksum(filmChecksum(result.film, window, checksummedMetadata(beauty)));
        if (stored->value() != computed)
            throwFileError(
                path, fmt::format("the film's sums or metadata do not match their checksum ({} stored, {} "
                                  "computed): the file is corrupt",
                                  stored->value(), computed));
    } else {
        // Films written before the checksum still read (a render resumed after an update keeps
        // its hours), but nothing shows that their sums are intact.
        std::fprintf(stderr,
                     "penumbra: warning: %s: film layout version %d has no checksum, so its sums cannot be "
                     "verified (written by an older penumbra)\n",
                     path.string().c_str(), layout);
    }
    return result;
}

// OpenEXR's output through a CheckedFile: its own std::ofstream would lose the last buffered bytes
// silently when the disk is full, at a flush in its destructor.
class CheckedExrStream : public Imf::OStream {
public:
    CheckedExrStream(CheckedFile& file, const std::string& name) : Imf::OStream(name.c_str()), file_(file) {}
    void write(const char c[], int n) override { file_.write(c, size_t(n)); }
    uint64_t tellp() override { return file_.tell(); }
    void seekp(uint64_t position) override { file_.seek(position); }

private:
    CheckedFile& file_;
};

// OpenEXR compresses and decompresses blocks of lines on its own global thread pool, which has no
// threads until it is given some (then a file's blocks are spread over them).
int exrThreads() {
    static const int threads = [] {
        const int n = int(std::max(1u, std::thread::hardware_concurrency()));
        Imf::setGlobalThreadCount(n);
        // OpenEXR itself allocates by the data window when it opens a file; a corrupt header must
        // not make it allocate more than our largest image would.
        Imf::Header::setMaxImageSize(limits::kMaxImageSide, limits::kMaxImageSide);
        return n;
    }();
    return threads;
}

}  // namespace

void writeExr(const Film& film, const RenderMetadata& metadata, const std::filesystem::path& path,
              FilmContents contents) {
    const PixelWindow full{0, film.width(), 0, film.height()};
    const PixelWindow window = metadata.crop.value_or(full);
    if (window.x0 < 0 || window.y0 < 0 || window.x1 > film.width() || window.y1 > film.height() ||
        window.width() <= 0 || window.height() <= 0)
        throwFileError(
            path,
            fmt::format("cannot write the EXR image: the crop window {} does not lie inside the {}x{} image",
                        formatWindow(window), film.width(), film.height()));
    const Imath::Box2i data = boxOf(window);

    // Part 0, "beauty": what viewers and compositors read; it carries the metadata.
    Imf::Header beauty(boxOf(full), data);
    beauty.insert("Software", Imf::StringAttribute(penumbraSoftwareName()));
    beauty.insert("penumbra:film",
                  Imf::IntAttribute(metadata.adaptive ? kFirstAdaptiveLayout : kNonAdaptiveLayoutVersion));
    if (metadata.adaptive)
        beauty.insert(kAdaptiveAttribute, Imf::StringAttribute(formatAdaptiveAttribute(*metadata.adaptive)));
    beauty.insert("penumbra:spp", Imf::IntAttribute(metadata.samplesPerPixel));
    // EXR has no 64-bit integer attribute; a decimal string keeps every seed exact.
    beauty.insert("penumbra:seed", Imf::StringAttribute(std::to_string(metadata.seed)));
    beauty.insert("penumbra:sampler", Imf::StringAttribute(metadata.sampler));
    beauty.insert("penumbra:accel", Imf::StringAttribute(metadata.accelerator));
    beauty.insert("penumbra:scene", Imf::StringAttribute(metadata.sceneFile));
    beauty.insert("penumbra:sceneHash", Imf::StringAttribute(metadata.sceneHash));
    beauty.insert("penumbra:renderTime", Imf::DoubleAttribute(metadata.renderSeconds));
    beauty.insert("penumbra:version", Imf::StringAttribute(metadata.version));
    beauty.insert("penumbra:resolution",
                  Imf::StringAttribute(fmt::format("{}x{}", film.width(), film.height())));
    beauty.insert("penumbra:samples",
                  Imf::StringAttribute(fmt::format("{}:{}", metadata.firstSample, metadata.endSample)));
    beauty.insert("penumbra:crop", Imf::StringAttribute(formatWindow(window)));
    beauty.setType(Imf::SCANLINEIMAGE);
    // The beauty and AOVs alone: marked, so that a resume or merge says why it cannot use the file
    // (the checksum and the sums parts below are left out).
    if (contents == FilmContents::Beauty) beauty.insert(kContentsAttribute, Imf::StringAttribute("beauty"));

    // Parts "sums" and "sums.noise": the film itself, losslessly, with the same windows and metadata.
    Imf::Header sums = beauty, noise = beauty;
    sums.setName(kSumsPart);
    sums.insert(
        kChecksumAttribute,
        Imf::StringAttribute(formatFilmChecksum(filmChecksum(film, window, checksummedMetadata(beauty)))));
    sums.compression() = Imf::ZIP_COMPRESSION;
    sums.zipCompressionLevel() = 1;
    noise.setName(kNoisePart);
    noise.compression() = Imf::RLE_COMPRESSION;
    beauty.setName("beauty");
    // RLE: on the beauty's noisy floats, deflate (ZIP, any level) takes about three times as long,
    // as long as all the rest of the write, for a file about a sixth smaller.
    beauty.compression() = Imf::RLE_COMPRESSION;

    const std::vector<std::string>& beautyNames = beautyChannels();
    for (const std::string& name : beautyNames) beauty.channels().insert(name, Imf::Channel(Imf::FLOAT));
    // An adaptive film's per-pixel sample counts also in the beauty part, where viewers look and
    // where `--film beauty` keeps them.
    if (metadata.adaptive) beauty.channels().insert(sumChannels()[kSppChannel], Imf::Channel(Imf::UINT));

    const int width = window.width(), height = window.height();
    const size_t pixelCount = size_t(width) * height;
    // Every element is written below, so the buffer is not zero-filled first; huge pages, since it
    // is as large as a fifth of the film, and faulting it in by 4 KiB pages costs more than filling it.
    HugePageBuffer<float> beautyPixels(pixelCount * beautyNames.size());

    // First pass, rows on every core: the beauty, and what decides which sum words are stored where.
    struct WordStats {
        int neededWords[kSumCount];  // per sum, the most low words a pixel needs (wordsNeeded)
        // Per word: the OR over the pixels (0: zero everywhere), how many pixels repeat their left
        // neighbour's nonzero value, and how many differ from it.
        uint32_t bits[kSppChannel];
        uint64_t repeats[kSppChannel], changes[kSppChannel];
    };
    std::vector<WordStats> rowStats(height);
    tbb::parallel_for(0, height, [&](int row) {
        WordStats& stats = rowStats[row];
        stats = {};
        std::fill(std::begin(stats.neededWords), std::end(stats.neededWords), 1);
        uint32_t words[2][kSppChannel];  // this pixel's and its left neighbour's
        float* out = beautyPixels.get() + size_t(row) * width * beautyNames.size();
        for (int x = 0; x < width; ++x) {
            const PixelSums& p = film.at(window.x0 + x, window.y0 + row);
            const Rgb mean = p.mean(), albedo = p.meanAlbedo(), variance = p.varianceOfMean();
            const Vec3f normal = p.meanNormal();
            const float values[] = {mean.r,     mean.g,    mean.b,        p.sampleCount > 0 ? 1.0f : 0.0f,
                                    albedo.r,   albedo.g,  albedo.b,      normal.x,
                                    normal.y,   normal.z,  p.meanDepth(), variance.r,
                                    variance.g, variance.b};
            out = std::copy(std::begin(values), std::end(values), out);
            uint32_t* w = words[x & 1];
            const uint32_t* left = words[(x & 1) ^ 1];
            for (int s = 0; s < kSumCount; ++s) {
                p.sum(s).toWords(w + 4 * s);
                stats.neededWords[s] = std::max(stats.neededWords[s], wordsNeeded(w + 4 * s));
            }
            for (int c = 0; c < kSppChannel; ++c) stats.bits[c] |= w[c];
            if (x == 0) continue;
            for (int c = 0; c < kSppChannel; ++c) {
                stats.repeats[c] += w[c] == left[c] && w[c] != 0;
                stats.changes[c] += w[c] != left[c];
            }
        }
    });
    WordStats total = {};
    std::fill(std::begin(total.neededWords), std::end(total.neededWords), 1);
    for (const WordStats& row : rowStats) {
        for (int s = 0; s < kSumCount; ++s)
            total.neededWords[s] = std::max(total.neededWords[s], row.neededWords[s]);
        for (int c = 0; c < kSppChannel; ++c) {
            total.bits[c] |= row.bits[c];
            total.repeats[c] += row.repeats[c];
            total.changes[c] += row.changes[c];
        }
    }

    // Stored: the low words each sum needs (the highest of them always, when it is above w0),
    // less those that are zero in every pixel; the reader restores the rest. A word that repeats
    // a nonzero value at least as often as it changes goes to "sums" (ZIP level 1: deflate codes
    // such runs nearly for free, while RLE, which sees the bytes of a word alternately, hardly
    // shrinks them); the others to "sums.noise" (RLE: deflate takes several times as long on
    // them, to save little). spp goes to "sums".
    std::vector<int> zipChannels{kSppChannel}, rleChannels;
    for (int s = 0; s < kSumCount; ++s)
        for (int w = 0; w < total.neededWords[s]; ++w) {
            const int c = 4 * s + w;
            if (total.bits[c] == 0 && !(w > 0 && w == total.neededWords[s] - 1)) continue;
            (total.repeats[c] >= total.changes[c] ? zipChannels : rleChannels).push_back(c);
        }
    for (int c : zipChannels) sums.channels().insert(sumChannels()[c], Imf::Channel(Imf::UINT));
    for (int c : rleChannels) noise.channels().insert(sumChannels()[c], Imf::Channel(Imf::UINT));

    // The low two words of each sum, and the sample counts, are read by OpenEXR in place, from the
    // film's own memory: copying them out first took a second pass over the film and buffers as
    // large as half of it. The high two words, where a sum needs them (rare: Film keeps them only
    // where a sum has outgrown 64 bits), are copied out.
    std::vector<int> highChannels;
    for (const std::vector<int>* stored : {&zipChannels, &rleChannels})
        for (int c : *stored)
            if (c != kSppChannel && c % 4 >= 2) highChannels.push_back(c);
    std::sort(highChannels.begin(), highChannels.end());
    std::optional<HugePageBuffer<uint32_t>> highWords;
    if (!highChannels.empty()) {
        highWords.emplace(pixelCount * highChannels.size());
        tbb::parallel_for(0, height, [&](int row) {
            uint32_t* out = highWords->get() + size_t(row) * width * highChannels.size();
            for (int x = 0; x < width; ++x) {
                const PixelSums p = film.at(window.x0 + x, window.y0 + row);
                for (int c : highChannels) {
                    uint32_t words[4];
                    p.sum(c / 4).toWords(words);
                    *out++ = words[c % 4];
                }
            }
        });
    }
    auto filmWord = [&](int c) {
        if (c != kSppChannel && c % 4 >= 2) {
            const size_t k =
                size_t(std::find(highChannels.begin(), highChannels.end(), c) - highChannels.begin());
            const size_t xStride = sizeof(uint32_t) * highChannels.size();
            return Imf::Slice::Make(Imf::UINT, highWords->get() + k, data, xStride, xStride * size_t(width));
        }
        const size_t xStride = c == kSppChannel ? Film::sampleCountStride() : Film::lowWordStride(c / 4);
        const size_t yStride = xStride * size_t(film.width());
        // The slices address pixels by absolute (x, y), from pixel (0, 0).
        const char* word = c == kSppChannel ? reinterpret_cast<const char*>(film.sampleCounts())
                                            : reinterpret_cast<const char*>(film.lowWords(c / 4)) +
                                                  ExactSum::wordOffset(c % 4);
        // OpenEXR takes a char* for reading and writing alike; writing a file only reads it.
        return Imf::Slice(Imf::UINT, const_cast<char*>(word), xStride, yStride);
    };
    auto filmWords = [&](const std::vector<int>& channels) {
        Imf::FrameBuffer buffer;
        for (int c : channels) buffer.insert(sumChannels()[c], filmWord(c));
        return buffer;
    };

    writeFileAtomically(path, "EXR image", [&](const std::string& tmp, std::string& error) {
        try {
            const Imf::Header headers[3] = {beauty, sums, noise};
            const int parts = contents == FilmContents::Beauty ? 1 : rleChannels.empty() ? 2 : 3;
            CheckedFile out(tmp);
            CheckedExrStream stream(out, tmp);
            {
                // Compressed on every core; the bytes do not depend on the thread count, since
                // each block of lines is compressed on its own.
                Imf::MultiPartOutputFile file(stream, headers, parts, false, exrThreads());
                Imf::OutputPart beautyPart(file, 0);
                Imf::FrameBuffer beautyBuffer =
                    interleaved(Imf::FLOAT, beautyPixels.get(), beautyNames, data);
                if (metadata.adaptive) beautyBuffer.insert(sumChannels()[kSppChannel], filmWord(kSppChannel));
                beautyPart.setFrameBuffer(beautyBuffer);
                beautyPart.writePixels(height);
                if (parts >= 2) {
                    Imf::OutputPart sumsPart(file, 1);
                    sumsPart.setFrameBuffer(filmWords(zipChannels));
                    sumsPart.writePixels(height);
                }
                if (parts == 3) {
                    Imf::OutputPart noisePart(file, 2);
                    noisePart.setFrameBuffer(filmWords(rleChannels));
                    noisePart.writePixels(height);
                }
            }  // the offset tables are written here, by the destructor
            out.close();
            return true;
        } catch (const std::exception& e) {  // OpenEXR throws Iex exceptions
            error = e.what();
            return false;
        }
    });
}

FilmHeader readFilmHeader(const std::filesystem::path& path) {
    InputFile(path, "film", UINT64_MAX);
    if (!Imf::isOpenExrFile(path.c_str()))
        throwFileError(path, fmt::format("{}: it is not an OpenEXR file", kNotOurs));
    try {
        Imf::MultiPartInputFile file(path.c_str(), exrThreads());
        int layout = 0;
        return readHeader(path, file, layout);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throwFileError(path, fmt::format("cannot read the image: {}", e.what()));
    }
}

bool isPenumbraFilm(const std::filesystem::path& path) {
    try {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) return false;  // opening a FIFO would block
        if (!Imf::isOpenExrFile(path.c_str())) return false;
        checkHeadersWithOpenExrCore(path);
        Imf::MultiPartInputFile file(path.c_str(), exrThreads());
        const Imf::Header& header = file.header(0);
        return header.find("penumbra:film") != header.end() &&
               header.find(kContentsAttribute) == header.end();
    } catch (const std::exception&) {
        return false;
    }
}

FilmFile readFilmExr(const std::filesystem::path& path) {
    InputFile(path, "film", UINT64_MAX);  // a regular file, or an error that says what it is
    if (!Imf::isOpenExrFile(path.c_str()))
        throwFileError(path, fmt::format("{}: it is not an OpenEXR file", kNotOurs));
    checkHeadersWithOpenExrCore(path);
    try {
        Imf::MultiPartInputFile file(path.c_str(), exrThreads());
        return readFilm(path, file);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {  // OpenEXR throws Iex exceptions
        throwFileError(path, fmt::format("cannot read the image: {}", e.what()));
    }
}

}  // namespace penumbra
