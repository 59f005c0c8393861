// The lexical level of pbrt-v4's scene format: comments (# to the end of the line), quoted strings
// (with pbrt's backslash escapes), the brackets of parameter lists, and bare words (directives,
// numbers, true/false). Each token knows its line and column for messages.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "core/error.h"

namespace penumbra::pbrt {

struct Token {
    enum class Kind : uint8_t { End, Word, String, OpenBracket, CloseBracket };
    Kind kind = Kind::End;
    std::string_view text;  // a word or the inside of a string as written (escapes not resolved)
    int line = 0, column = 0;
    bool hasEscapes = false;  // a string holding a backslash: use Tokenizer::unescape
};

// Tokens of one file's text. The text must outlive the tokenizer (it returns views into it).
class Tokenizer {
public:
    Tokenizer(std::string_view text, std::string file) : text_(text), file_(std::move(file)) {}

    // The next token, or one of kind End at the end of the text. Throws InputError at an
    // unterminated string or a control character.
    Token next();
    // The token next() would return, without consuming it.
    const Token& peek();

    const std::string& file() const { return file_; }
    SourceLocation locationOf(const Token& token) const { return {file_, token.line, token.column, {}}; }
    [[noreturn]] void fail(const Token& token, const std::string& message) const;

    // The value of a string token (escapes \n \t \\ \" ... resolved).
    std::string stringValue(const Token& token) const;

private:
    Token scan();

    std::string_view text_;
    std::string file_;
    size_t pos_ = 0;
    int line_ = 1;
    size_t lineStart_ = 0;
    bool peeked_ = false;
    Token peekedToken_;
};

}  // namespace penumbra::pbrt
