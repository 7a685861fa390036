"""cs123ray given what a scenefile may not hold: long names, NaN and infinities, zero axes, wrong
shapes and types. Each raises ValueError (InputError is one) or TypeError with a plain sentence
naming the argument, and changes nothing; nothing crashes the interpreter."""
import math
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import cs123ray

SCENES = Path(os.environ.get("RAY_SCENES_DIR", Path(__file__).parents[2] / "scenes"))


@pytest.mark.parametrize("length", [5000, 50000, 100000])
def test_a_name_of_any_length_raises_a_short_value_error(length):
    # In a child: a stack overflow would end the interpreter (it did, inside std::regex).
    script = textwrap.dedent(f"""
        import cs123ray
        for call in (lambda: cs123ray.load_scene("x" * {length}),
                     lambda: cs123ray.scene_from_string("<bad", "n" * {length})):
            try:
                call()
            except ValueError as e:
                assert len(str(e)) < 500, len(str(e))
                print(type(e).__name__, str(e)[-60:])
    """)
    child = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)
    assert child.returncode == 0, child.stderr
    assert child.stdout.count("InputError") == 2, child.stdout


def shadows():
    return cs123ray.load_scene(SCENES / "shadows.xml")


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_numbers_a_scenefile_cannot_hold_are_refused(bad):
    scene = shadows()
    lights, camera, material = scene.lights, scene.camera, scene.objects[0].material
    refusals = [
        lambda: scene.set_light(0, position=(bad, 0, 0)),
        lambda: scene.set_light(0, direction=(0, bad, 0)),
        lambda: scene.set_light(0, color=(1, 1, bad)),
        lambda: scene.add_light(position=(0, 0, bad)),
        lambda: scene.set_camera(position=(bad, 0, 0), look=(0, 0, -1)),
        lambda: scene.set_camera(position=(0, 0, 5), look=(0, 0, -1), height_angle=bad),
        lambda: scene.set_globals(ka=bad),
        lambda: scene.objects[0].set_material(shininess=bad),
        lambda: scene.objects[0].set_material(diffuse=(bad, 0, 0)),
        lambda: cs123ray.Transform.translate(bad, 0, 0),
        lambda: cs123ray.Transform.scale(1, bad, 1),
        lambda: cs123ray.Transform.rotate(axis=(0, 1, 0), degrees=bad),
        lambda: scene.objects[0].set_transform(cs123ray.Transform(np.array([[1, 0, 0, bad], [0, 1, 0, 0], [0, 0, 1, 0]]))),
    ]
    for refusal in refusals:
        with pytest.raises(ValueError) as raised:
            refusal()
        assert "finite" in str(raised.value) or "nan" in str(raised.value) or "inf" in str(raised.value), raised.value
    assert scene.lights == lights and scene.camera == camera and scene.objects[0].material == material
    assert "nan" not in scene.to_text() and "inf" not in scene.to_text()


def test_a_zero_rotation_axis_is_refused():
    with pytest.raises(ValueError, match=r"the axis \(0, 0, 0\) has no direction"):
        cs123ray.Transform.rotate(axis=(0, 0, 0), degrees=30)


def test_wrong_shapes_and_types_raise_type_error_naming_the_argument():
    scene = shadows()
    obj = scene.objects[0]
    cases = [
        (lambda: obj.set_material(diffuse=(1, 0)), "diffuse must be a sequence of 3 numbers, not 2"),
        (lambda: obj.set_material(diffuse="red"), "diffuse must be a sequence of 3 numbers, not str"),
        (lambda: obj.set_material(diffuse=(1, "a", 0)), "diffuse[1] must be a number, not str"),
        (lambda: obj.set_material(shininess="x"), "shininess must be a number, not str"),
        (lambda: obj.set_material(texture=1.5), "texture must be a string, not float"),
        (lambda: obj.set_material(texture_u=(1, 2)), "texture_u must be a number, not tuple"),
        (lambda: scene.set_light(0, position=None), "position must be a sequence of 3 numbers, not NoneType"),
        (lambda: scene.set_light(0, type=3), "type must be a string, not int"),
        (lambda: scene.add_light(color=(1, 1)), "color must be a sequence of 3 numbers, not 2"),
        (lambda: scene.add_material(ambient=[0] * 4), "ambient must be a sequence of 3 numbers, not 4"),
        (lambda: scene.set_camera(position=(0, 0), look=(0, 0, -1)), "position must be a sequence of 3 numbers"),
        (lambda: scene.set_globals(kd="half"), "kd must be a number, not str"),
        (lambda: cs123ray.Transform.translate(1, "a", 2), "y must be a number, not str"),
        (lambda: cs123ray.Transform.rotate(axis=(0, 1), degrees=3), "axis must be a sequence of 3 numbers, not 2"),
        (lambda: obj.set_material(diffuse="x" * 100000), "characters)"),
    ]
    for call, message in cases:
        with pytest.raises(TypeError) as raised:
            call()
        assert message in str(raised.value), (message, str(raised.value))
        assert "pybind11" not in str(raised.value) and "Unable to cast" not in str(raised.value)
        assert len(str(raised.value)) < 300


