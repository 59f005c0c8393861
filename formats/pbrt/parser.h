// pbrt-v4's scene grammar: directives with their fixed arguments and typed parameter lists, and
// Include / Import of other files. The parser knows each directive's argument shape and nothing
// of what it means; it hands every directive to a DirectiveTarget (the scene builder), as
// pbrt-v4's parser hands them to its ParserTarget.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "formats/pbrt/parameter_list.h"

namespace penumbra::pbrt {

struct Directive {
    std::string name;                  // "Shape", "Translate", ...
    SourceLocation where;              // of the directive's name
    std::vector<std::string> strings;  // leading string arguments: Shape "sphere" -> {"sphere"}
    std::vector<double> numbers;       // numeric arguments: Translate 1 2 3 -> {1, 2, 3}
    ParameterList parameters;
};

class DirectiveTarget {
public:
    virtual ~DirectiveTarget() = default;
    // The directive is the target's to keep (a shape's parameters are moved, not copied).
    virtual void directive(Directive&& directive) = 0;
    // The bytes of scene text read so far (every file, each time it is read), before the
    // directives of the text just read: what the target may make of the scene is bounded by it.
    virtual void textRead(uint64_t totalBytes) { (void)totalBytes; }
};

// Parses a scene file, with the files it includes, into `target`. Relative Include, Import and
// mesh file names are resolved against the folder of the first file, as pbrt-v4 does. Every file
// read is appended to `filesRead` (the scene file first). Throws InputError at FILE:LINE:COLUMN for
// syntax errors, unknown directives, malformed parameter lists and missing Include files, and at
// the Include or Import that would pass the limits on the files and text one scene may read
// (core/input_limits.h).
void parseSceneFile(const std::filesystem::path& file, DirectiveTarget& target,
                    std::vector<std::filesystem::path>& filesRead);

// The same for scene text in memory; `file` names it in messages and gives the base folder.
void parseSceneText(std::string_view text, const std::filesystem::path& file, DirectiveTarget& target,
                    std::vector<std::filesystem::path>& filesRead);

}  // namespace penumbra::pbrt
