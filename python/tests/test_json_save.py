"""cs123ray on a course JSON scene (issue 50): edited and saved, the file keeps its text but
for the lines of what was edited; an edit JSON cannot hold is refused with the reason and
changes nothing; saved under a .xml name, it is written as XML."""
import difflib
from pathlib import Path

import pytest

import cs123ray

SCENE = """{
  "globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
  "cameraData": {
    "position": [0, 2, 8],
    "up": [0, 1, 0],
    "heightAngle": 45,
    "look": [0, -0.25, -1]
  },
  "groups": [
    {
      "translate": [0, 4, 0],
      "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]
    },
    {
      "primitives": [
        {
          "type": "sphere",
          "diffuse": [1, 0, 0]
        },
        {
          "type": "cube"
        }
      ]
    }
  ]
}
"""


def changed(before, after):
    return [line for line in difflib.unified_diff(before.splitlines(), after.splitlines(), lineterm="", n=0)
            if line[:1] in "+-" and not line.startswith(("+++", "---"))]


def test_a_json_scene_saves_its_edits_in_its_text(tmp_path: Path):
    file = tmp_path / "scene.json"
    file.write_text(SCENE)
    scene = cs123ray.load_scene(file)
    objects = [entry["node"] for entry in scene.outline() if entry["kind"] == "object"]
    # The outline in the JSON format's words and places, as the studio shows it.
    assert [(entry["label"], entry["text"], entry["path"]) for entry in scene.outline()][2:] == [
        ("light", "point light", "groups[0].lights[0]"), ("groups", "", ""), ("group", "", "groups[0]"),
        ("group", "", "groups[1]"), ("object", "sphere", "groups[1].primitives[0]"),
        ("object", "cube", "groups[1].primitives[1]")]
    scene.set(objects[0], diffuse=(0.5, 0, 0))
    scene.set(objects[1], specular=(1, 1, 1))
    with pytest.raises(ValueError, match="JSON scene.*emissive colour"):
        scene.set(objects[1], emissive=(1, 1, 1))
    light = next(entry["node"] for entry in scene.outline() if entry["kind"] == "light")
    with pytest.raises(ValueError, match="JSON scene.*area light"):
        scene.set(light, type="area")
    assert scene.get(objects[1], "emissive") == (0, 0, 0)
    scene.save(file)
    lines = changed(SCENE, file.read_text())
    assert lines == ['-          "diffuse": [1, 0, 0]', '+          "diffuse": [0.5, 0, 0]',
                     '-          "type": "cube"', '+          "type": "cube",', '+          "specular": [1, 1, 1]'], lines
    again = cs123ray.load_scene(file)
    assert again.get(objects[1], "specular") == (1, 1, 1)
    scene.save(tmp_path / "scene.xml")  # under an XML name: written as XML
    assert "<scenefile>" in (tmp_path / "scene.xml").read_text()
    cs123ray.load_scene(tmp_path / "scene.xml")
