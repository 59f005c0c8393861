#include "core/plugin_library.h"

#include <dlfcn.h>

#include <string>

#include "core/error.h"

namespace penumbra::detail {

namespace {

SourceLocation fileOf(const std::filesystem::path& path) {
    SourceLocation where;
    where.file = path.string();
    return where;
}

}  // namespace

void* openPluginEntry(const std::filesystem::path& path, const char* entry, const char* what) {
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) throw InputError(fileOf(path), std::string("cannot load the ") + what + ": " + ::dlerror());
    void* function = ::dlsym(handle, entry);
    if (!function)
        throw InputError(fileOf(path), std::string("cannot load the ") + what + ": " + ::dlerror());
    return function;
}

void throwPluginOfAnotherVersion(const std::filesystem::path& path, const char* what, int expected) {
    throw InputError(fileOf(path), std::string("the ") + what + " is of another version (expected " +
                                       std::to_string(expected) + ")");
}

}  // namespace penumbra::detail
