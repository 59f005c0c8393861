// The help's layout: option descriptions wrapped at word boundaries so that no line of `--help` is
// wider than kHelpWidth columns (CLI11 2.1 prints each description on one line, however long).
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <sstream>
#include <string>

namespace penumbra {

inline constexpr size_t kHelpWidth = 100;

// `text` with its spaces turned into line breaks where a line would pass `width` (a word longer
// than that keeps a line of its own); existing line breaks stay.
inline std::string wrapWords(const std::string& text, size_t width) {
    std::string wrapped;
    size_t lineLength = 0;
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find_first_of(" \n", start);
        if (end == std::string::npos) end = text.size();
        const size_t wordLength = end - start;
        if (lineLength > 0 && lineLength + 1 + wordLength > width) {
            wrapped += '\n';
            lineLength = 0;
        } else if (lineLength > 0) {
            wrapped += ' ';
            ++lineLength;
        }
        wrapped.append(text, start, wordLength);
        lineLength += wordLength;
        if (end < text.size() && text[end] == '\n') {
            wrapped += '\n';
            lineLength = 0;
        }
        start = end + 1;
    }
    return wrapped;
}

class HelpFormatter : public CLI::Formatter {
public:
    std::string make_description(const CLI::App* app) const override {
        return wrapWords(CLI::Formatter::make_description(app), kHelpWidth);
    }
    std::string make_subcommand(const CLI::App* sub) const override {
        std::stringstream out;
        CLI::detail::format_help(out, sub->get_display_name(true),
                                 wrapWords(sub->get_description(), textWidth()), get_column_width());
        return out.str();
    }
    std::string make_option_desc(const CLI::Option* option) const override {
        return wrapWords(option->get_description(), textWidth());
    }

private:
    // Of a description beside the names' column.
    size_t textWidth() const {
        const size_t column = get_column_width();
        return kHelpWidth > column + 20 ? kHelpWidth - column : 20;
    }
};

}  // namespace penumbra
