// Images as the renderer reads them. The first byte chooses the file's extension (and with it the
// reader OpenImageIO tries first, and whether an environment map is read by OpenEXR directly) and
// the colour space; the rest is the file. It is opened as an image texture (the header checks, the
// sRGB linearisation), looked up with every filter, and the failed lookups taken as a render
// takes them; then read whole as an environment map (its header checks, the radiance check) and,
// when it reads, made into an environment light.
#include <array>

#include "fuzz/fuzz_input.h"
#include "lights/environment_light.h"
#include "textures/image_file.h"
#include "textures/image_texture.h"
#include "textures/texture.h"

namespace {

constexpr std::array<const char*, 8> kExtensions = {".png", ".exr", ".hdr", ".jpg",
                                                    ".tif", ".tga", ".bmp", ".ppm"};

// A few lookups with each filter: the corners, the middle, and footprints from a texel to the whole image.
void lookUp(const penumbra::ImageTextureSource& opened) {
    using namespace penumbra;
    for (TextureFilter filter : {TextureFilter::Closest, TextureFilter::Bilinear, TextureFilter::Trilinear,
                                 TextureFilter::Anisotropic}) {
        ImageTextureSource source = opened;
        source.filter = filter;
        const Texture texture = Texture::image(source, Rgb(1.0f));
        for (float footprint : {0.0f, 0.001f, 0.3f}) {
            TextureQuery query;
            for (Vec2f uv : {Vec2f{0.0f, 0.0f}, Vec2f{0.5f, 0.5f}, Vec2f{0.999f, 0.25f}}) {
                query.uv = uv;
                query.dudx = footprint;
                query.dvdy = footprint * 0.25f;
                (void)texture.evaluate(query);
            }
        }
    }
}

}  // namespace

// OpenImageIO 2.4's PNG reader copies its error message into a std::string inside libpng's read
// callback, and libpng's error handling longjmp()s past the string's destructor: 31 bytes lost per
// corrupt PNG (PNGInput::PngReadCallback). LeakSanitizer's fast unwinder stops at libstdc++'s
// _M_assign (built without frame pointers), so that is the frame matched: a string's buffer is a
// direct leak only when the string itself was never destroyed without being leaked in turn (a
// leaked object holding a string is reported as the object's direct leak).
extern "C" const char* __lsan_default_suppressions() { return "leak:PngReadCallback\nleak:_M_assign\n"; }

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    penumbra::fuzz::loadTexturePluginBeforeFuzzing();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace penumbra;
    if (size < 1) return 0;
    static std::array<fuzz::ScratchFile*, kExtensions.size()> files = [] {
        std::array<fuzz::ScratchFile*, kExtensions.size()> made{};
        for (size_t i = 0; i < kExtensions.size(); ++i)
            made[i] = new fuzz::ScratchFile(std::string("image") + kExtensions[i]);
        return made;
    }();
    const std::filesystem::path& path = files[data[0] % kExtensions.size()]->write(data + 1, size - 1);
    const int colorSpace = (data[0] / kExtensions.size()) % 3;  // auto, sRGB, linear
    fuzz::expectReadOrInputError([&] {
        lookUp(openImageTexture(path, colorSpace, SourceLocation{}));
        throwIfTextureLookupsFailed();
    });
    fuzz::expectReadOrInputError([&] {
        LinearRgbImage image = readLinearRgbImage(path, SourceLocation{});
        const EnvironmentLight light = EnvironmentLight::fromImage(
            EnvironmentImage{image.width, image.height, std::move(image.texels)}, Rgb(1.0f), Transform());
        (void)light.sample(Vec2f{0.5f, 0.5f});
    });
    // The next input is written under the same name: what the TextureSystem holds of this one goes.
    if (texturePluginLoaded()) texturePlugin().forget(path.c_str());
    return 0;
}
