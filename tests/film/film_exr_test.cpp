// The production film: exact sums (any split of a render, resumed, in passes, cancelled or merged,
// gives the same bits as one render), the AOVs against closed forms (a sphere's normal and
// distance), and the EXR round trip (sums bit for bit, metadata, refusal of foreign files).
#include "film/film_exr.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "cameras/camera.h"
#include "core/error.h"
#include "core/sampler.h"
#include "film/film.h"
#include "film/scene_hash.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

class FilmFiles : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("penumbra-film-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

Film renderRange(const Scene& scene, uint32_t first, uint32_t end, uint32_t passSize = 0,
                 std::optional<PixelWindow> crop = std::nullopt) {
    Film film(scene.film.width, scene.film.height);
    RenderOptions options;
    options.firstSample = first;
    options.endSample = end;
    options.passSize = passSize;
    options.crop = crop;
    render(scene, options, film);
    return film;
}

// The sums are exact: a sum does not depend on how its terms are grouped, unlike doubles.
TEST(ExactSum, GroupingDoesNotChangeTheBits) {
    std::mt19937 rng(7);
    std::lognormal_distribution<double> value(0.0, 4.0);  // values over many orders of magnitude
    std::vector<double> terms(1000);
    for (double& t : terms) t = float(value(rng));
    ExactSum inOrder, reversed, halves[2];
    double doubleInOrder = 0, doubleReversed = 0;
    for (size_t i = 0; i < terms.size(); ++i) {
        inOrder.add(terms[i]);
        reversed.add(terms[terms.size() - 1 - i]);
        halves[i % 2].add(terms[i]);
        doubleInOrder += terms[i];
        doubleReversed += terms[terms.size() - 1 - i];
    }
    ExactSum merged = halves[1];
    merged += halves[0];
    EXPECT_TRUE(inOrder == reversed);
    EXPECT_TRUE(inOrder == merged);
    // Plain doubles do depend on the order here (or this test would show nothing).
    EXPECT_NE(doubleInOrder, doubleReversed);
    EXPECT_NEAR(inOrder.value(), doubleInOrder, 1e-12 * doubleInOrder);
    // Words round-trip, negative values included.
    ExactSum negative;
    negative.add(-3.25);
    uint32_t words[4];
    negative.toWords(words);
    EXPECT_TRUE(ExactSum::fromWords(words) == negative);
    EXPECT_EQ(ExactSum::fromWords(words).value(), -3.25);
}

// A film larger than the machine's memory is refused with a message that says so, before any
// allocation (2^30 x 2^30 pixels of 256 bytes: 2^68 bytes, more than any machine has).
TEST(Film, ImpossibleSizeIsAClearError) {
    try {
        Film film(1 << 30, 1 << 30);
        FAIL() << "a 2^30 x 2^30 film was made";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("1073741824x1073741824 film needs"), std::string::npos)
            << e.what();
    }
}

// value() converts sums that fit 64 bits on a fast path; sums beyond it must read the same as the
// 128-bit integer they are, rounded to the nearest double once.
TEST(ExactSum, ValuesBeyondSixtyFourBitsReadExactly) {
    const uint32_t twoTo64Units[4] = {0, 0, 1, 0};  // 2^64 units of 2^-48: 2^16
    EXPECT_EQ(ExactSum::fromWords(twoTo64Units).value(), 65536.0);
    const uint32_t minusTwoTo64Units[4] = {0, 0, ~0u, ~0u};
    EXPECT_EQ(ExactSum::fromWords(minusTwoTo64Units).value(), -65536.0);
    // 2^64 + 2^11 units: exactly halfway between two doubles (their spacing there is 2^12 units),
    // rounded to the even one, 2^64 units; one unit more rounds up. A conversion through the low
    // 64 bits alone would read 2^-37 and 2^-37 + 2^-48.
    const uint32_t halfway[4] = {1u << 11, 0, 1, 0};
    EXPECT_EQ(ExactSum::fromWords(halfway).value(), 65536.0);
    const uint32_t aboveHalfway[4] = {(1u << 11) + 1, 0, 1, 0};
    EXPECT_EQ(ExactSum::fromWords(aboveHalfway).value(), 65536.0 + 0x1p-36);
    // The largest sum of 64 bits and the smallest: the fast path.
    const uint32_t largest64[4] = {~0u, 0x7fffffffu, 0, 0};
    EXPECT_EQ(ExactSum::fromWords(largest64).value(), 0x1p63 * 0x1p-48);
    const uint32_t smallest64[4] = {0, 0x80000000u, ~0u, ~0u};
    EXPECT_EQ(ExactSum::fromWords(smallest64).value(), -0x1p63 * 0x1p-48);
}

