#include "formats/pbrt/tokenizer.h"

#include <fmt/format.h>

namespace penumbra::pbrt {

namespace {

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
bool isDelimiter(char c) { return isSpace(c) || c == '"' || c == '[' || c == ']' || c == '#'; }

}  // namespace

void Tokenizer::fail(const Token& token, const std::string& message) const {
    throw InputError(locationOf(token), message);
}

const Token& Tokenizer::peek() {
    if (!peeked_) {
        peekedToken_ = scan();
        peeked_ = true;
    }
    return peekedToken_;
}

Token Tokenizer::next() {
    if (peeked_) {
        peeked_ = false;
        return peekedToken_;
    }
    return scan();
}

Token Tokenizer::scan() {
    const size_t size = text_.size();
    while (pos_ < size) {
        const char c = text_[pos_];
        if (c == '\n' || (c == '\r' && (pos_ + 1 == size || text_[pos_ + 1] != '\n'))) {
            // A lone CR ends a line too (old Mac files), as it ends a comment in pbrt-v4: counted
            // as one, so that messages name the line an editor shows.
            ++pos_;
            ++line_;
            lineStart_ = pos_;
        } else if (isSpace(c)) {
            ++pos_;
        } else if (c == '#') {
            // pbrt-v4 ends a comment at CR as at LF: a CR-only file's comment must not swallow
            // the rest of the file.
            while (pos_ < size && text_[pos_] != '\n' && text_[pos_] != '\r') ++pos_;
        } else {
            break;
        }
    }
    Token token;
    token.line = line_;
    token.column = int(pos_ - lineStart_) + 1;
    if (pos_ >= size) return token;
    const char c = text_[pos_];
    if (c == '[' || c == ']') {
        token.kind = c == '[' ? Token::Kind::OpenBracket : Token::Kind::CloseBracket;
        token.text = text_.substr(pos_++, 1);
        return token;
    }
    if (c == '"') {
        const size_t start = ++pos_;
        while (true) {
            if (pos_ >= size || text_[pos_] == '\n' || text_[pos_] == '\r')
                fail(token, "unterminated string: a string must end with \" on the line where it starts");
            if (text_[pos_] == '\\') {
                token.hasEscapes = true;
                if (++pos_ >= size) continue;  // reported as unterminated above
            } else if (text_[pos_] == '"') {
                break;
            }
            ++pos_;
        }
        token.kind = Token::Kind::String;
        token.text = text_.substr(start, pos_ - start);
        ++pos_;
        return token;
    }
    if (static_cast<unsigned char>(c) < 0x20)
        fail(token, fmt::format("unexpected control character (code {}) in the scene text", int(c)));
    const size_t start = pos_;
    while (pos_ < size && !isDelimiter(text_[pos_])) ++pos_;
    token.kind = Token::Kind::Word;
    token.text = text_.substr(start, pos_ - start);
    return token;
}

std::string Tokenizer::stringValue(const Token& token) const {
    if (!token.hasEscapes) return std::string(token.text);
    std::string out;
    for (size_t i = 0; i < token.text.size(); ++i) {
        char c = token.text[i];
        if (c == '\\' && i + 1 < token.text.size()) {
            switch (token.text[++i]) {
                case 'b':
                    c = '\b';
                    break;
                case 'f':
                    c = '\f';
                    break;
                case 'n':
                    c = '\n';
                    break;
                case 'r':
                    c = '\r';
                    break;
                case 't':
                    c = '\t';
                    break;
                case '\\':
                    c = '\\';
                    break;
                case '\'':
                    c = '\'';
                    break;
                case '"':
                    c = '"';
                    break;
                default:
                    fail(token, fmt::format("unknown escape sequence \\{} in a string", token.text[i]));
            }
        }
        out += c;
    }
    return out;
}

}  // namespace penumbra::pbrt
