#include "formats/pbrt/parameter_list.h"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "formats/pbrt/warning_log.h"

namespace penumbra::pbrt {

namespace {

struct TypeName {
    std::string_view name;
    ParamType type;
};

constexpr std::array<TypeName, 17> kTypeNames{{
    {"integer", ParamType::Integer},
    {"float", ParamType::Float},
    {"point2", ParamType::Point2},
    {"vector2", ParamType::Vector2},
    {"point3", ParamType::Point3},
    {"vector3", ParamType::Vector3},
    {"normal", ParamType::Normal},
    {"bool", ParamType::Bool},
    {"string", ParamType::String},
    {"texture", ParamType::Texture},
    {"rgb", ParamType::Rgb},
    {"blackbody", ParamType::Blackbody},
    {"spectrum", ParamType::Spectrum},
    // The format's aliases.
    {"point", ParamType::Point3},
    {"vector", ParamType::Vector3},
    {"normal3", ParamType::Normal},
    {"color", ParamType::Rgb},
}};

std::string listTypes(std::initializer_list<ParamType> types) {
    std::string out;
    size_t i = 0;
    for (ParamType t : types) {
        if (i++) out += i == types.size() ? " or " : ", ";
        out += paramTypeName(t);
    }
    return out;
}

}  // namespace

void failAt(const SourceLocation& where, const std::string& message) { throw InputError(where, message); }

std::string_view paramTypeName(ParamType type) {
    for (const TypeName& t : kTypeNames)
        if (t.type == type) return t.name;
    return "?";
}

std::optional<ParamType> paramTypeFromName(std::string_view name) {
    for (const TypeName& t : kTypeNames)
        if (t.name == name) return t.type;
    return std::nullopt;
}

int valuesPerElement(ParamType type) {
    switch (type) {
        case ParamType::Integer:
        case ParamType::Float:
        case ParamType::Blackbody:
            return 1;
        case ParamType::Point2:
        case ParamType::Vector2:
            return 2;
        case ParamType::Point3:
        case ParamType::Vector3:
        case ParamType::Normal:
        case ParamType::Rgb:
            return 3;
        default:
            return 0;
    }
}

std::string Parameter::declaration() const { return fmt::format("{} {}", paramTypeName(type), name); }

const Parameter* ParameterList::find(std::string_view name, std::initializer_list<ParamType> accepted) const {
    const Parameter* found = nullptr;
    for (const Parameter& p : parameters_)
        if (p.name == name) found = &p;  // the last one given wins, as in pbrt
    if (!found) return nullptr;
    for (const Parameter& p : parameters_)
        if (p.name == name) p.used = true;
    for (ParamType t : accepted)
        if (found->type == t) return found;
    failAt(found->where, fmt::format("parameter \"{}\" has the wrong type: expected {}, found \"{}\"", name,
                                     listTypes(accepted), found->declaration()));
}

bool ParameterList::has(std::string_view name) const {
    for (const Parameter& p : parameters_)
        if (p.name == name) return true;
    return false;
}

namespace {

const Parameter* single(const Parameter* p, size_t count) {
    if (p && count != 1)
        failAt(p->where, fmt::format("parameter \"{}\" takes one value, found {}", p->declaration(), count));
    return p;
}

}  // namespace

std::optional<double> ParameterList::getFloat(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::Float, ParamType::Integer});
    if (!single(p, p ? p->numbers.size() : 0)) return std::nullopt;
    return p->numbers[0];
}

std::optional<int64_t> ParameterList::getInt(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::Integer});
    if (!single(p, p ? p->numbers.size() : 0)) return std::nullopt;
    return int64_t(p->numbers[0]);
}

std::optional<bool> ParameterList::getBool(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::Bool});
    if (!single(p, p ? p->bools.size() : 0)) return std::nullopt;
    return p->bools[0] != 0;
}

std::optional<std::string> ParameterList::getString(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::String});
    if (!single(p, p ? p->strings.size() : 0)) return std::nullopt;
    return p->strings[0];
}

std::optional<Vec3d> ParameterList::getPoint3(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::Point3, ParamType::Vector3});
    if (!single(p, p ? p->numbers.size() / 3 : 0)) return std::nullopt;
    return Vec3d{p->numbers[0], p->numbers[1], p->numbers[2]};
}

std::vector<double> ParameterList::getFloats(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::Float, ParamType::Integer});
    return p ? p->numbers : std::vector<double>{};
}

std::vector<int64_t> ParameterList::getInts(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::Integer});
    std::vector<int64_t> out;
    if (p)
        for (double v : p->numbers) out.push_back(int64_t(v));
    return out;
}

namespace {

std::vector<Vec3d> triples(const Parameter* p) {
    std::vector<Vec3d> out;
    if (!p) return out;
    out.reserve(p->numbers.size() / 3);
    for (size_t i = 0; i + 2 < p->numbers.size(); i += 3)
        out.push_back({p->numbers[i], p->numbers[i + 1], p->numbers[i + 2]});
    return out;
}

}  // namespace

std::vector<Vec3d> ParameterList::getPoint3s(std::string_view name) const {
    return triples(find(name, {ParamType::Point3}));
}
std::vector<Vec3d> ParameterList::getNormals(std::string_view name) const {
    return triples(find(name, {ParamType::Normal}));
}

std::vector<Vec2d> ParameterList::getPoint2s(std::string_view name) const {
    const Parameter* p = find(name, {ParamType::Point2, ParamType::Float});
    std::vector<Vec2d> out;
    if (!p) return out;
    if (p->numbers.size() % 2 != 0)
        failAt(p->where, fmt::format("parameter \"{}\" needs pairs of numbers, found {} numbers",
                                     p->declaration(), p->numbers.size()));
    for (size_t i = 0; i + 1 < p->numbers.size(); i += 2) out.push_back({p->numbers[i], p->numbers[i + 1]});
    return out;
}

void ParameterList::markAllUsed() const {
    for (const Parameter& p : parameters_) p.used = true;
}

void ParameterList::reportUnused(WarningLog& log, std::string_view owner) const {
    for (const Parameter& p : parameters_)
        if (!p.used)
            log.warn(p.where, fmt::format("parameter \"{}\" of {} is not supported and was ignored",
                                          p.declaration(), owner));
}

}  // namespace penumbra::pbrt
