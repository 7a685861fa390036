// ray's modules: shared libraries holding what only some runs need, opened with dlopen
// when first needed, so that their libraries cost the other runs nothing at start-up:
// libray_oiio.so (OpenImageIO, for images neither PNG nor JPEG), libray_viewer.so (ray view:
// cpp-httplib, OpenSSL) and libray_mpi.so (mpirun -n N ray: Open MPI).
//
// Where a module is looked for, in order: the path in its environment variable when that is
// set (then nowhere else); beside the binary or library holding this code (the build folder,
// or the install's library folder for libray.so); the install's library folder next to that
// binary (bin/../lib, for an install made with another prefix than the configured one); then
// the install's and the build's library folders compiled in.
#pragma once

#include <filesystem>
#include <string>

namespace ray {

struct ModuleSpec {
    const char* fileName;     // "libray_oiio.so"
    const char* environment;  // "RAY_OIIO_MODULE": a full path to the module, tried alone
    const char* description;  // "ray's OpenImageIO module": names it in the messages
    bool global = false;      // RTLD_GLOBAL: its libraries' symbols visible to what they load
};

// A module opened (never closed), or why not.
struct LoadedModule {
    const ModuleSpec* spec = nullptr;
    void* library = nullptr;     // dlopen's handle; null when the module was not loaded
    std::filesystem::path path;  // where it was found
    // What is missing, where ray looked and what to do, in one line; empty while usable.
    std::string failure;
};

LoadedModule loadModule(const ModuleSpec& spec);

// The exported symbol `name` of a loaded module, or null with module.failure set.
void* moduleSymbol(LoadedModule& module, const char* name);

// Resolves an entry point into `function`; false (module.failure says why) when the module
// was not loaded or lacks it.
template <typename Function>
bool resolveEntryPoint(LoadedModule& module, const char* name, Function& function) {
    function = reinterpret_cast<Function>(moduleSymbol(module, name));
    return function != nullptr;
}

}  // namespace ray
