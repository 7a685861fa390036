"""renderer.scene, renderer.pick and renderer.stats: a renderer as an editor's component."""
import os
import statistics
import time
from pathlib import Path

import numpy as np
import pytest

import cs123ray

SCENES = Path(os.environ.get("RAY_SCENES_DIR", Path(__file__).parents[2] / "scenes"))
CORPUS = Path(os.environ.get("RAY_CORPUS_DIR", Path(__file__).parents[2].parent / "shared" / "cs123"))
CHESS = CORPUS / "scenes" / "chess.xml"

have_cpu = any(d["cpu"] for d in cs123ray.list_devices())
needs_chess = pytest.mark.skipif(not CHESS.exists(), reason=f"{CHESS} (the course's corpus) is not there")
needs_cpu = pytest.mark.skipif(not have_cpu, reason="no OpenCL CPU device")


def chess_renderer(device):
    renderer = cs123ray.Renderer(cs123ray.load_scene(CHESS), device=device)
    renderer.set_options(width=320, height=240, aa="off")
    return renderer


@needs_chess
def test_pick_finds_the_object_under_a_pixel_and_none_on_the_background():
    devices = ["ref"] + (["cpu"] if have_cpu else [])
    picks = {}
    for device in devices:
        renderer = chess_renderer(device)
        centre = renderer.pick(160, 120)
        assert isinstance(centre, cs123ray.Pick)
        assert 0 <= centre.instance < renderer.scene.primitive_count
        assert centre.distance > 0
        assert np.linalg.norm(centre.normal) == pytest.approx(1.0)
        assert renderer.pick(0, 0) is None  # the sky above the board
        # The scenefile's object: a SceneObject of the renderer's scene, with its path in the tree.
        assert isinstance(centre.object, cs123ray.SceneObject)
        assert centre.object.id == centre.object_id
        assert renderer.scene.object_of_instance(centre.instance) == centre.object
        assert centre.path == centre.object.path and centre.path.startswith("root/")
        picks[device] = (centre.instance, centre.object_id, centre.path, centre.point, centre.normal, centre.distance)
        with pytest.raises(ValueError):
            renderer.pick(320, 0)
        with pytest.raises(cs123ray.InputError):
            renderer.pick(-1, 5)
    # The host finds it, so every device gives the same answer.
    assert len(set(picks.values())) == 1


@needs_chess
def test_pick_follows_the_size_and_the_camera():
    renderer = chess_renderer("ref")
    centre = renderer.pick(160, 120)
    renderer.set_options(width=640, height=480)
    same = renderer.pick(320, 240)
    assert same is not None and same.instance == centre.instance
    camera = renderer.scene.camera
    renderer.set_camera(position=(0, 40, 0), look=(0, 1, 0), up=(0, 0, 1))  # looking up, at the sky
    assert renderer.pick(320, 240) is None


@needs_chess
@needs_cpu
def test_stats_and_edits_on_the_renderer_scene():
    renderer = chess_renderer("cpu")
    assert renderer.stats == {}
    assert renderer.scene is renderer.scene
    first = renderer.render()
    assert renderer.stats["bvh_build_seconds"] > 0 and renderer.stats["upload_seconds"] > 0
    renderer.render()
    assert renderer.stats["pack_seconds"] == 0 and renderer.stats["upload_seconds"] == 0

    # A material edit, on the object under the centre pixel: its table only, no BVH.
    picked = renderer.pick(160, 120)
    picked.object.set_material(diffuse=(1, 0, 0))
    recolored = renderer.render()
    assert renderer.stats["bvh_build_seconds"] == 0
    assert renderer.stats["pack_seconds"] > 0 and renderer.stats["upload_seconds"] > 0
    assert not np.array_equal(recolored, first)
    assert recolored[120, 160, 0] > 4 * max(recolored[120, 160, 1], recolored[120, 160, 2])  # red there
    fresh = cs123ray.Renderer(renderer.scene, device="cpu")
    fresh.set_options(width=320, height=240, aa="off")
    assert np.array_equal(recolored, fresh.render())

    # A transform edit: the tree refitted, no BVH build, the image a fresh renderer makes.
    moved = picked.object.transform @ cs123ray.Transform.translate(0, 0.3, 0)
    picked.object.set_transform(moved)
    shifted = renderer.render()
    assert renderer.stats["bvh_build_seconds"] == 0
    assert not np.array_equal(shifted, recolored)
    fresh = cs123ray.Renderer(renderer.scene, device="cpu")
    fresh.set_options(width=320, height=240, aa="off")
    assert np.array_equal(shifted, fresh.render())

    renderer.scene.add_light("point", color=(0.5, 0.2, 0.2), position=(0, 6, 0))
    lit = renderer.render()
    assert renderer.stats["bvh_build_seconds"] == 0
    assert renderer.stats["pack_seconds"] > 0 and renderer.stats["upload_seconds"] > 0
    assert not np.array_equal(lit, shifted)
    # What a fresh renderer of the edited scene renders.
    fresh = cs123ray.Renderer(renderer.scene, device="cpu")
    fresh.set_options(width=320, height=240, aa="off")
    assert np.array_equal(lit, fresh.render())

    # The renderer made from a scene has its own copy: editing the original changes nothing.
    original = cs123ray.load_scene(CHESS)
    separate = cs123ray.Renderer(original, device="cpu")
    original.add_light("point", color=(1, 1, 1), position=(0, 6, 0))
    assert separate.scene.light_count == original.light_count - 1


@needs_chess
@needs_cpu
def test_a_table_edit_costs_little_beside_a_frame():
    """A material edit then a frame: at most 25% + 5 ms over the median plain frame (medians of
    alternating runs; bench/edit_frame.py measures this against a whole ray process)."""
    renderer = chess_renderer("cpu")
    renderer.render()
    target = renderer.pick(160, 120).object
    plain, edited = [], []
    for i in range(9):
        start = time.perf_counter()
        renderer.render()
        plain.append(time.perf_counter() - start)
        start = time.perf_counter()
        target.set_material(diffuse=(i / 10, 0.2, 0.2))
        renderer.render()
        edited.append(time.perf_counter() - start)
        assert renderer.stats["bvh_build_seconds"] == 0
    assert statistics.median(edited) <= 1.25 * statistics.median(plain) + 0.005
