"""Where object.add puts an object given no position: standing on the ground in front of the camera, clear of the
other objects, in view; the same spot for the same scene and camera; recorded with the spot it took, so a replay
does not depend on the camera."""
from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from app.console.demo import VirtualClock
from app.console.text import number
from app.editor import Editor
from app.model.lights3d.scene import DEFAULT_SIZES, Lights3DCamera, Object3D, Scene3D, default_scene, new_object
from app.model.lights3d.gizmo import project
from app.model.lights3d.placement import GAP, ground_spot

VIEWS = [(320, 200), (200, 320)]  # a wide view and a tall one


def lights3d_editor(orbit: str = "") -> Editor:
    editor = Editor(clock=VirtualClock(), configs=False)
    assert editor.execute("workspace lights3d" + (f"; view.orbit {orbit}" if orbit else ""))
    return editor


def scene(editor) -> Scene3D:
    return editor.workspaces["lights3d"].scene


def overlap(a: Object3D, b: Object3D, margin: float = 0.0) -> bool:
    """Whether the bounding boxes share inside points, a's grown by `margin` across the ground (touching is not
    overlapping: an object standing on the ground plane does not overlap it)."""
    grow = np.array([margin, 0.0, margin])
    (alo, ahi), (blo, bhi) = a.bounds, b.bounds
    return bool((alo - grow < bhi).all() and (blo < ahi + grow).all())


def in_view(camera: Lights3DCamera, obj: Object3D, size: tuple[int, int]) -> bool:
    """Every corner of the object's bounding box in front of the eye and inside the view."""
    pixels, depth = project(camera, size, list(itertools.product(*zip(*obj.bounds))))
    return bool((depth > camera.NEAR).all() and (pixels >= 0).all() and (pixels <= size).all())


@pytest.mark.parametrize("orbit", ["35 30 450", "200 45 300", "120 12 160", "300 70 900", "80 -20 500"])
def test_three_objects_added_in_a_row_stand_clear_of_each_other_and_in_view(orbit):
    editor = lights3d_editor(orbit)
    for kind in ("box", "sphere", "torus"):
        assert editor.execute(f"object.add {kind}")
    objects, camera = scene(editor).objects, editor.workspaces["lights3d"].camera
    assert [o.kind for o in objects[5:]] == ["box", "sphere", "torus"]
    for i, new in enumerate(objects[5:], start=5):
        assert new.bounds[0][1] == 0.0  # standing on the ground
        assert not any(overlap(new, other) for j, other in enumerate(objects) if j != i)
        assert all(in_view(camera, new, size) for size in VIEWS), (new, orbit)


def test_the_nearest_clear_spot_is_taken_the_way_the_camera_faces_first():
    lone = Scene3D(objects=(Object3D("box", (30.0, 30.0, 30.0), (0.0, 15.0, 0.0)),))
    box = new_object("box")
    # clear of the box at the origin, 15 + GAP + 15 away along an axis: the nearest spots, four of them
    assert ground_spot(lone, Lights3DCamera(yaw=0.0), box) == (0.0, 15.0, -32.0)    # the eye on +z looks to -z
    assert ground_spot(lone, Lights3DCamera(yaw=90.0), box) == (-32.0, 15.0, 0.0)   # on +x looks to -x
    assert ground_spot(Scene3D(), Lights3DCamera(), box) == (0.0, 15.0, 0.0)       # below the camera's target
    above = Scene3D(objects=(Object3D("box", (30.0, 30.0, 30.0), (0.0, 200.0, 0.0)),))
    assert ground_spot(above, Lights3DCamera(), box) == (0.0, 15.0, 0.0)  # under a box up in the air: no overlap


def test_a_plane_keeps_clear_of_planes_at_its_height_and_of_what_it_cuts_through():
    camera = Lights3DCamera()
    spot = ground_spot(default_scene(), camera, new_object("plane"))
    ground = default_scene().objects[0]
    placed = Object3D("plane", DEFAULT_SIZES["plane"], spot)
    footprint = [(o.bounds[0][[0, 2]], o.bounds[1][[0, 2]]) for o in (placed, ground)]
    (alo, ahi), (blo, bhi) = footprint
    assert not ((alo < bhi).all() and (blo < ahi).all())  # not laid over the ground, where both would show
    shelf = Scene3D(objects=(Object3D("plane", (100.0,), (0.0, 10.0, 0.0)),))  # a plane 10 up cuts a box
    placed = Object3D("box", DEFAULT_SIZES["box"], ground_spot(shelf, camera, new_object("box")))
    assert not overlap(placed, Object3D("box", (100.0, 1.0, 100.0), (0.0, 10.0, 0.0)))


boxes = st.lists(st.builds(lambda x, z, s: Object3D("box", (s, s, s), (x, s / 2, z)),
                           st.integers(-150, 150), st.integers(-150, 150), st.integers(5, 80)), max_size=8)
cameras = st.builds(Lights3DCamera, yaw=st.floats(0, 360), pitch=st.floats(-89, 89), distance=st.floats(20, 2000))


@settings(max_examples=80, deadline=None)
@given(others=boxes, camera=cameras, kind=st.sampled_from(["box", "sphere", "torus", "lprism"]))
def test_the_spot_is_clear_and_the_same_for_the_same_scene_and_camera(others, camera, kind):
    scene3d = Scene3D(objects=(default_scene().objects[0], *others))
    obj = new_object(kind)
    spot = ground_spot(scene3d, camera, obj)
    assert spot == ground_spot(scene3d, camera, obj)
    placed = Object3D(kind, obj.size, spot)
    assert spot[1] == obj.position[1] and all(v == round(v) for v in spot[::2])
    # GAP apart across the ground, less what rounding to whole units may take
    assert not any(overlap(placed, other, GAP - 0.5 - 1e-9) for other in scene3d.objects)


def test_the_recorded_line_carries_the_spot_so_a_replay_needs_no_camera():
    editor = lights3d_editor("35 30 450")
    recorded = []
    editor.console.record_listeners.append(recorded.append)
    assert editor.execute("object.add box; object.add sphere; object.add box 1 2 3")
    box, sphere = scene(editor).objects[5:7]
    assert recorded == [f"object.add box {' '.join(map(number, box.position))}",
                        f"object.add sphere {' '.join(map(number, sphere.position))}", "object.add box 1 2 3"]
    elsewhere = lights3d_editor("250 -20 900")  # a camera that would choose other spots
    assert elsewhere.execute("object.add box")
    assert scene(elsewhere).objects[5].position != box.position
    assert elsewhere.execute("undo")
    for line in recorded:
        assert elsewhere.execute(line)
    assert scene(elsewhere) == scene(editor)


def test_a_recorded_demo_of_added_objects_replays_to_the_same_digest(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    clock = VirtualClock()
    recorded = Editor(clock=clock, configs=False)
    assert recorded.execute("workspace lights3d; record adds")
    for line in ("object.add box", "view.orbit 120 20 300", "object.add torus", "object.add lprism"):
        clock.advance(0.1)
        assert recorded.execute(line)
    assert recorded.execute("stop")
    lines = (tmp_path / "adds.demo").read_text().splitlines()
    assert sum(len(line.split()) == 6 and line.split()[1] == "object.add" for line in lines) == 3  # with x y z
    fresh_clock = VirtualClock()
    fresh = Editor(clock=fresh_clock, configs=False)
    assert fresh.execute("play adds")
    fresh_clock.advance(10)
    fresh.demos.update()
    assert not fresh.demos.playing and fresh.digest() == recorded.digest()
