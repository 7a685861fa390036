"""cs123ray in Jupyter (issue 52, python/notebook.py): a render is a RenderedImage, an ndarray
that shows itself as a PNG; a scene shows a small picture and its outline; cs123ray.view
starts the studio (`ray view`) on the scene, shown as an IFrame on its URL with the token,
which a framing page may open; the page's edits reach the notebook's scene and the
notebook's the page; the studio stops with stop(), with its object, and with the process."""
import base64
import http.client
import io
import json
import os
import re
import subprocess
import sys
import textwrap
import time

import numpy
import pytest

cs123ray = pytest.importorskip("cs123ray")

SCENES = os.environ.get("RAY_SCENES_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "scenes"))
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def shadows():
    return cs123ray.load_scene(os.path.join(SCENES, "shadows.xml"))


def decoded(png):
    Image = pytest.importorskip("PIL.Image")
    return numpy.asarray(Image.open(io.BytesIO(png)).convert("RGB"))


def test_a_render_is_an_array_that_shows_itself_as_a_png():
    image = cs123ray.render(shadows(), device="ref", width=64, height=48, dtype="uint8")
    assert isinstance(image, cs123ray.RenderedImage) and isinstance(image, numpy.ndarray)
    assert image.shape == (48, 64, 3) and image.dtype == numpy.uint8
    png = image._repr_png_()
    assert png.startswith(PNG_SIGNATURE)
    assert numpy.array_equal(decoded(png), numpy.asarray(image))  # the same pixels, not a picture of numbers
    assert image[..., 0]._repr_png_() is None  # a channel is no longer an image: Jupyter shows numbers
    assert type(numpy.asarray(image)) is numpy.ndarray
    floats = cs123ray.Renderer(shadows(), device="ref")
    floats.set_options(width=32, height=24)
    frame = floats.render()
    assert isinstance(frame, cs123ray.RenderedImage) and frame.dtype == numpy.float32
    assert decoded(frame._repr_png_()).shape == (24, 32, 3)


def test_a_scene_shows_a_small_picture_and_its_outline():
    scene = shadows()
    html = scene._repr_html_()
    match = re.search(r'src="data:image/png;base64,([^"]+)"', html)
    assert match, html[:300]
    picture = decoded(base64.b64decode(match.group(1)))
    assert picture.shape == (180, 240, 3) and picture.std() > 1  # a picture, not one colour
    for entry in scene.outline():
        assert entry["node"] in html


def request(studio, method, path, body=None, headers=None):
    connection = http.client.HTTPConnection("127.0.0.1", studio.port, timeout=30)
    sent = {"Authorization": "token " + studio.url.split("token=")[1]} if headers is None else headers
    if body is not None:
        sent["Content-Type"] = "application/json"
    connection.request(method, path, body=None if body is None else json.dumps(body), headers=sent)
    response = connection.getresponse()
    data = response.read()
    connection.close()
    return response.status, response, data


def wait_until(condition, timeout=30):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.1)
    return condition()


def node_field(studio, node, field):
    status, _, data = request(studio, "GET", "/node?id=" + node)
    assert status == 200, data
    return next(f["value"] for f in json.loads(data)["fields"] if f["name"] == field)


@pytest.fixture
def studio():
    scene = shadows()
    opened = cs123ray.view(scene, device="ref", width=64, height=48)
    yield opened
    opened.stop()


def test_view_returns_an_iframe_on_the_live_viewer_with_its_token(studio):
    html = studio._repr_html_()
    match = re.search(r'<iframe src="(http://127\.0\.0\.1:(\d+)/\?token=[0-9a-f]+)"', html)
    assert match and match.group(1) == studio.url and int(match.group(2)) == studio.port
    # The page as an IFrame of a notebook on another port opens it: cross-site, framed.
    status, response, page = request(studio, "GET", "/?token=" + studio.url.split("token=")[1], headers={
        "Sec-Fetch-Site": "cross-site", "Sec-Fetch-Mode": "navigate", "Sec-Fetch-Dest": "iframe"})
    assert status == 200 and b"<html" in page.lower()
    assert "frame-ancestors http://localhost:*" in response.getheader("Content-Security-Policy")
    assert response.getheader("X-Frame-Options") is None
    status, _, _ = request(studio, "GET", "/", headers={  # without the token: refused
        "Sec-Fetch-Site": "cross-site", "Sec-Fetch-Mode": "navigate", "Sec-Fetch-Dest": "iframe"})
    assert status == 403


def first_light(scene):
    return next(entry["node"] for entry in scene.outline() if entry["kind"] == "light")


def test_edits_in_the_page_reach_the_scene_and_the_scenes_reach_the_page(studio):
    scene = studio.scene
    light = first_light(scene)
    status, _, data = request(studio, "POST", "/op", {"op": "set", "node": light, "fields": {"color": [0, 1, 0]}})
    assert status == 200, data
    assert tuple(scene.lights[0]["color"]) == (0.0, 1.0, 0.0)  # read before the scene is used
    scene.set(first_light(scene), color=(0.5, 0.25, 1))
    light = None  # the studio's ids are made anew when it reloads the notebook's scene
    assert wait_until(lambda: node_field(studio, first_light(scene), "color") == [0.5, 0.25, 1]), \
        node_field(studio, first_light(scene), "color")
    # A second edit in the page after the notebook's: the notebook's is kept, the page's added.
    objects_before = len(scene.objects)
    status, _, data = request(studio, "POST", "/op", {"op": "add-primitive", "shape": "sphere"})
    assert status == 200, data
    assert len(scene.objects) == objects_before + 1
    assert tuple(scene.lights[0]["color"]) == (0.5, 0.25, 1.0)


def test_the_studio_stops_with_stop_and_with_the_kernel():
    scene = shadows()
    opened = cs123ray.view(scene, device="ref", width=64, height=48)
    folder = os.path.dirname(opened.file)
    opened.stop()
    assert not opened.running and not os.path.exists(folder)
    assert "stopped" in opened._repr_html_()
    # A kernel that ends without stopping its studio: atexit ends `ray view`.
    program = textwrap.dedent(f"""
        import cs123ray
        studio = cs123ray.view(cs123ray.load_scene({os.path.join(SCENES, 'shadows.xml')!r}), device="ref")
        print(studio._process.pid, studio.file, flush=True)
    """)
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=120,
                          env=os.environ)
    assert done.returncode == 0, done.stderr
    pid, file = done.stdout.split()
    assert wait_until(lambda: not os.path.exists(f"/proc/{pid}") or
                      open(f"/proc/{pid}/stat").read().split()[2] == "Z", timeout=10), "ray view outlived its kernel"
    assert not os.path.exists(os.path.dirname(file))


def test_a_studio_that_cannot_start_says_why():
    with pytest.raises(cs123ray.Error, match="ray view did not start"):
        cs123ray.view(shadows(), device="no-such-device")
