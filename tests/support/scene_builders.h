// Small scenes built in code for the renderer's tests.
#pragma once

#include "scenes/scene.h"

namespace penumbra::testing {

// Appends a quad corner, corner + edge1 + edge2, ... whose front normal is cross(edge1, edge2).
inline TriangleMesh makeQuad(Vec3f corner, Vec3f edge1, Vec3f edge2, uint32_t material) {
    TriangleMesh mesh;
    mesh.name = "quad";
    mesh.positions = {corner, corner + edge1, corner + edge1 + edge2, corner + edge2};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.material = material;
    return mesh;
}

inline Material makeLambert(Rgb albedo) { return Material(Lambert{albedo}); }

// A closed box of diffuse walls lit by a small ceiling light, with a block inside: enough
// structure (occlusion, several bounces, a one-sided emitter) for determinism tests.
inline Scene makeSmallBoxScene(int width, int height, int spp) {
    Scene scene;
    scene.film.width = width;
    scene.film.height = height;
    scene.film.samplesPerPixel = spp;
    scene.camera.lookFrom = {0.0f, 1.0f, 3.5f};
    scene.camera.lookAt = {0.0f, 1.0f, 0.0f};
    scene.camera.verticalFovDegrees = 40.0f;
    scene.materials = {makeLambert(Rgb(0.7f)), makeLambert({0.6f, 0.1f, 0.1f}), makeLambert(Rgb(0.0f))};
    scene.meshes.push_back(makeQuad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0}, 0));  // floor, normal +y
    scene.meshes.push_back(makeQuad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}, 0));  // ceiling, normal -y
    scene.meshes.push_back(makeQuad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}, 0));  // back wall, +z
    scene.meshes.push_back(makeQuad({-1, 0, -1}, {0, 2, 0}, {0, 0, 2}, 1));  // left wall, +x
    scene.meshes.push_back(makeQuad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}, 0));   // right wall, -x
    TriangleMesh light = makeQuad({-0.25f, 1.99f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, 2);  // faces -y
    light.emission.radiance = {12.0f, 10.0f, 8.0f};
    scene.meshes.push_back(light);
    scene.meshes.push_back(
        makeQuad({-0.3f, 0.6f, -0.3f}, {0.6f, 0, 0}, {0, 0, 0.6f}, 0));  // floating panel: a shadow caster
    Sphere ball;
    ball.center = {0.4f, 0.3f, 0.2f};
    ball.radius = 0.3f;
    ball.material = 0;
    scene.spheres.push_back(ball);
    return scene;
}

}  // namespace penumbra::testing
