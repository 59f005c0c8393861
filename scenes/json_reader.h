// Typed, located access to a parsed JSON document, for scene files.
//
// Every read says what it expected and names the file and the value's JSON pointer when the value
// does not fit, e.g. `scene.json: /film/spp: expected an integer >= 1, found 0`. Objects are
// opened with the list of keys they accept, so a misspelt key is reported instead of ignored.
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/rgb.h"
#include "core/vec.h"

namespace penumbra {

// Objects keep the order of the file, so that lists in messages and material indices follow it.
using Json = nlohmann::ordered_json;

// Parses JSON text with // and /* */ comments allowed. Syntax errors throw InputError with the
// file, line and column; duplicate keys throw InputError with the JSON pointer of the repeated key.
Json parseJsonText(std::string_view text, const std::string& fileForMessages);

// RFC 6901 escaping of one pointer token: "~" becomes "~0" and "/" becomes "~1".
std::string escapeJsonPointerToken(std::string_view token);

// A value of the document together with its place in it. Holds a reference: the document must
// outlive it.
class JsonValue {
public:
    JsonValue(const Json& json, std::string file, std::string pointer)
        : json_(&json), file_(std::move(file)), pointer_(std::move(pointer)) {}

    const Json& json() const { return *json_; }
    const std::string& file() const { return file_; }
    const std::string& pointer() const { return pointer_; }

    // Throws InputError at this value: "FILE: POINTER: message".
    [[noreturn]] void fail(const std::string& message) const;
    // Throws "expected WHAT, found <this value>".
    [[noreturn]] void failExpected(const std::string& what) const;
    // A short description of the value for messages: `-1`, `"abc"`, `an array of 2 values`, ...
    std::string describe() const;

    bool boolean() const;
    std::string string() const;
    // The string as the name of a regular file, relative to `folder` unless absolute; otherwise
    // fails with "the WHAT PATH does not exist" (or "is not a regular file").
    std::filesystem::path existingFile(const std::filesystem::path& folder, std::string_view what) const;
    // The string, which must be one of `choices`; returns its position in them.
    size_t choice(std::initializer_list<std::string_view> choices) const;
    size_t choice(std::span<const std::string_view> choices) const;

    // Finite numbers that fit in a float (1e39 does not).
    float number() const;
    float numberAtLeast(float min) const;             // number >= min
    float numberAbove(float min) const;               // number > min
    float numberInRange(float min, float max) const;  // min <= number <= max
    // A number without a fractional part, within [min, max].
    int64_t integer(int64_t min = std::numeric_limits<int64_t>::min(),
                    int64_t max = std::numeric_limits<int64_t>::max()) const;
    uint64_t unsignedInteger() const;

    Vec2f vec2() const;  // [x, y]
    Vec3f vec3() const;  // [x, y, z]
    // A colour given as [r, g, b] or as one number for grey; each channel within [min, max].
    Rgb rgb(float min, float max = std::numeric_limits<float>::max()) const;

    // Arrays.
    size_t arraySize() const;                 // fails unless this is an array
    JsonValue element(size_t index) const;    // fails unless this is an array of more than index
    std::vector<JsonValue> elements() const;  // fails unless this is an array

    // Objects: the members in file order, and a member's value when present.
    std::vector<std::pair<std::string, JsonValue>> members() const;
    std::optional<JsonValue> member(std::string_view key) const;
    JsonValue requiredMember(std::string_view key) const;

private:
    void requireObject() const;
    JsonValue child(const Json& json, std::string_view token) const;

    const Json* json_;
    std::string file_;
    std::string pointer_;
};

// An object whose keys have been checked against the keys it accepts (like pbrt-v4's
// ReportUnused, but up front): an unknown key is an error naming its pointer and the accepted keys.
class JsonObject {
public:
    JsonObject(const JsonValue& value, std::initializer_list<std::string_view> allowedKeys);
    JsonObject(const JsonValue& value, std::span<const std::string_view> allowedKeys);

    const JsonValue& value() const { return value_; }
    std::optional<JsonValue> get(std::string_view key) const { return value_.member(key); }
    JsonValue require(std::string_view key) const { return value_.requiredMember(key); }

private:
    JsonValue value_;
};

}  // namespace penumbra
