"""ray view against hostile clients: each case prints its outcome (for the report) and asserts
that the server survives, serves no file and keeps its memory bounded; requests without the
access token, with a wrong one or a stolen-format one get 403 and change nothing.
Usage: python3 test_hostile_clients.py RAY_BINARY SCENE"""
import http.client
import json
import os
import re
import shutil
import socket
import sys
import tempfile
import time

from viewer_harness import Viewer

ray, scene = sys.argv[1], sys.argv[2]
viewer = Viewer(ray, scene, "--width", "64", "--height", "48")
outcomes = []


def case(name, outcome):
    assert viewer.alive(), f"{name}: the server died"
    outcomes.append((name, outcome))
    print(f"{name}: {outcome}", flush=True)


def raw(data, read=True, timeout=10):
    s = socket.create_connection(("127.0.0.1", viewer.port), timeout=timeout)
    s.sendall(data)
    reply = b""
    if read:
        try:
            while chunk := s.recv(65536):
                reply += chunk
        except socket.timeout:
            pass
    s.close()
    return reply


def auth_line():
    return f"Authorization: token {viewer.token}\r\n"


try:
    viewer.wait_frame_done()
    baseline = viewer.rss_kib()
    assert viewer.token and re.fullmatch(r"[0-9a-f]{32}", viewer.token), viewer.url

    # The access token: every route, and paths that are none, answer 403 without it, with a
    # wrong one, with one of the right format (32 hex digits) but another value (a token
    # stolen from another viewer, or guessed), in the query, the header or a cookie, and
    # with the right token under another port's cookie name.
    status, before = viewer.json("GET", "/state")
    assert status == 200
    routes = [("GET", "/"), ("GET", "/state"), ("GET", "/events"), ("GET", "/explain?x=1&y=1"),
              ("POST", "/view"), ("GET", "/nonexistent"), ("GET", "/../../etc/passwd")]
    other = "%032x" % (int(viewer.token, 16) ^ 1)  # right format, one bit off
    stolen = "0123456789abcdef0123456789abcdef"
    presented = [
        ("no token", "", {}),
        ("empty token", "token=", {}),
        ("wrong token", "token=abc", {}),
        ("right format, wrong value (query)", "token=" + other, {}),
        ("stolen-format token (header)", "", {"Authorization": "token " + stolen}),
        ("right format, wrong value (cookie)", "", {"Cookie": f"ray_view_token_{viewer.port}={other}"}),
        ("the token one character longer", "token=" + viewer.token + "0", {}),
        ("the right token under another port's cookie", "", {"Cookie": f"ray_view_token_{viewer.port + 1}={viewer.token}"}),
        ("the token in upper case", "token=" + viewer.token.upper(), {}),
    ]
    refused = 0
    for name, query, headers in presented:
        for method, path in routes:
            target = path + (("&" if "?" in path else "?") + query if query else "")
            body = b'{"position": [50, 50, 50]}' if method == "POST" else None
            status, data = viewer.request(method, target, body, headers=headers)
            assert status == 403, (name, method, target, status, data[:200])
            assert viewer.token.encode() not in data
            refused += 1
    status, after = viewer.json("GET", "/state")
    assert after["position"] == before["position"], "a refused POST /view moved the camera"
    case("requests without the access token", f"{refused} requests ({len(presented)} kinds x {len(routes)} routes): all 403, nothing changed")

    # The printed URL: the token in the query gets the cookie and is sent on to the bare URL.
    # The cookie then opens the page (which holds the token for its own requests), and
    # nothing else: every other page of 127.0.0.1 gets it sent too (request_guard.h).
    connection = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=30)
    connection.request("GET", "/?token=" + viewer.token)
    response = connection.getresponse()
    response.read()
    cookie = response.getheader("Set-Cookie")
    assert response.status == 303 and response.getheader("Location") == "/", response.status
    assert cookie.startswith(f"ray_view_token_{viewer.port}={viewer.token};") and "HttpOnly" in cookie, cookie
    connection.close()
    cookie_only = {"Cookie": cookie.split(";")[0]}
    status, page = viewer.request("GET", "/", headers=cookie_only)
    assert status == 200 and f'<meta name="ray-token" content="{viewer.token}">'.encode() in page, status
    for method, path, body in [("GET", "/state", None), ("GET", "/events", None), ("POST", "/edit", b'{"light": 0, "color": [0, 1, 0]}'),
                               ("POST", "/save", b'{"as": "stolen.xml"}'), ("POST", "/view", b'{"position": [50, 50, 50]}')]:
        headers = dict(cookie_only, **({"Content-Type": "application/json"} if body else {}))
        status, _ = viewer.request(method, path, body, headers=headers)
        assert status == 403, (method, path, status)
    assert not os.path.exists(os.path.join(viewer.folder, "stolen.xml"))
    case("the printed URL", "303 to / with an HttpOnly cookie, which then opens the page alone: 5 routes 403 with it")

    # Other pages of the same browser (another local port, a DNS-rebound name): refused even
    # with the token, by Origin, Fetch Metadata and Host; no CORS preflight; no form bodies.
    status, before = viewer.json("GET", "/state")
    edit = b'{"light": 0, "color": [0, 1, 0]}'
    json_type = {"Content-Type": "application/json"}
    other_page = [
        ("Origin of another port", dict(json_type, Origin=f"http://127.0.0.1:{viewer.port + 1}")),
        ("Origin null (a sandboxed frame)", dict(json_type, Origin="null")),
        ("Sec-Fetch-Site same-site (another port)", dict(json_type, **{"Sec-Fetch-Site": "same-site", "Sec-Fetch-Mode": "no-cors"})),
        ("Sec-Fetch-Site cross-site", dict(json_type, **{"Sec-Fetch-Site": "cross-site", "Sec-Fetch-Mode": "cors"})),
        ("a DNS-rebound Host", dict(json_type, Host=f"evil.example:{viewer.port}", Origin=f"http://evil.example:{viewer.port}")),
    ]
    for name, headers in other_page:
        for path in ("/edit", "/save", "/view", "/undo"):
            status, answer = viewer.request("POST", path, edit, headers=dict(viewer.auth_headers(), **headers))
            assert status == 403 and b"error" in answer, (name, path, status, answer[:200])
        status, _ = viewer.request("GET", "/state", headers=dict(viewer.auth_headers(), **headers))
        assert status == 403, (name, status)
    status, _ = viewer.request("GET", "/", headers={"Cookie": cookie_only["Cookie"], "Sec-Fetch-Site": "same-site",
                                                    "Sec-Fetch-Mode": "no-cors", "Sec-Fetch-Dest": "empty"})
    assert status == 403, status  # another page may not read the page (and the token in it)
    status, _ = viewer.request("GET", "/", headers={"Cookie": cookie_only["Cookie"], "Sec-Fetch-Dest": "iframe"})
    assert status == 403, status  # nor frame it
    status, _ = viewer.request("GET", "/", headers={"Cookie": cookie_only["Cookie"], "Sec-Fetch-Site": "cross-site",
                                                    "Sec-Fetch-Mode": "navigate", "Sec-Fetch-Dest": "document"})
    assert status == 200, status  # a link followed to the page: the user's own navigation
    connection = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=30)
    connection.request("OPTIONS", "/edit", headers={"Origin": f"http://127.0.0.1:{viewer.port + 1}",
                                                    "Access-Control-Request-Method": "POST"})
    response = connection.getresponse()
    response.read()
    assert response.status == 403 and response.getheader("Access-Control-Allow-Origin") is None, response.status
    connection.close()
    for content_type in ("text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x", ""):
        headers = dict(viewer.auth_headers(), **({"Content-Type": content_type} if content_type else {}))
        status, _ = viewer.request("POST", "/edit", edit, headers=headers)
        assert status == 415, (content_type, status)
    status, after = viewer.json("GET", "/state")
    assert after["lights"] == before["lights"] and not after["modified"], after["lights"]
    case("other pages of the browser", f"{len(other_page)} kinds x 5 routes, a preflight, a read and a frame of the page, "
         "4 form content types: all refused, the scene unchanged")

    # Save as: a plain .xml name in the scene's folder, nothing else; an existing file only
    # with "replace"; no link followed or replaced; names in messages cut short.
    folder = viewer.folder
    parent = os.path.dirname(folder)
    precious = os.path.join(folder, "precious.txt")
    with open(precious, "w") as f:
        f.write("precious\n")
    outside = tempfile.mkdtemp(prefix="ray_view_outside_")
    os.symlink(os.path.join(outside, "target.xml"), os.path.join(folder, "link.xml"))
    with open(os.path.join(folder, "mine.xml"), "w") as f:
        f.write("mine\n")
    refused_names = ["../escaped.xml", "../../escaped.xml", os.path.join(parent, "escaped.xml"), "/tmp/escaped.xml",
                     "precious.txt\u0000.xml", "sub/x.xml", "..", "", "x.txt", "link.xml", "a\nb.xml",
                     os.path.join(outside, "x.xml"), "n" * 5000 + ".xml"]
    for name in refused_names:
        status, answer = viewer.json("POST", "/save", json.dumps({"as": name}).encode())
        assert status == 400 and len(answer["error"]) < 600, (name[:40], status, answer)
        assert "\u0000" not in answer["error"] and "\x00" not in answer["error"], answer
    status, answer = viewer.json("POST", "/save", json.dumps({"as": "mine.xml"}).encode())
    assert status == 409 and answer["exists"], (status, answer)
    assert open(os.path.join(folder, "mine.xml")).read() == "mine\n"
    assert open(precious).read() == "precious\n" and not os.path.exists(os.path.join(outside, "target.xml"))
    assert not os.path.exists(os.path.join(parent, "escaped.xml")) and not os.path.exists("/tmp/escaped.xml")
    assert os.path.islink(os.path.join(folder, "link.xml"))
    status, answer = viewer.json("POST", "/save", json.dumps({"as": "mine.xml", "replace": True}).encode())
    assert status == 200 and open(os.path.join(folder, "mine.xml")).read().startswith("<"), (status, answer)
    status, answer = viewer.json("POST", "/save", json.dumps({"as": "fresh.xml"}).encode())
    assert status == 200 and os.path.dirname(answer["saved"]) == os.path.realpath(folder), answer
    assert "\x00" not in viewer.log() and "\0" not in viewer.log()
    shutil.rmtree(outside)
    case("save as", f"{len(refused_names)} names leaving the folder, links, NUL, control characters, 5,000 characters: "
         "400 with short messages; an existing file 409 then replaced on request; a new name written in the folder")

    # Path traversal and any file but the page: only five routes exist, nothing is read from disk.
    secret_markers = [b"root:", b"<scenefile", b"<?xml"]
    for path in ["/../../../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/etc/passwd", "/" + scene.split("/")[-1],
                 "/..%2f..%2fetc%2fpasswd", "/index.html", "/web/index.html", "//etc/passwd", "/state/../../etc/passwd"]:
        reply = raw(f"GET {path} HTTP/1.1\r\nHost: 127.0.0.1:{viewer.port}\r\n{auth_line()}Connection: close\r\n\r\n".encode())
        status = reply.split(b"\r\n", 1)[0]
        assert not any(m in reply for m in secret_markers), f"{path} served a file: {reply[:200]}"
        assert b" 200 " not in status, f"{path}: {status}"
    case("path traversal / other files", "9 paths, all 404 or 400, no file content")

    # Malformed requests.
    for data in [b"GARBAGE\r\n\r\n", b"GET\r\n\r\n", b"\x00\xff\xfe" * 100 + b"\r\n\r\n",
                 b"GET / HTTP/9.9\r\n\r\n", b"POST /view HTTP/1.1\r\nContent-Length: -5\r\n\r\n",
                 b"POST /view HTTP/1.1\r\nContent-Length: 10\r\n\r\n{"]:
        raw(data, timeout=8)
    for body in [b"garbage", b"[]", b'{"width": 99999}', b'{"position": [1, 2]}', b'{"look": [0, 0, 0]}',
                 b'{"position": [1e400, 0, 0]}', b'{"depth": "x"}', b'{"aa": "sideways"}', b'{"look":[0,1,0],"up":[0,1,0]}']:
        status, reply = viewer.json("POST", "/view", body)
        assert status == 400, (body, status)
    for query in ["x=abc&y=1", "x=-1&y=0", "x=99999&y=0", "", "x=1"]:
        status, _ = viewer.request("GET", "/explain?" + query)
        assert status == 400, (query, status)
    # Every refusal says why in a sentence of its own, never a library's word.
    status, answer = viewer.json("GET", "/pick?x=abc&y=1")
    assert status == 400 and answer["error"] == "x must be a whole number, not 'abc'", answer
    status, answer = viewer.json("GET", "/object?id=99999999999")
    assert status == 400 and "99999999999" in answer["error"] and "in range" in answer["error"], answer
    status, answer = viewer.json("GET", "/object?id=" + "9" * 5000)
    assert status == 400 and len(answer["error"]) < 200, answer
    connection = http.client.HTTPConnection("127.0.0.1", viewer.port, timeout=30)
    connection.putrequest("POST", "/undo")
    connection.putheader("Authorization", f"token {viewer.token}")
    connection.endheaders()
    response = connection.getresponse()
    undo_answer = json.loads(response.read())
    connection.close()
    assert "error" in undo_answer or "done" in undo_answer, undo_answer
    status, answer = viewer.json("GET", "/nonexistent")
    assert status == 404 and "route" in answer["error"], (status, answer)
    case("malformed requests", "15 raw/JSON bodies and 5 bad explain queries: 400 or dropped, server up; "
         "bad numbers, a body-less POST and an unknown route each answered with a sentence")

    # Oversized: a body over the 16 KiB cap (16 KiB itself is taken), and a huge header block.
    padding = b" " * (16 * 1024 - len(b'{"position": [5, 5, 5]}'))
    status, _ = viewer.request("POST", "/view", b'{"position": [5, 5, 5]}' + padding)
    assert status == 200, status
    status, answer = viewer.json("POST", "/view", b'{"position": [5, 5, 5]}' + padding + b" ")
    assert status == 413 and "16 KiB" in answer["error"], (status, answer)
    status, _ = viewer.request("POST", "/view", b'{"a":"' + b"x" * 1_000_000 + b'"}')
    assert status == 413, status
    reply = raw(b"GET / HTTP/1.1\r\nHost: x\r\nX-Big: " + b"y" * 200_000 + b"\r\n\r\n")
    assert b" 200 " not in reply.split(b"\r\n", 1)[0]
    first_line = reply.split(b"\r\n", 1)[0].decode(errors="replace") or "connection closed"
    case("oversized requests", f"1 MB body: 413; 200 kB header: refused ({first_line})")

    # A flood of camera changes: the view shown at the end is the last one asked for, however
    # many of the others a machine of this speed had time to render (each change cancels the
    # frame in flight, so a slow machine renders few and a fast one may render all).
    status, state = viewer.json("GET", "/state")
    first_request = state["view"]
    for i in range(300):
        viewer.request("POST", "/view", f'{{"position": [{5 + i * 0.01}, 5, 5], "look": [-1, -1, -1]}}'.encode())
    viewer.request("POST", "/view", b'{"position": [9, 4, 2], "look": [-1, -0.5, -0.3]}')
    status, state = viewer.json("GET", "/state")
    assert state["position"] == [9, 4, 2] and state["view"] == first_request + 301, state
    done = viewer.wait_frame_done(final=True)
    while done["view"] != state["view"]:  # a frame of an earlier view may still have been finishing
        assert done["view"] < state["view"], (done, state)
        done = viewer.wait_frame_done(final=True)
    case("flood of 301 camera changes", f"the frame at rest shows the last view ({done['view']}), "
         f"{done['frame']} frames in all")

    # The switches beyond the course's four round-trip through /view and /state.
    for on in (True, False):
        flag = "true" if on else "false"
        viewer.request("POST", "/view", f'{{"fresnel": {flag}, "course_meshes": {flag}}}'.encode())
        status, state = viewer.json("GET", "/state")
        assert status == 200 and state["fresnel"] is on and state["course_meshes"] is on, state
    case("fresnel and course_meshes switches", "set and cleared through /view, reported by /state")
    for dof in ("off", "disk", "course"):
        viewer.request("POST", "/view", f'{{"dof": "{dof}"}}'.encode())
        status, state = viewer.json("GET", "/state")
        assert status == 200 and state["dof"] == dof, state
    status, _ = viewer.request("POST", "/view", b'{"dof": "sideways"}')
    assert status == 400, status
    case("dof modes", "off, disk and course set through /view and reported by /state; another name refused")

    # The page's controls come from the settings table: every antialiasing mode, and the
    # settings beyond the switches, each set through /view within its range.
    status, controls = viewer.json("GET", "/settings")
    assert status == 200, status
    by_name = {c["name"]: c for c in controls}
    assert by_name["aa"]["choices"] == ["off", "course", "stratified", "adaptive"], by_name["aa"]
    assert by_name["samples"]["kind"] == "integer" and by_name["samples"]["max"] == 4096, by_name["samples"]
    for aa in ("stratified", "adaptive", "off", "course"):
        viewer.request("POST", "/view", f'{{"aa": "{aa}", "samples": 4}}'.encode())
        status, state = viewer.json("GET", "/state")
        assert status == 200 and state["aa"] == aa and state["samples"] == 4, state
    for body in (b'{"samples": 0}', b'{"samples": 2.5}', b'{"shutter": "x"}', b'{"texture_filter": "sharp"}'):
        status, _ = viewer.request("POST", "/view", body)
        assert status == 400, (body, status)
    case("settings from the table", "/settings lists every aa mode; aa and samples round-trip; out of range refused")

    # Clients that connect and never read (nor send).
    sockets = []
    for _ in range(50):
        s = socket.create_connection(("127.0.0.1", viewer.port))
        s.sendall(f"GET /events HTTP/1.1\r\nHost: x\r\n{auth_line()}\r\n".encode())
        s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1024)
        sockets.append(s)
    for _ in range(20):
        sockets.append(socket.create_connection(("127.0.0.1", viewer.port)))
    time.sleep(1)
    viewer.request("POST", "/view", b'{"position": [5, 5, 6]}')
    time.sleep(12)  # past the 5 s read/write timeouts
    status, _ = viewer.request("GET", "/state", timeout=60)
    assert status == 200
    for s in sockets:
        s.close()
    case("70 clients that never read", "server still answers /state after the timeouts")

    growth = viewer.rss_kib() - baseline
    case("memory", f"RSS grew by {growth} KiB over the run")
    assert growth < 200_000, growth

    # The token is printed once, in the URL, and never logged after it.
    time.sleep(0.3)
    log = viewer.log()
    assert log.count(viewer.token) == 1 and viewer.token in log.splitlines()[0], log[-2000:]
    case("the token in the terminal", f"only in the printed URL ({len(log.splitlines())} lines printed)")
finally:
    viewer.close()

# --no-token: open to anyone, as before the token.
open_viewer = Viewer(ray, scene, "--width", "16", "--height", "12", "--no-token")
try:
    assert open_viewer.token is None and "token" not in open_viewer.url, open_viewer.url
    status, _ = open_viewer.request("GET", "/state", headers={})
    assert status == 200
    outcomes.append(("--no-token", "open"))
    print("--no-token: no token in the URL, /state answers 200 without one")
finally:
    open_viewer.close()

print("all hostile-client cases passed:", len(outcomes))
