"""The voxel volume model: slices, painting, undo and dirty boxes (pure numpy, no GL)."""
import math
import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from app.model.volume import painting, voxels as vx
from app.model.volume.volume import Volume
from app.model.volume.voxels import AXES, Box, VolumeError
from app.model.volume.samples import coords3d

RED = (255, 0, 0, 255)
BLUE = (0, 0, 255, 255)


def coded(w: int, h: int, d: int) -> Volume:
    """Each voxel holds its own (x, y, z) in r, g, b and alpha 255, so mix-ups show."""
    z, y, x = np.meshgrid(np.arange(d), np.arange(h), np.arange(w), indexing="ij")
    return Volume(np.stack([x, y, z, np.full_like(x, 255)], axis=-1).astype(np.uint8))


def painted(vol: Volume, axis: str = "z", index: int = 0) -> np.ndarray:
    """0/1 image of the slice's painted (non-transparent) voxels, rows = v."""
    return (vol.voxels.slice(axis, index)[..., 3] > 0).astype(int)


def stamp(size: int, round_brush: bool) -> np.ndarray:
    vol = Volume.new(9, 9, 1)
    vol.paint.stroke("z", 0, size, RED, [(4, 4)], round_brush)
    return painted(vol)[2:8, 2:8]


# --- creation ---------------------------------------------------------------------------------


def test_new_is_transparent_with_the_asked_size():
    vol = Volume.new(5, 7, 3)
    assert vol.voxels.size == (5, 7, 3)
    assert vol.voxels.data.shape == (3, 7, 5, 4) and vol.voxels.data.dtype == np.uint8
    assert vol.voxels.data.flags.c_contiguous and not vol.voxels.data.any()
    assert vol.voxels.full_box() == Box(0, 0, 0, 5, 7, 3)
    assert vol.voxels.version == 0 and vol.history.undo_depth == 0 and vol.history.redo_depth == 0


@pytest.mark.parametrize("size", [(0, 4, 4), (4, -1, 4), (4, 4, 0), (4097, 1, 1), (2.5, 4, 4)])
def test_new_refuses_bad_sides(size):
    with pytest.raises(VolumeError):
        Volume.new(*size)


def test_new_refuses_huge_before_allocating(monkeypatch):
    def no_alloc(*args, **kwargs):
        raise AssertionError("allocated")

    monkeypatch.setattr(vx.np, "zeros", no_alloc)
    with pytest.raises(VolumeError) as err:
        Volume.new(4096, 4096, 4096)
    msg = str(err.value)
    assert "4096 x 4096 x 4096" in msg and "256.0 GiB" in msg
    assert vx._fmt_bytes(vx.MAX_BYTES) in msg


def test_byte_limit_is_exact_and_reported_in_mib(monkeypatch):
    assert 0 < vx.MAX_BYTES <= 4 << 30
    monkeypatch.setattr(vx, "MAX_BYTES", 1 << 20)
    assert Volume.new(64, 64, 64).voxels.size == (64, 64, 64)  # exactly 1 MiB
    with pytest.raises(VolumeError, match=r"65 x 64 x 64 .*1\.0 MiB of RGBA data, over the 1\.0 MiB limit"):
        Volume.new(65, 64, 64)


@pytest.mark.parametrize("data", [
    np.zeros((2, 2, 2, 4), np.float32),
    np.zeros((2, 2, 4), np.uint8),
    np.zeros((2, 2, 2, 3), np.uint8),
    np.zeros((0, 2, 2, 4), np.uint8),
    [[[[0, 0, 0, 0]]]],
])
def test_constructor_validates(data):
    with pytest.raises(VolumeError):
        Volume(data)


def test_constructor_copies_into_a_contiguous_array():
    src = np.zeros((4, 3, 2, 4), np.uint8)
    strided = np.zeros((4, 3, 4, 4), np.uint8)[:, :, ::2]
    vol = Volume(src)
    src[0, 0, 0] = 9
    assert not vol.voxels.data.any()
    assert Volume(strided).voxels.data.flags.c_contiguous


# --- slices -----------------------------------------------------------------------------------


def test_slices_on_a_non_cube():
    vol = coded(5, 7, 3)
    assert [vol.voxels.slice_size(a) for a in AXES] == [(7, 3), (5, 3), (5, 7)]
    assert [vol.voxels.depth(a) for a in AXES] == [5, 7, 3]
    assert vol.voxels.voxel_of("z", 2, 4, 6) == (4, 6, 2)
    assert vol.voxels.voxel_of("y", 6, 4, 2) == (4, 6, 2)
    assert vol.voxels.voxel_of("x", 4, 6, 2) == (4, 6, 2)
    for axis in AXES:
        us, vs = vol.voxels.slice_size(axis)
        for index in range(vol.voxels.depth(axis)):
            sl = vol.voxels.slice(axis, index)
            assert sl.shape == (vs, us, 4)
            for v in range(vs):
                for u in range(us):
                    xyz = vol.voxels.voxel_of(axis, index, u, v)
                    assert tuple(sl[v, u]) == (*xyz, 255) == vol.voxels.pick(*xyz)


