#include "core/resource_paths.h"

#include <system_error>

#include "core/error.h"

namespace penumbra {

namespace {

constexpr int kLevelsUp = 3;  // build/tests/FOLDER/test_program -> build

std::filesystem::path findPrefix() {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) throw InputError("cannot find the running executable (/proc/self/exe): " + ec.message());
    std::filesystem::path dir = exe.parent_path();
    for (int level = 0; level <= kLevelsUp; ++level) {
        if (std::filesystem::is_directory(dir / "share" / "penumbra", ec)) return dir;
        if (!dir.has_parent_path() || dir.parent_path() == dir) break;
        dir = dir.parent_path();
    }
    throw InputError(
        "cannot find penumbra's data: no share/penumbra folder at or above " + exe.parent_path().string() +
        " (install with 'cmake --install BUILD --prefix PREFIX', which puts the program in PREFIX/bin "
        "and its data in PREFIX/share/penumbra and PREFIX/lib/penumbra)");
}

}  // namespace

std::filesystem::path resourcePrefix() {
    static const std::filesystem::path prefix = findPrefix();  // a failure is retried on the next call
    return prefix;
}

std::filesystem::path sharedDataPath(const std::filesystem::path& relative) {
    return resourcePrefix() / "share" / "penumbra" / relative;
}

std::filesystem::path pluginPath(const std::filesystem::path& relative) {
    return resourcePrefix() / "lib" / "penumbra" / relative;
}

}  // namespace penumbra
