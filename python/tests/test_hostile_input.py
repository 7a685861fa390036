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
        (lambda: obj.set_material(texture=1.5), "texture must be an integer, not float"),
        (lambda: obj.set_material(repeat=(1, 2, 3)), "repeat must be a sequence of 2 numbers, not 3"),
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
