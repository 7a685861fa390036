// `ray view new.xml` on a file that does not exist: the viewer opens a new scene, a camera
// and a light, and writes it there on the first save (nothing is written before).
#pragma once

#include <filesystem>
#include <string>

namespace ray {

// The scenefile text of a new scene: the course's globals, a camera looking at the origin
// from above and to the side, one white point light, an empty root tree to add to.
const std::string& newSceneText();

// Whether `file` is a new scene: it does not exist, names a .xml file, and its folder
// exists (else it is opened as ever, and the load says it cannot be).
bool opensAsNewScene(const std::filesystem::path& file);

}  // namespace ray
