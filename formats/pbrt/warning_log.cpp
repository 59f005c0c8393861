#include "formats/pbrt/warning_log.h"

#include <fmt/format.h>

namespace penumbra::pbrt {

void WarningLog::warn(const SourceLocation& where, const std::string& message) {
    auto [it, inserted] = index_.try_emplace(message, entries_.size());
    if (inserted) entries_.push_back({message, Entry{where, 0}});
    ++entries_[it->second].second.count;
}

std::vector<std::string> WarningLog::lines() const {
    std::vector<std::string> out;
    for (const auto& [message, entry] : entries_) {
        const std::string place = entry.first.describe();
        std::string line = place.empty() ? message : place + ": " + message;
        if (entry.count > 1) line += fmt::format(" ({} times)", entry.count);
        out.push_back(std::move(line));
    }
    return out;
}

}  // namespace penumbra::pbrt