TEST(RenderPasses, PassesResumeAndMergeAreBitIdenticalToOneRender) {
    const Scene scene = testing::makeSmallBoxScene(24, 18, 13);
    const Film once = renderRange(scene, 0, 13);
    ASSERT_GT(once.totalSamples(), 0u);

    // In passes of 4 samples (4 + 4 + 4 + 1).
    EXPECT_TRUE(renderRange(scene, 0, 13, 4).identicalTo(once));

    // Resumed: [0, 5) then [5, 13) into the same film.
    Film resumed = renderRange(scene, 0, 5);
    EXPECT_FALSE(resumed.identicalTo(once));
    RenderOptions more;
    more.firstSample = 5;
    more.endSample = 13;
    render(scene, more, resumed);
    EXPECT_TRUE(resumed.identicalTo(once));

    // Separate renders merged, in either order; and crops stitched.
    Film merged = renderRange(scene, 5, 13);
    merged.merge(renderRange(scene, 0, 5));
    EXPECT_TRUE(merged.identicalTo(once));
    Film stitched = renderRange(scene, 0, 13, 0, PixelWindow{0, 10, 0, 18});
    stitched.merge(renderRange(scene, 0, 13, 0, PixelWindow{10, 24, 0, 18}));
    EXPECT_TRUE(stitched.identicalTo(once));
}

TEST(RenderPasses, CancellationStopsAtAPassBoundary) {
    const Scene scene = testing::makeSmallBoxScene(16, 12, 40);
    std::atomic<bool> cancel{false};
    std::vector<uint32_t> passEnds;
    Film film(16, 12);
    RenderOptions options;
    options.passSize = 3;
    options.cancel = &cancel;
    options.passDone = [&](uint32_t end) {
        passEnds.push_back(end);
        if (end >= 6) cancel = true;  // as a signal handler would, between passes
    };
    const RenderStats stats = render(scene, options, film);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_EQ(stats.endSample, 6u);
    EXPECT_EQ(passEnds, (std::vector<uint32_t>{3, 6}));
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x) ASSERT_EQ(film.at(x, y).sampleCount, 6u);
    EXPECT_TRUE(film.identicalTo(renderRange(scene, 0, 6)));
}

// Passes end at multiples of the pass size, also when the range starts between them (a resume),
// and the film is still that of one render.
TEST(RenderPasses, PassesEndAtMultiplesOfThePassSize) {
    const Scene scene = testing::makeSmallBoxScene(16, 12, 23);
    std::vector<uint32_t> passEnds;
    Film film(16, 12);
    RenderOptions options;
    options.firstSample = 5;
    options.endSample = 23;
    options.passSize = 8;
    options.passDone = [&](uint32_t end) { passEnds.push_back(end); };
    const RenderStats stats = render(scene, options, film);
    EXPECT_EQ(stats.endSample, 23u);
    EXPECT_EQ(passEnds, (std::vector<uint32_t>{8, 16, 23}));
    EXPECT_TRUE(film.identicalTo(renderRange(scene, 5, 23)));
    // Pass size 0: one pass, wherever the range starts.
    passEnds.clear();
    Film once(16, 12);
    options.passSize = 0;
    render(scene, options, once);
    EXPECT_EQ(passEnds, (std::vector<uint32_t>{23}));
    EXPECT_TRUE(once.identicalTo(film));
}

// Explicit pass boundaries (convergence rungs) split the passes there, and only there.
TEST(RenderPasses, PassesEndAtTheGivenBoundaries) {
    const Scene scene = testing::makeSmallBoxScene(16, 12, 10);
    std::vector<uint32_t> passEnds;
    Film film(16, 12);
    RenderOptions options;
    options.passEnds = {1, 2, 4, 10, 40};
    options.passDone = [&](uint32_t end) { passEnds.push_back(end); };
    render(scene, options, film);
    EXPECT_EQ(passEnds, (std::vector<uint32_t>{1, 2, 4, 10}));
    EXPECT_TRUE(film.identicalTo(renderRange(scene, 0, 10)));
    passEnds.clear();
    Film withSize(16, 12);
    options.passSize = 3;
    render(scene, options, withSize);
    EXPECT_EQ(passEnds, (std::vector<uint32_t>{1, 2, 3, 4, 6, 9, 10}));
    EXPECT_TRUE(withSize.identicalTo(film));
}

