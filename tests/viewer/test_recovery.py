"""Unsaved edits survive a stopped `ray view` (issue 49). In a scratch HOME and XDG_STATE_HOME:
- an edit, then SIGTERM: exit 143, a line saying where the edits are kept and how to open
  them; the scene file untouched; the recovery in $XDG_STATE_HOME/ray/recovery (folder 700,
  file 600); the next `ray view FILE` names it; `ray view FILE --recover` serves the scene
  with the edit, unsaved, the file still untouched; its save writes the edit and removes
  every recovery;
- an edit, then SIGKILL three seconds later: the same, the copy written without any stop;
- SIGINT and SIGHUP stop with 130 and 129, keeping the edits; without edits nothing is kept;
- POST /recovery discards the offer; edits replaced by a change of the file on disk are set
  aside, kept, and offered;
- --recover with nothing kept is refused (exit 2); a recovery file that is a FIFO, a link, not
  a recovery, cut short, damaged or larger than any scene is passed over with a message, never
  read or waited on.
No browser needed. Usage: python3 test_recovery.py RAY_BINARY SCENE (scenes/shadows.xml)"""
import json
import os
import signal
import subprocess
import sys
import time

from recovery_harness import Home, ViewerOf, fnv1a64, mode_of, scene_key

ray, source = sys.argv[1], sys.argv[2]
ADD_TORUS = {"op": "add-primitive", "shape": "torus"}


def shapes(viewer):
    status, outline = viewer.json("GET", "/outline")
    assert status == 200, outline
    return [n.get("shape") for n in outline["nodes"] if n["kind"] == "object"]


def shininess(viewer):
    status, node = viewer.json("GET", "/node?id=object-0")
    assert status == 200, node
    return next(f["value"] for f in node["fields"] if f["name"] == "shininess")


def modified(viewer):
    status, state = viewer.json("GET", "/state")
    assert status == 200, state
    return state["modified"]


def wait_log(viewer, text, timeout=10):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if text in viewer.log():
            return viewer.log()
        time.sleep(0.05)
    raise AssertionError(f"'{text}' not printed:\n{viewer.log()}")


def check_offered(home, kept):
    """The next plain `ray view FILE` names the recovery on the terminal and in GET /recovery."""
    viewer = ViewerOf(ray, home)
    try:
        log = wait_log(viewer, "--recover")
        line = next(l for l in log.splitlines() if "unsaved edits of" in l)
        assert kept in line and "ray view " in line and "--recover" in line, line
        status, offer = viewer.json("GET", "/recovery")
        assert status == 200 and offer["offer"]["file"] == kept, offer
        assert not modified(viewer), "a plain ray view opened the edits"
        print(f"  next ray view FILE: '{line}'")
    finally:
        code = viewer.stop()
    # Nothing edited here: the stop says so and keeps nothing more.
    assert code == 143 and viewer.log().strip().splitlines()[-1] == "ray view: stopped (SIGTERM)", viewer.log()
    assert home.recoveries() == [kept]


def has_torus(viewer):
    assert "torus" in shapes(viewer), shapes(viewer)


def has_shininess_37(viewer):
    assert shininess(viewer) == 37, shininess(viewer)


def recover(home, check):
    """`ray view FILE --recover`: the edit served, unsaved, the file untouched, the old copy
    replaced by the viewer's own; its save writes the edit and removes every recovery."""
    before = home.recoveries()
    viewer = ViewerOf(ray, home, "--recover")
    try:
        wait_log(viewer, "opened with the unsaved edits")
        check(viewer)
        assert modified(viewer) and home.scene_untouched()
        # Its own copy replaces the one it opened (never a moment without one).
        deadline = time.time() + 10
        while time.time() < deadline and (set(home.recoveries()) & set(before) or not home.recoveries()):
            time.sleep(0.05)
        assert len(home.recoveries()) == 1 and home.recoveries()[0] not in before, (before, home.recoveries())
        status, answer = viewer.json("POST", "/save", b"{}")
        assert status == 200 and not answer["modified"], answer
        assert not home.scene_untouched(), "the save wrote nothing"
        home.wait_recoveries(0)
        print("  --recover: the edit served, unsaved, the file untouched; its save writes it and removes the recovery")
    finally:
        viewer.stop()


