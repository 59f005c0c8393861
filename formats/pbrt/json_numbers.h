// Numbers as the pbrt importer writes them into penumbra's JSON: a float as the shortest decimal
// that reads back as the same float ("0.63", not "0.6299999952316284"): the loader reads floats,
// and the converted file stays readable.
#pragma once

#include <fmt/format.h>

#include <string>

#include "core/rgb.h"
#include "formats/pbrt/double_math.h"
#include "scenes/json_reader.h"

namespace penumbra::pbrt {

inline double shortest(float v) { return std::stod(fmt::format("{}", v)); }
inline Json rgbJson(Rgb c) { return Json::array({shortest(c.r), shortest(c.g), shortest(c.b)}); }
inline Json vec3Json(Vec3d v) { return Json::array({v.x, v.y, v.z}); }
// A matrix as penumbra's transform step {"matrix": [16 numbers, row by row]} takes it.
inline Json matrixJson(const Matrix4d& m) {
    Json out = Json::array();
    for (const auto& row : m.m)
        for (double v : row) out.push_back(v);
    return out;
}

}  // namespace penumbra::pbrt