def test_slice_is_read_only_and_bad_addresses_are_refused():
    vol = coded(5, 7, 3)
    with pytest.raises(ValueError):
        vol.voxels.slice("x", 0)[0, 0] = 1
    v = vol.voxels
    for call in (lambda: v.slice("w", 0), lambda: v.slice("x", 5), lambda: v.slice("z", -1),
                 lambda: v.depth("Z"), lambda: v.voxel_of("y", 0, 5, 0), lambda: v.voxel_of("x", 0, 0, 3),
                 lambda: v.pick(5, 0, 0), lambda: v.pick(0, 0, -1)):
        with pytest.raises(VolumeError):
            call()


# --- set_voxel / pick -------------------------------------------------------------------------


def test_set_voxel_pick_and_erase():
    vol = Volume.new(5, 7, 3)
    vol.paint.set_voxel(4, 6, 2, (10, 20, 30, 40))
    assert vol.voxels.pick(4, 6, 2) == (10, 20, 30, 40)
    assert vol.voxels.data[2, 6, 4].tolist() == [10, 20, 30, 40]
    assert vol.history.undo_depth == 1 and vol.voxels.version == 1
    assert vol.voxels.changed_since(0) == Box(4, 6, 2, 5, 7, 3)
    vol.paint.set_voxel(4, 6, 2, (10, 20, 30, 40))  # same colour: no step
    assert vol.history.undo_depth == 1 and vol.voxels.version == 1
    vol.paint.set_voxel(4, 6, 2, (99, 99, 99, 0))  # alpha 0 erases to all zeros
    assert vol.voxels.pick(4, 6, 2) == (0, 0, 0, 0)
    assert not vol.voxels.data.any()


REFUSED = [("set_voxel", (5, 7, 3), args) for args in [
    (5, 0, 0, RED), (0, 7, 0, RED), (0, 0, -1, RED), (0, 0, 0, (256, 0, 0, 255)), (0, 0, 0, (1, 2, 3)),
    (0, 0, 0, (1.5, 0, 0, 255)), (0, 0, 0, "red"), (0.5, 0, 0, RED),
]] + [("stroke", (4, 4, 2), args) for args in [
    ("w", 0, 1, RED, [(0, 0)]), ("z", 2, 1, RED, [(0, 0)]), ("z", 0, 0, RED, [(0, 0)]),
    ("z", 0, 4097, RED, [(0, 0)]), ("z", 0, 1, (0, 0, 300, 255), [(0, 0)]), ("z", 0, 1, RED, [(0,)]),
    ("z", 0, 1, RED, [(0, 0), (1.5, 0)]), ("z", 0, 1, RED, [(0, 10**9)]), ("z", 0, 1, RED, [5]),
]]


@pytest.mark.parametrize("method, size, args", REFUSED)
def test_refused_edits_change_nothing(method, size, args):
    vol = coded(*size)
    before = vol.voxels.digest()
    with pytest.raises(VolumeError):
        getattr(vol.paint, method)(*args)
    assert vol.voxels.digest() == before and vol.voxels.version == 0 and vol.history.undo_depth == 0


# --- stroke -----------------------------------------------------------------------------------


def test_brush_masks():
    square3 = np.zeros((6, 6), int)
    square3[1:4, 1:4] = 1  # offsets -1..1 round the centre (4, 4)
    assert (stamp(3, False) == square3).all()
    # Size 3 round keeps the corners: they lie sqrt(2) < 1.5 from the centre.
    assert (stamp(3, True) == square3).all()
    square4 = np.zeros((6, 6), int)
    square4[1:5, 1:5] = 1  # offsets -1..2
    assert (stamp(4, False) == square4).all()
    round4 = square4.copy()
    round4[[1, 1, 4, 4], [1, 4, 1, 4]] = 0  # corners lie sqrt(4.5) > 2 from the centre (4.5, 4.5)
    assert (stamp(4, True) == round4).all()
    vol = Volume.new(9, 9, 1)
    vol.paint.stroke("z", 0, 5, RED, [(4, 4)])
    assert painted(vol)[2:7, 2:7].tolist() == [[0, 1, 1, 1, 0]] + [[1] * 5] * 3 + [[0, 1, 1, 1, 0]]
    assert painted(vol).sum() == 21
    for size in (1, 2):
        assert (stamp(size, True) == stamp(size, False)).all()
    assert stamp(1, True).sum() == 1 and stamp(2, True)[2:4, 2:4].all() and stamp(2, True).sum() == 4


def test_stroke_single_stamp_box_and_step():
    vol = Volume.new(9, 9, 1)
    box = vol.paint.stroke("z", 0, 4, RED, [(4, 4)])
    assert box == Box(3, 3, 0, 7, 7, 1)
    assert vol.history.undo_depth == 1 and vol.voxels.version == 1 and vol.voxels.changed_since(0) == box
    assert vol.voxels.pick(3, 4, 0) == RED and vol.voxels.pick(3, 3, 0) == (0, 0, 0, 0)


def test_stroke_on_x_and_y_slices_maps_u_v():
    vol = Volume.new(5, 7, 3)
    assert vol.paint.stroke("x", 4, 1, RED, [(6, 2)]) == Box(4, 6, 2, 5, 7, 3)
    assert vol.voxels.pick(4, 6, 2) == RED
    assert vol.paint.stroke("y", 1, 1, BLUE, [(3, 0), (3, 2)]) == Box(3, 1, 0, 4, 2, 3)
    assert [vol.voxels.pick(3, 1, z) for z in range(3)] == [BLUE] * 3
    assert np.count_nonzero(vol.voxels.data[..., 3]) == 4


