// pbrt-v4's typed parameter lists: `"float fov" [45]`, `"rgb L" [1 2 3]`, `"string filename" "a.ply"`.
// The parser checks each value against its declared type; the readers then ask for parameters by
// name and type. A parameter of the wrong type is an error at its place, and every parameter that
// no reader asked for is reported afterwards (pbrt-v4's ReportUnused, here a warning).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "formats/pbrt/double_math.h"

namespace penumbra::pbrt {

class WarningLog;

enum class ParamType : uint8_t {
    Integer,
    Float,
    Point2,
    Vector2,
    Point3,
    Vector3,
    Normal,
    Bool,
    String,
    Texture,
    Rgb,
    Blackbody,
    Spectrum
};

// The type's name as the format spells it ("point3", "normal", ...).
std::string_view paramTypeName(ParamType type);
// The type a declaration names; "point", "vector", "normal3" and "color" are the format's aliases.
std::optional<ParamType> paramTypeFromName(std::string_view name);
// How many numbers make one value of the type (1 for scalars, 3 for points, 0 for non-numeric).
int valuesPerElement(ParamType type);

struct Parameter {
    ParamType type = ParamType::Float;
    std::string name;
    SourceLocation where;              // of the declaration string
    std::vector<double> numbers;       // numeric types, and spectra given as (wavelength, value) pairs
    std::vector<std::string> strings;  // string, texture, and spectra given by name or file
    std::vector<uint8_t> bools;
    mutable bool used = false;

    std::string declaration() const;  // "float fov", for messages
};

class ParameterList {
public:
    ParameterList() = default;
    explicit ParameterList(std::vector<Parameter> parameters) : parameters_(std::move(parameters)) {}

    // The parameter of this name, marked used; empty when absent. Throws InputError at the
    // parameter when its type is not one of `accepted`.
    const Parameter* find(std::string_view name, std::initializer_list<ParamType> accepted) const;
    bool has(std::string_view name) const;

    // Single values, which must be given exactly once; empty when absent.
    std::optional<double> getFloat(std::string_view name) const;
    std::optional<int64_t> getInt(std::string_view name) const;
    std::optional<bool> getBool(std::string_view name) const;
    std::optional<std::string> getString(std::string_view name) const;
    std::optional<Vec3d> getPoint3(std::string_view name) const;  // point3 or vector3

    // Arrays.
    std::vector<double> getFloats(std::string_view name) const;
    std::vector<int64_t> getInts(std::string_view name) const;
    std::vector<Vec3d> getPoint3s(std::string_view name) const;  // point3
    std::vector<Vec3d> getNormals(std::string_view name) const;  // normal
    std::vector<Vec2d> getPoint2s(std::string_view name) const;  // point2

    // Marks every parameter used (a directive that is ignored as a whole warns once for itself).
    void markAllUsed() const;
    // One warning per parameter no reader asked for: "unused parameter "float foo" of Shape "sphere"".
    void reportUnused(WarningLog& log, std::string_view owner) const;

    const std::vector<Parameter>& parameters() const { return parameters_; }
    std::vector<Parameter>& parameters() { return parameters_; }

private:
    std::vector<Parameter> parameters_;
};

[[noreturn]] void failAt(const SourceLocation& where, const std::string& message);

}  // namespace penumbra::pbrt
