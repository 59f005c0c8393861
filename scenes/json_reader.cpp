#include "scenes/json_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <system_error>

#include "core/error.h"
#include "core/input_limits.h"
#include "scenes/name_suggestion.h"

namespace penumbra {

namespace {

// 1-based line and column of the byte at `offset` (clamped to the end of the text).
SourceLocation locationOfOffset(std::string_view text, size_t offset, const std::string& file) {
    offset = std::min(offset, text.size());
    SourceLocation where;
    where.file = file;
    const std::string_view before = text.substr(0, offset);
    where.line = 1 + int(std::count(before.begin(), before.end(), '\n'));
    const size_t lineStart = before.rfind('\n');
    where.column = int(offset - (lineStart == std::string_view::npos ? 0 : lineStart + 1)) + 1;
    return where;
}

// nlohmann's messages start with "[json.exception.parse_error.101] parse error at line 3,
// column 5: "; we print our own location, so keep only the explanation after it.
std::string explanationOf(const std::string& what) {
    size_t start = what.find("] ");
    start = start == std::string::npos ? 0 : start + 2;
    const size_t afterLocation = what.find(": ", start);
    if (what.compare(start, 11, "parse error") == 0 && afterLocation != std::string::npos)
        start = afterLocation + 2;
    return what.substr(start);
}

// Tracks where the parser is, to name a repeated key by its JSON pointer (nlohmann keeps one of
// the two values silently, which would hide e.g. two materials with the same name).
class DuplicateKeyCheck {
public:
    explicit DuplicateKeyCheck(std::string file) : file_(std::move(file)) {}

    bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
        switch (event) {
            case Json::parse_event_t::object_start:
                frames_.emplace_back(false);
                break;
            case Json::parse_event_t::array_start:
                frames_.emplace_back(true);
                break;
            case Json::parse_event_t::key: {
                Frame& top = frames_.back();
                top.key = parsed.get<std::string>();
                if (!top.keys.insert(top.key).second)
                    throw InputError({file_, 0, 0, pointer()}, "duplicate key (each key may appear once)");
                break;
            }
            case Json::parse_event_t::object_end:
            case Json::parse_event_t::array_end:
                frames_.pop_back();
                finishedValue();
                break;
            case Json::parse_event_t::value:
                finishedValue();
                break;
        }
        return true;
    }

private:
    struct Frame {
        explicit Frame(bool array) : isArray(array) {}
        bool isArray;
        size_t index = 0;  // arrays: index of the element being read
        std::string key;   // objects: key of the member being read
        std::set<std::string> keys;
    };

    void finishedValue() {
        if (!frames_.empty() && frames_.back().isArray) ++frames_.back().index;
    }

    std::string pointer() const {
        std::string out;
        for (const Frame& f : frames_)
            out += "/" + (f.isArray ? std::to_string(f.index) : escapeJsonPointerToken(f.key));
        return out;
    }

    std::string file_;
    std::vector<Frame> frames_;
};

}  // namespace

Json parseJsonText(std::string_view text, const std::string& file) {
    try {
        return Json::parse(text.begin(), text.end(), DuplicateKeyCheck(file),
                           /*allow_exceptions=*/true, /*ignore_comments=*/true);
    } catch (const Json::parse_error& e) {
        // e.byte counts the bytes read, so the offending byte is the last one read.
        throw InputError(locationOfOffset(text, e.byte == 0 ? 0 : e.byte - 1, file), explanationOf(e.what()));
    } catch (const Json::out_of_range& e) {
        // A number too large for a double ("number overflow parsing '1e400'") comes without a
        // position; point at the first occurrence of the number in the text instead.
        const std::string message = explanationOf(e.what());
        const size_t open = message.find('\''), close = message.rfind('\'');
        size_t offset = std::string_view::npos;
        if (open != std::string::npos && close > open)
            offset = text.find(message.substr(open + 1, close - open - 1));
        if (offset == std::string_view::npos) throw InputError({file, 0, 0, ""}, message);
        throw InputError(locationOfOffset(text, offset, file), message);
    } catch (const Json::exception& e) {
        throw InputError({file, 0, 0, ""}, explanationOf(e.what()));
    }
}