def test_stroke_long_diagonal_is_gap_free_and_exact():
    vol = Volume.new(32, 32, 2)
    box = vol.paint.stroke("z", 1, 1, RED, [(0, 0), (31, 31)])
    assert box == Box(0, 0, 1, 32, 32, 2)
    assert (painted(vol, "z", 1) == np.eye(32, dtype=int)).all()
    vol = Volume.new(10, 4, 1)
    vol.paint.stroke("z", 0, 1, RED, [(0, 0), (9, 3)])
    img = painted(vol)
    assert (img.sum(axis=0) == 1).all()  # x-major: exactly one voxel per column
    assert img.argmax(axis=0).tolist() == [0, 0, 1, 1, 1, 2, 2, 2, 3, 3]  # nearest to y = x / 3
    _, n = ndimage.label(img, structure=np.ones((3, 3)))
    assert n == 1


def test_stroke_fast_jump_leaves_no_holes():
    vol = Volume.new(40, 8, 1)
    box = vol.paint.stroke("z", 0, 3, RED, [(1, 3), (38, 3)], round_brush=False)
    assert box == Box(0, 2, 0, 40, 5, 1)
    expected = np.zeros((8, 40), int)
    expected[2:5, :] = 1
    assert (painted(vol) == expected).all()
    assert vol.history.undo_depth == 1
    vol = Volume.new(40, 40, 1)
    vol.paint.stroke("z", 0, 2, RED, [(2, 2), (37, 30), (5, 35)])
    _, n = ndimage.label(painted(vol))  # 4-connected even: a size-2 brush overlaps on diagonal steps
    assert n == 1


def test_stroke_clips_at_the_borders():
    vol = Volume.new(8, 6, 1)
    assert vol.paint.stroke("z", 0, 3, RED, [(0, 0)], round_brush=False) == Box(0, 0, 0, 2, 2, 1)
    assert painted(vol).sum() == 4
    vol = Volume.new(8, 6, 1)
    box = vol.paint.stroke("z", 0, 1, RED, [(-100, 2), (10**6, 2)])  # enters and leaves the slice
    assert box == Box(0, 2, 0, 8, 3, 1)
    assert painted(vol).sum() == 8 and painted(vol)[2].all()
    # Size 4 reaches offsets -1..2 from its centre.
    assert vol.paint.stroke("z", 0, 4, BLUE, [(10, 5)], round_brush=False) is None
    assert vol.paint.stroke("z", 0, 4, BLUE, [(-3, 0)], round_brush=False) is None
    assert vol.paint.stroke("z", 0, 4, BLUE, [(8, 6)], round_brush=False) == Box(7, 5, 0, 8, 6, 1)
    assert vol.paint.stroke("z", 0, 4, BLUE, [(-2, -2)], round_brush=False) == Box(0, 0, 0, 1, 1, 1)
    assert vol.paint.stroke("z", 0, 4, RED, [(-2, -2)]) is None  # that cell is a corner the round brush drops


def test_stroke_far_off_points_are_cheap(monkeypatch):
    walked = []  # points of each segment the stroke stamps: the work done
    line = painting._line
    monkeypatch.setattr(painting, "_line", lambda *args: walked.append(len(points := line(*args))) or points)
    vol = Volume.new(16, 16, 1)
    assert vol.paint.stroke("z", 0, 8, RED, [(-10**7, -10**7), (10**7, -10**7 + 3)]) is None
    box = vol.paint.stroke("z", 0, 1, RED, [(-10**7, -10**7), (10**7, 10**7)])
    assert sum(walked) <= 64  # only the part near the slice, not 2e7 points a segment
    assert box == Box(0, 0, 0, 16, 16, 1) and (painted(vol) == np.eye(16, dtype=int)).all()


def test_noop_stroke_adds_no_step():
    vol = Volume.new(8, 8, 2)
    vol.paint.stroke("z", 0, 3, RED, [(4, 4), (6, 4)])
    depth, version, digest = vol.history.undo_depth, vol.voxels.version, vol.voxels.digest()
    assert vol.paint.stroke("z", 0, 3, RED, [(4, 4), (5, 4)]) is None  # already that colour
    assert vol.paint.stroke("z", 1, 3, RED, [(-9, -9)]) is None  # wholly outside
    assert vol.paint.stroke("z", 1, 3, RED, []) is None
    assert vol.paint.stroke("z", 1, 3, (5, 5, 5, 0), [(3, 3)]) is None  # erasing nothing
    assert (vol.history.undo_depth, vol.voxels.version, vol.voxels.digest()) == (depth, version, digest)


def test_stroke_returns_the_box_of_changed_voxels_only():
    vol = Volume.new(10, 10, 1)
    vol.paint.stroke("z", 0, 3, RED, [(2, 2), (7, 2)], round_brush=False)  # rows 1..3, x 1..8
    box = vol.paint.stroke("z", 0, 5, RED, [(4, 2)], round_brush=False)  # rows 0..4, x 2..6: only rows 0 and 4 change
    assert box == Box(2, 0, 0, 7, 5, 1)
    vol.history.undo()
    assert painted(vol)[[0, 4]].sum() == 0 and painted(vol).sum() == 24


