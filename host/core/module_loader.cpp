#include "core/module_loader.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <vector>

namespace ray {
namespace fs = std::filesystem;

namespace {

// The folder of the binary or shared library this function was linked into.
fs::path folderOfThisCode() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&folderOfThisCode), &info) == 0 || !info.dli_fname) return {};
    std::error_code ec;
    fs::path object = fs::canonical(info.dli_fname, ec);
    return ec ? fs::path() : object.parent_path();
}

const char* explicitPath(const ModuleSpec& spec) {
    const char* path = std::getenv(spec.environment);
    return path && *path ? path : nullptr;
}

std::vector<fs::path> moduleCandidates(const ModuleSpec& spec) {
    if (const char* path = explicitPath(spec)) return {fs::path(path)};  // set on purpose: the only one tried
    std::vector<fs::path> folders;
    if (fs::path here = folderOfThisCode(); !here.empty()) {
        folders.push_back(here);
        folders.push_back(here / RAY_MODULE_RELATIVE_DIR);
    }
    folders.emplace_back(RAY_MODULE_INSTALL_DIR);
    folders.emplace_back(RAY_MODULE_BUILD_DIR);
    std::vector<fs::path> candidates;
    for (const fs::path& folder : folders) {
        fs::path candidate = (folder / spec.fileName).lexically_normal();
        if (std::find(candidates.begin(), candidates.end(), candidate) == candidates.end())
            candidates.push_back(candidate);
    }
    return candidates;
}

// The end of every message: what the user can do about it.
std::string advice(const ModuleSpec& spec) {
    if (explicitPath(spec))
        return std::string("; set ") + spec.environment + " to the path of a working " + spec.fileName + ", or unset it";
    return std::string("; reinstall or rebuild ray, or set ") + spec.environment + " to the path of " + spec.fileName;
}

std::string notFound(const ModuleSpec& spec, const std::vector<fs::path>& candidates) {
    std::string looked;
    for (const fs::path& candidate : candidates) looked += (looked.empty() ? "" : ", ") + candidate.string();
    if (explicitPath(spec)) looked += std::string(", from ") + spec.environment;
    return std::string(spec.description) + " " + spec.fileName + " was not found (looked for " + looked + ")" +
           advice(spec);
}

}  // namespace

LoadedModule loadModule(const ModuleSpec& spec) {
    LoadedModule module;
    module.spec = &spec;
    const std::vector<fs::path> candidates = moduleCandidates(spec);
    for (const fs::path& candidate : candidates) {
        std::error_code ec;
        if (!fs::exists(candidate, ec)) continue;
        module.path = candidate;
        // RTLD_NOW: a symbol missing from ray or from the module's libraries is reported
        // here, in a message, rather than ending the process when it is first called.
        module.library = dlopen(candidate.c_str(), RTLD_NOW | (spec.global ? RTLD_GLOBAL : RTLD_LOCAL));
        if (!module.library)
            module.failure = std::string("cannot load ") + spec.description + " " + candidate.string() + " (" +
                             dlerror() + ")" + advice(spec);
        return module;
    }
    module.failure = notFound(spec, candidates);
    return module;
}

void* moduleSymbol(LoadedModule& module, const char* name) {
    if (!module.library) return nullptr;
    void* symbol = dlsym(module.library, name);
    if (!symbol)
        module.failure = module.path.string() + " is not " + module.spec->description + " (its entry point " + name +
                         " is missing)" + advice(*module.spec);
    return symbol;
}

}  // namespace ray
