#include "scenes/mesh_import.h"

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "core/error.h"
#include "core/input_file.h"
#include "core/input_limits.h"

namespace penumbra {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// Shared helpers

[[noreturn]] void fail(const std::string& file, const std::string& message) {
    throw InputError(SourceLocation{file, 0, 0, ""}, message);
}

[[noreturn]] void failAt(const std::string& file, int line, int column, const std::string& message) {
    throw InputError(SourceLocation{file, line, column, ""}, message);
}

// Parses a whole token as a number ("nan" and "inf" included); false when it is not one.
bool parseNumber(std::string_view token, double& value) {
    if (token.size() > 1 && token[0] == '+') token.remove_prefix(1);  // from_chars rejects '+'
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, value);
    if (result.ptr != end) return false;
    if (result.ec == std::errc::result_out_of_range) {
        value = std::strtod(std::string(token).c_str(), nullptr);  // +-inf or (almost) 0
        return true;
    }
    return result.ec == std::errc();
}

bool parseInteger(std::string_view token, int64_t& value) {
    if (token.size() > 1 && token[0] == '+') token.remove_prefix(1);
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, value);
    return result.ec == std::errc() && result.ptr == end;
}

bool isFiniteFloat(double value) { return std::isfinite(float(value)); }

struct Token {
    std::string_view text;
    int column;  // 1-based
};

// Splits a line at spaces, tabs and carriage returns.
std::vector<Token> tokenize(std::string_view line) {
    std::vector<Token> tokens;
    size_t pos = 0;
    while (true) {
        pos = line.find_first_not_of(" \t\r", pos);
        if (pos == std::string_view::npos) break;
        const size_t end = std::min(line.find_first_of(" \t\r", pos), line.size());
        tokens.push_back({line.substr(pos, end - pos), int(pos) + 1});
        pos = end;
    }
    return tokens;
}

// Calls `visit(line, lineNumber)` for each line of `text`, ending lines where tinyobjloader does:
// at "\n", "\r\n" and a lone "\r". The validator must see the lines the loader sees, or a lone CR
// could hide a face from it ("#\rf 1 2 4" would be a comment to one and a face to the other).
template <typename Visit>
void forEachObjLine(std::string_view text, Visit visit) {
    int lineNumber = 0;
    for (size_t start = 0; start < text.size();) {
        const size_t end = std::min(text.find_first_of("\r\n", start), text.size());
        const std::string_view line = text.substr(start, end - start);
        start = end + 1;
        if (end < text.size() && text[end] == '\r' && start < text.size() && text[start] == '\n') ++start;
        visit(line, ++lineNumber);
    }
}

std::string readPlainFile(const fs::path& path, uint64_t maxBytes) {
    return InputFile(path, "mesh file", maxBytes).readAll();
}

// Defence in depth: whatever a loader produced, the mesh handed on must be one that the rest of the
// renderer can use without further checks (face frames and Embree read it unguarded).
void checkImportedMesh(const TriangleMesh& mesh, const std::string& file) {
    if (mesh.positions.empty() || mesh.indices.empty() || mesh.indices.size() % 3 != 0)
        fail(file, "the file contains no triangles");
    for (size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.positions.size())
            fail(file, fmt::format(
                           "triangle {} (counting from 0) uses vertex {}, but the mesh has only {} vertices",
                           i / 3, mesh.indices[i], mesh.positions.size()));
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        if (!isFinite(mesh.positions[i]))
            fail(file, fmt::format("vertex {} (counting from 0) has a non-finite coordinate", i));
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
        fail(file, "the file gives normals for some vertices only");
    for (size_t i = 0; i < mesh.normals.size(); ++i)
        if (!isFinite(mesh.normals[i]))
            fail(file, fmt::format("the normal of vertex {} (counting from 0) is not finite", i));
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
        fail(file, "the file gives uvs for some vertices only");
    for (size_t i = 0; i < mesh.uvs.size(); ++i)
        if (!std::isfinite(mesh.uvs[i].x) || !std::isfinite(mesh.uvs[i].y))
            fail(file, fmt::format("the uv of vertex {} (counting from 0) is not finite", i));
}

// ---------------------------------------------------------------------------------------------
// OBJ

