#include "scenes/name_suggestion.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <vector>

namespace penumbra {

namespace {

// Other renderers' names for what penumbra calls otherwise (their scene formats' type names and
// Cycles' node names), with whose they are. A name that penumbra spells the same way is not here.
struct ForeignName {
    std::string_view name, ours, whose;
};
constexpr std::array<ForeignName, 24> kForeignNames{{
    // Materials
    {"diffuse", "lambert", "pbrt-v4 and Mitsuba 3 call it 'diffuse', Cycles 'Diffuse BSDF'"},
    {"diffuse_bsdf", "lambert", "Cycles calls it 'Diffuse BSDF'"},
    {"coateddiffuse", "coated_diffuse", "pbrt-v4 calls it 'coateddiffuse'"},
    {"plastic", "coated_diffuse", "Mitsuba 3 calls a smooth coated diffuse 'plastic'"},
    {"roughplastic", "coated_diffuse", "Mitsuba 3 calls it 'roughplastic'"},
    {"thindielectric", "thin_dielectric", "pbrt-v4 and Mitsuba 3 call it 'thindielectric'"},
    {"roughdielectric", "rough_dielectric", "Mitsuba 3 calls it 'roughdielectric'"},
    {"glass", "dielectric", "Cycles calls it 'Glass BSDF'"},
    {"glass_bsdf", "dielectric", "Cycles calls it 'Glass BSDF'"},
    {"roughconductor", "rough_conductor", "Mitsuba 3 calls it 'roughconductor'"},
    {"glossy", "rough_conductor", "Cycles calls a metal 'Glossy BSDF'"},
    {"glossy_bsdf", "rough_conductor", "Cycles calls a metal 'Glossy BSDF'"},
    {"diffusetransmission", "diffuse_transmission", "pbrt-v4 calls it 'diffusetransmission'"},
    {"translucent_bsdf", "diffuse_transmission", "Cycles calls diffuse transmission 'Translucent BSDF'"},
    // Shapes
    {"trianglemesh", "triangle_mesh", "pbrt-v4 calls it 'trianglemesh'"},
    {"plymesh", "mesh_file", "pbrt-v4 calls it 'plymesh'"},
    {"obj", "mesh_file", "Mitsuba 3 calls it 'obj'"},
    {"ply", "mesh_file", "Mitsuba 3 calls it 'ply'"},
    {"rectangle", "quad", "Mitsuba 3 calls it 'rectangle'"},
    // Lights and the environment
    {"distant", "directional", "pbrt-v4 calls it 'distant'"},
    {"sun", "directional", "Cycles calls it 'Sun'"},
    {"envmap", "image", "Mitsuba 3 calls an environment map 'envmap'"},
    // Textures
    {"imagemap", "image", "pbrt-v4 calls it 'imagemap'"},
    {"bitmap", "image", "Mitsuba 3 calls it 'bitmap'"},
}};

// Names for a light that is a shape: penumbra has no such type; a shape emits by its "emission".
constexpr std::array<std::string_view, 6> kEmittingShapeNames{"emission", "emitter",   "emissive",
                                                              "area",     "arealight", "diffuselight"};

// The name as compared: lower case, without separators.
std::string folded(std::string_view name) {
    std::string f;
    for (char c : name)
        if (c != '_' && c != '-' && c != ' ') f += char(std::tolower(static_cast<unsigned char>(c)));
    return f;
}

bool isAccepted(std::string_view name, std::span<const std::string_view> accepted) {
    return std::find(accepted.begin(), accepted.end(), name) != accepted.end();
}

}  // namespace

int nameDistance(std::string_view a, std::string_view b) {
    const std::string s = folded(a), t = folded(b);
    // Optimal string alignment: three rows of the dynamic programme.
    std::vector<int> before(t.size() + 1), previous(t.size() + 1), current(t.size() + 1);
    for (size_t j = 0; j <= t.size(); ++j) previous[j] = int(j);
    for (size_t i = 1; i <= s.size(); ++i) {
        current[0] = int(i);
        for (size_t j = 1; j <= t.size(); ++j) {
            const int substitution = previous[j - 1] + (s[i - 1] == t[j - 1] ? 0 : 1);
            current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
            if (i > 1 && j > 1 && s[i - 1] == t[j - 2] && s[i - 2] == t[j - 1])
                current[j] = std::min(current[j], before[j - 2] + 1);
        }
        before.swap(previous);
        previous.swap(current);
    }
    return previous[t.size()];
}

std::string suggestName(std::string_view given, std::span<const std::string_view> accepted) {
    const std::string key = folded(given);
    for (std::string_view name : kEmittingShapeNames)
        if (key == name)
            return "; a shape that emits light is any shape with an \"emission\" object "
                   "({\"radiance\": [r, g, b]}), not a type of its own (scenes/README.md)";
    for (const ForeignName& f : kForeignNames)
        if (folded(f.name) == key && isAccepted(f.ours, accepted))
            return fmt::format("; did you mean '{}'? ({})", f.ours, f.whose);
    // A slip: at most a third of the name's letters wrong (one for names of up to five letters).
    const size_t allowed = std::max<size_t>(1, key.size() / 3);
    std::string_view best;
    size_t bestDistance = allowed + 1;
    for (std::string_view name : accepted) {
        // The distance is at least the difference in length: a long name (a whole line pasted as
        // a key) is passed over without the quadratic comparison.
        const size_t length = folded(name).size();
        if ((key.size() > length ? key.size() - length : length - key.size()) > allowed) continue;
        const size_t d = size_t(nameDistance(given, name));
        if (d < bestDistance) {
            best = name;
            bestDistance = d;
        }
    }
    return best.empty() ? "" : fmt::format("; did you mean '{}'?", best);
}

}  // namespace penumbra
