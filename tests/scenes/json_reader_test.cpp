#include "scenes/json_reader.h"

#include <gtest/gtest.h>

#include "tests/support/expect_input_error.h"

namespace penumbra {
namespace {

using testing::catchInputError;

TEST(JsonReader, ParsesCommentsAndKeepsKeyOrder) {
    const Json json = parseJsonText("// leading comment\n{\"b\": 1, /* inline */ \"a\": [2, 3]}", "t.json");
    ASSERT_TRUE(json.is_object());
    EXPECT_EQ(json.begin().key(), "b");  // file order, not sorted
    EXPECT_EQ(json["a"][1].get<int>(), 3);
}

TEST(JsonReader, SyntaxErrorReportsLineAndColumn) {
    // The stray '}' after the trailing comma is at line 3, column 22.
    const std::string text = "// comment\n{\n  \"film\": {\"spp\": 16,}\n}\n";
    const InputError e = catchInputError([&] { parseJsonText(text, "bad.json"); });
    EXPECT_EQ(e.where().file, "bad.json");
    EXPECT_EQ(e.where().line, 3);
    EXPECT_EQ(e.where().column, 22);
    EXPECT_CONTAINS(e.what(), "bad.json:3:22: ");
    EXPECT_CONTAINS(e.what(), "syntax error");
    EXPECT_CONTAINS(e.what(), "expected string literal");
    EXPECT_EQ(std::string(e.what()).find("json.exception"), std::string::npos) << e.what();
}

TEST(JsonReader, UnexpectedEndOfInputPointsAtTheEnd) {
    const InputError e = catchInputError([] { parseJsonText("{\n  \"a\": [1, 2", "cut.json"); });
    EXPECT_EQ(e.where().line, 2);
    EXPECT_CONTAINS(e.what(), "cut.json:2:");
    EXPECT_CONTAINS(e.what(), "end of input");
}

TEST(JsonReader, NumberTooLargeForADoubleHasAPosition) {
    const InputError e = catchInputError([] { parseJsonText("{\n \"a\": 1e400\n}", "big.json"); });
    EXPECT_EQ(e.where().line, 2);
    EXPECT_EQ(e.where().column, 7);
    EXPECT_CONTAINS(e.what(), "1e400");
}

TEST(JsonReader, DuplicateKeysAreErrorsNamingTheirPointer) {
    InputError e = catchInputError([] { parseJsonText(R"({"materials": {"a": {}, "a": {}}})", "dup.json"); });
    EXPECT_EQ(e.where().jsonPointer, "/materials/a");
    EXPECT_CONTAINS(e.what(), "duplicate key");

    e = catchInputError(
        [] { parseJsonText(R"({"shapes": [{"x": [1, {}]}, {"t": 1, "t": 2}]})", "dup.json"); });
    EXPECT_EQ(e.where().jsonPointer, "/shapes/1/t");

    // The same key in different objects is fine.
    EXPECT_NO_THROW(parseJsonText(R"({"a": {"k": 1}, "b": {"k": 2}, "c": [{"k": 3}, {"k": 4}]})", "ok.json"));
}

TEST(JsonReader, TypedReadsNameThePointerAndWhatWasExpected) {
    const Json json = parseJsonText(
        R"({"s": "abc", "big": 1e39, "half": 16.5, "whole": 16.0, "pair": [1, 2], "neg": -1,
            "grey": 0.25, "rgb": [0.1, 2, 0.3], "flag": 1})",
        "t.json");
    const JsonValue root(json, "t.json", "");
    const JsonObject object(root, {"s", "big", "half", "whole", "pair", "neg", "grey", "rgb", "flag"});

    InputError e = catchInputError([&] { object.require("s").number(); });
    EXPECT_EQ(std::string(e.what()), "t.json: /s: expected a number, found the string \"abc\"");

    e = catchInputError([&] { object.require("big").number(); });
    EXPECT_EQ(e.where().jsonPointer, "/big");
    EXPECT_CONTAINS(e.what(), "out of range");

    e = catchInputError([&] { object.require("half").integer(1); });
    EXPECT_CONTAINS(e.what(), "/half: expected an integer >= 1, found 16.5");
    EXPECT_EQ(object.require("whole").integer(1), 16);

    e = catchInputError([&] { object.require("pair").vec3(); });
    EXPECT_CONTAINS(e.what(), "/pair: expected an array of 3 numbers, found an array of 2 values");
    const Vec2f pair = object.require("pair").vec2();
    EXPECT_EQ(pair.x, 1.0f);
    EXPECT_EQ(pair.y, 2.0f);

    e = catchInputError([&] { object.require("neg").unsignedInteger(); });
    EXPECT_CONTAINS(e.what(), "/neg: expected an integer >= 0, found -1");

    EXPECT_EQ(object.require("grey").rgb(0, 1), Rgb(0.25f));
    e = catchInputError([&] { object.require("rgb").rgb(0, 1); });
    EXPECT_EQ(e.where().jsonPointer, "/rgb/1");
    EXPECT_CONTAINS(e.what(), "expected a number in [0, 1], found 2");

    e = catchInputError([&] { object.require("flag").boolean(); });
    EXPECT_CONTAINS(e.what(), "/flag: expected true or false, found 1");

    e = catchInputError([&] { object.require("missing"); });
    EXPECT_CONTAINS(e.what(), "t.json: missing required key \"missing\"");
}

TEST(JsonReader, ChoiceListsTheChoices) {
    const Json json = parseJsonText(R"({"type": "gauss"})", "t.json");
    const JsonValue root(json, "t.json", "");
    const InputError e = catchInputError([&] { root.requiredMember("type").choice({"box", "tent"}); });
    EXPECT_CONTAINS(e.what(), "/type: expected one of: box, tent, found the string \"gauss\"");
}

TEST(JsonReader, UnknownKeysAreErrorsListingTheAcceptedKeys) {
    const Json json = parseJsonText(R"({"shapes": [{}, {}, {"type": "sphere", "radus": 1}]})", "scene.json");
    const JsonValue shape = JsonValue(json, "scene.json", "").requiredMember("shapes").element(2);
    const InputError e = catchInputError([&] {
        JsonObject(shape, {"type", "center", "radius", "material", "emission"});
    });
    EXPECT_EQ(std::string(e.what()),
              "scene.json: /shapes/2/radus: unknown key (expected one of: type, center, radius, material, "
              "emission); did you mean 'radius'?");
    EXPECT_NO_THROW(JsonObject(shape, {"type", "radus"}));
}

TEST(JsonReader, PointerTokensAreEscaped) {
    EXPECT_EQ(escapeJsonPointerToken("a/b~c"), "a~1b~0c");
    const Json json = parseJsonText(R"({"a/b": {"c~d": "x"}})", "t.json");
    const JsonValue value = JsonValue(json, "t.json", "").requiredMember("a/b").requiredMember("c~d");
    EXPECT_EQ(value.pointer(), "/a~1b/c~0d");
}

}  // namespace
}  // namespace penumbra