// Checks what tinyobjloader would accept silently (it reads "abc" as 0, skips faces with bad
// indices): every number parses, vertices are finite, faces have 3+ corners whose indices exist.
void validateObj(std::string_view text, const std::string& file) {
    enum Kind { Position, TexCoord, Normal };
    static const char* const kindName[] = {"vertex", "texture coordinate", "normal"};
    static const char* const kindPlural[] = {"vertices", "texture coordinates", "normals"};
    int64_t count[3] = {0, 0, 0};  // elements of each kind defined so far
    struct ForwardIndex {          // a positive index beyond what was defined so far: checked at the end
        int line, column;
        int64_t index;
        Kind kind;
    };
    std::vector<ForwardIndex> forward;

    forEachObjLine(text, [&](std::string_view line, int lineNumber) {
        line = line.substr(0, line.find('#'));
        const std::vector<Token> tokens = tokenize(line);
        if (tokens.empty()) return;
        const std::string_view keyword = tokens[0].text;

        if (keyword == "v" || keyword == "vt" || keyword == "vn") {
            const Kind kind = keyword == "v" ? Position : keyword == "vt" ? TexCoord : Normal;
            // v: x y z [w] or x y z r g b; vt: u [v [w]]; vn: x y z.
            const size_t minCount = kind == TexCoord ? 1 : 3, maxCount = kind == Position ? 6 : 3;
            const size_t numbers = tokens.size() - 1;
            ++count[kind];
            if (numbers < minCount || numbers > maxCount)
                failAt(file, lineNumber, tokens[0].column,
                       fmt::format("expected {} to {} numbers after '{}', found {}", minCount, maxCount,
                                   keyword, numbers));
            for (size_t i = 1; i < tokens.size(); ++i) {
                double value = 0;
                if (!parseNumber(tokens[i].text, value))
                    failAt(file, lineNumber, tokens[i].column,
                           fmt::format("expected a number, found '{}'", tokens[i].text));
                if (!isFiniteFloat(value))
                    failAt(file, lineNumber, tokens[i].column,
                           fmt::format("{} {} has a non-finite coordinate ({})", kindName[kind], count[kind],
                                       tokens[i].text));
            }
        } else if (keyword == "f") {
            if (tokens.size() < 4)
                failAt(file, lineNumber, tokens[0].column,
                       fmt::format("a face needs at least 3 vertices, found {}", tokens.size() - 1));
            if (tokens.size() - 1 > size_t(limits::kMaxObjFaceCorners))
                failAt(
                    file, lineNumber, tokens[0].column,
                    fmt::format("a face with {} corners; penumbra takes at most {} (polygons are split into "
                                "triangles in time that grows with the square of their corners)",
                                tokens.size() - 1, limits::kMaxObjFaceCorners));
            for (size_t c = 1; c < tokens.size(); ++c) {
                const Token& corner = tokens[c];
                // v, v/vt, v//vn or v/vt/vn
                std::vector<std::string_view> parts;
                for (size_t pos = 0;;) {
                    const size_t slash = std::min(corner.text.find('/', pos), corner.text.size());
                    parts.push_back(corner.text.substr(pos, slash - pos));
                    if (slash == corner.text.size()) break;
                    pos = slash + 1;
                }
                bool wellFormed = parts.size() <= 3 && !parts[0].empty() && !parts.back().empty();
                for (size_t k = 0; wellFormed && k < parts.size(); ++k) {
                    if (parts[k].empty()) continue;  // the uv of v//vn
                    int64_t index = 0;
                    if (!parseInteger(parts[k], index)) {
                        wellFormed = false;
                        break;
                    }
                    const Kind kind = k == 0 ? Position : k == 1 ? TexCoord : Normal;
                    if (index == 0)
                        failAt(
                            file, lineNumber, corner.column,
                            fmt::format("{} index 0 is invalid (OBJ indices count from 1)", kindName[kind]));
                    if (index < 0 && count[kind] + index < 0)
                        failAt(file, lineNumber, corner.column,
                               fmt::format("relative {} index {} is out of range: only {} {} come before it",
                                           kindName[kind], index, count[kind], kindPlural[kind]));
                    if (index > count[kind]) forward.push_back({lineNumber, corner.column, index, kind});
                }
                if (!wellFormed)
                    failAt(file, lineNumber, corner.column,
                           fmt::format("expected a face corner of indices 'v', 'v/vt', 'v//vn' or 'v/vt/vn', "
                                       "found '{}'",
                                       corner.text));
            }
        }
        // Other statements (o, g, s, usemtl, mtllib, l, p, ...) do not affect the triangles.
    });
    for (const ForwardIndex& f : forward)
        if (f.index > count[f.kind])
            failAt(file, f.line, f.column,
                   fmt::format("{} index {} is out of range: the file has {} {}", kindName[f.kind], f.index,
                               count[f.kind], kindPlural[f.kind]));
}

// Defence in depth: the indices tinyobjloader produced must name elements it read, whatever the
// validator concluded, before any of them is used to read its arrays.
void checkObjLoaderIndices(const tinyobj::attrib_t& attrib, const std::vector<tinyobj::index_t>& corners,
                           const std::string& file) {
    const size_t counts[3] = {attrib.vertices.size() / 3, attrib.texcoords.size() / 2,
                              attrib.normals.size() / 3};
    static const char* const kindPlural[] = {"vertices", "texture coordinates", "normals"};
    for (const tinyobj::index_t& c : corners) {
        const int indices[3] = {c.vertex_index, c.texcoord_index, c.normal_index};
        for (int k = 0; k < 3; ++k) {
            const bool optional = k > 0;  // a corner may lack a uv or a normal (-1)
            if ((optional && indices[k] == -1) || (indices[k] >= 0 && size_t(indices[k]) < counts[k]))
                continue;
            fail(file,
                 fmt::format("the OBJ reader produced a face corner that refers to {} {} (counting from "
                             "1), but it read only {} {}; the file is malformed",
                             kindPlural[k], int64_t(indices[k]) + 1, counts[k], kindPlural[k]));
        }
    }
}

