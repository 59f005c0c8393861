// A scene file's reference to something the scene names (a material, a medium): the string, looked
// up among the names read so far. One rule for every such reference, and one message.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/json_reader.h"

namespace penumbra {

// The index of the name `value` holds in `names`. Otherwise fails at `value` with "unknown WHAT
// "x" (known PLURAL: a, b)" or "(the scene defines no PLURAL)", then `note` when given.
inline uint32_t readNameReference(const JsonValue& value, const std::vector<std::string>& names,
                                  std::string_view what, std::string_view plural,
                                  std::string_view note = "") {
    const std::string name = value.string();
    std::string known;
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i] == name) return uint32_t(i);
        known += (known.empty() ? "" : ", ") + names[i];
    }
    value.fail(fmt::format("unknown {} \"{}\" ({}{})", what, name,
                           known.empty() ? fmt::format("the scene defines no {}", plural)
                                         : fmt::format("known {}: {}", plural, known),
                           note));
}

}  // namespace penumbra