# ---- SIGTERM after an edit
home = Home(source)
try:
    viewer = ViewerOf(ray, home)
    try:
        viewer.op(ADD_TORUS)
        assert "torus" in shapes(viewer)
        [kept] = home.wait_recoveries(1, timeout=5)  # written a short while after the edit
        assert mode_of(home.folder) == 0o700 and mode_of(kept) == 0o600, (oct(mode_of(home.folder)), oct(mode_of(kept)))
        assert os.path.basename(kept).startswith(scene_key(home.scene) + "-"), kept
        code = viewer.stop(signal.SIGTERM)
    finally:
        viewer.close()
    stop_line = viewer.log().strip().splitlines()[-1]
    assert code == 143, (code, viewer.log())
    assert "stopped (SIGTERM)" in stop_line and kept in stop_line and "--recover" in stop_line, stop_line
    assert home.scene_untouched() and os.listdir(os.path.dirname(home.scene)) == ["scene.xml"]
    header = json.loads(open(kept, "rb").readline())
    assert header["scene"] == os.path.realpath(home.scene) and header["scene_file"]["size"] == len(home.original), header
    print(f"SIGTERM after an edit: exit 143, '{stop_line}'; nothing written beside the scene")
    check_offered(home, kept)
    recover(home, has_torus)
finally:
    home.close()

# ---- SIGKILL three seconds after an edit: the copy was already there
home = Home(source)
try:
    viewer = ViewerOf(ray, home)
    try:
        assert shininess(viewer) != 37
        viewer.op({"op": "set", "node": "object-0", "fields": {"shininess": 37}})
        time.sleep(3)
        code = viewer.stop(signal.SIGKILL)
    finally:
        viewer.close()
    assert code == -signal.SIGKILL and home.scene_untouched()
    [kept] = home.recoveries()
    print(f"SIGKILL 3 s after an edit: the scene untouched, the edit kept in {kept}")
    check_offered(home, kept)
    recover(home, has_shininess_37)
finally:
    home.close()

# ---- SIGINT and SIGHUP keep the edits too; a stop without edits keeps nothing
home = Home(source)
try:
    for sig, status in [(signal.SIGINT, 130), (signal.SIGHUP, 129)]:
        viewer = ViewerOf(ray, home)
        try:
            viewer.op(ADD_TORUS)
            code = viewer.stop(sig)  # at once: the stop writes the copy itself
        finally:
            viewer.close()
        assert code == status and "are kept in" in viewer.log(), (sig, code, viewer.log())
        print(f"{signal.Signals(sig).name}: exit {code}, the edits kept")
    assert len(home.recoveries()) == 2, home.recoveries()
    for kept in home.recoveries():
        os.remove(kept)
    viewer = ViewerOf(ray, home)
    try:
        time.sleep(0.5)
        code = viewer.stop(signal.SIGTERM)
    finally:
        viewer.close()
    assert code == 143 and home.recoveries() == [] and "unsaved" not in viewer.log(), viewer.log()
    print("a stop without edits: exit 143, nothing kept")
finally:
    home.close()

# ---- A new scene (its file not there yet): its edits are kept and recovered the same way
home = Home(source)
try:
    os.remove(home.scene)
    viewer = ViewerOf(ray, home)
    try:
        time.sleep(1.5)
        assert home.recoveries() == [], "a new scene's camera and light are no edits to keep"
        viewer.op(ADD_TORUS)
        code = viewer.stop(signal.SIGTERM)
    finally:
        viewer.close()
    assert code == 143 and "are kept in" in viewer.log() and not os.path.exists(home.scene), viewer.log()
    viewer = ViewerOf(ray, home, "--recover")
    try:
        wait_log(viewer, "is written when you save")
        has_torus(viewer)
        assert modified(viewer) and not os.path.exists(home.scene)
    finally:
        viewer.stop()
        viewer.close()
    print("a new scene: nothing kept until an edit; its edits recovered, the file not written until saved")
finally:
    home.close()

# ---- The page's routes: Discard; and an undo back to the file removes the copy
home = Home(source)
try:
    viewer = ViewerOf(ray, home)
    try:
        viewer.op(ADD_TORUS)
        home.wait_recoveries(1)
        status, answer = viewer.json("POST", "/undo", b"{}")
        assert status == 200 and not answer["modified"], answer
        home.wait_recoveries(0)
        viewer.op(ADD_TORUS)
        [kept] = home.wait_recoveries(1)
        viewer.stop(signal.SIGKILL)
    finally:
        viewer.close()
    print("undo back to the file: the copy removed")
    viewer = ViewerOf(ray, home, "--no-token")
    try:
        status, answer = viewer.json("POST", "/recovery", json.dumps({"action": "discard"}).encode())
        assert status == 403 and os.path.exists(kept), (status, answer)
    finally:
        viewer.stop()
    viewer = ViewerOf(ray, home)
    try:
        for body, says in [({"action": "keep"}, "restore"), ({}, "action"), ({"action": "discard", "file": "/x"}, "offered")]:
            status, answer = viewer.json("POST", "/recovery", json.dumps(body).encode())
            assert status in (400, 409) and says in answer["error"], (body, status, answer)
        status, answer = viewer.json("POST", "/recovery", json.dumps({"action": "discard", "file": kept}).encode())
        assert status == 200 and answer["discarded"] == kept and not os.path.exists(kept), answer
        status, offer = viewer.json("GET", "/recovery")
        assert offer == {"offer": None}, offer
        status, answer = viewer.json("POST", "/recovery", json.dumps({"action": "restore"}).encode())
        assert status == 400 and "no recovery" in answer["error"], answer
    finally:
        viewer.stop()
    print("POST /recovery discard: the file removed, no offer left (403 without the token, 400 for a bad answer)")
