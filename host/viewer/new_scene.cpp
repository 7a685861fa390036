#include "viewer/new_scene.h"

namespace ray {

const std::string& newSceneText() {
    static const std::string text = R"(<scenefile>
  <globaldata>
    <diffusecoeff v="0.5"/>
    <specularcoeff v="0.5"/>
    <ambientcoeff v="0.5"/>
  </globaldata>
  <cameradata>
    <pos x="4" y="3" z="5"/>
    <focus x="0" y="0" z="0"/>
    <up x="0" y="1" z="0"/>
    <heightangle v="45"/>
  </cameradata>
  <lightdata>
    <id v="0"/>
    <color r="1" g="1" b="1"/>
    <position x="3" y="5" z="4"/>
  </lightdata>
  <object type="tree" name="root">
  </object>
</scenefile>
)";
    return text;
}

bool opensAsNewScene(const std::filesystem::path& file) {
    std::error_code ec;
    const std::filesystem::path folder = file.parent_path().empty() ? "." : file.parent_path();
    return !std::filesystem::exists(file, ec) && (file.extension() == ".xml" || file.extension() == ".json") &&
           std::filesystem::is_directory(folder, ec);
}

}  // namespace ray
