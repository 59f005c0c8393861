// The project's version, as the files penumbra writes record it.
#pragma once

#include <string>

namespace penumbra {

// The project's version, as film files record it.
std::string penumbraVersion();
// The "Software" attribute of the images penumbra writes: "penumbra VERSION".
std::string penumbraSoftwareName();

}  // namespace penumbra
