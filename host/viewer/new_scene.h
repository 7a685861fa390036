// `ray view new.xml` on a file that does not exist: the viewer opens a new scene, a camera
// and a light, and writes it there on the first save (nothing is written before).
#pragma once

#include <filesystem>
#include <string>

namespace ray {

// The scenefile text of a new scene: the course's globals, a camera looking at the origin
// from above and to the side, one white point light, an empty root tree to add to; in the
// course's JSON for a .json `file` (the light in a group of its own), XML otherwise.
const std::string& newSceneText(const std::filesystem::path& file);

// Whether `file` is a new scene: it does not exist, names a .xml or .json file, and its folder
// exists (else it is opened as ever, and the load says it cannot be).
bool opensAsNewScene(const std::filesystem::path& file);

}  // namespace ray
