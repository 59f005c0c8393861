// The checks of `penumbra merge` and `render --resume` through the C++ API: parts of different
// renders, overlapping samples, holes, and films a render cannot continue are refused with a
// message that says what differs; exact merges are order-independent.
#include "film/film_merge.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "renderer/render.h"
#include "tests/support/scene_builders.h"

namespace penumbra {
namespace {

FilmFile part(const Scene& scene, uint32_t first, uint32_t end,
              std::optional<PixelWindow> crop = std::nullopt) {
    FilmFile f{Film(scene.film.width, scene.film.height), {}};
    RenderOptions options;
    options.firstSample = first;
    options.endSample = end;
    options.crop = crop;
    render(scene, options, f.film);
    RenderMetadata& m = f.metadata;
    m.samplesPerPixel = int(end - first);
    m.seed = scene.settings.seed;
    m.sampler = std::string(samplerKindName(scene.settings.sampler));
    m.accelerator = "embree";
    m.sceneFile = "box.json";
    m.sceneHash = "fnv1a64:0000000000000001";
    m.firstSample = first;
    m.endSample = end;
    m.crop = crop;
    return f;
}

std::string mergeError(const std::vector<FilmFile>& parts) {
    std::vector<std::string> names;
    for (size_t i = 0; i < parts.size(); ++i) names.push_back("part" + std::to_string(i) + ".exr");
    try {
        mergeFilms(parts, names);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

bool mentions(const std::string& text, const std::string& what) {
    return text.find(what) != std::string::npos;
}

TEST(Merge, ExactInAnyOrderWithTheRangeAndWindowOfTheUnion) {
    const Scene scene = testing::makeSmallBoxScene(16, 12, 6);
    const FilmFile once = part(scene, 0, 6);
    const std::vector<FilmFile> parts = {part(scene, 3, 6, PixelWindow{0, 16, 0, 5}), part(scene, 0, 3),
                                         part(scene, 3, 6, PixelWindow{0, 16, 5, 12})};
    const MergeResult r = mergeFilms(parts, {"a", "b", "c"});
    EXPECT_TRUE(r.uniform) << r.note;
    EXPECT_TRUE(r.merged.film.identicalTo(once.film));
    EXPECT_EQ(r.merged.metadata.firstSample, 0u);
    EXPECT_EQ(r.merged.metadata.endSample, 6u);
    EXPECT_EQ(r.merged.metadata.samplesPerPixel, 6);
    EXPECT_FALSE(r.merged.metadata.crop.has_value());
    // A part missing: a hole in the range of some pixels, so the result is not uniform.
    const MergeResult holes = mergeFilms({parts[0], parts[1]}, {"a", "b"});
    EXPECT_FALSE(holes.uniform);
    EXPECT_FALSE(holes.note.empty());
    // Crops of the same samples side by side: a uniform film over their union.
    const MergeResult sides =
        mergeFilms({part(scene, 0, 2, PixelWindow{2, 8, 1, 9}), part(scene, 0, 2, PixelWindow{8, 14, 1, 9})},
                   {"l", "r"});
    EXPECT_TRUE(sides.uniform) << sides.note;
    ASSERT_TRUE(sides.merged.metadata.crop.has_value());
    EXPECT_TRUE((*sides.merged.metadata.crop == PixelWindow{2, 14, 1, 9}));
}

TEST(Merge, PartsOfDifferentRendersOrOverlappingSamplesAreRefused) {
    const Scene scene = testing::makeSmallBoxScene(8, 6, 4);
    const FilmFile a = part(scene, 0, 2);
    FilmFile b = part(scene, 2, 4);
    ASSERT_EQ(mergeError({a, b}), "");

    FilmFile other = b;
    other.metadata.sceneHash = "fnv1a64:0000000000000002";
    EXPECT_TRUE(mentions(mergeError({a, other}), "different scenes")) << mergeError({a, other});
    other = b;
    other.metadata.seed = 7;
    EXPECT_TRUE(mentions(mergeError({a, other}), "different seeds"));
    other = b;
    other.metadata.sampler = "independent";
    EXPECT_TRUE(mentions(mergeError({a, other}), "different samplers"));
    other = b;
    other.metadata.accelerator = "bvh";
    EXPECT_TRUE(mentions(mergeError({a, other}), "--accel"));
    Scene wider = scene;
    wider.film.width = 9;
    EXPECT_TRUE(mentions(mergeError({a, part(wider, 2, 4)}), "different resolutions"));
    // Overlapping samples on shared pixels; the same samples on disjoint pixels are fine.
    const std::string overlap = mergeError({a, b, part(scene, 1, 3)});
    EXPECT_TRUE(mentions(overlap, "overlap")) << overlap;
    EXPECT_TRUE(mentions(overlap, "[1, 3)")) << overlap;
    EXPECT_EQ(
        mergeError({part(scene, 0, 2, PixelWindow{0, 4, 0, 6}), part(scene, 0, 2, PixelWindow{4, 8, 0, 6})}),
        "");
    EXPECT_TRUE(mentions(
        mergeError({part(scene, 0, 2, PixelWindow{0, 5, 0, 6}), part(scene, 1, 2, PixelWindow{4, 8, 0, 6})}),
        "overlap"));
    EXPECT_THROW(mergeFilms({}, {}), InputError);
}

TEST(Resume, OnlyAFilmOfTheSameRenderCanBeContinued) {
    const Scene scene = testing::makeSmallBoxScene(8, 6, 4);
    const FilmFile f = part(scene, 0, 3, PixelWindow{1, 7, 0, 6});
    const ResumeTarget good{"fnv1a64:0000000000000001", 8, 6, 0, "stratified", "embree",
                            PixelWindow{1, 7, 0, 6},    8, {}};
    EXPECT_NO_THROW(checkResumable(f, "f.exr", good));

    auto error = [&](ResumeTarget t) -> std::string {
        try {
            checkResumable(f, "f.exr", t);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    ResumeTarget t = good;
    t.sceneHash = "fnv1a64:0000000000000009";
    EXPECT_TRUE(mentions(error(t), "different scene")) << error(t);
    EXPECT_TRUE(mentions(error(t), "f.exr")) << error(t);
    t = good;
    t.width = 10;
    EXPECT_TRUE(mentions(error(t), "--res 8x6")) << error(t);
    t = good;
    t.seed = 3;
    EXPECT_TRUE(mentions(error(t), "--seed 0")) << error(t);
    t = good;
    t.sampler = "independent";
    EXPECT_TRUE(mentions(error(t), "--sampler stratified")) << error(t);
    t = good;
    t.accelerator = "bvh";
    EXPECT_TRUE(mentions(error(t), "--accel")) << error(t);
    t = good;
    t.crop.reset();
    EXPECT_TRUE(mentions(error(t), "--crop 1,7,0,6")) << error(t);
    t = good;
    t.endSample = 2;
    EXPECT_TRUE(mentions(error(t), "beyond --spp 2")) << error(t);
    // A film whose pixels do not all hold the recorded samples.
    FilmFile uneven = f;
    uneven.film.add(3, 3, Rgb(1.0f), 1.0f);
    EXPECT_THROW(checkResumable(uneven, "u.exr", good), InputError);
}

}  // namespace
}  // namespace penumbra
