// Splitting command-line values such as "1,2,4" or "64:256" at a separator.
#pragma once

#include <string>
#include <vector>

namespace penumbra {

// The pieces between separators, empty ones included ("a,,b" gives "a", "", "b").
inline std::vector<std::string> splitText(const std::string& text, char separator) {
    std::vector<std::string> parts;
    size_t start = 0;
    for (size_t i = 0; i <= text.size(); ++i)
        if (i == text.size() || text[i] == separator) {
            parts.push_back(text.substr(start, i - start));
            start = i + 1;
        }
    return parts;
}

}  // namespace penumbra