// About 2^20 samples a pass, in whole packets of camera rays (8 sample indices).
TEST(RenderPasses, DefaultPassSizeIsAMultipleOfThePacketSize) {
    EXPECT_EQ(defaultPassSize(512 * 512), 8u);    // 2^20 / 2^18 = 4, rounded up to 8
    EXPECT_EQ(defaultPassSize(256 * 256), 16u);   // 2^20 / 2^16, a multiple already
    EXPECT_EQ(defaultPassSize(300 * 200), 24u);   // 17, rounded up
    EXPECT_EQ(defaultPassSize(4096 * 4096), 8u);  // 2^20 / 2^24 is 0: at least one packet
    EXPECT_EQ(defaultPassSize(1), 1u << 20);
    EXPECT_EQ(defaultPassSize(0), 1u << 20);
}

TEST(Sampler, FrozenDimensionsReturnTheirCentre) {
    PixelSample sample(SamplerKind::Stratified, 3, 17, 5);
    const Vec2f lens = sample.get2D(Dim::Lens);
    const float time = sample.get1D(Dim::Time);
    sample.freeze(PixelSample::dimBit(Dim::Lens) | PixelSample::dimBit(Dim::LightPosition));
    EXPECT_EQ(sample.get2D(Dim::Lens).x, 0.5f);
    EXPECT_EQ(sample.get2D(Dim::Lens).y, 0.5f);
    EXPECT_EQ(sample.get2D(Dim::LightPosition, 3).x, 0.5f);
    EXPECT_EQ(sample.get1D(Dim::Time), time);  // others are untouched
    EXPECT_FALSE(lens.x == 0.5f && lens.y == 0.5f);
}

// A unit sphere at distance 4 in front of a pinhole camera, filling most of the image, with a box
// filter of 1e-3 pixels: every sample of a pixel follows (nearly) the pixel centre's ray.
Scene sphereScene() {
    Scene scene;
    scene.film = {40, 30, 4, FilterKind::Box, 1e-3f};
    scene.camera.lookFrom = {0.3f, 0.2f, 4.0f};
    scene.camera.lookAt = {0.0f, 0.0f, 0.0f};
    scene.camera.verticalFovDegrees = 35.0f;
    scene.materials = {testing::makeLambert({0.8f, 0.4f, 0.2f})};
    Sphere ball;
    ball.center = {0.0f, 0.0f, 0.0f};
    ball.radius = 1.0f;
    scene.spheres.push_back(ball);
    scene.lights.push_back(PointLight{{2.0f, 3.0f, 3.0f}, Rgb(20.0f)});
    scene.environment = EnvironmentLight::constant(Rgb(0.1f));
    return scene;
}

TEST(Aovs, SphereNormalDepthAndAlbedoMatchTheClosedForm) {
    const Scene scene = sphereScene();
    const Film film = renderRange(scene, 0, 4);
    const Camera camera(scene.camera, scene.film.width, scene.film.height);
    int hits = 0, misses = 0;
    for (int y = 0; y < scene.film.height; ++y)
        for (int x = 0; x < scene.film.width; ++x) {
            const PixelSums& p = film.at(x, y);
            const Ray ray = camera.generateRay({x + 0.5f, y + 0.5f}, {0.5f, 0.5f}, 0.0f).ray;
            // |o + t d|^2 = 1 with |d| = 1 (double precision).
            const double ox = ray.origin.x, oy = ray.origin.y, oz = ray.origin.z;
            const double dx = ray.direction.x, dy = ray.direction.y, dz = ray.direction.z;
            const double b = ox * dx + oy * dy + oz * dz, c = ox * ox + oy * oy + oz * oz - 1.0;
            const double disc = b * b - c;
            if (disc < 0.05) {  // off the sphere, or so close to its outline that the footprint matters
                if (disc < -0.05) {
                    ++misses;
                    EXPECT_TRUE(std::isinf(p.meanDepth())) << x << "," << y;
                    EXPECT_EQ(p.meanAlbedo().r, 0.0f);
                    EXPECT_EQ(p.meanNormal().z, 0.0f);
                }
                continue;
            }
            ++hits;
            const double t = -b - std::sqrt(disc);
            const double n[3] = {ox + t * dx, oy + t * dy, oz + t * dz};  // the unit sphere's normal
            const Vec3f normal = p.meanNormal();
            EXPECT_NEAR(normal.x, n[0], 2e-4) << x << "," << y;
            EXPECT_NEAR(normal.y, n[1], 2e-4) << x << "," << y;
            EXPECT_NEAR(normal.z, n[2], 2e-4) << x << "," << y;
            EXPECT_NEAR(p.meanDepth(), t, 1e-4 * t) << x << "," << y;
            EXPECT_NEAR(p.meanAlbedo().r, 0.8f, 1e-6);
            EXPECT_NEAR(p.meanAlbedo().b, 0.2f, 1e-6);
        }
    EXPECT_GT(hits, 300);
    EXPECT_GT(misses, 50);
}

