"""`ray view new.xml` on a file that does not exist (issue 43): a new scene, a camera and a
light, rendered; nothing written until the page saves, then the file is there and `ray`
renders it; a missing file that cannot become a scene file (not .xml, no such folder) is
a file that cannot be opened, as before (exit status 2). No browser needed.
Usage: python3 test_new_scene.py RAY_BINARY"""
import json
import os
import subprocess
import sys
import tempfile

from viewer_harness import Viewer

ray = sys.argv[1]
viewer = Viewer(ray, "new.xml", "--device", "cpu", "--width", "64", "--height", "48", new_file=True)
try:
    done = viewer.wait_frame_done(final=True, timeout=120)
    status, state = viewer.json("GET", "/state")
    assert status == 200 and len(state["lights"]) == 1 and state["modified"], state
    assert os.path.samefile(os.path.dirname(state["file"]), viewer.folder) and state["file"].endswith("new.xml")
    assert not os.path.exists(viewer.scene), "written before any save"
    assert "new.xml does not exist: a new scene" in viewer.log(), viewer.log()
    print(f"new.xml (absent): a new scene, one light, rendered (frame {done['frame']}), nothing written")
    status, answer = viewer.json("POST", "/save", b"{}")
    assert status == 200 and os.path.exists(viewer.scene) and not answer["modified"], answer
    ppm = os.path.join(viewer.folder, "new.ppm")
    subprocess.run([ray, viewer.scene, "16", "12", "--device", "cpu", "-o", ppm, "--quiet"], check=True)
    print(f"save: {viewer.scene} written ({os.path.getsize(viewer.scene)} bytes); ray renders it")
finally:
    viewer.close()

# ray view new.json: the same new scene in the course's JSON; a sphere added, saved in the
# course's style (2-space indent, arrays of numbers on one line), which ray renders.
viewer = Viewer(ray, "new.json", "--device", "cpu", "--width", "64", "--height", "48", new_file=True)
try:
    viewer.wait_frame_done(final=True, timeout=120)
    status, answer = viewer.json("POST", "/op", json.dumps({"op": "add-primitive", "shape": "sphere",
                                                            "fields": {"diffuse": [1, 0, 0]}}).encode())
    assert status == 200, answer
    status, answer = viewer.json("POST", "/op", json.dumps({"op": "add-primitive", "shape": "torus"}).encode())
    assert status == 400 and "JSON scene" in answer["error"] and "torus" in answer["error"], (status, answer)
    assert not os.path.exists(viewer.scene), "written before any save"
    status, answer = viewer.json("POST", "/save", b"{}")
    assert status == 200, answer
    text = open(viewer.scene).read()
    scene = json.loads(text)
    assert scene["groups"][0]["lights"][0]["type"] == "point", text
    assert scene["groups"][1]["primitives"] == [{"type": "sphere", "diffuse": [1, 0, 0]}], text
    assert '\n  "globalData": {\n    "ambientCoeff": 0.5,' in text and '"position": [4, 3, 5],' in text, text
    ppm = os.path.join(viewer.folder, "new.ppm")
    subprocess.run([ray, viewer.scene, "16", "12", "--device", "cpu", "-o", ppm, "--quiet"], check=True)
    print(f"new.json: a sphere added (a torus refused: JSON has none), saved in the course's style; ray renders it")
finally:
    viewer.close()

folder = tempfile.mkdtemp()
for name, says in [(os.path.join(folder, "new.txt"), "cannot open the scene file"),
                   (os.path.join(folder, "no-such-folder", "new.xml"), "cannot open the scene file")]:
    run = subprocess.run([ray, "view", name, "--port", "0"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2 and says in run.stderr, (name, run.returncode, run.stderr)
    print(f"{os.path.relpath(name, folder)}: exit 2, '{run.stderr.splitlines()[0]}'")
print("new scene test passed")
