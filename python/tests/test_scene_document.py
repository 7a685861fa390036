"""The scene as its file has it: objects, their edits, lights, saving (cs123ray.Scene)."""
import os
from pathlib import Path

import numpy as np
import pytest

import cs123ray

T = cs123ray.Transform
OUTPUT = Path(os.environ.get("RAY_TEST_OUTPUT_DIR", "/tmp/cs123ray-tests"))
SHARED = Path(os.environ.get("RAY_SHARED_DIR", Path(__file__).resolve().parents[3] / "shared"))
CHESS = SHARED / "cs123" / "scenes" / "chess.xml"

TABLE = """<scenefile>
  <cameradata><pos x="0" y="1" z="6"/><look x="0" y="-0.2" z="-1"/><up x="0" y="1" z="0"/><heightangle v="45"/></cameradata>
  <lightdata><id v="0"/><type v="point"/><color r="1" g="1" b="1"/><position x="3" y="4" z="5"/></lightdata>
  <object type="tree" name="leg">
    <transblock><scale x="0.2" y="2" z="0.2"/>
      <object type="primitive" name="cylinder"><diffuse r="0.8" g="0.5" b="0.2"/></object>
    </transblock>
  </object>
  <object type="tree" name="root">
    <transblock><translate x="-1" y="0" z="0"/><object type="master" name="leg"/></transblock>
    <transblock><translate x="1" y="0" z="0"/><object type="master" name="leg"/></transblock>
    <transblock><translate x="0" y="1.5" z="0"/>
      <object type="primitive" name="sphere"><diffuse r="0.2" g="0.3" b="0.9"/><shininess v="10"/></object>
    </transblock>
  </object>
</scenefile>"""


@pytest.fixture(scope="module")
def output():
    folder = OUTPUT / "scene_document"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def render(scene):
    return cs123ray.render(scene, device="ref", width=64, height=48, aa="off")


def test_objects_are_the_files_with_paths_and_instances():
    scene = cs123ray.scene_from_string(TABLE, "table.xml")
    leg, sphere = scene.objects
    assert leg.path == "leg/transblock[0]/object[0]" and leg.in_master and leg.instances == 2
    assert sphere.path == "root/transblock[2]/object[0]" and not sphere.in_master
    assert sphere.shape == "sphere"
    # An XML scene's outline in XML's words (a JSON scene's: test_json_save.py), with its paths.
    outline = scene.outline()
    assert all(entry["label"] == entry["kind"] for entry in outline)
    assert ("placement", "master leg") in [(entry["kind"], entry["text"]) for entry in outline]
    assert "root/transblock[2]/object[0]" in [entry["path"] for entry in outline]
    assert sphere.material["diffuse"] == (0.2, 0.3, 0.9) and sphere.material["shininess"] == 10
    assert np.allclose(sphere.transform.matrix(), T.translate(x=0, y=1.5, z=0).matrix())
    assert scene.object_of_instance(2) == sphere
    assert [node["path"] for node in scene.nodes][:2] == ["leg/transblock[0]", "root/transblock[0]"]


def test_set_material_changes_only_the_fields_given_and_the_next_render():
    scene = cs123ray.scene_from_string(TABLE, "table.xml")
    sphere = scene.objects[1]
    before = render(scene)
    sphere.set_material(diffuse=(1, 0, 0), ambient=(0.2, 0, 0))
    assert sphere.material["diffuse"] == (1, 0, 0) and sphere.material["ambient"] == (0.2, 0, 0)
    assert sphere.material["shininess"] == 10  # kept
    assert not np.array_equal(render(scene), before)


def test_set_transform_and_the_transform_property():
    scene = cs123ray.scene_from_string(TABLE, "table.xml")
    leg = scene.objects[0]
    before = render(scene)
    moved = T.translate(x=-1.5, y=0.5, z=0) @ T.scale(0.3, 1, 0.3)
    leg.set_transform(moved)
    assert np.allclose(leg.transform.matrix(), moved.matrix())
    assert leg.instances == 2  # the master's other instance moved with it
    after = render(scene)
    assert not np.array_equal(after, before)
    leg.transform = T.translate(x=-1, y=0, z=0) @ T.scale(0.2, 2, 0.2)  # back where it was
    assert np.allclose(render(scene), before, atol=1e-6)


