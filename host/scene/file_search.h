// Resolving the file references of a scene (textures, bump maps, meshes): SPEC §1.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ray {

struct FileSearch {
    std::vector<std::filesystem::path> roots;  // user roots, in order, searched first
    std::filesystem::path sceneFolder;         // the folder of the scene file

    // The search roots in the order SPEC §1 gives: the user's roots, then the scene
    // folder and up to three of its ancestors.
    std::vector<std::filesystem::path> searchRoots() const;

    // Resolves a course path ("/course/cs123/data/image/board.png", "image\\board.png",
    // "C:\\...\\board.png"): the path as given if it exists (relative to the scene folder
    // when relative), otherwise the first of its trailing parts that exists under a root.
    // Fills `tried` (when given) with every candidate looked at, for the warning.
    std::optional<std::filesystem::path> resolve(const std::string& reference,
                                                 std::vector<std::filesystem::path>* tried = nullptr) const;
};

// Splits RAY_SEARCH_PATH (':'-separated) into folders.
std::vector<std::filesystem::path> searchPathsFromEnvironment();

}  // namespace ray
