// What a pbrt scene asks for that penumbra does not do, or does differently: never silent, and
// never one line per occurrence. Each distinct warning is one line with its first place and how
// many times it occurred: "scene.pbrt:12:5: unsupported directive MakeNamedMedium (3 times)".
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"

namespace penumbra::pbrt {

class WarningLog {
public:
    void warn(const SourceLocation& where, const std::string& message);
    // The lines, in the order the warnings first occurred.
    std::vector<std::string> lines() const;
    bool empty() const { return entries_.empty(); }

private:
    struct Entry {
        SourceLocation first;
        size_t count = 0;
    };
    std::map<std::string, size_t> index_;  // message -> position in entries_
    std::vector<std::pair<std::string, Entry>> entries_;
};

}  // namespace penumbra::pbrt
