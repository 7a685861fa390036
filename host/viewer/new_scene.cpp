#include "viewer/new_scene.h"

namespace ray {

namespace {

// The same scene in the course's JSON (SPEC §7), its style: saved, it is written as this
// text with the edits spliced in.
const char* const kNewJsonScene = R"({
  "name": "root",
  "globalData": {
    "ambientCoeff": 0.5,
    "diffuseCoeff": 0.5,
    "specularCoeff": 0.5
  },
  "cameraData": {
    "position": [4, 3, 5],
    "up": [0, 1, 0],
    "heightAngle": 45,
    "focus": [0, 0, 0]
  },
  "groups": [
    {
      "translate": [3, 5, 4],
      "lights": [
        {
          "type": "point",
          "color": [1, 1, 1],
          "attenuationCoeff": [1, 0, 0]
        }
      ]
    }
  ]
}
)";

bool namesJson(const std::filesystem::path& file) { return file.extension() == ".json"; }

}  // namespace

const std::string& newSceneText(const std::filesystem::path& file) {
    static const std::string json = kNewJsonScene;
    if (namesJson(file)) return json;
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
    return !std::filesystem::exists(file, ec) && (file.extension() == ".xml" || namesJson(file)) &&
           std::filesystem::is_directory(folder, ec);
}

}  // namespace ray
