#include "film/display_image.h"

#include <OpenColorIO/OpenColorIO.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/resource_paths.h"
#include "film/atomic_file.h"
#include "film/image_plugin_loader.h"
#include "film/version.h"

namespace OCIO = OCIO_NAMESPACE;

namespace penumbra {

namespace {

SourceLocation fileLocation(const std::string& file) {
    SourceLocation where;
    where.file = file;
    return where;
}

// The OCIO config: $OCIO when set and non-empty, otherwise the shipped one. CreateFromEnv rather
// than GetCurrentConfig, because GetCurrentConfig caches the first config it loads and would
// ignore later changes of $OCIO within the process.
OCIO::ConstConfigRcPtr loadOcioConfig() {
    const char* env = std::getenv("OCIO");
    const bool fromEnv = env != nullptr && *env != '\0';
    const std::string configPath = fromEnv ? std::string(env) : sharedDataPath("ocio/config.ocio").string();
    try {
        return fromEnv ? OCIO::Config::CreateFromEnv() : OCIO::Config::CreateFromFile(configPath.c_str());
    } catch (const OCIO::Exception& e) {
        throw InputError(fileLocation(configPath), fmt::format("cannot load the OpenColorIO config{}: {}",
                                                               fromEnv ? " named by $OCIO" : "", e.what()));
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

// The display and view `options` name (the config's defaults where empty), checked against the
// config. Throws InputError listing the available ones.
std::pair<std::string, std::string> resolveView(const OCIO::Config& config, const DisplayOptions& options) {
    const std::string& display = options.display;
    const std::string& view = options.view;
    const std::string displayName = display.empty() ? config.getDefaultDisplay() : display;
    bool displayKnown = false;
    for (int i = 0; i < config.getNumDisplays(); ++i) displayKnown |= displayName == config.getDisplay(i);
    if (!displayKnown)
        throw InputError(
            fmt::format("unknown OpenColorIO display '{}'; available displays: {}", displayName,
                        joinQuoted(config.getNumDisplays(), [&](int i) { return config.getDisplay(i); })));

    const std::string viewName = view.empty() ? config.getDefaultView(displayName.c_str()) : view;
    bool viewKnown = false;
    const int numViews = config.getNumViews(displayName.c_str());
    for (int i = 0; i < numViews; ++i) viewKnown |= viewName == config.getView(displayName.c_str(), i);
    if (!viewKnown)
        throw InputError(fmt::format(
            "unknown OpenColorIO view '{}' of display '{}'; available views: {}", viewName, displayName,
            joinQuoted(numViews, [&](int i) { return config.getView(displayName.c_str(), i); })));

    return {displayName, viewName};
}

}  // namespace

void checkDisplayOptions(const DisplayOptions& options) { resolveView(*loadOcioConfig(), options); }

void writeDisplayImage(const Film& film, const std::filesystem::path& path, const DisplayOptions& options) {
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (extension != ".png" && extension != ".jpg" && extension != ".jpeg")
        throwFileError(
            path,
            fmt::format("unsupported display image format '{}' (expected .png, .jpg or .jpeg)", extension));

    const OCIO::ConstConfigRcPtr config = loadOcioConfig();

    const auto [displayName, viewName] = resolveView(*config, options);

    std::vector<float> rgb = film.meanRgb();
    if (options.exposure != 0.0f) {
        const float scale = std::exp2(options.exposure);
        for (float& v : rgb) v *= scale;
    }
    try {
        const auto processor = config->getProcessor(OCIO::ROLE_SCENE_LINEAR, displayName.c_str(),
                                                    viewName.c_str(), OCIO::TRANSFORM_DIR_FORWARD);
        if (!rgb.empty()) {
            OCIO::PackedImageDesc image(rgb.data(), film.width(), film.height(), 3);
            processor->getDefaultCPUProcessor()->apply(image);
        }
    } catch (const OCIO::Exception& e) {
        throwFileError(path,
                       fmt::format("OpenColorIO cannot convert scene_linear to display '{}', view '{}': {}",
                                   displayName, viewName, e.what()));
    }

    std::vector<uint8_t> pixels(rgb.size());
    std::transform(rgb.begin(), rgb.end(), pixels.begin(), quantize8);

    // Encoding PNG/JPEG needs OpenImageIO, which lives in the plugin (film/image_plugin.h).
    const PenumbraImagePlugin& plugin = imagePlugin();
    const std::string software = penumbraSoftwareName();
    const std::string exposure = fmt::format("{:+g}", options.exposure);
    const std::string description =
        fmt::format("scene-linear to display '{}', view '{}', exposure {} stops (OpenColorIO)", displayName,
                    viewName, exposure);
    const char* const attributes[] = {"Software",
                                      software.c_str(),
                                      "ImageDescription",
                                      description.c_str(),
                                      "penumbra:display",
                                      displayName.c_str(),
                                      "penumbra:view",
                                      viewName.c_str(),
                                      "penumbra:exposure",
                                      exposure.c_str(),
                                      nullptr};
    writeFileAtomically(path, "display image", [&](const std::string& tmp, std::string& error) {
        char message[1024];
        if (plugin.writeRgb8(tmp.c_str(), film.width(), film.height(), pixels.data(), attributes,
                             extension == ".png" ? 0 : 95, message, sizeof message))
            return true;
        error = message;
        return false;
    });
}

}  // namespace penumbra