def test_a_preview_is_shown_but_put_back_before_any_edit_undo_or_redo():
    vol = Volume.new(6, 6, 1)
    vol.paint.set_voxel(0, 0, 0, BLUE)
    key, digest = vol.history.key, vol.voxels.digest()
    assert vol.paint.preview_stroke("z", 0, 1, RED, [(1, 1), (4, 1)]) == Box(1, 1, 0, 5, 2, 1)
    assert painted(vol)[1].sum() == 4 and vol.history.undo_depth == 1 and vol.history.key != key
    vol.paint.preview_stroke("z", 0, 1, RED, [(1, 3)])  # the next preview replaces it
    assert painted(vol)[1].sum() == 0 and painted(vol)[3].sum() == 1
    assert vol.history.undo() and vol.voxels.digest() == Volume.new(6, 6, 1).voxels.digest()  # preview and step
    assert vol.history.redo() and vol.voxels.digest() == digest
    vol.paint.preview_stroke("z", 0, 1, RED, [(2, 2)])
    vol.paint.fill("z", 0, 5, 5, BLUE)  # an edit: the fill sees the slice without the preview
    assert vol.voxels.pick(2, 2, 0) == BLUE and vol.history.undo_depth == 2
    vol.paint.preview_stroke("z", 0, 1, RED, [(3, 3)])
    vol.history.clear_preview()
    assert vol.history.key == (2, 2, False) and (vol.voxels.data[..., 2] == 255).all()


# --- fill -------------------------------------------------------------------------------------


def test_fill_exact_region_stops_at_other_colours_and_is_4_connected():
    wall = [(3, v) for v in range(6)] + [(0, 2), (1, 2), (2, 3)]
    vol = Volume.new(7, 6, 3)
    for u, v in wall:
        vol.paint.set_voxel(u, v, 1, BLUE)
    base = vol.voxels.digest()
    box = vol.paint.fill("z", 1, 0, 0, RED)
    img = vol.voxels.slice("z", 1)
    region = np.zeros((6, 7), bool)
    region[0:2, 0:3] = True
    region[2, 2] = True
    assert ((img == RED).all(-1) == region).all()
    assert box == Box(0, 0, 1, 3, 3, 2)
    # (0, 3)..(1, 3) touch the filled region only diagonally across (2, 3)/(1, 2): untouched.
    assert vol.voxels.pick(0, 3, 1) == (0, 0, 0, 0) and vol.voxels.pick(0, 5, 1) == (0, 0, 0, 0)
    assert not vol.voxels.data[0].any() and not vol.voxels.data[2].any()
    assert vol.paint.fill("z", 1, 1, 1, RED) is None and vol.history.undo_depth == len(wall) + 1
    vol.history.undo()
    assert vol.voxels.digest() == base


def test_fill_replaces_an_exact_colour_and_erases():
    vol = coded(4, 3, 2)  # every voxel a different colour
    assert vol.paint.fill("x", 2, 1, 1, RED) == Box(2, 1, 1, 3, 2, 2)
    assert vol.voxels.pick(2, 1, 1) == RED and np.count_nonzero((vol.voxels.data == RED).all(-1)) == 1
    vol = Volume.new(4, 3, 2)
    assert vol.paint.fill("y", 2, 0, 0, BLUE) == Box(0, 2, 0, 4, 3, 2)
    assert (vol.voxels.data[:, 2] == BLUE).all() and not vol.voxels.data[:, :2].any()
    assert vol.paint.fill("y", 2, 3, 1, (1, 2, 3, 0)) == Box(0, 2, 0, 4, 3, 2)
    assert not vol.voxels.data.any()


@pytest.mark.parametrize("tolerance, filled", [(0, 1), (10, 25), (255, 64 * 64)])
def test_fill_tolerance_on_the_gradient_sample(tolerance, filled):
    """coords3d steps about 4 levels a voxel in r (x) and g (y): 10 takes in two voxels each way, 255 the slice."""
    vol = Volume(coords3d(64))
    base = vol.voxels.digest()
    colour = (250, 250, 250, 128)  # no voxel of coords3d has it
    box = vol.paint.fill("z", 5, 32, 32, colour, tolerance)
    filled_voxels = (vol.voxels.data == colour).all(-1)
    assert np.count_nonzero(filled_voxels) == np.count_nonzero(filled_voxels[5]) == filled
    side = math.isqrt(filled)
    lo, hi = 32 - side // 2, 32 + side - side // 2
    assert box == (Box(lo, lo, 5, hi, hi, 6) if tolerance < 255 else Box(0, 0, 5, 64, 64, 6))
    assert filled_voxels[5, lo:hi, lo:hi].all()
    assert vol.history.undo() and vol.voxels.digest() == base


