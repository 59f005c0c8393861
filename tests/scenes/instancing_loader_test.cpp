// Loading instanced meshes: the "prototypes" section and "instance" shapes (placement, motion keys,
// material per instance), and the errors for bad references and impossible combinations, each
// naming the offending value by its JSON pointer.
#include <gtest/gtest.h>

#include "scenes/scene_loader.h"
#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

using testing::catchInputError;

// Two materials and a unit right triangle in the xy plane as the prototype "tri".
const std::string kHead =
    R"("materials": {"grey": {"type": "lambert"}, "red": {"type": "lambert", "albedo": [0.8, 0.1, 0.1]}},
    "camera": {"shutter": [0, 1]},
    "prototypes": {"tri": {"type": "triangle_mesh", "positions": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [0, 1, 2]}})";

Scene parse(const std::string& shapes) {
    return parseScene("{" + kHead + R"(, "shapes": [)" + shapes + "]}", "scene.json");
}

TEST(InstancingLoader, PrototypeIsStoredOnceAndEachInstanceHasItsPlacementAndMaterial) {
    const Scene scene = parse(R"(
        {"type": "instance", "prototype": "tri", "material": "grey", "transform": [{"translate": [5, 0, 0]}]},
        {"type": "instance", "prototype": "tri", "material": "red", "transform": [{"scale": 2}]})");
    ASSERT_EQ(scene.prototypes.size(), 1u);
    EXPECT_TRUE(scene.meshes.empty());  // nothing copied
    ASSERT_EQ(scene.instances.size(), 2u);
    EXPECT_EQ(scene.instances[0].prototype, 0u);
    EXPECT_EQ(scene.instances[0].material, 0u);
    EXPECT_EQ(scene.instances[1].material, 1u);
    EXPECT_EQ(scene.instances[0].placement.applyPoint({1, 0, 0}), Vec3f(6, 0, 0));
    EXPECT_EQ(scene.instances[1].toWorld(0.5f).applyPoint({0, 1, 0}), Vec3f(0, 2, 0));
    EXPECT_EQ(scene.instances[1].name, "/shapes/1");
    EXPECT_FALSE(scene.shapesMove());
    // The prototype stays in its own space.
    EXPECT_EQ(scene.prototypes[0].positions[1], Vec3f(1, 0, 0));
}

TEST(InstancingLoader, PrototypeTransformIsBakedIntoTheSharedMesh) {
    const Scene scene = parseScene(R"({"materials": {"grey": {"type": "lambert"}},
        "prototypes": {"q": {"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0],
                             "transform": [{"translate": [0, 0, 3]}]}},
        "shapes": [{"type": "instance", "prototype": "q", "material": "grey"}]})",
                                   "scene.json");
    ASSERT_EQ(scene.prototypes.size(), 1u);
    EXPECT_EQ(scene.prototypes[0].positions[0], Vec3f(0, 0, 3));
    EXPECT_EQ(scene.prototypes[0].triangleCount(), 2u);
}

TEST(InstancingLoader, MotionKeysMoveAnInstance) {
    const Scene scene = parse(R"({"type": "instance", "prototype": "tri", "material": "grey",
        "motion": {"transforms": [{"translate": [0, 0, 0]}, {"translate": [2, 0, 0]}]}})");
    ASSERT_EQ(scene.instances.size(), 1u);
    EXPECT_TRUE(scene.instances[0].moves());
    EXPECT_TRUE(scene.shapesMove());
    EXPECT_EQ(scene.instances[0].toWorld(0.5f).applyPoint({0, 0, 0}), Vec3f(1, 0, 0));
}

TEST(InstancingLoader, HitIdsNameTheInstanceAndThePrototypeTriangle) {
    Scene scene = parse(
        R"({"type": "quad", "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], "material": "grey"},
        {"type": "instance", "prototype": "tri", "material": "grey"},
        {"type": "instance", "prototype": "tri", "material": "red"})");
    const ShapeRef ref{ShapeKind::Instance, 1, 0};
    const Hit ids = scene.idsOf(ref);
    EXPECT_EQ(ids.geomId, scene.instanceGeomId(1));
    const ShapeRef back = scene.shapeOf(ids);
    EXPECT_EQ(back.kind, ShapeKind::Instance);
    EXPECT_EQ(back.index, 1u);
    EXPECT_EQ(back.primitive, 0u);
    EXPECT_EQ(&scene.triangleMeshOf(back), &scene.prototypes[0]);
    // The other shapes keep their ids.
    EXPECT_EQ(scene.shapeOf(scene.idsOf({ShapeKind::Mesh, 0, 1})).kind, ShapeKind::Mesh);
    EXPECT_EQ(scene.shapeOf(scene.idsOf({ShapeKind::Sphere, 3, 0})).kind, ShapeKind::Sphere);
}