def test_save_loads_back_to_the_same_bytes(output):
    scene = cs123ray.scene_from_string(TABLE, "table.xml")
    scene.objects[1].set_material(diffuse=(0, 1, 0))
    scene.objects[0].set_transform(T.translate(x=-1.2, y=0, z=0.3) @ T.scale(0.2, 1.5, 0.2))
    path = output / "table.xml"
    scene.save(path)
    assert path.read_text() == scene.to_text()
    assert '<object type="master" name="leg"/>' in path.read_text()
    reloaded = cs123ray.load_scene(path)
    assert np.array_equal(render(reloaded), render(scene))
    assert reloaded.to_text() == scene.to_text()


def test_bad_edits_raise_value_error_and_change_nothing():
    scene = cs123ray.scene_from_string(TABLE, "table.xml")
    sphere = scene.objects[1]
    text = scene.to_text()
    with pytest.raises(ValueError, match="shininess"):
        sphere.set_material(shininess=-1)
    with pytest.raises(ValueError, match="singular"):
        sphere.set_transform(T.scale(1, 0, 1))
    with pytest.raises(ValueError, match="glossiness"):
        sphere.set_material(glossiness=2)
    with pytest.raises(ValueError, match="light 3 does not exist"):
        scene.set_light(3, color=(1, 1, 1))
    with pytest.raises(cs123ray.InputError, match="color"):
        scene.set_light(0, color=(-1, 1, 1))
    assert scene.to_text() == text
    sphere.remove()
    assert len(scene.objects) == 1 and scene.primitive_count == 2
    for use in (lambda: sphere.path, lambda: sphere.set_material(diffuse=(1, 1, 1)),
                lambda: sphere.set_transform(T()), sphere.remove):
        with pytest.raises(ValueError, match="does not exist"):
            use()
    assert "removed" in repr(sphere)


def test_a_primitive_added_in_a_master_is_in_every_instance():
    scene = cs123ray.scene_from_string(TABLE, "table.xml")
    leg_block, first_place = scene.nodes[0], scene.nodes[1]
    assert first_place["masters"] == ["leg"] and leg_block["masters"] == []
    foot = scene.add_primitive("sphere", T.translate(x=0, y=-0.5, z=0), material=scene.add_material(), node=leg_block["id"])
    assert foot.in_master and foot.instances == 2 and scene.primitive_count == 5


def test_lights_are_read_set_and_removed():
    scene = cs123ray.scene_from_string(TABLE, "table.xml")
    assert scene.lights[0]["position"] == (3, 4, 5)
    scene.set_light(0, color=(0.5, 0.25, 0))
    assert scene.lights[0]["color"] == (0.5, 0.25, 0) and scene.lights[0]["position"] == (3, 4, 5)
    scene.add_light(type="directional", direction=(0, -1, 0))
    scene.remove_light(0)
    assert [light["type"] for light in scene.lights] == ["directional"]


def test_objects_added_in_code_are_objects_and_save(output):
    scene = cs123ray.Scene()
    scene.set_camera(position=(0, 1, 4), look=(0, -1, -4))
    scene.add_light(position=(3, 4, 5))
    green = scene.add_material(diffuse=(0.2, 0.8, 0.2))
    added = scene.add_primitive("sphere", T.scale(1.5, 1.5, 1.5), material=green)
    (sphere,) = scene.objects
    assert added == sphere
    assert sphere.path == "root/transblock[0]/object[0]" and sphere.material["diffuse"] == (0.2, 0.8, 0.2)
    path = output / "built.xml"
    scene.save(path)
    assert np.array_equal(render(cs123ray.load_scene(path)), render(scene))


@pytest.mark.skipif(not CHESS.exists(), reason="../shared/cs123 (the course corpus) is absent")
def test_chess_edit_render_save(output):
    scene = cs123ray.load_scene(CHESS)
    before = render(scene)
    piece = scene.objects[-1]
    piece.set_material(diffuse=(1, 0, 0), ambient=(0.3, 0, 0))
    recolored = render(scene)
    assert not np.array_equal(recolored, before)
    piece.set_transform(T.translate(x=0, y=0.5, z=0) @ piece.transform)
    moved = render(scene)
    assert not np.array_equal(moved, recolored)
    path = output / "chess.xml"
    scene.save(path)
    assert np.array_equal(render(cs123ray.load_scene(path)), moved)


