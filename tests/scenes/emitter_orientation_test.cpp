// The warning for a one-sided emitter turned the wrong way (scenes/emitter_orientation.h): a quad
// light over a floor, its front down (what lights the floor), up (nothing above it), up under a
// ceiling (it lights the ceiling), two-sided, and up but seen by the camera from above.
#include "scenes/emitter_orientation.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenes/scene_loader.h"

namespace penumbra {
namespace {

Scene sceneWith(const std::string& light, const std::string& extraShape = "",
                const std::string& camera = "[0, 1, 5]") {
    const std::string json = R"({"camera": {"look_from": )" + camera + R"(, "look_at": [0, 0, 0]},
        "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
        "shapes": [{"type": "quad", "corner": [-5, 0, 5], "edge1": [10, 0, 0], "edge2": [0, 0, -10], "material": "grey"},
                   )" + light +
                             extraShape + R"(]})";
    return parseScene(json, "emitters.json");
}

const std::string kDown =
    R"({"type": "quad", "corner": [-0.5, 3, -0.5], "edge1": [1, 0, 0], "edge2": [0, 0, 1], "material": "grey", "emission": {"radiance": 5}})";
const std::string kUp =
    R"({"type": "quad", "corner": [-0.5, 3, -0.5], "edge1": [0, 0, 1], "edge2": [1, 0, 0], "material": "grey", "emission": {"radiance": 5}})";

TEST(EmitterOrientation, ALightFacingAwayFromEverythingIsNamed) {
    const std::vector<std::string> messages = emittersFacingAway(sceneWith(kUp));
    ASSERT_EQ(messages.size(), 1u);
    EXPECT_NE(messages[0].find("/shapes/1: emits on its front side only"), std::string::npos) << messages[0];
    EXPECT_NE(messages[0].find("\"two_sided\": true"), std::string::npos) << messages[0];
}

TEST(EmitterOrientation, LightsWithSomethingInFrontAreNotNamed) {
    EXPECT_TRUE(emittersFacingAway(sceneWith(kDown)).empty());
    const std::string ceiling =
        R"(, {"type": "quad", "corner": [-5, 4, -5], "edge1": [10, 0, 0], "edge2": [0, 0, 10], "material": "grey"})";
    EXPECT_TRUE(emittersFacingAway(sceneWith(kUp, ceiling)).empty());
    std::string twoSided = kUp;
    twoSided.replace(twoSided.find("\"radiance\": 5"), 13, "\"radiance\": 5, \"two_sided\": true");
    EXPECT_TRUE(emittersFacingAway(sceneWith(twoSided)).empty());
    EXPECT_TRUE(emittersFacingAway(sceneWith(kUp, "", "[0, 6, 5]")).empty());  // the camera sees its front
}

}  // namespace
}  // namespace penumbra
