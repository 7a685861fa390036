// Loading a scenefile's text in a test (XML or JSON, by `file`'s name or the text), with the
// loader's warnings collected or its error's message returned.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene_loader.h"

namespace ray::test {

struct LoadedText {
    Scene scene;
    std::vector<std::string> warnings;
};

inline LoadedText loadText(const std::string& text, const std::filesystem::path& file, LoadOptions options = {}) {
    LoadedText result;
    options.warn = [&result](const std::string& w) { result.warnings.push_back(w); };
    result.scene = loadSceneFromText(text, file, options);
    return result;
}

// The message of the InputError that loading throws ("" when it loads).
inline std::string loadError(const std::string& text, const std::filesystem::path& file, LoadOptions options = {}) {
    options.warn = [](const std::string&) {};
    try {
        loadSceneFromText(text, file, options);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace ray::test