def test_fill_tolerance_holds_for_every_channel_and_stays_4_connected():
    vol = Volume.new(5, 1, 1)
    for u, colour in enumerate([(10, 10, 10, 255), (60, 10, 10, 255), (10, 10, 10, 200), (0, 0, 0, 0),
                                (10, 10, 10, 255)]):
        vol.paint.set_voxel(u, 0, 0, colour)
    base = vol.voxels.digest()
    for tolerance, x1 in ((49, 1), (50, 2), (55, 3), (254, 3), (255, 5)):
        # r is 50 off, then alpha 55, then the empty voxel 255: the seed's own colour beyond it is not connected
        assert vol.paint.fill("z", 0, 0, 0, RED, tolerance) == Box(0, 0, 0, x1, 1, 1)
        assert vol.history.undo() and vol.voxels.digest() == base
    assert vol.paint.fill("z", 0, 0, 0, RED, 255) and vol.paint.fill("z", 0, 2, 0, RED, 255) is None  # all RED: no step


def test_fill_refusals():
    vol = Volume.new(4, 3, 2)
    for args in (("z", 0, 4, 0, RED), ("z", 0, 0, -1, RED), ("q", 0, 0, 0, RED), ("z", 2, 0, 0, RED),
                 ("z", 0, 0, 0, (0, 0, 0)), ("z", 0, 0, 0, RED, 256), ("z", 0, 0, 0, RED, -1),
                 ("z", 0, 0, 0, RED, 2.5)):
        with pytest.raises(VolumeError):
            vol.paint.fill(*args)
    assert vol.voxels.version == 0 and vol.history.undo_depth == 0


# --- smooth -----------------------------------------------------------------------------------


def test_smooth_spreads_one_voxel_to_its_26_neighbours():
    vol = Volume.new(5, 5, 5)
    vol.paint.set_voxel(2, 2, 2, (200, 14, 13, 255))
    box = vol.paint.smooth()
    assert box == Box(1, 1, 1, 4, 4, 4)
    expected = np.zeros((5, 5, 5, 4), np.uint8)
    expected[1:4, 1:4, 1:4] = (7, 1, 0, 9)  # 200/27 = 7.4, 14/27 = 0.52, 13/27 = 0.48, 255/27 = 9.4
    assert (vol.voxels.data == expected).all()


def test_smooth_box_limits_writes_but_reads_outside():
    vol = Volume.new(5, 5, 5)
    vol.paint.set_voxel(2, 2, 2, (27, 27, 27, 27))
    box = vol.paint.smooth(Box(3, 0, 0, 5, 5, 5))
    assert box == Box(3, 1, 1, 4, 4, 4)
    assert (vol.voxels.data[1:4, 1:4, 3] == 1).all() and vol.voxels.pick(2, 2, 2) == (27, 27, 27, 27)
    assert np.count_nonzero(vol.voxels.data[..., 0]) == 10
    assert vol.paint.smooth(Box(-5, -5, -5, 0, 9, 9)) is None and vol.paint.smooth(Box(9, 0, 0, 12, 5, 5)) is None


def test_smooth_clamps_at_the_border_and_keeps_uniform_volumes():
    vol = Volume.new(4, 4, 4)
    vol.paint.set_voxel(0, 0, 0, (243, 243, 243, 243))  # 9 * 27
    vol.paint.smooth()
    assert vol.voxels.pick(0, 0, 0)[0] == 72  # counted 8 times by the clamped 3x3x3
    assert vol.voxels.pick(1, 0, 0)[0] == 36 and vol.voxels.pick(1, 1, 0)[0] == 18 and vol.voxels.pick(1, 1, 1)[0] == 9
    assert vol.voxels.pick(2, 0, 0)[0] == 0
    uniform = Volume(np.full((3, 4, 5, 4), 77, np.uint8))
    assert uniform.paint.smooth() is None and uniform.history.undo_depth == 0


@pytest.mark.parametrize("tile", [1, 7, 60, 1 << 20])  # voxels: part of a row, rows, layers, all at once
def test_smooth_in_tiles_matches_a_float_reference(monkeypatch, tile):
    """Later tiles read neighbours that earlier tiles have already overwritten: they must see the originals."""
    monkeypatch.setattr(painting, "_SMOOTH_TILE", tile)
    data = np.random.default_rng(tile).integers(0, 256, (5, 6, 9, 4), dtype=np.uint8)
    data[:, :, :2] = 40  # a uniform edge the filter leaves alone: the changed box is smaller than the asked one
    vol = Volume(data)
    box = vol.paint.smooth(Box(0, 1, 0, 8, 6, 4))
    ref = np.floor(ndimage.uniform_filter(data.astype(float), size=(3, 3, 3, 1), mode="nearest") + 0.5)
    expected = data.copy()
    expected[0:4, 1:6, 0:8] = ref[0:4, 1:6, 0:8]
    assert (vol.voxels.data == expected).all()
    assert box == Box(1, 1, 0, 8, 6, 4)
    vol.history.undo()
    assert (vol.voxels.data == data).all()


def test_smooth_peaks_at_the_volume_and_its_undo_copy():
    """It made a full result, uint16 sums and a comparison beside the volume (8x a 4 MiB one, 3.5x a large one);
    now only the undo copy of the changed box and one tile's temporaries, about 1 MiB."""
    vol = Volume(np.random.default_rng(4).integers(0, 256, (64, 128, 128, 4), dtype=np.uint8))
    tracemalloc.start()
    try:
        vol.paint.smooth()
        peak = tracemalloc.get_traced_memory()[1]  # the volume itself was there before: not counted
    finally:
        tracemalloc.stop()
    assert peak <= vol.voxels.data.nbytes + (2 << 20)


