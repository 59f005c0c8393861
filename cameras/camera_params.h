// The camera as the scene gives it (scenes/README.md, `camera`): where it is and how it moves, its
// shutter, and one of the projections with its own parameters. Read by scenes/camera_reader.cpp
// and the pbrt importer; turned into a Camera (cameras/camera.h) by the renderer.
#pragma once

#include <vector>

#include "core/vec.h"

namespace penumbra {

// Where the camera is and what it looks at. A moving camera has several poses, evenly spaced over
// the shutter; between them the three points are interpolated linearly.
struct CameraPose {
    Vec3f lookFrom, lookAt, up;
};

// How film positions become rays; each has a header of its own in cameras/.
enum class CameraProjection {
    Perspective,   // a pinhole or a thin lens (thin_lens.h)
    Orthographic,  // parallel rays, optionally through a thin lens (orthographic.h)
    Spherical,     // the whole sphere of directions (spherical.h)
    Fisheye,       // a hemisphere or more onto a disk (fisheye.h)
    LensSystem,    // rays traced through a real lens design (lens_system.h)
};

enum class SphericalMapping { Equirectangular, EqualArea };
// Image radius r against the angle theta from the view direction: r ~ theta (equidistant) or
// r ~ 2 sin(theta / 2) (equisolid angle, each pixel the same solid angle).
enum class FisheyeMapping { Equidistant, Equisolid };

// An aperture's shape as an image of its transmission over the square [-1, 1]^2 around the lens
// (the square that circumscribes the round aperture of the same radius): row 0 is the top (+y),
// values >= 0. Empty: the aperture is round, or a polygon of `apertureBlades`.
struct ApertureImage {
    int width = 0, height = 0;
    std::vector<float> values;  // width * height, row-major
    bool empty() const { return values.empty(); }
};

// One surface of a lens design as pbrt-v4's lens files give it, in millimetres, front (object
// side) to back: the signed radius of curvature (0: the aperture stop, a plane), the distance to
// the next surface along the axis, the refractive index behind the surface (0 or 1: air) and the
// surface's clear aperture diameter.
struct LensSurface {
    float curvatureRadius = 0.0f;
    float thickness = 0.0f;
    float eta = 0.0f;
    float apertureDiameter = 0.0f;
};

struct LensSystemParams {
    std::vector<LensSurface> surfaces;
    float apertureDiameterMm = 0.0f;  // the stop opened to this diameter; 0: as wide as the file's stop
    float filmDiagonalMm = 35.0f;     // the film's physical size (35 mm: full frame)
    // The length of one scene unit in millimetres: the lens and the film are given in millimetres
    // (pbrt-v4 takes scenes in metres: 1000).
    float mmPerSceneUnit = 1000.0f;
};

struct CameraParams {
    Vec3f lookFrom{0.0f, 0.0f, 0.0f};
    Vec3f lookAt{0.0f, 0.0f, -1.0f};
    Vec3f up{0.0f, 1.0f, 0.0f};
    // Camera motion: empty, or >= 2 poses evenly spaced over the shutter, interpolated linearly;
    // they replace lookFrom / lookAt / up.
    std::vector<CameraPose> motion;
    CameraProjection projection = CameraProjection::Perspective;
    // Perspective: the angle across the image's height. Fisheye: the angle across the image's
    // shorter side (up to 360 degrees).
    float verticalFovDegrees = 40.0f;
    float orthographicHeight = 2.0f;  // orthographic: the height the image spans, in scene units
    SphericalMapping sphericalMapping = SphericalMapping::Equirectangular;
    bool mirrorColumns = false;  // spherical: the columns run the other way (pbrt-v4's handedness)
    FisheyeMapping fisheyeMapping = FisheyeMapping::Equidistant;
    // The thin lens (perspective and orthographic).
    float apertureRadius = 0.0f;  // lens radius in scene units; 0 is a pinhole
    float focusDistance = 0.0f;   // along the view direction; 0 means |lookAt - lookFrom|
    int apertureBlades = 0;       // 0: a circular aperture; >= 3: a regular polygon (shaped bokeh)
    float apertureRotationDegrees = 0.0f;
    // The aperture's shape as an image (thin lens and lens system): replaces the blades.
    ApertureImage apertureImage;
    LensSystemParams lensSystem;  // LensSystem; focusDistance too (0: 10 scene units, as pbrt-v4)
    // The shutter interval, in the scene's time unit; motion keys are spread over it. Rays carry
    // the shutter fraction (0 = open, 1 = closed).
    float shutterOpen = 0.0f;
    float shutterClose = 0.0f;
};

}  // namespace penumbra
