// Where penumbra's own files are at run time, found relative to the running executable, so that
// no source or build path is compiled in: a build tree, an installed tree, and either of them
// moved or renamed, all find their files.
//
// The layout is the installed one (`cmake --install build --prefix PREFIX`):
//   PREFIX/bin/penumbra
//   PREFIX/lib/penumbra/   the image plugin (film/image_plugin.h)
//   PREFIX/share/penumbra/ the OpenColorIO config (ocio/), the convergence plot script, scenes/
// A build tree mirrors it: build/tools/penumbra beside build/lib/penumbra and build/share/penumbra
// (CMake copies the data there), and test programs deeper in build/tests/ find the same folders.
#pragma once

#include <filesystem>

namespace penumbra {

// The prefix: the nearest folder at or above the executable's own (at most three levels up) that
// holds share/penumbra. Throws InputError naming the executable when there is none.
std::filesystem::path resourcePrefix();

// PREFIX/share/penumbra/relative and PREFIX/lib/penumbra/relative.
std::filesystem::path sharedDataPath(const std::filesystem::path& relative);
std::filesystem::path pluginPath(const std::filesystem::path& relative);

}  // namespace penumbra