TEST_F(FilmFiles, ExrRoundTripKeepsSumsAovsAndMetadata) {
    Scene scene = sphereScene();
    const PixelWindow crop{3, 31, 2, 25};
    const Film film = renderRange(scene, 2, 7, 0, crop);

    RenderMetadata meta;
    meta.samplesPerPixel = 5;
    meta.seed = 0xfedcba9876543210ull;
    meta.sampler = "independent";
    meta.accelerator = "bvh";
    meta.sceneFile = "scenes/a b.json";
    meta.sceneHash = "fnv1a64:0123456789abcdef";
    meta.renderSeconds = 1.625;
    meta.version = "9.8.7";
    meta.firstSample = 2;
    meta.endSample = 7;
    meta.crop = crop;
    const fs::path path = dir_ / "film.exr";
    writeExr(film, meta, path);

    const FilmFile back = readFilmExr(path);
    EXPECT_TRUE(back.film.identicalTo(film));
    const RenderMetadata& m = back.metadata;
    EXPECT_EQ(m.samplesPerPixel, 5);
    EXPECT_EQ(m.seed, meta.seed);
    EXPECT_EQ(m.sampler, meta.sampler);
    EXPECT_EQ(m.accelerator, meta.accelerator);
    EXPECT_EQ(m.sceneFile, meta.sceneFile);
    EXPECT_EQ(m.sceneHash, meta.sceneHash);
    EXPECT_EQ(m.renderSeconds, meta.renderSeconds);
    EXPECT_EQ(m.version, meta.version);
    EXPECT_EQ(m.firstSample, 2u);
    EXPECT_EQ(m.endSample, 7u);
    ASSERT_TRUE(m.crop.has_value());
    EXPECT_TRUE(*m.crop == crop);

    // The beauty part holds the means and AOVs under the channel names other tools read.
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec spec = in->spec(0, 0);
    EXPECT_EQ(spec.full_width, 40);
    EXPECT_EQ(spec.x, 3);
    EXPECT_EQ(spec.width, 28);
    std::vector<float> pixels(size_t(spec.width) * spec.height * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()));
    const int x = 20, y = 15;  // on the sphere
    const float* px = pixels.data() + (size_t(y - spec.y) * spec.width + (x - spec.x)) * spec.nchannels;
    const PixelSums& p = film.at(x, y);
    EXPECT_EQ(px[spec.channelindex("R")], p.mean().r);
    EXPECT_EQ(px[spec.channelindex("A")], 1.0f);
    EXPECT_EQ(px[spec.channelindex("albedo.G")], p.meanAlbedo().g);
    EXPECT_EQ(px[spec.channelindex("N.X")], p.meanNormal().x);
    EXPECT_EQ(px[spec.channelindex("N.Z")], p.meanNormal().z);
    EXPECT_EQ(px[spec.channelindex("Z")], p.meanDepth());
    EXPECT_EQ(px[spec.channelindex("variance.B")], p.varianceOfMean().b);
    EXPECT_GT(p.varianceOfMean().b, 0.0f);
    EXPECT_EQ(spec.get_string_attribute("penumbra:samples"), "2:7");
    EXPECT_EQ(spec.get_string_attribute("penumbra:crop"), "3,31,2,25");
}

