"""cs123ray, ray's Python module: renders, scenes built in Python, errors, Ctrl-C."""
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import cs123ray

SCENES = Path(os.environ.get("RAY_SCENES_DIR", Path(__file__).parents[2] / "scenes"))
OUTPUT = Path(os.environ.get("RAY_TEST_OUTPUT_DIR", "/tmp/cs123ray-tests"))
RAY = os.environ.get("RAY_BINARY")


@pytest.fixture(scope="module")
def output():
    OUTPUT.mkdir(parents=True, exist_ok=True)
    return OUTPUT


def read_png(path):
    from PIL import Image
    return np.asarray(Image.open(path).convert("RGB"))


@pytest.mark.skipif(RAY is None, reason="RAY_BINARY (the ray command) is not set")
def test_bundled_scene_as_uint8_equals_the_cli_png(output):
    png = output / "cli_shadows.png"
    subprocess.run([RAY, str(SCENES / "shadows.xml"), "64", "48", "--device", "ref", "--quiet", "-o", str(png)],
                   check=True)
    scene = cs123ray.load_scene(SCENES / "shadows.xml")
    assert scene.warnings == []
    image = cs123ray.render(scene, device="ref", dtype="uint8", width=64, height=48)
    assert image.shape == (48, 64, 3) and image.dtype == np.uint8
    assert np.array_equal(image, read_png(png))


def build_sphere_scene():
    scene = cs123ray.Scene()
    scene.set_camera(position=(0, 1, 4), look=(0, -1, -4), height_angle=40)
    scene.add_light("point", color=(1, 1, 1), position=(3, 4, 5))
    green = scene.add_material(diffuse=(0.3, 0.9, 0.3), ambient=(0.1, 0.1, 0.1), specular=(0.6, 0.6, 0.6),
                               shininess=20)
    T = cs123ray.Transform
    scene.add_primitive("sphere", T.rotate((1, 1, 0), 25) @ T.scale(1.5, 1.5, 1.5), material=green)
    checker = np.zeros((8, 8, 3), np.float32)
    checker[::2, ::2] = checker[1::2, 1::2] = 1
    floor = scene.add_material(diffuse=(1, 1, 1), texture=scene.add_texture(checker), blend=1, repeat=(4, 4))
    scene.add_mesh(np.array([[-3, -1.5, -3], [3, -1.5, -3], [3, -1.5, 3], [-3, -1.5, 3]], np.float32),
                   np.array([[0, 2, 1], [0, 3, 2]]))
    scene.add_primitive("mesh", material=floor, mesh=0)
    return scene


def test_a_scene_built_in_python_renders(output):
    scene = build_sphere_scene()
    assert scene.primitive_count == 2
    fractions = []
    image = cs123ray.render(scene, device="ref", width=64, height=48, aa="off", progress=fractions.append)
    assert image.shape == (48, 64, 3) and image.dtype == np.float32
    centre = image[24, 32]
    assert centre[1] > centre[0] and centre[1] > 0.2  # the green sphere
    assert fractions and fractions[-1] == 1.0
    cs123ray.save_image(image, output / "built_in_python.png")
    assert read_png(output / "built_in_python.png").shape == (48, 64, 3)


def test_one_renderer_many_frames():
    scene = build_sphere_scene()
    renderer = cs123ray.Renderer(scene, device="ref")
    renderer.set_options(width=32, height=24, aa="off")
    first = renderer.render()
    renderer.set_camera(position=(1, 1, 4), look=(-1, -1, -4), height_angle=40)
    second = renderer.render()
    assert not np.array_equal(first, second)
    with pytest.raises(TypeError):
        renderer.set_options(colour=1)


def check_switch_changes_only(option, scene_name):
    """The switch `option` changes the bundled scene it is for, is off by default, and
    leaves an opaque sphere scene as it was."""
    scene = cs123ray.load_scene(SCENES / scene_name)
    plain = cs123ray.render(scene, device="ref", width=48, height=36, aa="off")
    assert np.array_equal(plain, cs123ray.render(scene, device="ref", width=48, height=36, aa="off", **{option: False}))
    switched = cs123ray.render(scene, device="ref", width=48, height=36, aa="off", **{option: True})
    assert not np.array_equal(plain, switched)
    renderer = cs123ray.Renderer(build_sphere_scene(), device="ref")
    renderer.set_options(width=32, height=24, aa="off")
    first = renderer.render()
    renderer.set_options(**{option: True})
    assert np.array_equal(first, renderer.render())


