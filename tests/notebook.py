#!/usr/bin/env python3
"""docs/notebook.ipynb run headless as Jupyter runs it (issue 52): `python3 -m nbconvert
--execute` (Debian's jupyter-nbconvert and python3-ipykernel) with the build's cs123ray and
ray; then its output cells are read: the renders are PNG images of the size asked for (not
one colour), the scene shows a PNG picture and its outline, the studio an IFrame on the
live viewer's URL with its token; and the studio stopped with the kernel (its port closed).
Usage: notebook.py NOTEBOOK MODULE_DIR RAY WORK_DIR
Prints SKIPPED when nbconvert or ipykernel is missing."""
import base64
import json
import os
import re
import socket
import struct
import subprocess
import sys
import time

notebook, module_dir, ray, work = (os.path.abspath(path) for path in sys.argv[1:5])  # the kernel runs in docs/
python = sys.executable
for module in ("nbconvert", "ipykernel"):
    if subprocess.run([python, "-c", f"import {module}"], capture_output=True).returncode != 0:
        print(f"SKIPPED: {module} is not installed for {python} (apt-get install jupyter-nbconvert python3-ipykernel)")
        sys.exit(0)

failures = []


def fail(message):
    failures.append(message)
    print("FAIL:", message)


def png_size(data):
    """Width and height from a PNG's IHDR, or None when it is no PNG."""
    if not data.startswith(b"\x89PNG\r\n\x1a\n") or data[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", data[16:24])


os.makedirs(work, exist_ok=True)
executed = os.path.join(work, "notebook.ipynb")
environment = dict(os.environ, PYTHONPATH=module_dir + os.pathsep + os.environ.get("PYTHONPATH", ""), RAY_BINARY=ray)
run = subprocess.run([python, "-m", "nbconvert", "--to", "notebook", "--execute", "--ExecutePreprocessor.timeout=600",
                      "--ExecutePreprocessor.kernel_name=python3", "--output-dir", work, "--output", "notebook.ipynb",
                      notebook], capture_output=True, text=True, env=environment, timeout=900)
if run.returncode != 0:
    print(run.stdout[-4000:], run.stderr[-4000:])
    print("FAIL: nbconvert --execute failed")
    sys.exit(1)

cells = [cell for cell in json.load(open(executed, encoding="utf-8"))["cells"] if cell["cell_type"] == "code"]
outputs = [[output.get("data", {}) for output in cell.get("outputs", [])] for cell in cells]
errors = [output for cell in cells for output in cell.get("outputs", []) if output.get("output_type") == "error"]
if errors:
    fail(f"a cell raised: {errors[0].get('ename')}: {errors[0].get('evalue')}")

# The renders: cells whose source renders at 320 x 240 show PNGs of that size.
renders = [i for i, cell in enumerate(cells) if "cs123ray.render(" in "".join(cell["source"])]
if len(renders) < 2:
    fail(f"the notebook renders in {len(renders)} cells, not 2")
for index in renders:
    pngs = [base64.b64decode(data["image/png"]) for data in outputs[index] if "image/png" in data]
    if not pngs:
        fail(f"code cell {index} (a render) shows no PNG: {[list(d) for d in outputs[index]]}")
    elif png_size(pngs[0]) != (320, 240):
        fail(f"code cell {index}'s PNG is {png_size(pngs[0])}, not 320 x 240")
    elif len(set(pngs[0][40:])) < 16:
        fail(f"code cell {index}'s PNG holds almost nothing: {len(pngs[0])} bytes")
    else:
        print(f"code cell {index}: a 320 x 240 PNG of the render ({len(pngs[0])} bytes)")

# The scene: a picture and its outline.
html = [data.get("text/html", "") for data in outputs[0]]
html = "".join("".join(h) if isinstance(h, list) else h for h in html)
picture = re.search(r'src="data:image/png;base64,([^"]+)"', html)
if not picture or png_size(base64.b64decode(picture.group(1))) is None:
    fail("the scene's cell shows no PNG picture")
elif not re.search(r"<code>light-\d+</code>", html) or "<code>camera</code>" not in html:
    fail("the scene's cell shows no outline")
else:
    print("code cell 0: the scene as a PNG picture", png_size(base64.b64decode(picture.group(1))), "and its outline")

# The studio: an IFrame on the viewer's URL with its token; stopped with the kernel.
studio = [i for i, cell in enumerate(cells) if "cs123ray.view(" in "".join(cell["source"])]
frames = [re.search(r'<iframe src="http://127\.0\.0\.1:(\d+)/\?token=[0-9a-f]{16,}"', "".join(d.get("text/html", "")))
          for i in studio for d in outputs[i]]
frames = [f for f in frames if f]
if not frames:
    fail("the studio's cell shows no IFrame on the viewer's URL with its token")
else:
    port = int(frames[0].group(1))
    print(f"the studio's cell: an IFrame on http://127.0.0.1:{port}/?token=...")
    deadline = time.time() + 15
    while time.time() < deadline:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            time.sleep(0.2)
        except OSError:
            print("the studio stopped with the kernel (its port is closed)")
            break
    else:
        fail(f"the studio still listens on port {port} after the kernel ended")

if failures:
    sys.exit(1)
print("notebook: all passed")