// The layout of docs/exr-layout.md as OpenImageIO (and so other tools) sees it.
TEST_F(FilmFiles, ExrLayoutAsOpenImageIoReadsIt) {
    const PixelWindow crop{1, 7, 2, 5};
    Film film(8, 6);
    film.add(3, 3, Rgb(0.5f, 1.0f, 2.0f), 1.0f);
    RenderMetadata meta;
    meta.samplesPerPixel = 3;
    meta.seed = 42;
    meta.sampler = "stratified";
    meta.accelerator = "embree";
    meta.sceneFile = "s.json";
    meta.sceneHash = "fnv1a64:0000000000000001";
    meta.renderSeconds = 0.5;
    meta.version = "1.2.3";
    meta.firstSample = 4;
    meta.endSample = 7;
    meta.crop = crop;
    const fs::path path = dir_ / "layout.exr";
    writeExr(film, meta, path);

    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    EXPECT_STREQ(in->format_name(), "openexr");
    const OIIO::ImageSpec beauty = in->spec(0, 0);
    EXPECT_EQ(beauty.get_string_attribute("oiio:subimagename"), "beauty");
    EXPECT_EQ(beauty.get_string_attribute("compression"), "rle");
    EXPECT_EQ(beauty.format, OIIO::TypeDesc::FLOAT);
    EXPECT_TRUE(beauty.channelformats.empty());  // all FLOAT
    std::vector<std::string> names(beauty.channelnames.begin(), beauty.channelnames.end());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names,
              (std::vector<std::string>{"A", "B", "G", "N.X", "N.Y", "N.Z", "R", "Z", "albedo.B", "albedo.G",
                                        "albedo.R", "variance.B", "variance.G", "variance.R"}));
    EXPECT_EQ(beauty.full_x, 0);
    EXPECT_EQ(beauty.full_y, 0);
    EXPECT_EQ(beauty.full_width, 8);
    EXPECT_EQ(beauty.full_height, 6);
    EXPECT_EQ(beauty.x, 1);
    EXPECT_EQ(beauty.y, 2);
    EXPECT_EQ(beauty.width, 6);
    EXPECT_EQ(beauty.height, 3);
    EXPECT_EQ(beauty.get_int_attribute("penumbra:film"), 3);
    EXPECT_EQ(beauty.get_int_attribute("penumbra:spp"), 3);
    EXPECT_EQ(beauty.get_string_attribute("penumbra:seed"), "42");
    EXPECT_EQ(beauty.get_string_attribute("penumbra:sampler"), "stratified");
    EXPECT_EQ(beauty.get_string_attribute("penumbra:accel"), "embree");
    EXPECT_EQ(beauty.get_string_attribute("penumbra:scene"), "s.json");
    EXPECT_EQ(beauty.get_string_attribute("penumbra:sceneHash"), "fnv1a64:0000000000000001");
    double seconds = 0;
    EXPECT_TRUE(beauty.getattribute("penumbra:renderTime", OIIO::TypeDesc::DOUBLE, &seconds));
    EXPECT_EQ(seconds, 0.5);
    EXPECT_EQ(beauty.get_string_attribute("penumbra:version"), "1.2.3");
    EXPECT_EQ(beauty.get_string_attribute("penumbra:resolution"), "8x6");
    EXPECT_EQ(beauty.get_string_attribute("penumbra:samples"), "4:7");
    EXPECT_EQ(beauty.get_string_attribute("penumbra:crop"), "1,7,2,5");
    EXPECT_EQ(std::string(beauty.get_string_attribute("Software")).rfind("penumbra ", 0), 0u);

    // The sums: part "sums" (zip), and "sums.noise" (rle) when some word changes more often than
    // it repeats. The one sample, of weight 1, makes every sum a multiple of 2^-16 below 2^15, so
    // each nonzero sum needs its words w0 and w1, and w0 is zero: only w1 is stored.
    const PixelSums& sample = film.at(3, 3);
    std::map<std::string, uint32_t> words;  // channel -> its value at pixel (3, 3)
    for (int subimage = 1; in->seek_subimage(subimage, 0); ++subimage) {
        const OIIO::ImageSpec sums = in->spec(subimage, 0);
        const std::string part = sums.get_string_attribute("oiio:subimagename");
        ASSERT_TRUE(part == "sums" || part == "sums.noise") << part;
        EXPECT_EQ(sums.get_string_attribute("compression"), part == "sums" ? "zip" : "rle");
        for (int c = 0; c < sums.nchannels; ++c)
            EXPECT_EQ(sums.channelformat(c), OIIO::TypeDesc::UINT32) << c;
        EXPECT_EQ(sums.x, 1);
        EXPECT_EQ(sums.width, 6);
        EXPECT_EQ(sums.full_width, 8);
        if (part == "sums") {
            EXPECT_GE(sums.channelindex("spp"), 0);
        }
        std::vector<uint32_t> pixels(size_t(sums.width) * sums.height * sums.nchannels);
        ASSERT_TRUE(in->read_image(subimage, 0, 0, sums.nchannels, OIIO::TypeDesc::UINT32, pixels.data()));
        const uint32_t* px = pixels.data() + (size_t(3 - 2) * 6 + (3 - 1)) * sums.nchannels;
        for (int c = 0; c < sums.nchannels; ++c)
            EXPECT_TRUE(words.emplace(sums.channelnames[c], px[c]).second);
    }
    std::map<std::string, uint32_t> expected = {{"spp", 1u}};
    const std::pair<const char*, const ExactSum*> nonzero[] = {
        {"sum.R", &sample.radiance[0]},          {"sum.G", &sample.radiance[1]},
        {"sum.B", &sample.radiance[2]},          {"sumsq.R", &sample.radianceSquared[0]},
        {"sumsq.G", &sample.radianceSquared[1]}, {"sumsq.B", &sample.radianceSquared[2]},
        {"sum.weight", &sample.weight}};
    for (const auto& [name, sum] : nonzero) {
        uint32_t w[4];
        sum->toWords(w);
        EXPECT_EQ(w[0], 0u) << name;
        EXPECT_NE(w[1], 0u) << name;
        expected[std::string(name) + ".w1"] = w[1];
    }
    EXPECT_EQ(words, expected);
    EXPECT_EQ(words["sum.B.w1"], 2u << 16);  // 2.0 in units of 2^-48
}