def test_course_meshes_option_changes_meshes_only():
    check_switch_changes_only("course_meshes", "mesh_vase.xml")


def test_fresnel_option_changes_glass_only():
    check_switch_changes_only("fresnel", "refraction.xml")


def test_dof_mode_picks_the_lens():
    """dof_mode: "course" (the default, the course's 5x5 lens grid) or "disk" (a random lens
    point a sample); a scene without an aperture is the same either way."""
    scene = cs123ray.load_scene(SCENES / "depth_of_field.xml")
    options = dict(device="ref", width=32, height=24, aa="off")
    course = cs123ray.render(scene, **options)
    assert np.array_equal(course, cs123ray.render(scene, dof_mode="course", **options))
    assert not np.array_equal(course, cs123ray.render(scene, dof_mode="disk", **options))
    pinhole = build_sphere_scene()
    assert np.array_equal(cs123ray.render(pinhole, dof_mode="disk", **options), cs123ray.render(pinhole, **options))
    with pytest.raises(ValueError):
        cs123ray.render(scene, dof_mode="pinhole", **options)


def test_a_bad_scene_raises_naming_file_and_line(output):
    broken = output / "broken.xml"
    broken.write_text("<scenefile>\n<object type=\"tree\" name=\"root\">\n<transblock>\n</scenefile>\n")
    with pytest.raises(cs123ray.InputError) as raised:
        cs123ray.load_scene(broken)
    assert raised.value.file == str(broken)
    assert raised.value.line > 0
    assert f"{broken}:{raised.value.line}:" in str(raised.value)
    assert isinstance(raised.value, cs123ray.Error)
    with pytest.raises(cs123ray.InputError):
        cs123ray.load_scene("/nonexistent/scene.xml")
    with pytest.raises(cs123ray.InputError):
        cs123ray.render(build_sphere_scene(), device="ref", width=0, height=10)


def test_list_devices():
    for device in cs123ray.list_devices():
        assert {"index", "name", "platform", "gpu", "cpu"} <= device.keys()


