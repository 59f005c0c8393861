// "Did you mean": what a scene file's unknown `type` or key most likely meant. A name another
// renderer uses for one of ours (pbrt-v4's, Mitsuba 3's, Cycles') is answered from a table that
// says whose name it is; any other name gets the accepted one closest to it in spelling, when one
// is close enough to be a slip rather than another word.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace penumbra {

// "; did you mean 'lambert'? (pbrt-v4 and Mitsuba 3 call it 'diffuse')", or "; did you mean
// 'color'?", or "" when nothing accepted is near `given`. Only names in `accepted` are suggested.
std::string suggestName(std::string_view given, std::span<const std::string_view> accepted);

// The edit distance (insertions, deletions, substitutions, and swaps of neighbours) between two
// names, ignoring case and the separators '_', '-' and ' ' ("roughConductor" is 0 from
// "rough_conductor").
int nameDistance(std::string_view a, std::string_view b);

}  // namespace penumbra
