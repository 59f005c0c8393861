// pbrt-v4's scene semantics: the graphics state (transform stack with motion, materials, area
// lights, orientation), named coordinate systems, materials, textures and object definitions,
// and the mapping of each directive to penumbra's scene. The result is a scene in penumbra's own
// format (a JSON document, scenes/README.md), which the native loader then builds: one set of
// checks, and `penumbra convert` writes that document as it is.
//
// Conventions honoured (docs/pbrt-import.md): pbrt's camera is left-handed (camera space: +x to
// the image's right, +y up, +z forward, with the image as pbrt-v4 shows it), the fov is for the
// shorter image axis, area lights are one-sided on the side of the surface normal pbrt-v4 computes
// (ReverseOrientation, mirroring transforms and mesh normals included), and RGB values are taken
// as pbrt-v4 uses them (formats/pbrt/spectrum.h).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "formats/pbrt/double_math.h"
#include "formats/pbrt/materials.h"
#include "formats/pbrt/parser.h"
#include "formats/pbrt/warning_log.h"
#include "scenes/json_reader.h"

namespace penumbra::pbrt {

// Where a part of the produced document came from: a JSON pointer prefix and the directive.
struct Origin {
    std::string pointer;
    SourceLocation where;
};

class SceneBuilder : public DirectiveTarget {
public:
    // `mainFile` is the scene file: relative file names (meshes, images) are resolved against
    // its folder, as pbrt-v4 does.
    SceneBuilder(std::filesystem::path mainFile, WarningLog& log);

    void directive(Directive&& d) override;
    void textRead(uint64_t totalBytes) override { textBytes_ = totalBytes; }

    // The scene in penumbra's format, once every directive has been given (called once: the
    // document is moved out). Throws InputError for what is still open (AttributeBegin, ObjectBegin).
    Json finish();
    const std::vector<Origin>& origins() const { return origins_; }

private:
    struct AreaLight {
        Rgb radiance;
        bool twoSided = false;
        SourceLocation where;
    };
    struct GraphicsState {
        std::array<Matrix4d, 2> ctm = {Matrix4d::identity(),
                                       Matrix4d::identity()};  // at the start and end time
        unsigned activeTransforms = 3;                         // bit 0: start, bit 1: end
        bool reverseOrientation = false;
        std::string material;  // the JSON name of the current material; empty: pbrt's default
        std::optional<AreaLight> areaLight;
        // MediumInterface's names ("" the vacuum): where they differ, shapes are medium boundaries.
        std::string insideMedium, outsideMedium;
        SourceLocation mediumWhere;  // of the MediumInterface that set them
    };
    struct PushedState {
        GraphicsState state;
        bool attributes = true;  // AttributeBegin, or TransformBegin (transform only)
        SourceLocation where;
    };
    // A shape as the scene gave it, kept for object definitions, which are placed once per instance.
    struct ShapeRecord {
        std::string type;
        ParameterList params;
        GraphicsState state;
        SourceLocation where;
    };

    // Directive groups.
    void transformDirective(const Directive& d);
    void optionDirective(const Directive& d);  // Camera, Film, Sampler, PixelFilter, Integrator, ...
    void materialDirective(const Directive& d);
    void lightSource(const Directive& d);
    void areaLightSource(const Directive& d);
    // Constant infinite lights add up into "background".
    void addBackground(Rgb radiance, const SourceLocation& where);
    // LightSource "infinite" with "filename": penumbra's image environment for a latitude-longitude
    // image (in pbrt's orientation convention), a constant of its mean for pbrt-v4's square
    // equal-area maps.
    void imageEnvironment(const Parameter& filename, float scale, const SourceLocation& where);
    void objectDirective(const Directive& d);

    // Applies `t` to the active transforms: ctm = ctm * t (pbrt's order).
    void concat(const Matrix4d& t);
    void requireWorld(const Directive& d, bool inWorld) const;