def test_ctrl_c_raises_keyboard_interrupt_within_a_second():
    # Minutes of work on the reference renderer if left alone (as the CLI's Ctrl-C test).
    script = textwrap.dedent(f"""
        import sys, time, cs123ray
        scene = cs123ray.load_scene({str(SCENES / "reflection_depth.xml")!r})
        print("rendering", flush=True)
        try:
            cs123ray.render(scene, device="ref", width=1200, height=900, depth=8, aa="stratified", samples=1024)
        except KeyboardInterrupt:
            print("KeyboardInterrupt", flush=True)
            sys.exit(42)
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "rendering"
    time.sleep(0.5)
    signalled = time.monotonic()
    child.send_signal(signal.SIGINT)
    try:
        out, _ = child.communicate(timeout=30)
    finally:
        child.kill()
    seconds = time.monotonic() - signalled
    assert "KeyboardInterrupt" in out
    assert child.returncode == 42
    assert seconds < 1.5, f"stopped {seconds:.2f} s after SIGINT"


# --- What NumPy users pass, and the errors they get (issue 25) ---

def test_uint8_render_saves_as_the_same_bytes(output):
    scene = cs123ray.load_scene(SCENES / "shadows.xml")
    image = cs123ray.render(scene, device="ref", dtype=np.uint8, width=64, height=48)
    assert image.dtype == np.uint8
    cs123ray.save_image(image, output / "uint8.png")
    assert np.array_equal(read_png(output / "uint8.png"), image)
    floats = cs123ray.render(scene, device="ref", dtype="float32", width=64, height=48)
    cs123ray.save_image(floats, output / "float.png")
    assert np.array_equal(read_png(output / "float.png"), image)
    cs123ray.save_image(floats.astype(np.float64), output / "float64.png")
    assert np.array_equal(read_png(output / "float64.png"), image)
    with pytest.raises(TypeError, match="int64"):
        cs123ray.save_image(image.astype(np.int64), output / "int64.png")
    with pytest.raises(ValueError, match=r"H x W x 3"):
        cs123ray.save_image(image[:, :, 0], output / "grey.png")


def test_uint8_texture_reads_as_the_loader_reads_8_bit_files():
    bytes_ = np.arange(4 * 4 * 3, dtype=np.uint8).reshape(4, 4, 3) * 5
    renders = []
    for pixels in (bytes_, bytes_.astype(np.float32) / 255):
        scene = build_sphere_scene()
        scene.add_material(texture=scene.add_texture(pixels), blend=1)
        scene.add_primitive("cube", cs123ray.Transform.scale(x=4, y=4, z=0.1), material=2)
        renders.append(cs123ray.render(scene, device="ref", width=32, height=24, aa="off"))
    assert np.array_equal(renders[0], renders[1])


def test_width_and_height_go_together():
    scene = build_sphere_scene()
    for one in ({"width": 64}, {"height": 64}):
        with pytest.raises(ValueError, match="give both"):
            cs123ray.render(scene, device="ref", **one)
        with pytest.raises(ValueError, match="give both"):
            cs123ray.Renderer(scene, device="ref").set_options(**one)


def plain(message):
    """A message as a person writes it: no C++ or pybind11 internals, no 1.000000."""
    for internal in ("PYBIND11", "Unable to cast", "C++", ".000000", "error: "):
        assert internal not in message, message
    return message


def test_bad_values_raise_value_error_with_plain_messages():
    scene = build_sphere_scene()
    with pytest.raises(ValueError) as raised:
        cs123ray.render(scene, device="ref", width=0, height=10)
    assert plain(str(raised.value)) == "width must be between 1 and 16384, not 0"
    for options, expected in [({"depth": 65}, "depth must be between 0 and 64, not 65"),
                              ({"shutter": 2}, "shutter must be between 0 and 1, not 2"),
                              ({"seed": -1}, "seed must be between 0 and 4294967295, not -1"),
                              ({"aa": "cours"}, "aa must be one of off, course, stratified, adaptive, not 'cours'")]:
        with pytest.raises(ValueError) as raised:
            cs123ray.render(scene, device="ref", **options)
        assert plain(str(raised.value)) == expected
    with pytest.raises(ValueError, match="dtype must be float32 or uint8, not float64"):
        cs123ray.render(scene, device="ref", dtype=np.float64, width=4, height=4)


def test_wrong_types_raise_type_error_with_plain_messages():
    scene = build_sphere_scene()
    for options, expected in [({"width": "640", "height": 480}, "width must be an integer, not str ('640')"),
                              ({"width": 64.5, "height": 48}, "width must be an integer, not float (64.5)"),
                              ({"shadows": 1}, "shadows must be True or False, not int (1)"),
                              ({"shutter": "0.5"}, "shutter must be a number, not str ('0.5')"),
                              ({"aa": 1}, "aa must be a string, not int (1)")]:
        with pytest.raises(TypeError) as raised:
            cs123ray.render(scene, device="ref", **options)
        assert plain(str(raised.value)) == expected
    with pytest.raises(TypeError, match="did you mean 'width'"):
        cs123ray.render(scene, device="ref", widht=64)
    # NumPy's own scalars are numbers and booleans like Python's.
    image = cs123ray.render(scene, device="ref", width=np.int64(8), height=np.int32(6), shadows=np.bool_(False),
                            shutter=np.float32(0.5))
    assert image.shape == (6, 8, 3)


def test_materials_lights_and_cameras_follow_the_loaders_rules():
    scene = build_sphere_scene()
    refused = [(scene.add_material, {"shininess": -5}, "shininess must be 0 or more, not -5"),
               (scene.add_material, {"ior": 0}, "ior must be more than 0, not 0"),
               (scene.add_material, {"blend": 1.5}, "blend must be between 0 and 1, not 1.5"),
               (scene.add_material, {"diffuse": (1, -1, 0)}, "diffuse must be 0 or more in each component"),
               (scene.add_light, {"type": "spot", "angle": 0}, "angle must be more than 0 and at most 180, not 0"),
               (scene.add_light, {"attenuation": (1, -1, 0)}, "function must be 0 or more in each component"),
               (scene.add_light, {"function": (1, -1, 0)}, "function must be 0 or more in each component"),
               (scene.add_light, {"type": "area", "width": 0}, "width must be more than 0, not 0"),
               (scene.set_camera, {"position": (0, 0, 0), "look": (0, 0, 0)}, "look (0, 0, 0) has no direction")]
    for add, arguments, expected in refused:
        with pytest.raises(ValueError) as raised:
            add(**arguments)
        assert isinstance(raised.value, cs123ray.InputError)
        assert plain(str(raised.value)).startswith(expected)
    assert scene.primitive_count == 2 and scene.light_count == 1
    # The same value in a scenefile is refused by the same rule, at its line.
    xml = ('<scenefile>\n<lightdata><id v="0"/></lightdata>\n<object type="tree" name="root"><transblock>\n'
           '<object type="primitive" name="sphere">\n<shininess v="-5"/>\n</object>\n'
           '</transblock></object>\n</scenefile>\n')
    with pytest.raises(cs123ray.InputError) as raised:
        cs123ray.scene_from_string(xml, "negative.xml")
    assert raised.value.line == 5
    assert "shininess must be 0 or more, not -5" in str(raised.value)


JSON_SCENE = """{
  "globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
  "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "heightAngle": 45, "look": [0, 0, -1]},
  "groups": [
    {"translate": [2, 2, 2], "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]},
    {"translate": [0, 1, 0], "primitives": [{"type": "sphere", "diffuse": [1, 0, 0]}]}
  ]
}
"""


def test_course_json_scenes_load_from_files_and_strings(output):
    """The course's JSON (SPEC 7) loads as XML does: from a file by its extension, from a
    string by its first character, and renders the same as the same scene in XML."""
    path = output / "json_scene.json"
    path.write_text(JSON_SCENE)
    from_file = cs123ray.load_scene(path)
    from_string = cs123ray.scene_from_string(JSON_SCENE)
    xml = cs123ray.scene_from_string(
        '<scenefile><globaldata><ambientcoeff v="0.5"/><diffusecoeff v="0.5"/><specularcoeff v="0.5"/>'
        '<transparentcoeff v="0"/></globaldata>'
        '<cameradata><pos x="0" y="0" z="5"/><look x="0" y="0" z="-1"/><up x="0" y="1" z="0"/>'
        '<heightangle v="45"/></cameradata>'
        '<lightdata><type v="point"/><color r="1" g="1" b="1"/><function v1="1" v2="0" v3="0"/>'
        '<position x="2" y="2" z="2"/></lightdata>'
        '<object type="tree" name="root"><transblock><translate x="0" y="1" z="0"/>'
        '<object type="primitive" name="sphere"><diffuse r="1" g="0" b="0"/></object>'
        '</transblock></object></scenefile>')
    images = [cs123ray.render(s, width=32, height=24, device="ref") for s in (from_file, from_string, xml)]
    assert np.array_equal(images[0], images[1])
    assert np.array_equal(images[0], images[2])
    with pytest.raises(cs123ray.InputError) as raised:
        cs123ray.scene_from_string(JSON_SCENE.replace('"diffuse"', '"colour"'), "course.json")
    assert raised.value.line == 6
    assert 'unknown key "colour" in groups[1].primitives[0]' in str(raised.value)


def test_keywords_reprs_docstrings_and_version():
    T = cs123ray.Transform
    moved = T.translate(x=1, y=2, z=3) @ T.scale(x=2, y=2, z=2) @ T.rotate(axis=(0, 1, 0), degrees=90)
    assert np.allclose(moved.matrix()[:3, 3], (1, 2, 3))
    assert repr(T.translate(x=1, y=2, z=3)) == "Transform([[1, 0, 0, 1], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]])"
    scene = build_sphere_scene()
    assert repr(scene) == "<cs123ray.Scene: 2 primitives, 1 light, camera at (0, 1, 4) looking (0, -1, -4)>"
    renderer = cs123ray.Renderer(scene=scene, device="ref")
    renderer.set_options(width=32, height=24, aa="off")
    assert repr(renderer) == "<cs123ray.Renderer device='ref', 32 x 24, depth 4, aa='off'>"
    for documented in (cs123ray, cs123ray.render, cs123ray.save_image, cs123ray.load_scene, cs123ray.Scene,
                       cs123ray.Scene.add_material, cs123ray.Scene.add_light, cs123ray.Renderer.set_options,
                       cs123ray.Transform.translate, cs123ray.InputError):
        assert documented.__doc__ and len(documented.__doc__) > 20, documented
    assert cs123ray.__version__.count(".") == 2
    if RAY:
        version = subprocess.run([RAY, "--version"], capture_output=True, text=True, check=True).stdout
        assert cs123ray.__version__ in version


def test_without_numpy_the_import_says_what_to_install():
    script = "import sys\nsys.modules['numpy'] = None\nimport cs123ray\n"
    child = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert child.returncode != 0
    last = child.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: cs123ray needs NumPy")
    assert "python3-numpy" in last and "initialization failed" not in last