std::string escapeJsonPointerToken(std::string_view token) {
    std::string out;
    for (char c : token) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
    return out;
}

// ---- JsonValue ----

void JsonValue::fail(const std::string& message) const { throw InputError({file_, 0, 0, pointer_}, message); }

void JsonValue::failExpected(const std::string& what) const {
    fail("expected " + what + ", found " + describe());
}

std::string JsonValue::describe() const {
    const Json& j = *json_;
    if (j.is_object()) return j.empty() ? "an empty object" : "an object";
    if (j.is_array())
        return j.size() == 1 ? "an array of 1 value" : fmt::format("an array of {} values", j.size());
    std::string text = j.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return j.is_string() ? "the string " + text : text;
}

bool JsonValue::boolean() const {
    if (!json_->is_boolean()) failExpected("true or false");
    return json_->get<bool>();
}

std::string JsonValue::string() const {
    if (!json_->is_string()) failExpected("a string");
    return json_->get<std::string>();
}

std::filesystem::path JsonValue::existingFile(const std::filesystem::path& folder,
                                              std::string_view what) const {
    std::filesystem::path path = string();
    if (path.is_relative()) path = folder / path;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        fail(fmt::format("the {} {} {}", what, path.string(),
                         std::filesystem::exists(path, ec) ? "is not a regular file" : "does not exist"));
    return path;
}

size_t JsonValue::choice(std::initializer_list<std::string_view> choices) const {
    return choice(std::span<const std::string_view>(choices.begin(), choices.size()));
}

size_t JsonValue::choice(std::span<const std::string_view> choices) const {
    std::string list;
    for (std::string_view c : choices) list += (list.empty() ? "" : ", ") + std::string(c);
    if (!json_->is_string()) failExpected("one of: " + list);
    const std::string s = json_->get<std::string>();
    size_t index = 0;
    for (std::string_view c : choices) {
        if (s == c) return index;
        ++index;
    }
    fail("expected one of: " + list + ", found " + describe() + suggestName(s, choices));
}

float JsonValue::number() const {
    if (!json_->is_number()) failExpected("a number");
    const double d = json_->get<double>();
    if (!std::isfinite(d) || std::abs(d) > double(std::numeric_limits<float>::max()))
        fail(fmt::format("the number {} is out of range (expected a finite 32-bit float)", json_->dump()));
    return float(d);
}

float JsonValue::numberAtLeast(float min) const {
    if (!json_->is_number() || number() < min) failExpected(fmt::format("a number >= {}", min));
    return number();
}

float JsonValue::numberAbove(float min) const {
    if (!json_->is_number() || !(number() > min)) failExpected(fmt::format("a number > {}", min));
    return number();
}

float JsonValue::numberInRange(float min, float max) const {
    if (!json_->is_number() || number() < min || number() > max)
        failExpected(fmt::format("a number in [{}, {}]", min, max));
    return number();
}

int64_t JsonValue::integer(int64_t min, int64_t max) const {
    // Bounds at or beyond 32-bit limits only guard against overflow; messages leave them out
    // unless the value breaks them.
    constexpr int64_t kLarge = std::numeric_limits<int32_t>::max();
    std::string what = "an integer";
    if (min > -kLarge && max < kLarge)
        what = fmt::format("an integer in [{}, {}]", min, max);
    else if (min > -kLarge)
        what = fmt::format("an integer >= {}", min);
    else if (max < kLarge)
        what = fmt::format("an integer <= {}", max);
    const std::string whatWithBounds = fmt::format("an integer in [{}, {}]", min, max);

    int64_t value = 0;
    if (json_->is_number_unsigned()) {
        const uint64_t u = json_->get<uint64_t>();
        if (u > uint64_t(max)) failExpected(whatWithBounds);
        value = int64_t(u);
    } else if (json_->is_number_integer()) {
        value = json_->get<int64_t>();
    } else if (json_->is_number_float()) {
        // 16.0 is accepted as 16; 16.5 and 1e30 are not.
        const double d = json_->get<double>();
        if (d != std::floor(d)) failExpected(what);
        if (!(std::abs(d) < 9.0e18)) failExpected(whatWithBounds);
        value = int64_t(d);
    } else {
        failExpected(what);
    }
    if (value < min) failExpected(what);
    if (value > max) failExpected(whatWithBounds);
    return value;
}