TEST(InstancingLoader, UnknownPrototypeNamesTheKnownOnes) {
    const InputError e =
        catchInputError([] { parse(R"({"type": "instance", "prototype": "dragon", "material": "grey"})"); });
    EXPECT_CONTAINS(e.what(),
                    "scene.json: /shapes/0/prototype: unknown prototype \"dragon\" (known prototypes: tri)");
}

TEST(InstancingLoader, NoPrototypesAtAll) {
    const InputError e = catchInputError([] {
        parseScene(
            R"({"materials": {"grey": {"type": "lambert"}}, "shapes": [{"type": "instance", "prototype": "x", "material": "grey"}]})",
            "scene.json");
    });
    EXPECT_CONTAINS(e.what(),
                    "/shapes/0/prototype: unknown prototype \"x\" (the scene defines no prototypes)");
}

TEST(InstancingLoader, UnknownMaterialOfAnInstance) {
    const InputError e =
        catchInputError([] { parse(R"({"type": "instance", "prototype": "tri", "material": "gold"})"); });
    EXPECT_CONTAINS(e.what(), "/shapes/0/material: unknown material \"gold\"");
}

TEST(InstancingLoader, MissingPrototypeKey) {
    const InputError e = catchInputError([] { parse(R"({"type": "instance", "material": "grey"})"); });
    EXPECT_CONTAINS(e.what(), "/shapes/0");
    EXPECT_CONTAINS(e.what(), "prototype");
}

TEST(InstancingLoader, EmittingInstanceIsRefused) {
    const InputError e = catchInputError([] {
        parse(R"({"type": "instance", "prototype": "tri", "material": "grey", "emission": {"radiance": 1}})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/emission: an instance cannot emit light");
}

TEST(InstancingLoader, TransformAndMotionTogetherAreRefused) {
    const InputError e = catchInputError([] {
        parse(R"({"type": "instance", "prototype": "tri", "material": "grey", "transform": [{"scale": 2}],
                  "motion": {"transforms": [{}, {"translate": [1, 0, 0]}]}})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0/motion: an instance takes either transform or motion");
}

TEST(InstancingLoader, PrototypeTakesNoMaterialEmissionOrMotion) {
    for (const char* key : {R"("material": "grey")", R"("emission": {"radiance": 1})", R"("motion": {})"}) {
        const InputError e = catchInputError([&] {
            parseScene(
                std::string(
                    R"({"materials": {"grey": {"type": "lambert"}}, "prototypes": {"p": {"type": "quad",
                "corner": [0, 0, 0], "edge1": [1, 0, 0], "edge2": [0, 1, 0], )") +
                    key + "}}}",
                "scene.json");
        });
        EXPECT_CONTAINS(e.what(), "/prototypes/p/");
        EXPECT_CONTAINS(e.what(), "unknown key");
    }
}

TEST(InstancingLoader, UnknownPrototypeType) {
    const InputError e = catchInputError([] {
        parseScene(R"({"prototypes": {"p": {"type": "sphere", "center": [0, 0, 0], "radius": 1}}})",
                   "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "/prototypes/p/type");
}

TEST(InstancingLoader, PrototypeErrorsNameThePrototype) {
    const InputError e = catchInputError([] {
        parseScene(
            R"({"prototypes": {"p": {"type": "triangle_mesh", "positions": [[0, 0, 0]], "indices": [0, 0, 7]}}})",
            "scene.json");
    });
    EXPECT_CONTAINS(e.what(), "/prototypes/p/indices/2");
}

TEST(InstancingLoader, PlacementBeyondTheCoordinateLimit) {
    const InputError e = catchInputError([] {
        parse(
            R"({"type": "instance", "prototype": "tri", "material": "grey", "transform": [{"scale": 1e19}]})");
    });
    EXPECT_CONTAINS(e.what(), "/shapes/0: the placed prototype \"tri\" reaches beyond the coordinate limit");
}

TEST(InstancingLoader, PrototypesMustBeAnObject) {
    const InputError e = catchInputError([] { parseScene(R"({"prototypes": [1]})", "scene.json"); });
    EXPECT_CONTAINS(e.what(), "/prototypes");
}

}  // namespace
}  // namespace penumbra