finally:
    home.close()

# ---- Unsaved edits that a change on disk replaces are set aside, kept and offered
home = Home(source)
try:
    viewer = ViewerOf(ray, home)
    try:
        viewer.op(ADD_TORUS)
        time.sleep(0.2)
        changed = home.original.replace(b"<!-- hard shadows", b"<!-- changed elsewhere: hard shadows", 1)
        assert changed != home.original
        with open(home.scene + ".tmp", "wb") as f:
            f.write(changed)
        os.replace(home.scene + ".tmp", home.scene)
        log = wait_log(viewer, "replaced are kept in")
        [kept] = home.wait_recoveries(1)
        assert "torus" not in shapes(viewer) and kept in log, log
        time.sleep(1.5)  # the viewer's own copy (none: no edits since the reload) stays away
        assert home.recoveries() == [kept]
        code = viewer.stop()
    finally:
        viewer.close()
    assert code == 143
    home.original = changed
    check_offered(home, kept)
    print("a reload over unsaved edits: they are set aside in a recovery and offered")
finally:
    home.close()

# ---- Bad input: nothing to recover; recovery files that are not ones
home = Home(source)
try:
    run = subprocess.run([ray, "view", home.scene, "--port", "0", "--recover"], capture_output=True, text=True,
                         timeout=60, env=home.env)
    assert run.returncode == 2 and "no unsaved edits of" in run.stderr, (run.returncode, run.stderr)
    print(f"--recover with nothing kept: exit 2, '{run.stderr.splitlines()[0]}'")
    os.makedirs(home.folder)
    key = scene_key(home.scene)
    fifo = os.path.join(home.folder, key + "-fifo.ray-recovery")
    os.mkfifo(fifo)
    link = os.path.join(home.folder, key + "-link.ray-recovery")
    os.symlink(home.scene, link)
    junk = os.path.join(home.folder, key + "-junk.ray-recovery")
    with open(junk, "w") as f:
        f.write('{"ray_recovery": 1}\n<scenefile/>')
    # Recoveries in the right form but cut short, damaged, or larger than any scene's.
    document = home.original
    header = {"ray_recovery": 1, "scene": os.path.realpath(home.scene), "written": "2026-01-01 00:00:00",
              "written_unix": 1767225600, "pid": 1,
              "scene_file": {"exists": True, "size": len(document), "mtime_ns": 0, "fnv1a64": fnv1a64(document)},
              "document_bytes": len(document), "document_fnv1a64": fnv1a64(document)}
    whole = json.dumps(header).encode() + b"\n" + document
    short, damaged, huge = (os.path.join(home.folder, f"{key}-{n}.ray-recovery") for n in ("short", "damaged", "huge"))
    with open(short, "wb") as f:
        f.write(whole[:-10])
    with open(damaged, "wb") as f:
        f.write(whole.replace(b"sphere", b"sphera", 1))
    with open(huge, "wb") as f:
        f.write(whole)
        f.truncate((1 << 30) + 1)  # sparse: nothing of it is written or read
    started = time.time()
    run = subprocess.run([ray, "view", home.scene, "--port", "0", "--recover"], capture_output=True, text=True,
                         timeout=60, env=home.env)
    assert run.returncode == 2 and time.time() - started < 30, run
    for path, says in [(fifo, "not a regular file"), (link, "cannot be opened"), (junk, "header"), (short, "cut short"),
                       (damaged, "does not match its own hash"), (huge, "more than any scene's")]:
        line = next((l for l in run.stderr.splitlines() if os.path.basename(path) in l), "")
        assert says in line and "passed over" in line, (path, run.stderr)
    print("a FIFO, a link, a file that is not a recovery, one cut short, one damaged, one of 1 GiB: passed over, "
          "each with a message")
    # A whole recovery whose scene does not load: refused, naming it, the scene untouched.
    broken = b"<scenefile><object type=\"primitive\" name=\"sphere\">"
    header.update(document_bytes=len(broken), document_fnv1a64=fnv1a64(broken))
    kept = os.path.join(home.folder, f"{key}-broken.ray-recovery")
    with open(kept, "wb") as f:
        f.write(json.dumps(header).encode() + b"\n" + broken)
    run = subprocess.run([ray, "view", home.scene, "--port", "0", "--recover"], capture_output=True, text=True,
                         timeout=60, env=home.env)
    assert run.returncode == 2 and "which do not load" in run.stderr and kept in run.stderr, run.stderr
    assert home.scene_untouched() and os.path.exists(kept)
    print("--recover of edits that do not load: exit 2, the recovery named, nothing changed")
finally:
    home.close()
print("recovery test passed")
