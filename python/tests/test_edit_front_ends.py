"""One sequence of edits (tests/data/edits/sequence.json) made through each front end of the
one edit model saves the same file, byte for byte (issue 43): the page's routes (POST /op and
/save of `ray view`, docs/modeler-protocol.md), the C++ API (tests/front_ends/edit_sequence.cpp)
and this module. The sequence starts from tests/data/edits/start.xml (a floor, a master placed
twice, a light) and touches every operation: adds of a sphere, a light and a mesh, a move
by its world matrix, a texture, a duplicate, a group, a rename, a make-unique, material,
light, camera, globals and transblock fields, a delete.

A step names nodes as "$N.added.K" (the K-th node step N added: the answers' `added`) or
"@kind.K" (the K-th node of that kind in the outline, from the end when negative), so that
each front end finds them through its own outline and answers.

The same sequence from tests/data/edits/start.json (the same scene as the course's JSON,
issue 50) saves one JSON file through the three front ends: its text kept, the edits spliced
in, new groups written in the course's style."""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import cs123ray

ROOT = Path(__file__).parents[2]
SEQUENCE = ROOT / "tests" / "data" / "edits" / "sequence.json"
START = ROOT / "tests" / "data" / "edits" / "start.xml"
START_JSON = ROOT / "tests" / "data" / "edits" / "start.json"
SCENES = Path(os.environ.get("RAY_SCENES_DIR", ROOT / "scenes"))
ASSETS = [SCENES / "textures" / "wood.png", SCENES / "meshes" / "vase.obj"]  # the files the sequence names
RAY = os.environ.get("RAY_BINARY")
EDIT_SEQUENCE = os.environ.get("RAY_EDIT_SEQUENCE")

needs_front_ends = pytest.mark.skipif(not RAY or not EDIT_SEQUENCE,
                                      reason="RAY_BINARY and RAY_EDIT_SEQUENCE (set by CTest) name the ray command "
                                             "and the C++ front end")


def folder_with_start(tmp_path, name, start=START):
    """A folder holding the start scene and the files the sequence names, as a user's scene
    folder (tmp_path/name/scene: a JSON scene names files from the folder above its own)."""
    folder = tmp_path / name / "scene"
    folder.mkdir(parents=True)
    for asset in [start, *ASSETS]:
        shutil.copy(asset, folder)
    return folder / start.name


def resolve(node, answers, outline):
    """A step's node name as an id (the module docstring says how); `outline` a list of dicts of
    node and kind, asked for only when needed."""
    if not node or node[0] not in "$@":
        return node
    head, _, index = node.rpartition(".")
    if node[0] == "$":
        return answers[int(head[1:].split(".")[0])]["added"][int(index)]
    kind = head[1:]
    kind = "transblock" if kind == "block" else kind
    return [entry["node"] for entry in outline() if entry["kind"] == kind][int(index)]


def python_steps(kind, v):
    return (kind, tuple(v))


def python_value(name, value):
    """A JSON value of the sequence as this module takes it (cs123ray.fields() kinds)."""
    if name == "world":
        return cs123ray.Transform([value[0:4], value[4:8], value[8:12]])
    if name == "transform":
        return [python_steps(step["kind"], step["v"]) for step in value]
    if isinstance(value, list):
        return tuple(value)
    return value


def through_python(start, out):
    scene = cs123ray.load_scene(start)
    answers = []
    outline = scene.outline
    for step in json.loads(SEQUENCE.read_text()):
        fields = {name: python_value(name, value) for name, value in step.get("fields", {}).items()}
        nodes = [resolve(n, answers, outline) for n in step.get("nodes", [])]
        op = step["op"]
        if op == "set":
            answer = scene.set(resolve(step["node"], answers, outline), **fields)
        elif op == "add-primitive":
            file = str(start.parent / step["file"]) if "file" in step else None
            answer = scene.add(step["shape"], file=file, **fields)
        elif op == "add-light":
            answer = scene.add_light(step["type"], **fields)
        elif op == "duplicate":
            answer = scene.duplicate(*nodes)
        elif op == "group":
            answer = scene.group(*nodes)
        elif op == "delete":
            answer = scene.delete(*nodes)
        elif op == "rename":
            answer = scene.rename(resolve(step["node"], answers, outline), step["name"])
        elif op == "make-unique":
            answer = scene.make_unique(resolve(step["node"], answers, outline))
        else:
            raise AssertionError(f"the sequence's op {op} has no Python front end here")
        answers.append(answer)
    scene.save(out)