def test_save_does_not_replace_a_file_changed_since_it_was_loaded(output):
    path = output / "changed.xml"
    path.write_text(TABLE)
    scene = cs123ray.load_scene(path)
    scene.objects[1].set_material(diffuse=(0, 1, 0))
    theirs = TABLE.replace("<scenefile>", "<scenefile>\n<!-- another program's edit -->", 1)
    path.write_text(theirs)
    with pytest.raises(cs123ray.InputError, match="changed on disk .*overwrite_changes"):
        scene.save(path)
    assert path.read_text() == theirs  # their change kept
    scene.save(path, overwrite_changes=True)
    assert path.read_text() == scene.to_text()
    scene.objects[1].set_material(diffuse=(0, 0, 1))
    scene.save(path)  # its own save is no change
    assert path.read_text() == scene.to_text()


def test_a_save_is_always_readable(tmp_path):
    """Names and files XML cannot hold are refused at the edit; a long name made unique is cut between
    characters; an ISO-8859-1 scene is saved in ISO-8859-1."""
    latin1 = TABLE.replace('name="leg"', 'name="caf\xe9"')
    path = tmp_path / "table.xml"
    path.write_bytes(('<?xml version="1.0" encoding="ISO-8859-1"?>\n<!-- caf\xe9 -->\n' + latin1).encode("latin-1"))
    scene = cs123ray.load_scene(path)
    tree = next(entry["node"] for entry in scene.outline() if entry["kind"] == "tree" and entry["text"] != "root")
    text = scene.to_text()
    with pytest.raises(ValueError, match=r"name: U\+FFFF at character 3 cannot be written in an XML file"):
        scene.rename(tree, "ab\uffff")
    with pytest.raises(ValueError, match=r"texture: U\+FFFE at character 5 cannot be written in an XML file"):
        scene.objects[1].set_material(texture="wood\ufffe.png")
    assert scene.to_text() == text

    scene.save(path)
    assert path.read_bytes() == ('<?xml version="1.0" encoding="ISO-8859-1"?>\n<!-- caf\xe9 -->\n' + latin1).encode("latin-1")
    scene.rename(tree, "\u03a9 caf\xe9 " + "\xe9" * 120)  # 127 characters, 249 bytes in UTF-8
    placement = next(entry["node"] for entry in scene.outline() if entry["kind"] == "placement")
    scene.make_unique(placement)
    scene.save(path)
    saved = path.read_bytes()
    assert b"<!-- caf\xe9 -->" in saved and b'name="&#x3A9; caf\xe9 ' in saved
    assert b"\xc3" not in saved  # no UTF-8 in an ISO-8859-1 file
    names = {entry["text"].removeprefix("master ") for entry in cs123ray.load_scene(path).outline()
             if entry["kind"] == "tree"}
    made = "\u03a9 caf\xe9 " + "\xe9" * 119 + "_2"
    assert len(made) == 128
    assert names == {"root", "\u03a9 caf\xe9 " + "\xe9" * 120, made}


def test_a_scene_saved_as_json_is_the_courses_json(output):
    """Scene.save("x.json") writes the course's JSON (issue 50): the same image; what JSON
    cannot hold (a torus) is refused with the reason, and nothing is written."""
    scene = cs123ray.scene_from_string(TABLE)
    path = output / "table.json"
    scene.save(path)
    text = path.read_text()
    assert text.startswith('{\n  "name": "root",\n  "globalData": {\n'), text
    assert '"templateGroups": [' in text and '"name": "leg"' in text
    assert np.array_equal(render(cs123ray.load_scene(path)), render(scene))
    scene.add_primitive("torus", T.translate(0, 3, 0), material=scene.add_material())
    refused = output / "torus.json"
    with pytest.raises(cs123ray.InputError, match="a torus .* cannot be written in the course's JSON"):
        scene.save(refused)
    assert not refused.exists()
