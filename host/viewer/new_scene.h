// `ray view new.xml` (or new.json) on a file that does not exist: the viewer opens a new
// scene, a camera and a light, and writes it there on the first save (nothing is written
// before): in the format the name says, new.json as the course's JSON (scene/json_writer.h).
#pragma once

#include <filesystem>
#include <string>

namespace ray {

// The scenefile text of a new scene (XML, whatever the file's name: the document it reads as
// is saved in the format of the file's name): the course's globals, a camera looking at the origin
// from above and to the side, one white point light, an empty root tree to add to.
const std::string& newSceneText();

// Whether `file` is a new scene: it does not exist, names a .xml or .json file, and its
// folder exists (else it is opened as ever, and the load says it cannot be).
bool opensAsNewScene(const std::filesystem::path& file);

}  // namespace ray