uint64_t JsonValue::unsignedInteger() const {
    if (json_->is_number_unsigned()) return json_->get<uint64_t>();
    return uint64_t(integer(0));
}

Vec2f JsonValue::vec2() const {
    if (!json_->is_array() || json_->size() != 2) failExpected("an array of 2 numbers");
    return {element(0).number(), element(1).number()};
}

Vec3f JsonValue::vec3() const {
    if (!json_->is_array() || json_->size() != 3) failExpected("an array of 3 numbers");
    // Positions, offsets and axes alike: beyond the limit, squared distances overflow a float.
    float v[3];
    for (size_t i = 0; i < 3; ++i) {
        const JsonValue e = element(i);
        v[i] = e.number();
        if (std::abs(v[i]) > limits::kMaxCoordinate)
            e.fail(fmt::format(
                "the coordinate {} is beyond penumbra's limit of {:g} in magnitude (docs/limits.md)",
                e.json().dump(), limits::kMaxCoordinate));
    }
    return {v[0], v[1], v[2]};
}

Rgb JsonValue::rgb(float min, float max) const {
    const bool bounded = max < std::numeric_limits<float>::max();
    auto channel = [&](const JsonValue& v) {
        return bounded ? v.numberInRange(min, max) : v.numberAtLeast(min);
    };
    if (json_->is_number()) return Rgb(channel(*this));
    if (!json_->is_array() || json_->size() != 3)
        failExpected("a number or an array of 3 numbers (r, g, b), each " +
                     (bounded ? fmt::format("in [{}, {}]", min, max) : fmt::format(">= {}", min)));
    return {channel(element(0)), channel(element(1)), channel(element(2))};
}

size_t JsonValue::arraySize() const {
    if (!json_->is_array()) failExpected("an array");
    return json_->size();
}

JsonValue JsonValue::element(size_t index) const {
    if (index >= arraySize()) failExpected(fmt::format("an array of at least {} values", index + 1));
    return child((*json_)[index], std::to_string(index));
}

std::vector<JsonValue> JsonValue::elements() const {
    std::vector<JsonValue> out;
    out.reserve(arraySize());
    for (size_t i = 0; i < json_->size(); ++i) out.push_back(child((*json_)[i], std::to_string(i)));
    return out;
}

void JsonValue::requireObject() const {
    if (!json_->is_object()) failExpected("an object");
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::members() const {
    requireObject();
    std::vector<std::pair<std::string, JsonValue>> out;
    for (const auto& [key, value] : json_->items()) out.emplace_back(key, child(value, key));
    return out;
}

std::optional<JsonValue> JsonValue::member(std::string_view key) const {
    requireObject();
    const auto it = json_->find(std::string(key));
    if (it == json_->end()) return std::nullopt;
    return child(*it, key);
}

JsonValue JsonValue::requiredMember(std::string_view key) const {
    if (auto value = member(key)) return *value;
    fail(fmt::format("missing required key \"{}\"", key));
}

JsonValue JsonValue::child(const Json& json, std::string_view token) const {
    return JsonValue(json, file_, pointer_ + "/" + escapeJsonPointerToken(token));
}

// ---- JsonObject ----

JsonObject::JsonObject(const JsonValue& value, std::initializer_list<std::string_view> allowedKeys)
    : JsonObject(value, std::span<const std::string_view>(allowedKeys.begin(), allowedKeys.size())) {}

JsonObject::JsonObject(const JsonValue& value, std::span<const std::string_view> allowedKeys)
    : value_(value) {
    for (const auto& [key, member] : value.members()) {
        if (std::find(allowedKeys.begin(), allowedKeys.end(), key) != allowedKeys.end()) continue;
        std::string list;
        for (std::string_view k : allowedKeys) list += (list.empty() ? "" : ", ") + std::string(k);
        member.fail("unknown key (expected one of: " + list + ")" + suggestName(key, allowedKeys));
    }
}

}  // namespace penumbra