struct CornerKey {
    int position, texCoord, normal;
    bool operator==(const CornerKey&) const = default;
};

struct CornerKeyHash {
    size_t operator()(const CornerKey& k) const {
        return std::hash<uint64_t>()((uint64_t(uint32_t(k.position)) << 32) ^
                                     (uint64_t(uint32_t(k.texCoord)) << 16) ^ uint64_t(uint32_t(k.normal)));
    }
};

}  // namespace

namespace {

// The OBJ text checked by our validator, then read by tinyobjloader, its polygons split into
// triangles or kept. No material reader: materials come from the scene file, so mtllib lines are ignored.
void loadObj(std::string_view text, const std::string& file, bool triangulate, tinyobj::attrib_t& attrib,
             std::vector<tinyobj::shape_t>& shapes) {
    validateObj(text, file);
    std::vector<tinyobj::material_t> materials;
    std::string warnings, errors;
    std::istringstream stream{std::string(text)};
    if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warnings, &errors, &stream, nullptr, triangulate,
                          /*default_vcols_fallback=*/false))
        fail(file, "cannot read the OBJ file: " + errors);
}

}  // namespace

TriangleMesh importObj(std::string_view text, const std::string& file) {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    loadObj(text, file, /*triangulate=*/true, attrib, shapes);

    std::vector<tinyobj::index_t> corners;  // three per triangle
    for (const tinyobj::shape_t& shape : shapes) {
        size_t offset = 0;
        for (unsigned char n : shape.mesh.num_face_vertices) {
            if (n == 3)
                corners.insert(corners.end(), &shape.mesh.indices[offset], &shape.mesh.indices[offset + 3]);
            offset += n;
        }
    }
    if (corners.empty()) fail(file, "the file contains no triangles (no 'f' lines)");
    checkObjLoaderIndices(attrib, corners, file);

    // Normals and uvs are per corner in OBJ; keep them only where every corner has one.
    const bool hasNormals =
        std::all_of(corners.begin(), corners.end(), [](auto& c) { return c.normal_index >= 0; });
    const bool hasUvs =
        std::all_of(corners.begin(), corners.end(), [](auto& c) { return c.texcoord_index >= 0; });

    TriangleMesh mesh;
    mesh.name = fs::path(file).filename().string();
    auto position = [&](int i) {
        return Vec3f{attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]};
    };
    if (!hasNormals && !hasUvs) {
        // Positions alone: the file's vertices and indices are used as they are.
        mesh.positions.resize(attrib.vertices.size() / 3);
        for (size_t i = 0; i < mesh.positions.size(); ++i) mesh.positions[i] = position(int(i));
        for (const auto& c : corners) mesh.indices.push_back(uint32_t(c.vertex_index));
        checkImportedMesh(mesh, file);
        return mesh;
    }
    // One vertex per distinct (position, uv, normal) combination, as a single index buffer needs.
    std::unordered_map<CornerKey, uint32_t, CornerKeyHash> vertexOf;
    for (const auto& c : corners) {
        const CornerKey key{c.vertex_index, hasUvs ? c.texcoord_index : -1, hasNormals ? c.normal_index : -1};
        auto [it, inserted] = vertexOf.try_emplace(key, uint32_t(mesh.positions.size()));
        if (inserted) {
            mesh.positions.push_back(position(key.position));
            if (hasNormals) {
                const size_t n = size_t(key.normal);
                const Vec3f normal{attrib.normals[3 * n], attrib.normals[3 * n + 1],
                                   attrib.normals[3 * n + 2]};
                if (!(length(normal) > 0.0f))
                    fail(file, fmt::format("normal {} has zero length, so it has no direction", n + 1));
                mesh.normals.push_back(normalize(normal));
            }
            if (hasUvs)
                mesh.uvs.push_back({attrib.texcoords[2 * size_t(key.texCoord)],
                                    attrib.texcoords[2 * size_t(key.texCoord) + 1]});
        }
        mesh.indices.push_back(it->second);
    }
    checkImportedMesh(mesh, file);
    return mesh;
}