# Issue 49: budgets for arrays as for files, plain sentences, files ray writes and reads.

def test_a_texture_array_over_a_texture_files_budget_is_refused_before_it_is_copied():
    scene = cs123ray.Scene()
    # A view of one float that claims 100,000 x 100,000 pixels: copying it would take 120 GB.
    huge = np.lib.stride_tricks.as_strided(np.zeros(3, np.float32), shape=(100_000, 100_000, 3),
                                           strides=(0, 0, 4))
    with pytest.raises(cs123ray.InputError, match=r"texture of 100000 x 100000 pixels is more than .*2\^25"):
        scene.add_texture(huge)
    assert scene.add_texture(np.zeros((4, 8, 3), np.float32)) >= 0


def test_an_image_over_the_largest_render_is_refused_before_it_is_written(tmp_path):
    huge = np.lib.stride_tricks.as_strided(np.zeros(3, np.uint8), shape=(20_000, 10, 3), strides=(0, 0, 1))
    with pytest.raises(cs123ray.InputError, match="20000 pixels|16384"):
        cs123ray.save_image(huge, tmp_path / "tall.png")
    assert not (tmp_path / "tall.png").exists()


def test_an_unreadable_array_is_a_type_error_not_an_internal_error():
    scene = cs123ray.Scene()
    for bad in (np.array([[["a", "b", "c"]]]), np.zeros((2, 2, 3), np.complex64)):
        with pytest.raises(TypeError) as raised:
            scene.add_texture(bad)
        assert "Internal error" not in str(raised.value) and "pybind11" not in str(raised.value)


def test_an_unknown_keyword_says_which_was_meant():
    scene = shadows()
    with pytest.raises(ValueError, match="an object has no field 'difuse'; did you mean 'diffuse'"):
        scene.objects[0].set_material(difuse=(1, 0, 0))
    # A function whose arguments pybind11 matches itself: no C++ signatures, a sentence.
    with pytest.raises(TypeError) as raised:
        scene.add_material(difuse=(1, 0, 0))
    assert "add_material() has no argument 'difuse'; did you mean 'diffuse'?" in str(raised.value)
    assert "incompatible" not in str(raised.value) and "cs123ray.Scene" not in str(raised.value)
    with pytest.raises(TypeError, match="did you mean 'search_paths'"):
        cs123ray.load_scene(SCENES / "shadows.xml", search_path=[])
    with pytest.raises(TypeError) as raised:
        scene.add_texture(42)
    assert "add_texture() cannot take these arguments" in str(raised.value)
    assert "Invoked with" not in str(raised.value)


def test_saving_over_a_link_writes_its_file_and_keeps_its_mode(tmp_path):
    real = tmp_path / "real.xml"
    shadows().save(real)
    os.chmod(real, 0o600)
    (tmp_path / "link.xml").symlink_to("real.xml")
    scene = cs123ray.load_scene(tmp_path / "link.xml")
    scene.objects[0].set_material(diffuse=(0.25, 0.5, 0.75))
    scene.save(tmp_path / "link.xml")
    assert (tmp_path / "link.xml").is_symlink()
    assert "0.25" in real.read_text()
    assert os.stat(real).st_mode & 0o777 == 0o600


def test_a_read_only_file_is_refused_unless_replace_read_only(tmp_path):
    target = tmp_path / "locked.xml"
    target.write_text("kept")
    os.chmod(target, 0o444)
    with pytest.raises(cs123ray.InputError, match="read-only.*replace_read_only=True"):
        shadows().save(target)
    assert target.read_text() == "kept"
    image = tmp_path / "locked.png"
    image.write_bytes(b"kept")
    os.chmod(image, 0o444)
    with pytest.raises(cs123ray.InputError, match="read-only"):
        cs123ray.save_image(np.zeros((2, 2, 3), np.uint8), image)
    assert image.read_bytes() == b"kept"
    cs123ray.save_image(np.zeros((2, 2, 3), np.uint8), image, replace_read_only=True)
    assert image.read_bytes().startswith(b"\x89PNG")
    shadows().save(target, replace_read_only=True)
    assert "<scenefile" in target.read_text()
    assert os.stat(target).st_mode & 0o777 == 0o444


def test_a_mesh_file_that_is_a_fifo_is_refused_at_once(tmp_path):
    fifo = tmp_path / "mesh.obj"
    os.mkfifo(fifo)
    scene = cs123ray.Scene()
    with pytest.raises(cs123ray.InputError, match="FIFO"):
        scene.add("mesh", None, str(fifo))


def test_a_scene_in_a_folder_whose_name_is_not_utf8_raises_input_error(tmp_path):
    folder = os.path.join(os.fsencode(tmp_path), b"caf\xe9")
    os.mkdir(folder)
    scene_file = os.path.join(folder, b"broken.xml")
    with open(scene_file, "wb") as f:
        f.write(b"<scenefile><object type='tree' name='root'><transblock>\n</scenefile>\n")
    with pytest.raises(cs123ray.InputError) as raised:
        cs123ray.load_scene(os.fsdecode(scene_file))
    assert "caf\\xe9" in str(raised.value)
    assert os.fsencode(raised.value.file) == scene_file
