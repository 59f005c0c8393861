// The scene file's render settings: the "film", "integrator" and "render" sections
// (settings_reader.cpp). scenes/README.md documents the keys.
#pragma once

#include "scenes/json_reader.h"
#include "scenes/scene.h"

namespace penumbra {

// Each section's settings; missing keys keep the settings' defaults.
FilmSettings readFilm(const JsonValue& value);
IntegratorSettings readIntegrator(const JsonValue& value);
RenderSettings readRender(const JsonValue& value);

}  // namespace penumbra
