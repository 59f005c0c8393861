#include "tools/script_text.h"

#include <fmt/format.h>

#include <algorithm>
#include <string_view>

#include "core/error.h"

namespace penumbra {

namespace {

bool isControl(unsigned char c) { return c < 0x20 || c == 0x7f; }

// The text with its control characters written as \xNN, for a message of one line.
std::string printable(const std::string& text) {
    std::string shown;
    for (char c : text)
        shown += isControl(static_cast<unsigned char>(c)) ? fmt::format("\\x{:02x}", c) : std::string(1, c);
    return shown;
}

}  // namespace

void requireOneLineOfText(const std::string& what, const std::string& text) {
    for (size_t i = 0; i < text.size(); ++i)
        if (isControl(static_cast<unsigned char>(text[i])))
            throw InputError(
                fmt::format("{}: '{}' contains a control character (\\x{:02x}, at byte {}); it is written "
                            "into the batch scripts, where every value must be one line of text",
                            what, printable(text), text[i], i));
}

std::string shellQuote(const std::string& text) {
    std::string quoted = "'";
    for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

std::string sbatchQuote(const std::string& text) {
    const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               std::string_view("-_=.,:/+@%").find(c) != std::string_view::npos;
    });
    if (plain) return text;  // --account=lab reads as it is
    std::string quoted = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') quoted += '\\';
        quoted += c;
    }
    return quoted + "\"";
}

std::string sbatchQuoteFilenamePattern(const std::string& literalPath, const std::string& pattern) {
    std::string escaped;
    for (char c : literalPath) escaped += c == '%' ? std::string("%%") : std::string(1, c);
    return sbatchQuote(escaped + pattern);
}

}  // namespace penumbra