    // Shapes. `worldFromInstance`: the ObjectInstance's transform at both times, for a shape of an
    // object placed as a copy.
    void addShape(const ShapeRecord& shape, const std::array<Matrix4d, 2>* worldFromInstance);
    // The shape's geometry as penumbra's shape (or prototype) object, without material, emission
    // or placement; empty, with a warning, for the shapes penumbra does not have. `swaps`: the
    // placement mirrors (pbrt-v4 then turns a disk's normal). `exactPatches`: a bilinearmesh becomes
    // penumbra's bilinear_mesh (else two triangles a patch).
    std::optional<Json> shapeGeometry(const ShapeRecord& shape, bool swaps, bool exactPatches = false);
    // A shape's "alpha" (a float or a float texture's name) as penumbra's cut-out: a number or a
    // texture object; none for an opaque shape (alpha 1).
    std::optional<Json> cutOutAlpha(const Parameter& alpha) const;
    // Shape "curve": one curve, its control points taken to the world (so that curves under
    // different transforms share a set), appended to the last shape when that is a curve set of the
    // same material, type and media (a hair file's thousands of curves become one set).
    void addCurve(const ShapeRecord& shape, const std::array<Matrix4d, 2>& ctm);
    // The index in "shapes" of the last shape addCurve wrote, for it to append to.
    std::optional<size_t> lastCurves_;
    // ObjectInstance: each mesh of the object becomes a prototype (once, at its first instance) and
    // an "instance" shape; what penumbra's instances cannot hold (spheres, emitters, shapes that
    // move inside the object) is placed as a copy instead.
    void instantiate(const std::string& object, const std::array<Matrix4d, 2>& worldFromInstance,
                     const SourceLocation& where);
    // Why `shape` of an object cannot be a prototype, or empty when it can.
    std::string copyReason(const ShapeRecord& shape) const;
    // What placing `object` once adds to the shapes placed by instances (core/input_limits.h):
    // one per instance or copied shape, a copied mesh one per triangle.
    int64_t placementCost(const std::string& object) const;
    // `wanted`, or, when the document already has a member of that name under `section`
    // ("materials", "prototypes"), the first of "wanted#2", "wanted#3", ... that it has not:
    // generated names ("a/0" for object a's first shape, "Material at ...") must not replace
    // what a scene named so.
    std::string unusedName(const char* section, const std::string& wanted) const;
    // Opens an AttributeBegin, TransformBegin or ObjectBegin, within the nesting limit.
    void push(const Directive& d, bool attributes);
    // The material a shape was given (pbrt-v4: the one current where the Shape directive is, also
    // inside an object definition), or pbrt's default diffuse material.
    std::string materialOf(const ShapeRecord& shape);
    void addPlacement(Json& shape, const std::array<Matrix4d, 2>& ctm, const SourceLocation& where);

    void finishCamera(Json& scene);
    void projectiveCamera(Json& camera);
    void realisticCamera(Json& camera);
    Matrix4d toWorld(const Matrix4d& m) const { return mirror_ * m; }

    std::filesystem::path mainFile_, folder_;
    WarningLog& log_;
    Json scene_ = Json::object();
    std::vector<Origin> origins_;

    GraphicsState state_;
    std::vector<PushedState> stack_;
    std::map<std::string, std::array<Matrix4d, 2>> namedCoordinateSystems_;
    double transformTimes_[2] = {0.0, 1.0};
    bool inWorld_ = false;

    // The camera, finished when the film's resolution is known.
    struct Camera {
        std::array<Matrix4d, 2> cameraFromWorld = {Matrix4d::identity(), Matrix4d::identity()};
        ParameterList params;
        std::string type = "perspective";
        SourceLocation where;
        bool given = false;
        std::string medium;  // the outside medium of MediumInterface at Camera (pbrt-v4's CameraMedium)
        SourceLocation mediumWhere;
    } camera_;
    // pbrt's camera may be mirrored (its LookAt is left-handed), penumbra's is not: the whole
    // world is mirrored across the camera's vertical plane instead, which leaves the image as it is.
    Matrix4d mirror_ = Matrix4d::identity();
    int filmWidth_ = 1280, filmHeight_ = 720;
    double filmDiagonalMm_ = 35.0;  // Film "diagonal": the realistic camera's film size
    // Film "iso" and "whitebalance" (pbrt-v4's PixelSensor), exposed with the camera's shutter time.
    double filmIso_ = 100.0, filmWhiteBalance_ = 0.0;

    TextureTable textures_;
    std::map<std::string, std::string> namedMaterials_;  // pbrt name -> JSON material name
    // Media: the names MakeNamedMedium defined (those left out with a warning map to ""), and each
    // name used with where it was first used, checked once the file is read.
    std::map<std::string, std::string> namedMedia_;
    std::map<std::string, SourceLocation> usedMedia_;
    void mediumDirective(const Directive& d);
    // The JSON name standing for the pbrt medium `name` ("" for the vacuum).
    std::string mediumOf(const std::string& name, const SourceLocation& where);
    // A shape's "inside" and "outside" keys, where `state` makes it a medium boundary.
    void addMediumInterface(Json& shape, const GraphicsState& state);
    std::string defaultMaterial_;
    int anonymousMaterials_ = 0;
    bool filterGiven_ = false;

    std::map<std::string, std::vector<ShapeRecord>> objects_;
    // Per object, the prototype name of each of its shapes once it has been instanced ("" for a
    // shape placed as copies or left out).
    std::map<std::string, std::vector<std::string>> prototypes_;
    std::optional<std::pair<std::string, SourceLocation>> currentObject_;

    // Bounds on what the scene's text may ask for (core/input_limits.h).
    uint64_t textBytes_ = 0;
    int64_t placedShapes_ = 0;
};

}  // namespace penumbra::pbrt