// A film's sums in the order of docs/exr-layout.md.
std::vector<const ExactSum*> sumsInLayoutOrder(const PixelSums& p) {
    return {&p.radiance[0],
            &p.radiance[1],
            &p.radiance[2],
            &p.radianceSquared[0],
            &p.radianceSquared[1],
            &p.radianceSquared[2],
            &p.weight,
            &p.albedo[0],
            &p.albedo[1],
            &p.albedo[2],
            &p.normal[0],
            &p.normal[1],
            &p.normal[2],
            &p.depth,
            &p.hitWeight};
}

// A film in layout version 1 as its writer stored it (every sum as four words w0..w3 in part
// "sums", whole image, samples 0:1), written here by hand; or one tampered with: no sums part, a
// channel left out, a malformed seed, another layout version.
void writeLayout1(const fs::path& path, const Film& film, bool withSums, const std::string& seed,
                  const std::string& dropChannel, int version = 1) {
    const int width = film.width(), height = film.height();
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec beauty(width, height, 3, OIIO::TypeDesc::FLOAT);
    beauty.attribute("oiio:subimagename", "beauty");
    beauty.attribute("penumbra:film", version);
    beauty.attribute("penumbra:seed", seed);
    beauty.attribute("penumbra:samples", "0:1");
    beauty.attribute("penumbra:resolution", std::to_string(width) + "x" + std::to_string(height));
    beauty.attribute("penumbra:crop", "0," + std::to_string(width) + ",0," + std::to_string(height));
    OIIO::ImageSpec sums(width, height, 0, OIIO::TypeDesc::UINT32);
    sums.channelnames.clear();
    std::vector<bool> keep;
    for (const char* sum :
         {"sum.R", "sum.G", "sum.B", "sumsq.R", "sumsq.G", "sumsq.B", "sum.weight", "sum.albedo.R",
          "sum.albedo.G", "sum.albedo.B", "sum.N.X", "sum.N.Y", "sum.N.Z", "sum.Z", "sum.hits"})
        for (int w = 0; w < 4; ++w) {
            const std::string name = std::string(sum) + ".w" + std::to_string(w);
            keep.push_back(name != dropChannel);
            if (keep.back()) sums.channelnames.push_back(name);
        }
    const bool withSpp = dropChannel != "spp";
    if (withSpp) sums.channelnames.push_back("spp");
    sums.nchannels = int(sums.channelnames.size());
    sums.attribute("oiio:subimagename", "sums");
    const OIIO::ImageSpec specs[2] = {beauty, sums};
    std::vector<float> pixels;
    std::vector<uint32_t> words;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const PixelSums& p = film.at(x, y);
            const Rgb mean = p.mean();
            pixels.insert(pixels.end(), {mean.r, mean.g, mean.b});
            size_t k = 0;
            for (const ExactSum* sum : sumsInLayoutOrder(p)) {
                uint32_t w[4];
                sum->toWords(w);
                for (uint32_t word : w)
                    if (keep[k++]) words.push_back(word);
            }
            if (withSpp) words.push_back(p.sampleCount);
        }
    ASSERT_TRUE(out->open(path.string(), withSums ? 2 : 1, specs)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    if (withSums) {
        ASSERT_TRUE(out->open(path.string(), sums, OIIO::ImageOutput::AppendSubimage)) << out->geterror();
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT32, words.data()));
    }
    out->close();
}

