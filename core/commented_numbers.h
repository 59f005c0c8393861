// Text of numbers separated by white space, '#' starting a comment that runs to the end of its line:
// lens description files (cameras/lens_file.h) and pbrt-v4's spectrum files (formats/pbrt/spectrum.h).
// Each reader parses and checks the words itself (its own messages and bounds).
#pragma once

#include <string_view>

namespace penumbra {

inline bool isNumberTextSpace(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

// Calls visit(word, line) for each word outside comments (a run of characters that are neither white
// space nor '#'), in order, with its 1-based line; returns the text's last line.
template <typename Visit>
int forEachWordOutsideComments(std::string_view text, Visit&& visit) {
    int line = 1;
    size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (c == '\n') {
            ++line;
            ++i;
        } else if (isNumberTextSpace(c)) {
            ++i;
        } else if (c == '#') {
            while (i < text.size() && text[i] != '\n') ++i;
        } else {
            size_t end = i;
            while (end < text.size() && !isNumberTextSpace(text[end]) && text[end] != '#') ++end;
            visit(text.substr(i, end - i), line);
            i = end;
        }
    }
    return line;
}

}  // namespace penumbra