def test_smooth_matches_a_float_reference():
    rng = np.random.default_rng(3)
    data = rng.integers(0, 256, (6, 7, 8, 4), dtype=np.uint8)
    vol = Volume(data)
    vol.paint.smooth(Box(1, 2, 0, 7, 7, 4))
    ref = ndimage.uniform_filter(data.astype(float), size=(3, 3, 3, 1), mode="nearest")
    expected = data.copy()
    expected[0:4, 2:7, 1:7] = np.floor(ref[0:4, 2:7, 1:7] + 0.5)
    assert (vol.voxels.data == expected).all()


# --- rotate -----------------------------------------------------------------------------------

ROT = {"x": np.array([[1, 0, 0], [0, 0, -1], [0, 1, 0]]),
       "y": np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0]]),
       "z": np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1]])}


@pytest.mark.parametrize("axis", AXES)
def test_rotate_moves_voxels_by_a_right_handed_quarter_turn(axis):
    vol = coded(5, 7, 3)
    old_size = np.array(vol.voxels.size)
    vol.rotate(axis)
    new_size = np.abs(ROT[axis]) @ old_size
    assert vol.voxels.size == tuple(new_size)
    assert vol.voxels.data.flags.c_contiguous
    for x, y, z in [(0, 0, 0), (4, 1, 2), (1, 6, 0), (3, 5, 1)]:
        centre = np.array([x, y, z]) + 0.5 - old_size / 2
        nx, ny, nz = (ROT[axis] @ centre + new_size / 2 - 0.5).round().astype(int)
        assert vol.voxels.pick(nx, ny, nz) == (x, y, z, 255)


def test_rotate_examples_counter_clockwise_looking_down_the_axis():
    vol = Volume.new(5, 7, 3)
    vol.paint.set_voxel(4, 0, 0, RED)  # on +x
    vol.rotate("z")
    assert vol.voxels.size == (7, 5, 3) and vol.voxels.pick(6, 4, 0) == RED  # x -> y
    vol.rotate("x")
    assert vol.voxels.size == (7, 3, 5) and vol.voxels.pick(6, 2, 4) == RED  # y -> z
    vol.rotate("y")
    assert vol.voxels.size == (5, 3, 7) and vol.voxels.pick(4, 2, 0) == RED  # z -> x


@pytest.mark.parametrize("axis", AXES)
def test_rotate_four_turns_identity_and_undo(axis):
    vol = coded(5, 7, 3)
    start = vol.voxels.digest()
    for _ in range(4):
        vol.rotate(axis)
    assert vol.voxels.digest() == start and vol.history.undo_depth == 4
    vol.rotate(axis, 4)
    vol.rotate(axis, 0)
    assert vol.history.undo_depth == 4 and vol.voxels.version == 4
    vol.rotate(axis, -1)
    three = coded(5, 7, 3)
    three.rotate(axis, 3)
    assert vol.voxels.digest() == three.voxels.digest()
    assert vol.history.undo() and vol.voxels.digest() == start and vol.voxels.size == (5, 7, 3)
    assert vol.history.redo() and vol.voxels.digest() == three.voxels.digest()


def test_rotation_steps_store_no_voxels():
    vol = Volume.new(4, 5, 6, max_undo_bytes=0)  # no voxel step fits
    vol.paint.set_voxel(1, 2, 3, RED)
    vol.rotate("y", 1)
    vol.rotate("x", 2)
    assert vol.history.undo_depth == 2
    assert vol.history.undo() and vol.history.undo() and not vol.history.undo()
    assert vol.voxels.size == (4, 5, 6) and vol.voxels.pick(1, 2, 3) == RED


def test_rotate_refusals():
    vol = coded(2, 3, 4)
    for args in (("w", 1), ("x", 1.0), ("z", "1")):
        with pytest.raises(VolumeError):
            vol.rotate(*args)
    assert vol.voxels.version == 0


# --- replace ----------------------------------------------------------------------------------


def test_replace_is_one_undo_step_and_validates():
    vol = coded(5, 7, 3)
    start = vol.voxels.digest()
    seen = vol.voxels.version
    new = np.full((2, 3, 4, 4), 9, np.uint8)
    vol.replace(new)
    new[:] = 0
    assert vol.voxels.size == (4, 3, 2) and vol.voxels.pick(0, 0, 0) == (9, 9, 9, 9)
    assert vol.voxels.changed_since(seen) == Box(0, 0, 0, 4, 3, 2)
    with pytest.raises(VolumeError):
        vol.replace(np.zeros((2, 3, 4), np.uint8))
    assert vol.voxels.size == (4, 3, 2) and vol.history.undo_depth == 1
    assert vol.history.undo() and vol.voxels.digest() == start
    assert vol.history.redo() and vol.voxels.size == (4, 3, 2)


# --- undo / redo ------------------------------------------------------------------------------


