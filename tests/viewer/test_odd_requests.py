"""ray view's answers to requests and folders off the usual path: a scene in a folder whose
name is not UTF-8 (/state answers, an edit applied answers 200, a save names where it wrote,
each path in valid UTF-8 JSON with U+FFFD for the odd byte); a body that is not UTF-8 (400
with a sentence, nothing changed); the token in the query of an editing route (refused, as
only the Authorization header counts there); `Content-Type: application/json ; charset=utf-8`
(JSON).  Usage: python3 test_odd_requests.py RAY SCENE"""
import json
import os
import sys

from viewer_harness import Viewer

# A folder named in Latin-1 ("scène_..."): the byte 0xE8 is not UTF-8.
viewer = Viewer(sys.argv[1], sys.argv[2], "--width", "32", "--height", "24",
                folder_prefix=os.fsdecode(b"sc\xe8ne_"))


def parsed(data):
    """The answer's JSON, which must be valid UTF-8."""
    return json.loads(data.decode("utf-8"))


try:
    viewer.wait_frame_done()
    status, data = viewer.request("GET", "/state")
    assert status == 200, (status, data)
    state = parsed(data)
    assert "sc\ufffdne_" in state["file"], state["file"]
    print("/state in a folder named in Latin-1:", state["file"])

    op = json.dumps({"op": "set", "node": "globals", "fields": {"ambientcoeff": 0.25}})
    status, data = viewer.request("POST", "/op", op)
    assert status == 200, (status, data)
    answer = parsed(data)
    assert answer["editor"]["modified"] and answer["editor"]["can_undo"], answer
    status, data = viewer.request("GET", "/node?id=globals")
    assert status == 200 and any(f["name"] == "ambientcoeff" and f["value"] == 0.25 for f in parsed(data)["fields"]), data
    print("an edit there: applied, answered 200")

    status, data = viewer.request("POST", "/save", "{}")
    assert status == 200, (status, data)
    saved = parsed(data)["saved"]
    assert "sc\ufffdne_" in saved and b"0.25" in open(viewer.scene, "rb").read(), saved
    print("saved:", saved)

    # A body that is not UTF-8: 400 with a sentence, the view unchanged.
    status, before = viewer.json("GET", "/state")
    status, data = viewer.request("POST", "/view", b'{"depth": 3, "note": "\xff"}')
    assert status == 400, (status, data)
    error = parsed(data)["error"]
    assert "not UTF-8" in error and "byte 22 " in error, error
    status, data = viewer.request("POST", "/op", b'{"op": "set", "node": "globals", "fields": {"ambientcoeff": 0.5}, "x": "\xc3"}')
    assert status == 400 and "not UTF-8" in parsed(data)["error"], (status, data)
    status, after = viewer.json("GET", "/state")
    assert after["depth"] == before["depth"] and after["modified"] == before["modified"]
    print("a body that is not UTF-8:", error)

    # The token in the query of an editing route: refused, nothing done.
    status, data = viewer.request("POST", f"/op?token={viewer.token}", op,
                                  headers={"Content-Type": "application/json"})
    assert status == 403 and "Authorization header" in parsed(data)["error"], (status, data)
    status, after_query = viewer.json("GET", "/state")
    assert after_query["can_redo"] == after["can_redo"] and after_query["modified"] == after["modified"]
    print("POST /op?token=...: 403,", parsed(data)["error"])

    # JSON with a space before its parameters, in capitals: JSON.
    for content_type in ("application/json ; charset=utf-8", "Application/JSON;Charset=UTF-8"):
        headers = dict(viewer.auth_headers(), **{"Content-Type": content_type})
        status, data = viewer.request("POST", "/view", '{"depth": 4}', headers=headers)
        assert status == 200, (content_type, status, data)
    print("Content-Type: application/json ; charset=utf-8 taken as JSON")
    assert viewer.alive()
finally:
    viewer.close()
