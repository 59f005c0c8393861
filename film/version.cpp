#include "film/version.h"

namespace penumbra {

std::string penumbraVersion() { return PENUMBRA_VERSION; }

std::string penumbraSoftwareName() { return "penumbra " + penumbraVersion(); }

}  // namespace penumbra
