// Welding for the subdivision schemes (geometry/loop_subdivision.h, geometry/catmull_clark.h): a
// mesh file splits a vertex where its uvs or normals differ, but the surface's topology is that of
// its positions, so vertices at bitwise equal positions are one vertex of the scheme.
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <unordered_map>
#include <vector>

#include "core/vec.h"

namespace penumbra {

// For each vertex, the first vertex at a bitwise equal position.
inline std::vector<uint32_t> weldedVertexIds(const std::vector<Vec3f>& positions) {
    struct Bits {
        uint32_t x, y, z;
        bool operator==(const Bits&) const = default;
    };
    struct HashBits {
        size_t operator()(const Bits& b) const {
            return std::hash<uint64_t>()((uint64_t(b.x) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(b.y) << 21) ^
                                         (uint64_t(b.z) * 0xC2B2AE3D27D4EB4Full));
        }
    };
    std::unordered_map<Bits, uint32_t, HashBits> first;
    first.reserve(positions.size());
    std::vector<uint32_t> ids(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        Bits bits{};
        const Vec3f p = positions[i];
        std::memcpy(&bits.x, &p.x, 4), std::memcpy(&bits.y, &p.y, 4), std::memcpy(&bits.z, &p.z, 4);
        ids[i] = first.try_emplace(bits, uint32_t(i)).first->second;
    }
    return ids;
}

// The vertices of a mesh whose uvs are given per corner (face-varying): one per distinct (vertex,
// uv) pair, numbered in the order they first appear, so that one index buffer serves positions
// and uvs (a vertex is split along its uv seams).
class CornerVertices {
public:
    // The number of (vertex, uv); `added` is set when the pair is new (the caller appends its data).
    uint32_t idOf(uint32_t vertex, Vec2f uv, bool& added) {
        const auto [it, isNew] = ids_.try_emplace(Key{vertex, uv}, uint32_t(ids_.size()));
        added = isNew;
        return it->second;
    }
    void reserve(size_t count) { ids_.reserve(count); }

private:
    struct Key {
        uint32_t vertex;
        Vec2f uv;
        bool operator==(const Key& o) const { return vertex == o.vertex && uv.x == o.uv.x && uv.y == o.uv.y; }
    };
    struct HashKey {
        size_t operator()(const Key& k) const {
            uint32_t u, v;
            std::memcpy(&u, &k.uv.x, 4), std::memcpy(&v, &k.uv.y, 4);
            return std::hash<uint64_t>()((uint64_t(k.vertex) << 32) ^ (uint64_t(u) * 0x9E3779B97F4A7C15ull) ^
                                         v);
        }
    };
    std::unordered_map<Key, uint32_t, HashKey> ids_;
};

}  // namespace penumbra
