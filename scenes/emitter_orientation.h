// A one-sided emitter turned the wrong way is a common slip (a quad light whose corners run the
// other way round): it lights nothing the camera sees, and the image is merely dark. This finds
// the likely cases, for a warning: a still one-sided emitting mesh with nothing in front of it,
// not the camera, no other shape (its front: the side of its area-weighted normal, from its
// area-weighted centre).
#pragma once

#include <string>
#include <vector>

#include "scenes/scene.h"

namespace penumbra {

// One message per such mesh, naming it ("/shapes/3: ...").
std::vector<std::string> emittersFacingAway(const Scene& scene);

}  // namespace penumbra