PolygonMesh importObjPolygons(std::string_view text, const std::string& file) {
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    loadObj(text, file, /*triangulate=*/false, attrib, shapes);
    PolygonMesh mesh;
    std::vector<tinyobj::index_t> corners;
    for (const tinyobj::shape_t& shape : shapes) {
        size_t offset = 0;
        for (unsigned char n : shape.mesh.num_face_vertices) {
            if (n >= 3) {
                corners.insert(corners.end(), &shape.mesh.indices[offset], &shape.mesh.indices[offset + n]);
                mesh.faceSizes.push_back(n);
            }
            offset += n;
        }
    }
    if (corners.empty()) fail(file, "the file contains no polygons (no 'f' lines)");
    checkObjLoaderIndices(attrib, corners, file);
    const bool hasUvs =
        std::all_of(corners.begin(), corners.end(), [](auto& c) { return c.texcoord_index >= 0; });
    std::unordered_map<CornerKey, uint32_t, CornerKeyHash> vertexOf;
    for (const auto& c : corners) {
        const CornerKey key{c.vertex_index, hasUvs ? c.texcoord_index : -1, -1};
        auto [it, inserted] = vertexOf.try_emplace(key, uint32_t(mesh.positions.size()));
        if (inserted) {
            const size_t v = size_t(key.position);
            mesh.positions.push_back(
                {attrib.vertices[3 * v], attrib.vertices[3 * v + 1], attrib.vertices[3 * v + 2]});
            if (hasUvs)
                mesh.uvs.push_back({attrib.texcoords[2 * size_t(key.texCoord)],
                                    attrib.texcoords[2 * size_t(key.texCoord) + 1]});
        }
        mesh.corners.push_back(it->second);
    }
    // The same checks as a triangle mesh's, on its fans.
    checkImportedMesh(fanTriangulate(mesh), file);
    return mesh;
}

// ---------------------------------------------------------------------------------------------
// PLY

namespace {

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
    std::string name;
    int size = 0;           // bytes of a value (of each item, for lists)
    bool isFloat = false;   // float or double (of each item, for lists)
    bool isSigned = false;  // integers: signed (of each item, for lists)
    bool isList = false;
    int countSize = 0;  // lists: bytes of the item count
    bool countSigned = false;
};

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    size_t bodyOffset = 0;  // first byte after end_header's line
    int bodyLine = 0;       // line number of that byte (ASCII)
};

// Size in bytes of a PLY scalar type, 0 when the name is not a type.
int plyTypeSize(std::string_view type, bool& isSigned) {
    struct Entry {
        std::string_view name;
        int size;
        bool isSigned;
    };
    static constexpr Entry types[] = {
        {"char", 1, true},  {"int8", 1, true},    {"uchar", 1, false},  {"uint8", 1, false},
        {"short", 2, true}, {"int16", 2, true},   {"ushort", 2, false}, {"uint16", 2, false},
        {"int", 4, true},   {"int32", 4, true},   {"uint", 4, false},   {"uint32", 4, false},
        {"float", 4, true}, {"float32", 4, true}, {"double", 8, true},  {"float64", 8, true}};
    for (const Entry& e : types)
        if (e.name == type) {
            isSigned = e.isSigned;
            return e.size;
        }
    return 0;
}

