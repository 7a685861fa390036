"""Versions in ray view (issue 49): an edit, undo or save made against an older revision of the
scene gets 409 with the current state and changes nothing; ids stay with their elements when
another program rewrites the file (the view reloads it); a save does not replace a file that
another program changed since it was read, even when its modification time says nothing (409,
then overwrite or reload as the user says); the undo history's memory is reported in /state.
No browser needed.  Usage: python3 test_versions.py RAY_BINARY SCENE"""
import json
import os
import sys
import time

from viewer_harness import Viewer

ray, scene = sys.argv[1], sys.argv[2]
viewer = Viewer(ray, scene, "--device", "cpu", "--width", "32", "--height", "24")


def post(path, body):
    return viewer.json("POST", path, json.dumps(body).encode())


def state():
    status, answer = viewer.json("GET", "/state")
    assert status == 200, answer
    return answer


def diffuse(node):
    status, answer = viewer.json("GET", f"/node?id={node}")
    assert status == 200, answer
    return next(f["value"] for f in answer["fields"] if f["name"] == "diffuse")


def wait_reload(revision, timeout=30):
    deadline = time.time() + timeout
    while time.time() < deadline:
        now = state()
        if now["revision"] != revision:
            return now
        time.sleep(0.1)
    raise TimeoutError("the file was not reloaded")


def write_keeping_time(path, text):
    """Another program's write that leaves the modification time as it was (a coarse clock,
    or a tool that restores it): the viewer's watch cannot see it."""
    before = os.stat(path)
    with open(path, "w") as f:
        f.write(text)
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))


try:
    viewer.wait_frame_done()
    first = state()
    revision = first["revision"]
    assert first["history"]["bytes"] == 0 and first["history"]["limit"] == 64 << 20, first["history"]

    # An edit against the current revision is made; the answer carries the next revision.
    status, answer = post("/op", {"op": "set", "node": "object-1", "fields": {"shininess": 7}, "revision": revision})
    assert status == 200, answer
    assert answer["editor"]["revision"] == revision + 1, answer["editor"]
    assert answer["editor"]["history"]["bytes"] > 0, answer["editor"]["history"]
    print(f"/op at revision {revision}: made, now {revision + 1}; history {answer['editor']['history']['bytes']} bytes")

    # The same revision again is stale: 409, the current state, nothing changed.
    before = diffuse("object-2")
    for path, body in [("/op", {"op": "set", "node": "object-2", "fields": {"diffuse": [0, 0, 0]}}),
                       ("/op", {"op": "delete", "nodes": ["object-2"]}), ("/undo", {}), ("/redo", {}), ("/save", {})]:
        status, answer = post(path, {**body, "revision": revision})
        assert status == 409 and answer["stale"] and answer["revision"] == revision + 1, (path, status, answer)
        assert answer["state"]["revision"] == revision + 1 and answer["state"]["modified"], answer["state"]
        print(f"{path} at revision {revision} (stale): 409, '{answer['error'][:60]}...'")
    assert diffuse("object-2") == before and state()["revision"] == revision + 1 and state()["can_undo"]
    status, answer = post("/op", {"op": "set", "node": "object-2", "fields": {"shininess": 3}, "revision": "1"})
    assert status == 400 and "revision" in answer["error"], answer

    # Another program adds an object above the others: the view reloads it, and object-2 is
    # still the green sphere it was, not its neighbour; the new object has an id of its own.
    with open(viewer.scene) as f:
        text = f.read()
    root = text.index('<object type="tree" name="root">') + len('<object type="tree" name="root">')
    added = ('\n    <transblock>\n      <translate x="0" y="3" z="0"/>\n      <object type="primitive" name="cube">\n'
             '        <diffuse r="0.1" g="0.2" b="0.3"/>\n      </object>\n    </transblock>')
    with open(viewer.scene, "w") as f:
        f.write(text[:root] + added + text[root:])
    reloaded = wait_reload(revision + 1)
    assert diffuse("object-2") == before, (diffuse("object-2"), before)
    status, outline = viewer.json("GET", "/outline")
    ids = [n["node"] for n in outline["nodes"] if n["node"].startswith("object-")]
    assert len(ids) == len(set(ids)) and "object-5" in ids, ids
    assert diffuse("object-5") == [0.1, 0.2, 0.3], diffuse("object-5")
    print(f"reloaded after another program's insert: object-2 is the same sphere; the new cube is object-5 ({ids})")
    # An edit made before the reload is stale; made after it, it names the same element.
    status, answer = post("/op", {"op": "delete", "nodes": ["object-2"], "revision": revision + 1})
    assert status == 409 and answer["stale"], answer
    status, answer = post("/op", {"op": "delete", "nodes": ["object-2"], "revision": reloaded["revision"]})
    assert status == 200 and answer["removed"] == ["object-2"], answer
    assert diffuse("object-5") == [0.1, 0.2, 0.3]

    # A change on disk that the watch cannot see (the same modification time): the save
    # does not replace it.
    now = state()["revision"]
    with open(viewer.scene) as f:
        theirs = f.read().replace('<shininess v="20"/>', '<shininess v="21"/>', 1)
    write_keeping_time(viewer.scene, theirs)
    status, answer = post("/save", {"revision": now})
    assert status == 409 and answer["changed_on_disk"] and "changed on disk" in answer["error"], (status, answer)
    with open(viewer.scene) as f:
        assert f.read() == theirs
    assert state()["modified"]
    print(f"save over another program's change: 409, '{answer['error']}'; the file kept")
    status, answer = post("/save", {"revision": now, "overwrite": True})
    assert status == 200 and not answer["modified"], answer
    with open(viewer.scene) as f:
        ours = f.read()
    assert ours != theirs and '<shininess v="21"/>' not in ours
    print("save with overwrite: written")

    # Or the user takes the file as it is: /reload.
    status, answer = post("/op", {"op": "set", "node": "object-1", "fields": {"shininess": 9}, "revision": state()["revision"]})
    assert status == 200, answer
    write_keeping_time(viewer.scene, theirs)
    status, answer = post("/save", {})
    assert status == 409 and answer["changed_on_disk"], answer
    status, answer = post("/reload", {"revision": state()["revision"]})
    assert status == 200 and not answer["modified"] and not answer["can_undo"], answer
    with open(viewer.scene) as f:
        assert f.read() == theirs
    status, answer = post("/save", {})
    assert status == 200, answer
    print("save refused, then reload: the file's version shown, a save then goes through")
    assert viewer.alive()
finally:
    viewer.close()
print("versions test passed")
