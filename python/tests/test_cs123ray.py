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
        cs123ray.render(build_sphere_scene(), device="ref", width=0)


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