// Sums of every size: one that needs all four words, some that need three, two or one, negative
// ones, words that are zero in every pixel, one whose second word is zero in every pixel but
// still needed (its first word has the top bit set), a sum that is zero everywhere; some words
// change from pixel to pixel and some repeat.
Film filmOfEveryWordCount() {
    Film film(7, 5);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> value(0.0f, 4.0f);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x) film.add(x, y, Rgb(value(rng), value(rng), 0.5f), 1.0f);
    film.addAddend(0, 0, PixelSums::kRadiance, 0x1p46);      // the most one addition may add,
    film.addAddend(0, 0, PixelSums::kRadiance, 0x1p46);      // twice: 2^95 units needs all four words
    film.addAddend(1, 0, PixelSums::kDepth, -0x1p46);        // -2^94 units: three words
    film.addAddend(4, 3, PixelSums::kDepth, 0x1p40);         // 2^88 units: w0 and w1 are zero in every pixel
    film.addAddend(2, 1, PixelSums::kAlbedo, 0x1p-17);       // 2^31 units: w0 = 0x80000000, w1 = 0 but needed
    film.addAddend(3, 2, PixelSums::kNormal + 1, -0x1p-40);  // -256 units: one word, sign-extended
    film.addAddend(5, 4, PixelSums::kNormal + 1, -0x1p-44);  // -16 units
    return film;
}

TEST_F(FilmFiles, Layout2StoresOnlyTheWordsItNeedsAndRestoresTheRest) {
    const Film film = filmOfEveryWordCount();
    RenderMetadata meta;
    meta.seed = 5;
    meta.firstSample = 0;
    meta.endSample = 1;
    const fs::path path = dir_ / "words.exr";
    writeExr(film, meta, path);
    EXPECT_TRUE(readFilmExr(path).film.identicalTo(film));

    std::map<std::string, std::string> partOf;  // channel -> part
    auto in = OIIO::ImageInput::open(path.string());
    ASSERT_TRUE(in) << OIIO::geterror();
    for (int subimage = 1; in->seek_subimage(subimage, 0); ++subimage) {
        const OIIO::ImageSpec& spec = in->spec();
        for (const std::string& name : spec.channelnames)
            partOf[name] = spec.get_string_attribute("oiio:subimagename");
    }
    auto stored = [&](const std::string& channel) { return partOf.count(channel) > 0; };
    for (int w = 0; w < 4; ++w) EXPECT_TRUE(stored("sum.R.w" + std::to_string(w))) << w;
    EXPECT_FALSE(stored("sum.G.w2"));  // below 2^15: the high words only repeat the sign
    EXPECT_FALSE(stored("sum.G.w3"));
    EXPECT_TRUE(stored("sum.Z.w2"));
    EXPECT_FALSE(stored("sum.Z.w0") || stored("sum.Z.w1"));  // multiples of 2^40 units: zero everywhere
    EXPECT_FALSE(stored("sum.Z.w3"));
    EXPECT_TRUE(stored("sum.albedo.R.w0") && stored("sum.albedo.R.w1"));
    EXPECT_FALSE(stored("sum.albedo.R.w2"));
    EXPECT_TRUE(stored("sum.N.Y.w0"));
    EXPECT_FALSE(stored("sum.N.Y.w1"));
    EXPECT_FALSE(stored("sum.weight.w0"));                         // whole numbers of samples of weight 1
    EXPECT_FALSE(stored("sum.hits.w0") || stored("sum.hits.w1"));  // no sample hit anything
    // The same weight everywhere repeats; a random radiance changes.
    EXPECT_EQ(partOf["sum.weight.w1"], "sums");
    EXPECT_EQ(partOf["spp"], "sums");
    EXPECT_EQ(partOf["sum.G.w1"], "sums.noise");
}

