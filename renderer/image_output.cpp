#include "renderer/image_output.h"

#include <OpenColorIO/OpenColorIO.h>
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
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

// Writes `spec`-shaped `pixels` (packed, of type `pixelType`) to `path` through a temporary file
// that is renamed over `path` once complete. On failure the temporary file is removed and an
// InputError naming `path` is thrown.
void writeAtomically(const std::filesystem::path& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc pixelType,
                     const void* pixels, const char* what) {
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
    if (!out->open(tmp.string(), spec)) cleanupAndFail(out->geterror());
    if (!out->write_image(pixelType, pixels)) {
        const std::string message = out->geterror();
        out->close();
        cleanupAndFail(message);
    }
    if (!out->close()) cleanupAndFail(out->geterror());
    out.reset();

    std::filesystem::rename(tmp, path, ec);
    if (ec) cleanupAndFail(fmt::format("cannot rename '{}' to the destination: {}", tmp.string(), ec.message()));
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

}  // namespace

void writeExr(const Film& film, const RenderMetadata& metadata, const std::filesystem::path& path) {
    OIIO::ImageSpec spec(film.width(), film.height(), 3, OIIO::TypeDesc::HALF);
    spec.channelnames = {"R", "G", "B"};
    spec.attribute("compression", "zip");
    spec.attribute("Software", softwareName());
    spec.attribute("penumbra:spp", metadata.samplesPerPixel);
    // EXR has no 64-bit integer attribute; a decimal string keeps every seed exact.
    spec.attribute("penumbra:seed", std::to_string(metadata.seed));
    spec.attribute("penumbra:sampler", metadata.sampler);
    spec.attribute("penumbra:accel", metadata.accelerator);
    spec.attribute("penumbra:scene", metadata.sceneFile);
    spec.attribute("penumbra:renderTime", OIIO::TypeDesc::DOUBLE, &metadata.renderSeconds);
    spec.attribute("penumbra:version", metadata.version);

    const std::vector<float> rgb = film.meanRgb();
    writeAtomically(path, spec, OIIO::TypeDesc::FLOAT, rgb.data(), "EXR image");
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