def through_cpp(start, out):
    subprocess.run([EDIT_SEQUENCE, str(SEQUENCE), str(start), str(out)], check=True)


def through_the_page(start, out):
    """The page's requests: each step as a POST /op body (the sequence is written in its JSON),
    with a fresh action each (a step is one user action), then POST /save as `out`'s name."""
    sys.path.insert(0, str(ROOT / "tests" / "viewer"))
    from viewer_harness import Viewer
    viewer = Viewer(RAY, str(start), "--device", "ref")
    try:
        for asset in ASSETS:  # the viewer's copy of the scene is in a folder of its own
            shutil.copy(asset, viewer.folder)

        def outline():
            status, answer = viewer.json("GET", "/outline")
            assert status == 200, answer
            return answer["nodes"]

        answers = []
        for number, step in enumerate(json.loads(SEQUENCE.read_text())):
            body = dict(step, action=f"step-{number}")
            if "node" in step:
                body["node"] = resolve(step["node"], answers, outline)
            if "nodes" in step:
                body["nodes"] = [resolve(n, answers, outline) for n in step["nodes"]]
            status, answer = viewer.json("POST", "/op", json.dumps(body).encode())
            assert status == 200, (step, answer)
            answers.append(answer)
        status, answer = viewer.json("POST", "/save", json.dumps({"as": out.name}).encode())
        assert status == 200, answer
        shutil.copy(answer["saved"], out)
    finally:
        viewer.close()


@needs_front_ends
def test_one_sequence_of_edits_through_the_page_cpp_and_python_saves_one_file(tmp_path):
    saved = {}
    for name, front_end in [("python", through_python), ("cpp", through_cpp), ("page", through_the_page)]:
        start = folder_with_start(tmp_path, name)
        out = start.parent / f"{name}.xml"
        front_end(start, out)
        saved[name] = out.read_bytes()
    assert saved["cpp"] == saved["python"], "C++ and Python saved different files"
    assert saved["page"] == saved["python"], "the page's routes and Python saved different files"
    # The file is the edited scene: every front end made every edit, and it loads.
    text = saved["python"].decode()
    for made in ['name="marble"', 'name="marble_2"', "wood.png", "vase.obj", "<type v=\"spot\"/>", 'v="0.4"']:
        assert made in text, (made, text)
    assert text.count('type="master"') == 1, text  # one placement of each leg left: the second deleted
    cs123ray.load_scene(tmp_path / "python" / "scene" / "python.xml")


@needs_front_ends
def test_one_sequence_of_edits_on_a_json_scene_saves_one_json_file(tmp_path):
    saved = {}
    for name, front_end in [("python", through_python), ("cpp", through_cpp), ("page", through_the_page)]:
        start = folder_with_start(tmp_path, name, START_JSON)
        out = start.parent / f"{name}.json"
        front_end(start, out)
        saved[name] = out.read_text()
    # A JSON scene names its files from the folder above its own (SPEC §7): the page's copy of
    # the scene is in a folder of the viewer's, whose name its paths say.
    saved["page"] = saved["page"].replace(page_folder_name(saved["page"]) + "/", "scene/")
    assert saved["cpp"] == saved["python"], "C++ and Python saved different files"
    assert saved["page"] == saved["python"], "the page's routes and Python saved different files"
    text = saved["python"]
    course = START_JSON.read_text()
    for kept in ['"specularCoeff": 0.5', '"translate": [-2, 0, 0],', '"diffuse": [0.6, 0.4, 0.2]']:
        assert kept in text, (kept, text)  # the lines no edit touched, as they were
    for made in ['"name": "marble"', '"name": "marble_2"', "scene/wood.png", "scene/vase.obj", '"type": "spot"',
                 '"ambientCoeff": 0.4']:
        assert made in text, (made, text)
    assert text.count('"groups": [{"name": "marble') == 1 and '"leg"' not in text, text  # one placement left
    assert text.splitlines()[:3] == course.splitlines()[:3]
    cs123ray.load_scene(tmp_path / "python" / "scene" / "python.json")


def page_folder_name(text):
    """The folder a path of the page's saved JSON names its texture in (the viewer's own)."""
    marker = "/wood.png"
    end = text.index(marker)
    return text[text.rindex('"', 0, end) + 1:end]
