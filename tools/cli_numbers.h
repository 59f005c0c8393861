// The integers that command-line options carry (`--res 640x480`, `--samples 16:64`, `--spp 1,2,4`),
// parsed in one place: the whole text must be an integer within the option's range, or the error
// names the option, the range and the text.
#pragma once

#include <fmt/format.h>

#include <charconv>
#include <cstdint>
#include <string>

#include "core/error.h"

namespace penumbra {

inline int64_t parseIntegerOption(const std::string& option, const std::string& text, int64_t low,
                                  int64_t high) {
    size_t used = 0;
    long long value = 0;
    try {
        value = std::stoll(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (text.empty() || used != text.size() || value < low || value > high)
        throw InputError(
            fmt::format("{}: expected an integer in [{}, {}], got '{}'", option, low, high, text));
    return value;
}

// A 64-bit seed: the whole text must be decimal digits of a value below 2^64 ("-1" would wrap to
// 2^64 - 1 and "18446744073709551616" saturate, silently). "" when it is one, else what is wrong.
inline std::string checkSeedText(const std::string& text) {
    uint64_t value = 0;
    const char* end = text.data() + text.size();
    const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
    const auto result = std::from_chars(text.data(), end, value);
    if (digits && result.ec == std::errc() && result.ptr == end) return "";
    return fmt::format("expected an integer in [0, 18446744073709551615], got '{}'", text);
}

}  // namespace penumbra
