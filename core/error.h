// The one error type for bad user input: it carries the place (file, and a line or a JSON
// pointer) and says what was expected. `penumbra` prints it as
//   penumbra: error: FILE:LINE: message     or     penumbra: error: FILE: /json/pointer: message
// and exits non-zero.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace penumbra {

struct SourceLocation {
    std::string file;         // empty when the input is not a file (command line)
    int line = 0;             // 1-based, 0 when unknown
    int column = 0;           // 1-based, 0 when unknown
    std::string jsonPointer;  // RFC 6901 pointer into a JSON document, empty when unused

    std::string describe() const;
};

class InputError : public std::runtime_error {
public:
    InputError(SourceLocation where, const std::string& message);
    explicit InputError(const std::string& message) : InputError(SourceLocation{}, message) {}

    const SourceLocation& where() const { return where_; }
    const std::string& message() const { return message_; }

private:
    SourceLocation where_;
    std::string message_;
};

// An InputError about a whole file (no line or pointer): "FILE: message".
[[noreturn]] void throwFileError(const std::filesystem::path& file, const std::string& message);

}  // namespace penumbra
