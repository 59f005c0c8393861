// The integers that command-line options carry (`--res 640x480`, `--samples 16:64`, `--spp 1,2,4`),
// parsed in one place: the whole text must be an integer within the option's range, or the error
// names the option, the range and the text.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <string>

#include "core/error.h"

namespace penumbra {

inline int64_t parseIntegerOption(const std::string& option, const std::string& text, int64_t low, int64_t high) {
    size_t used = 0;
    long long value = 0;
    try {
        value = std::stoll(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (text.empty() || used != text.size() || value < low || value > high)
        throw InputError(fmt::format("{}: expected an integer in [{}, {}], got '{}'", option, low, high, text));
    return value;
}

}  // namespace penumbra