def test_150_steps_undo_to_the_start_and_redo_to_the_end():
    vol = Volume.new(12, 10, 4)
    digests = [vol.voxels.digest()]
    rng = np.random.default_rng(7)
    for i in range(150):
        colour = tuple(int(c) for c in rng.integers(1, 256, 4))
        if i % 3:
            vol.paint.set_voxel(i % 12, (i // 12) % 10, i % 4, colour)
        else:
            vol.paint.stroke("z", i % 4, 1 + i % 5, colour, [(int(rng.integers(12)), int(rng.integers(10))),
                                                       (int(rng.integers(12)), int(rng.integers(10)))])
        digests.append(vol.voxels.digest())
    assert vol.history.undo_depth == 150
    for k in range(150, 0, -1):
        assert vol.history.undo()
        assert vol.voxels.digest() == digests[k - 1]
    assert not vol.history.undo() and vol.voxels.digest() == digests[0] and vol.history.redo_depth == 150
    version = vol.voxels.version
    assert not vol.history.undo() and vol.voxels.version == version
    for k in range(1, 151):
        assert vol.history.redo() and vol.voxels.digest() == digests[k]
    assert not vol.history.redo() and vol.history.undo_depth == 150


def test_new_edit_clears_redo():
    vol = Volume.new(4, 4, 1)
    vol.paint.set_voxel(0, 0, 0, RED)
    vol.paint.set_voxel(1, 0, 0, RED)
    vol.history.undo()
    assert vol.history.redo_depth == 1
    vol.paint.set_voxel(2, 0, 0, BLUE)
    assert vol.history.redo_depth == 0 and not vol.history.redo()
    assert vol.voxels.pick(1, 0, 0) == (0, 0, 0, 0) and vol.history.undo_depth == 2


def test_history_caps_by_count():
    vol = Volume.new(16, 1, 1, max_undo_steps=10)
    history = Volume.new(1, 1, 1).history
    assert history.max_steps == 256 and history.max_bytes == 512 << 20
    for x in range(15):
        vol.paint.set_voxel(x, 0, 0, RED)
    assert vol.history.undo_depth == 10
    while vol.history.undo():
        pass
    assert painted(vol).tolist() == [[1] * 5 + [0] * 11]


def test_history_caps_by_bytes():
    vol = Volume.new(8, 8, 1, max_undo_bytes=100)
    for v in range(6):
        vol.paint.stroke("z", 0, 1, RED, [(0, v), (7, v)])  # 8 voxels = 32 bytes a step
    assert vol.history.undo_depth == 3
    while vol.history.undo():
        pass
    assert painted(vol).sum(axis=1).tolist() == [8, 8, 8, 0, 0, 0, 0, 0]
    vol.history.max_bytes = 10
    vol.paint.stroke("z", 0, 1, BLUE, [(0, 7), (7, 7)])  # bigger than the whole cap: cannot be undone
    assert vol.history.undo_depth == 0 and vol.history.redo_depth == 0


# --- changed_since / digest -------------------------------------------------------------------


def test_changed_since_unions_for_consumers_at_different_versions():
    vol = Volume.new(10, 10, 10)
    gpu = vol.voxels.version
    assert vol.voxels.changed_since(gpu) is None
    vol.paint.set_voxel(1, 2, 3, RED)
    dist = vol.voxels.version
    vol.paint.stroke("y", 5, 1, RED, [(7, 8)])
    assert vol.voxels.changed_since(gpu) == Box(1, 2, 3, 8, 6, 9)
    assert vol.voxels.changed_since(dist) == Box(7, 5, 8, 8, 6, 9)
    gpu = vol.voxels.version
    assert vol.voxels.changed_since(gpu) is None and vol.voxels.changed_since(gpu + 5) is None
    vol.history.undo()  # undo marks its box too
    assert vol.voxels.changed_since(gpu) == Box(7, 5, 8, 8, 6, 9)
    assert vol.voxels.changed_since(dist) == Box(7, 5, 8, 8, 6, 9)
    assert vol.voxels.changed_since(-1) == vol.voxels.full_box()


def test_changed_since_is_the_full_box_after_a_reshape():
    vol = Volume.new(4, 5, 6)
    seen = vol.voxels.version
    vol.paint.set_voxel(0, 0, 0, RED)
    vol.rotate("z")
    after_rotate = vol.voxels.version
    vol.paint.set_voxel(1, 1, 1, RED)
    assert vol.voxels.changed_since(seen) == Box(0, 0, 0, 5, 4, 6)
    assert vol.voxels.changed_since(after_rotate) == Box(1, 1, 1, 2, 2, 2)
    vol.history.undo()
    vol.history.undo()
    assert vol.voxels.changed_since(after_rotate) == Box(0, 0, 0, 4, 5, 6)
    seen = vol.voxels.version
    vol.replace(np.zeros((4, 5, 6, 4), np.uint8))  # same shape, every voxel may differ
    assert vol.voxels.changed_since(seen) == vol.voxels.full_box()


def test_changed_since_beyond_the_record_is_the_full_box():
    vol = Volume.new(64, 64, 1)
    vol.paint.set_voxel(0, 0, 0, RED)
    old = vol.voxels.version
    for i in range(vx.CHANGE_RECORDS + 1):
        vol.paint.set_voxel(1 + i % 7, 1, 0, RED if i % 2 else BLUE)  # every call a change
    assert vol.voxels.version == old + vx.CHANGE_RECORDS + 1
    recent = vol.voxels.version - vx.CHANGE_RECORDS  # exactly as far back as the record reaches
    assert vol.voxels.changed_since(old) == vol.voxels.full_box()
    assert vol.voxels.changed_since(recent) == Box(1, 1, 0, 8, 2, 1)


def test_digest_covers_size_and_voxels():
    assert Volume.new(2, 1, 1).voxels.digest() != Volume.new(1, 2, 1).voxels.digest()
    a, b = Volume.new(3, 3, 3), Volume.new(3, 3, 3)
    assert a.voxels.digest() == b.voxels.digest() and len(a.voxels.digest()) == 16
    b.paint.set_voxel(2, 2, 2, (0, 0, 1, 1))
    assert a.voxels.digest() != b.voxels.digest()


def test_box_helpers():
    a, b = Box(0, 1, 2, 3, 4, 5), Box(2, 0, 4, 6, 2, 9)
    assert a.union(b) == Box(0, 0, 2, 6, 4, 9) and a.shape == (3, 3, 3)
    assert a.slices() == (slice(2, 5), slice(1, 4), slice(0, 3))
    empty = Box(1, 1, 1, 1, 5, 5)
    assert empty.empty and not a.empty and a.union(empty) == a and empty.union(a) == a
    assert a.intersect(b) == Box(2, 1, 4, 3, 2, 5) and a.intersect(Box(5, 5, 5, 6, 6, 6)).empty


# --- random edit sequences --------------------------------------------------------------------

colours = st.sampled_from([RED, BLUE, (0, 255, 0, 128), (9, 9, 9, 0)])
axes = st.sampled_from(AXES)
small = st.integers(0, 7)
ops = st.one_of(
    st.tuples(st.just("set"), small, small, small, colours),
    st.tuples(st.just("stroke"), axes, small, st.integers(1, 4), colours,
              st.lists(st.tuples(st.integers(-3, 9), st.integers(-3, 9)), min_size=1, max_size=4), st.booleans()),
    st.tuples(st.just("fill"), axes, small, small, small, colours, st.sampled_from([0, 0, 1, 128, 255])),
    st.tuples(st.just("rotate"), axes, st.integers(-2, 5)),
    st.tuples(st.just("smooth"), st.none() | st.tuples(small, small, small, small, small, small)),
)


def apply(vol: Volume, op: tuple) -> Box | None:
    w, h, d = vol.voxels.size
    kind = op[0]
    if kind == "set":
        vol.paint.set_voxel(op[1] % w, op[2] % h, op[3] % d, op[4])
        return None
    if kind == "rotate":
        vol.rotate(op[1], op[2])
        return None
    if kind == "smooth":
        return vol.paint.smooth(None if op[1] is None else Box(*op[1]))
    axis, index = op[1], op[2] % vol.voxels.depth(op[1])
    if kind == "stroke":
        return vol.paint.stroke(axis, index, op[3], op[4], op[5], op[6])
    us, vs = vol.voxels.slice_size(axis)
    return vol.paint.fill(axis, index, op[3] % us, op[4] % vs, op[5], op[6])


@settings(max_examples=60, deadline=None, database=None)
@given(size=st.tuples(st.integers(1, 6), st.integers(1, 6), st.integers(1, 6)),
       seed=st.integers(0, 2**32 - 1), edits=st.lists(ops, max_size=14))
def test_random_edits_undo_and_redo_exactly(size, seed, edits):
    w, h, d = size
    rng = np.random.default_rng(seed)
    data = rng.choice(np.array([RED, BLUE, (0, 0, 0, 0)], np.uint8), size=(d, h, w))  # fills find regions
    vol = Volume(data)
    start = vol.voxels.digest()
    mirror, seen = vol.voxels.data.copy(), vol.voxels.version  # a GPU-upload consumer

    def sync() -> None:
        nonlocal mirror, seen
        box = vol.voxels.changed_since(seen)
        if mirror.shape != vol.voxels.data.shape:
            assert box == vol.voxels.full_box()
            mirror = vol.voxels.data.copy()
        elif box is not None:
            mirror[box.slices()] = vol.voxels.data[box.slices()]
        seen = vol.voxels.version
        assert (mirror == vol.voxels.data).all()

    for op in edits:
        version, before = vol.voxels.version, vol.voxels.data.copy()
        box = apply(vol, op)
        if box is not None:
            assert vol.voxels.changed_since(version) == box and vol.voxels.version == version + 1
            outside = np.ones(before.shape[:3], bool)
            outside[box.slices()] = False
            assert (vol.voxels.data[outside] == before[outside]).all()
        sync()
    end = vol.voxels.digest()
    assert vol.history.undo_depth == vol.voxels.version
    while vol.history.undo():
        sync()
    assert vol.voxels.digest() == start
    while vol.history.redo():
        sync()
    assert vol.voxels.digest() == end


def test_group_since_undoes_and_redoes_a_batch_as_one():
    vol = Volume.new(4, 4, 2)
    vol.paint.set_voxel(0, 0, 0, (1, 1, 1, 255))
    start = vol.voxels.digest()
    mark = vol.history.edits
    for x in range(4):
        vol.paint.set_voxel(x, 1, 1, (9, 9, 9, 255))
    vol.rotate("z")
    end = vol.voxels.digest()
    vol.history.group_since(mark)
    assert vol.history.undo_depth == 2
    assert vol.history.undo() and vol.voxels.digest() == start
    assert vol.history.redo() and vol.voxels.digest() == end
    assert vol.history.undo() and vol.history.undo() and not vol.history.undo()
