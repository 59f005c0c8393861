// What every render of a scene builds once before its first sample, beside the traversal backend:
// the camera, the light set, the face frames and the integrator's context over them. `render`,
// `converge` (through render()), the benchmarks and the tools all prepare a scene this way.
#pragma once

#include "cameras/camera.h"
#include "geometry/face_frames.h"
#include "lights/light_set.h"
#include "renderer/path_integrator.h"
#include "scenes/scene.h"

namespace penumbra {

class PreparedScene {
public:
    explicit PreparedScene(const Scene& scene)
        : scene_(scene),
          camera_(scene.camera, scene.film.width, scene.film.height),
          lights_(scene, scene.lights, scene.environment, scene.integrator.lightSampler),
          faceFrames_(scene),
          moves_(scene.hasMotion()) {}
    // The context points into this object.
    PreparedScene(const PreparedScene&) = delete;
    PreparedScene& operator=(const PreparedScene&) = delete;

    const Scene& scene() const { return scene_; }
    const Camera& camera() const { return camera_; }
    const LightSet& lights() const { return lights_; }
    // Whether a ray's time matters (otherwise no time sample is drawn).
    bool moves() const { return moves_; }
    IntegratorContext integratorContext() const {
        return IntegratorContext::forScene(scene_, lights_, &faceFrames_,
                                           camera_.footprint(scene_.film.samplesPerPixel));
    }

private:
    const Scene& scene_;
    Camera camera_;
    LightSet lights_;
    FaceFrames faceFrames_;
    bool moves_;
};

}  // namespace penumbra