TEST_F(FilmFiles, Layout1FilmsStillRead) {
    const Film film = filmOfEveryWordCount();
    const fs::path path = dir_ / "layout1.exr";
    writeLayout1(path, film, true, "11", "");
    const FilmFile back = readFilmExr(path);
    EXPECT_TRUE(back.film.identicalTo(film));
    EXPECT_EQ(back.metadata.seed, 11u);
    EXPECT_EQ(back.metadata.endSample, 1u);
}

TEST_F(FilmFiles, TamperedFilmsAreRefusedNamingWhatIsWrong) {
    const fs::path path = dir_ / "tampered.exr";
    auto expectRefusal = [&](const std::string& mention) {
        try {
            readFilmExr(path);
            ADD_FAILURE() << "expected an InputError mentioning " << mention;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        }
    };
    const Film zeros(4, 2);
    writeLayout1(path, zeros, true, "7", "");
    EXPECT_EQ(readFilmExr(path).metadata.seed, 7u);  // the control: well formed
    writeLayout1(path, zeros, false, "7", "");
    expectRefusal("no \"sums\" part");
    writeLayout1(path, zeros, true, "7", "sum.N.Y.w2");  // layout 1 stores every word
    expectRefusal("no channel 'sum.N.Y.w2'");
    writeLayout1(path, zeros, true, "7", "spp", 2);
    expectRefusal("no channel 'spp'");
    writeLayout1(path, zeros, true, "-3", "");
    expectRefusal("malformed penumbra:seed '-3'");
    writeLayout1(path, zeros, true, "7", "", 5);
    expectRefusal("film layout version 5");
    writeLayout1(path, zeros, true, "7", "", 4);  // layout 4 is an adaptive render's: it names its settings
    expectRefusal("malformed penumbra:adaptive ''");
    writeLayout1(path, zeros, true, "7", "", 3);  // layout 3 must carry its checksum
    expectRefusal("no penumbra:checksum attribute");
}

TEST_F(FilmFiles, ForeignFilesAreRefusedClearly) {
    // An EXR that is not ours.
    const fs::path plain = dir_ / "plain.exr";
    {
        auto out = OIIO::ImageOutput::create(plain.string());
        OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeDesc::FLOAT);
        std::vector<float> zeros(48, 0.25f);
        ASSERT_TRUE(out->open(plain.string(), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, zeros.data()));
        out->close();
    }
    const fs::path text = dir_ / "notes.exr";
    std::ofstream(text) << "hello";
    for (const fs::path& path : {plain, text, dir_ / "missing.exr"}) {
        try {
            readFilmExr(path);
            ADD_FAILURE() << "expected an InputError for " << path;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
        }
    }
    try {
        readFilmExr(plain);
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("not a film written by penumbra"), std::string::npos)
            << e.what();
    }
}

TEST_F(FilmFiles, SceneHashFollowsTheContents) {
    const fs::path a = dir_ / "a.json", b = dir_ / "b.json";
    std::ofstream(a) << "{\"film\": {\"spp\": 4}}";
    std::ofstream(b) << "{\"film\": {\"spp\": 5}}";
    EXPECT_EQ(hashFileContents(a), hashFileContents(a));
    EXPECT_NE(hashFileContents(a), hashFileContents(b));
    EXPECT_EQ(hashFileContents(a).rfind("fnv1a64:", 0), 0u);
    EXPECT_THROW(hashFileContents(dir_ / "absent.json"), InputError);
}

// The scene hash covers the mesh files too, so a resume or merge refuses a film rendered before a
// mesh changed; a scene without mesh files keeps the hash of its file alone.
TEST_F(FilmFiles, SceneHashCoversTheMeshFiles) {
    const fs::path scene = dir_ / "scene.json", mesh = dir_ / "mesh.obj";
    std::ofstream(scene) << "{\"shapes\": [{\"type\": \"mesh_file\", \"file\": \"mesh.obj\"}]}";
    { std::ofstream(mesh) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"; }
    EXPECT_EQ(hashSceneFiles(scene, {}), hashFileContents(scene));
    const std::string before = hashSceneFiles(scene, {mesh});
    EXPECT_NE(before, hashFileContents(scene));
    EXPECT_EQ(hashSceneFiles(scene, {mesh}), before);
    { std::ofstream(mesh) << "v 0 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\n"; }
    EXPECT_NE(hashSceneFiles(scene, {mesh}), before) << "a changed mesh file changes the hash";
    EXPECT_THROW(hashSceneFiles(scene, {dir_ / "absent.obj"}), InputError);
}

}  // namespace
}  // namespace penumbra