PlyHeader parsePlyHeader(std::string_view bytes, const std::string& file) {
    PlyHeader header;
    bool sawFormat = false;
    int lineNumber = 0;
    size_t start = 0;
    while (true) {
        if (start >= bytes.size())
            fail(file, "the PLY header is incomplete: no 'end_header' line (is the file truncated?)");
        const size_t end = std::min(bytes.find('\n', start), bytes.size());
        const std::string_view line = bytes.substr(start, end - start);
        const std::vector<Token> tokens = tokenize(line);
        start = end + 1;
        ++lineNumber;
        auto failHere = [&](const std::string& message) { failAt(file, lineNumber, 1, message); };
        // assimp ends header lines at "\n" only; a lone CR would make it read another header than ours.
        const size_t cr = line.find('\r');
        if (cr != std::string_view::npos && cr + 1 != line.size())
            failAt(file, lineNumber, int(cr) + 1,
                   "a carriage return that does not end the line: PLY header lines must end with LF or CR LF "
                   "(old Mac CR-only line endings are not accepted)");

        if (lineNumber == 1) {
            if (tokens.size() != 1 || tokens[0].text != "ply")
                failHere("not a PLY file: expected 'ply' on the first line");
            continue;
        }
        if (tokens.empty()) continue;
        const std::string_view keyword = tokens[0].text;
        if (keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") break;
        if (keyword == "format") {
            if (tokens.size() != 3 || tokens[2].text != "1.0")
                failHere(
                    "expected 'format ascii 1.0', 'format binary_little_endian 1.0' or 'format "
                    "binary_big_endian 1.0'");
            if (tokens[1].text == "ascii")
                header.format = PlyFormat::Ascii;
            else if (tokens[1].text == "binary_little_endian")
                header.format = PlyFormat::BinaryLittleEndian;
            else if (tokens[1].text == "binary_big_endian")
                header.format = PlyFormat::BinaryBigEndian;
            else
                failHere(fmt::format(
                    "unknown PLY format '{}' (expected ascii, binary_little_endian or binary_big_endian)",
                    tokens[1].text));
            sawFormat = true;
        } else if (keyword == "element") {
            int64_t count = 0;
            if (tokens.size() != 3 || !parseInteger(tokens[2].text, count) || count < 0 ||
                count > int64_t(UINT32_MAX))
                failHere("expected 'element NAME COUNT' with a COUNT from 0 to 4294967295");
            // assimp 5.2 stores a second 'vertex' element's values into the first one's arrays,
            // past their end (a heap overflow): each element may be declared once.
            for (const PlyElement& e : header.elements)
                if (e.name == tokens[1].text)
                    failHere(
                        fmt::format("the element '{}' is declared a second time (a PLY header declares each "
                                    "element once)",
                                    e.name));
            header.elements.push_back({std::string(tokens[1].text), uint64_t(count), {}});
        } else if (keyword == "property") {
            if (header.elements.empty()) failHere("a property must follow an 'element' line");
            PlyProperty property;
            bool isSigned = false;
            if (tokens.size() == 5 && tokens[1].text == "list") {
                property.isList = true;
                property.countSize = plyTypeSize(tokens[2].text, property.countSigned);
                property.size = plyTypeSize(tokens[3].text, isSigned);
                property.isSigned = isSigned;
                property.isFloat = tokens[3].text.starts_with("float") || tokens[3].text == "double";
                property.name = tokens[4].text;
                const bool integerCount = property.countSize > 0 &&
                                          tokens[2].text.find("float") == std::string_view::npos &&
                                          tokens[2].text != "double";
                if (!integerCount || property.size == 0)
                    failHere("expected 'property list COUNT_TYPE ITEM_TYPE NAME' with an integer COUNT_TYPE");
            } else if (tokens.size() == 3) {
                property.size = plyTypeSize(tokens[1].text, isSigned);
                property.isSigned = isSigned;
                property.isFloat = tokens[1].text.starts_with("float") || tokens[1].text == "double";
                property.name = tokens[2].text;
                if (property.size == 0) failHere(fmt::format("unknown property type '{}'", tokens[1].text));
            } else {
                failHere("expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'");
            }
            header.elements.back().properties.push_back(property);
        } else {
            failHere(fmt::format("unexpected '{}' in the PLY header", keyword));
        }
    }
    if (!sawFormat) fail(file, "the PLY header has no 'format' line");
    header.bodyOffset = std::min(start, bytes.size());
    header.bodyLine = lineNumber + 1;

    // The parts a triangle mesh needs.
    auto element = [&](std::string_view name) -> const PlyElement* {
        for (const PlyElement& e : header.elements)
            if (e.name == name) return &e;
        return nullptr;
    };
    auto hasProperty = [](const PlyElement& e, std::string_view name, bool list) {
        return std::any_of(e.properties.begin(), e.properties.end(),
                           [&](const PlyProperty& p) { return p.name == name && p.isList == list; });
    };
    const PlyElement* vertex = element("vertex");
    if (!vertex || !hasProperty(*vertex, "x", false) || !hasProperty(*vertex, "y", false) ||
        !hasProperty(*vertex, "z", false))
        fail(file, "the PLY header declares no 'vertex' element with properties x, y and z");
    const PlyElement* face = element("face");
    if (face && !hasProperty(*face, "vertex_indices", true) && !hasProperty(*face, "vertex_index", true))
        fail(file, "the PLY 'face' element has no list property 'vertex_indices'");
    return header;
}

// Collects what a triangle mesh needs from the values of a PLY body as the walkers below read
// them: the vertex element's x y z (nx ny nz, u v / s t), the face element's index lists.
// Reading the values in the same pass that checks them is what makes PLY loading fast (assimp's
// reader took three times as long as the check; bench/README.md).
class PlyMeshSink {
public:
    explicit PlyMeshSink(const PlyHeader& header) {
        for (size_t e = 0; e < header.elements.size(); ++e) {
            const PlyElement& element = header.elements[e];
            std::vector<int> slots(element.properties.size(), -1);
            if (element.name == "vertex" && vertexElement_ < 0) {
                vertexElement_ = int(e);
                vertexCount_ = element.count;
                static constexpr std::string_view kNames[][2] = {{"x", ""},  {"y", ""},  {"z", ""},
                                                                 {"nx", ""}, {"ny", ""}, {"nz", ""},
                                                                 {"u", "s"}, {"v", "t"}};
                for (size_t p = 0; p < element.properties.size(); ++p)
                    for (int slot = 0; slot < 8; ++slot)
                        if (!element.properties[p].isList &&
                            (element.properties[p].name == kNames[slot][0] ||
                             element.properties[p].name == kNames[slot][1]) &&
                            !(present_ & (1u << slot))) {
                            slots[p] = slot;
                            present_ |= 1u << slot;
                        }
            } else if (element.name == "face" && faceElement_ < 0) {
                faceElement_ = int(e);
                for (size_t p = 0; p < element.properties.size(); ++p)
                    if (element.properties[p].isList && faceProperty_ < 0 &&
                        (element.properties[p].name == "vertex_indices" ||
                         element.properties[p].name == "vertex_index"))
                        faceProperty_ = int(p);
            }
            slots_.push_back(std::move(slots));
        }
        hasNormals_ = (present_ & 0x38u) == 0x38u;
        hasUvs_ = (present_ & 0xC0u) == 0xC0u;
        mesh_.positions.resize(vertexCount_);
        if (hasNormals_) mesh_.normals.resize(vertexCount_);
        if (hasUvs_) mesh_.uvs.resize(vertexCount_);
    }

    // A scalar property's value of row `row` of element `e`.
    void scalar(size_t e, size_t p, uint64_t row, double v) {
        if (int(e) != vertexElement_) return;
        const int slot = slots_[e][p];
        if (slot < 0) return;
        const float f = float(v);
        if (slot < 3)
            mesh_.positions[row][slot] = f;
        else if (slot < 6) {
            if (hasNormals_) mesh_.normals[row][slot - 3] = f;
        } else if (hasUvs_)
            (slot == 6 ? mesh_.uvs[row].x : mesh_.uvs[row].y) = f;
    }
    bool wantsList(size_t e, size_t p) const { return int(e) == faceElement_ && int(p) == faceProperty_; }
    // The face list of one row: polygons become triangle fans (or are kept whole, keepPolygons);
    // points and lines have no area.
    void faceList(uint64_t row, const std::vector<double>& items, const std::string& file) {
        for (double v : items)
            if (!(v >= 0.0 && v < double(vertexCount_)))
                fail(file, fmt::format(
                               "face {} (counting from 0) uses vertex {}, but the file has only {} vertices "
                               "(indices count from 0)",
                               row, v, vertexCount_));  // v as read: it may not fit an integer
        if (keepPolygons_) {
            if (items.size() < 3) return;
            faceSizes_.push_back(uint32_t(items.size()));
            for (double v : items) corners_.push_back(uint32_t(v));
            return;
        }
        for (size_t k = 1; k + 1 < items.size(); ++k)
            for (size_t corner : {size_t(0), k, k + 1}) mesh_.indices.push_back(uint32_t(items[corner]));
    }
    // Record each face's polygon instead of its triangles (takePolygons).
    void keepPolygons() { keepPolygons_ = true; }
    PolygonMesh takePolygons(const std::string& file) {
        TriangleMesh mesh = take(file);
        PolygonMesh polygons;
        polygons.positions = std::move(mesh.positions);
        polygons.uvs = std::move(mesh.uvs);
        polygons.faceSizes = std::move(faceSizes_);
        polygons.corners = std::move(corners_);
        return polygons;
    }

    TriangleMesh take(const std::string& file) {
        for (size_t v = 0; v < mesh_.positions.size(); ++v)
            if (!isFinite(mesh_.positions[v]))
                fail(file, fmt::format("vertex {} (counting from 0) has a non-finite coordinate", v));
        for (size_t v = 0; v < mesh_.uvs.size(); ++v)
            if (!std::isfinite(mesh_.uvs[v].x) || !std::isfinite(mesh_.uvs[v].y))
                fail(file, fmt::format("the uv of vertex {} (counting from 0) is not finite", v));
        return std::move(mesh_);
    }

private:
    TriangleMesh mesh_;
    bool keepPolygons_ = false;
    std::vector<uint32_t> faceSizes_, corners_;
    std::vector<std::vector<int>> slots_;  // [element][property]: 0-2 x y z, 3-5 normal, 6-7 uv, -1 unused
    int vertexElement_ = -1, faceElement_ = -1, faceProperty_ = -1;
    uint64_t vertexCount_ = 0;
    unsigned present_ = 0;
    bool hasNormals_ = false, hasUvs_ = false;
};

bool isPlySpace(char c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Walks the ASCII body, reading the mesh into `sink`: every value the header declares must be
// there and be a number.
void readPlyAsciiBody(const PlyHeader& header, std::string_view bytes, const std::string& file,
                      PlyMeshSink& sink) {
    size_t pos = header.bodyOffset, lineStart = pos;
    int line = header.bodyLine;
    auto next = [&]() -> std::optional<Token> {
        while (pos < bytes.size() && isPlySpace(bytes[pos])) {
            if (bytes[pos] == '\n') ++line, lineStart = pos + 1;
            ++pos;
        }
        if (pos == bytes.size()) return std::nullopt;
        const size_t begin = pos;
        while (pos < bytes.size() && !isPlySpace(bytes[pos])) ++pos;
        return Token{bytes.substr(begin, pos - begin), int(begin - lineStart) + 1};
    };
    std::vector<double> items;
    for (size_t e = 0; e < header.elements.size(); ++e) {
        const PlyElement& element = header.elements[e];
        for (uint64_t i = 0; i < element.count; ++i)
            for (size_t p = 0; p < element.properties.size(); ++p) {
                const PlyProperty& property = element.properties[p];
                auto value = [&]() {
                    const std::optional<Token> token = next();
                    if (!token)
                        failAt(file, line, 0,
                               fmt::format(
                                   "the file ends early (truncated?): {} {} of the {} declared is incomplete",
                                   element.name, i, element.count));
                    double v = 0;
                    if (!parseNumber(token->text, v))
                        failAt(file, line, token->column,
                               fmt::format("expected a number for property '{}' of {} {}, found '{}'",
                                           property.name, element.name, i, token->text));
                    return v;
                };
                if (!property.isList) {
                    sink.scalar(e, p, i, value());
                    continue;
                }
                const double n = value();
                if (!(n >= 0 && n == std::floor(n) && n < 4294967296.0))
                    failAt(file, line, 0,
                           fmt::format("expected a list length for property '{}' of {} {}, found {}",
                                       property.name, element.name, i, n));
                const bool wanted = sink.wantsList(e, p);
                items.clear();
                for (uint64_t k = 0; k < uint64_t(n); ++k) {
                    const double v = value();
                    if (wanted) items.push_back(v);
                }
                if (wanted) sink.faceList(i, items, file);
            }
    }
}

uint64_t readUnsigned(const unsigned char* p, int size, bool bigEndian) {
    uint64_t v = 0;
    for (int b = 0; b < size; ++b) v |= uint64_t(p[bigEndian ? size - 1 - b : b]) << (8 * b);
    return v;
}

// One binary value of a property's type (its items' type, for lists).
double readPlyBinaryValue(const unsigned char* p, const PlyProperty& property, bool bigEndian) {
    const uint64_t bits = readUnsigned(p, property.size, bigEndian);
    if (property.isFloat) {
        if (property.size == 4) return double(std::bit_cast<float>(uint32_t(bits)));
        return std::bit_cast<double>(bits);
    }
    if (property.isSigned && property.size < 8 && ((bits >> (8 * property.size - 1)) & 1u))
        return double(int64_t(bits) - (int64_t(1) << (8 * property.size)));
    return double(bits);
}

// Walks the binary body, reading the mesh into `sink`: the file must hold every value the header
// declares.
void readPlyBinaryBody(const PlyHeader& header, std::string_view bytes, const std::string& file,
                       PlyMeshSink& sink) {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const bool bigEndian = header.format == PlyFormat::BinaryBigEndian;
    uint64_t pos = header.bodyOffset;
    std::vector<double> items;
    for (size_t e = 0; e < header.elements.size(); ++e) {
        const PlyElement& element = header.elements[e];
        auto truncated = [&](uint64_t i) {
            fail(file, fmt::format("the file ends early (truncated?): {} {} of the {} declared is incomplete",
                                   element.name, i, element.count));
        };
        const bool hasList = std::any_of(element.properties.begin(), element.properties.end(),
                                         [](const PlyProperty& p) { return p.isList; });
        if (!hasList) {  // fixed-size rows: one step
            uint64_t rowSize = 0;
            for (const PlyProperty& p : element.properties) rowSize += uint64_t(p.size);
            if (rowSize == 0) continue;
            if (rowSize * element.count > bytes.size() - pos) truncated((bytes.size() - pos) / rowSize);
            for (uint64_t i = 0; i < element.count; ++i)
                for (size_t q = 0; q < element.properties.size(); ++q) {
                    const PlyProperty& p = element.properties[q];
                    sink.scalar(e, q, i, readPlyBinaryValue(data + pos, p, bigEndian));
                    pos += uint64_t(p.size);
                }
            continue;
        }
        for (uint64_t i = 0; i < element.count; ++i)
            for (size_t q = 0; q < element.properties.size(); ++q) {
                const PlyProperty& p = element.properties[q];
                if (!p.isList) {
                    if (pos + uint64_t(p.size) > bytes.size()) truncated(i);
                    sink.scalar(e, q, i, readPlyBinaryValue(data + pos, p, bigEndian));
                    pos += uint64_t(p.size);
                    continue;
                }
                if (pos + uint64_t(p.countSize) > bytes.size()) truncated(i);
                uint64_t n = readUnsigned(data + pos, p.countSize, bigEndian);
                if (p.countSigned && (n >> (8 * p.countSize - 1)) & 1u)
                    fail(file, fmt::format("{} {} has a negative list length for property '{}'", element.name,
                                           i, p.name));
                pos += uint64_t(p.countSize);
                if (n > (bytes.size() - pos) / uint64_t(p.size))
                    truncated(i);  // n * size may not fit 64 bits
                if (sink.wantsList(e, q)) {
                    items.clear();
                    for (uint64_t k = 0; k < n; ++k)
                        items.push_back(readPlyBinaryValue(data + pos + k * uint64_t(p.size), p, bigEndian));
                    sink.faceList(i, items, file);
                }
                pos += n * uint64_t(p.size);
            }
    }
}

// Makes each normal unit length; a zero normal has no direction to keep, so it is an error.
void normalizePlyNormals(std::vector<Vec3f>& normals, const std::string& file) {
    for (size_t i = 0; i < normals.size(); ++i) {
        const float len = length(normals[i]);
        if (!(len > 0.0f) || !std::isfinite(len))
            fail(file,
                 fmt::format("the normal of vertex {} (counting from 0) has zero length or a non-finite "
                             "coordinate",
                             i));
        normals[i] = normals[i] / len;
    }
}

}  // namespace

// Every row of an element takes bytes of the body (a binary row at least its scalars and list
// counts, an ASCII row at least a character and a separator a value), so a header cannot declare
// more rows than the file holds: nothing is allocated for rows that are not there (a 300-byte file
// that declared 2 billion vertices asked for 25 GB; found by fuzzing).
void checkPlyRowsFitTheBody(const PlyHeader& header, std::string_view bytes, const std::string& file) {
    const uint64_t body = bytes.size() - header.bodyOffset;
    uint64_t needed = 0;
    for (const PlyElement& element : header.elements) {
        uint64_t rowBytes = 0;
        for (const PlyProperty& p : element.properties)
            rowBytes += header.format == PlyFormat::Ascii ? 2 : uint64_t(p.isList ? p.countSize : p.size);
        rowBytes = std::max<uint64_t>(rowBytes, 1);
        // The last value of an ASCII file may end it without a separator: one byte less.
        if (element.count > (body + 1 - std::min(needed, body + 1)) / rowBytes)
            fail(file,
                 fmt::format(
                     "the file ends early (truncated?): the element '{}' declares {} rows, which take at "
                     "least {} bytes, but the file "
                     "holds {} bytes after its header",
                     element.name, element.count, element.count * rowBytes, body));
        needed += element.count * rowBytes;
    }
}

TriangleMesh importPly(std::string_view bytes, const std::string& file) {
    const PlyHeader header = parsePlyHeader(bytes, file);
    checkPlyRowsFitTheBody(header, bytes, file);
    PlyMeshSink sink(header);
    if (header.format == PlyFormat::Ascii)
        readPlyAsciiBody(header, bytes, file, sink);
    else
        readPlyBinaryBody(header, bytes, file, sink);
    TriangleMesh mesh = sink.take(file);
    mesh.name = fs::path(file).filename().string();
    if (!mesh.normals.empty()) normalizePlyNormals(mesh.normals, file);
    if (mesh.indices.empty()) fail(file, "the file contains no triangles");
    checkImportedMesh(mesh, file);
    return mesh;
}

PolygonMesh importPlyPolygons(std::string_view bytes, const std::string& file) {
    const PlyHeader header = parsePlyHeader(bytes, file);
    checkPlyRowsFitTheBody(header, bytes, file);
    PlyMeshSink sink(header);
    sink.keepPolygons();
    if (header.format == PlyFormat::Ascii)
        readPlyAsciiBody(header, bytes, file, sink);
    else
        readPlyBinaryBody(header, bytes, file, sink);
    PolygonMesh mesh = sink.takePolygons(file);
    if (mesh.corners.empty()) fail(file, "the file contains no polygons");
    checkImportedMesh(fanTriangulate(mesh), file);
    return mesh;
}

namespace {

// The extension that decides a mesh file's format, in lower case.
std::string lowerCaseName(const fs::path& file) {
    std::string lower = file.filename().string();
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return lower;
}

// The file's bytes handed to `obj` or `ply` by its name's extension (a .ply.gz inflated first).
template <typename Obj, typename Ply>
auto importByFormat(const fs::path& file, uint64_t maxBytes, Obj obj, Ply ply) {
    const std::string name = file.string();
    const std::string lower = lowerCaseName(file);
    if (lower.ends_with(".obj")) return obj(readPlainFile(file, maxBytes), name);
    if (lower.ends_with(".ply")) return ply(readPlainFile(file, maxBytes), name);
    if (lower.ends_with(".ply.gz")) return ply(InputFile(file, "mesh file", maxBytes).readAllGzip(), name);
    fail(name, "unsupported mesh file type (expected a name ending in .obj, .ply or .ply.gz)");
}

}  // namespace

PolygonMesh importPolygons(const fs::path& file, uint64_t maxBytes) {
    return importByFormat(file, maxBytes, importObjPolygons, importPlyPolygons);
}

TriangleMesh importMesh(const fs::path& file, uint64_t maxBytes) {
    return importByFormat(file, maxBytes, importObj, importPly);
}

void transformMesh(TriangleMesh& mesh, const Transform& transform) {
    for (Vec3f& p : mesh.positions) p = transform.applyPoint(p);
    for (Vec3f& n : mesh.normals) n = normalize(transform.applyNormal(n));
    if (transform.swapsHandedness())
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
            std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

void orientFaces(TriangleMesh& mesh, FrontSide side) {
    const bool reverse = side == FrontSide::Reversed || side == FrontSide::ReversedNormals;
    const bool byNormals =
        (side == FrontSide::Normals || side == FrontSide::ReversedNormals) && !mesh.normals.empty();
    if (reverse)
        for (Vec3f& n : mesh.normals) n = -n;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        uint32_t* i = &mesh.indices[t];
        bool swap = reverse && !byNormals;
        if (byNormals) {
            const Vec3f winding = cross(mesh.positions[i[1]] - mesh.positions[i[0]],
                                        mesh.positions[i[2]] - mesh.positions[i[0]]);
            swap = dot(winding, mesh.normals[i[0]] + mesh.normals[i[1]] + mesh.normals[i[2]]) < 0.0f;
        }
        if (swap) std::swap(i[1], i[2]);
    }
}

}  // namespace penumbra
