#include "core/error.h"

namespace penumbra {

std::string SourceLocation::describe() const {
    std::string out = file;
    if (line > 0) {
        // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on ":" + std::to_string(...).
        out += ':';
        out += std::to_string(line);
        if (column > 0) {
            out += ':';
            out += std::to_string(column);
        }
    }
    if (!jsonPointer.empty()) out += (out.empty() ? "" : ": ") + jsonPointer;
    return out;
}

static std::string composeMessage(const SourceLocation& where, const std::string& message) {
    const std::string place = where.describe();
    return place.empty() ? message : place + ": " + message;
}

void throwFileError(const std::filesystem::path& file, const std::string& message) {
    SourceLocation where;
    where.file = file.string();
    throw InputError(where, message);
}

InputError::InputError(SourceLocation where, const std::string& message)
    : std::runtime_error(composeMessage(where, message)), where_(std::move(where)), message_(message) {}

}  // namespace penumbra
