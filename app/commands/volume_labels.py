"""A scan's labels in the editor (app/model/volume/labels.py): the label verbs, their cvars, and the labels file
beside a scan (app/io/volume_labels.py), which `load` reads and `save` writes. An RGBA volume has no labels: its
colours are painted (app/commands/volume.py)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from app.commands.volume_args import check_brush, check_tolerance, round_brush, stroke_points
from app.console import files
from app.console.command_set import CommandSet, Context
from app.console.registry import SCRIPTS, CommandError, Cvar, Registry
from app.io.volume_formats import FormatError
from app.io.volume_labels import labels_path, read_labels, write_labels
from app.model.volume import voxels as voxels_model
from app.model.volume.labels import DEFAULT_OPACITY, LABELS, Labels, check_label, check_rgb
from app.model.volume.voxels import VolumeError
from app.model.volume.workspace import VolumeWorkspace

OPACITY = "r_labelOpacity"
BRUSH_LABEL = "brush_label"
COMMANDS = CommandSet("volume")
Ctx = Context[VolumeWorkspace]


def add_cvars(reg: Registry) -> None:
    reg.add_cvar(Cvar(BRUSH_LABEL, int, 1, "The label the painter paints over a scan (0 erases; the eyedropper "
                      "picks the one under it)", min=0, max=LABELS))
    reg.add_cvar(Cvar(OPACITY, float, DEFAULT_OPACITY, "How opaque a scan's labels are over it, in the slice painter "
                      "and the 3D view (0: hidden, 1: opaque)", min=0.0, max=1.0, archive=True))


def _label(label: int, least: int = 0) -> int:
    try:
        return check_label(label, least)
    except VolumeError as exc:
        raise CommandError(str(exc)) from None


def summary(labels: Labels) -> str:
    """Which labels are painted: "labels 1, 3 (1200 voxels)", or that none is."""
    counts = labels.counts()
    present = np.flatnonzero(counts[1:]) + 1
    if not len(present):
        return "no label painted"
    names = ", ".join(map(str, present[:12])) + (", ..." if len(present) > 12 else "")
    return f"label{'s' if len(present) > 1 else ''} {names} ({counts[1:].sum()} voxels)"


# --- the labels file beside a scan ------------------------------------------------------------------------------


def beside(ctx: Ctx, scan: Path, shape: tuple[int, int, int]) -> Labels | None:
    """The labels file beside a scan of `shape` (d, h, w) being loaded, if there is one the commands may read; one
    that cannot be read or is not the scan's size is said, and the scan loads without labels."""
    path = labels_path(scan)
    if not path.exists() or not files.may_read(ctx.console, path):
        return None
    try:
        data, colours = read_labels(path, voxels_model.MAX_BYTES)
        if data.shape != shape:
            raise VolumeError("{}: its labels are {} x {} x {} voxels, the scan {} x {} x {}".format(
                path, *data.shape[::-1], *shape[::-1]))
        return Labels.loaded(data, colours)
    except (FormatError, VolumeError) as exc:
        ctx.console.error(f"{exc}; the scan loads without its labels")
        return None


def say_loaded(ctx: Ctx, scan: Path) -> None:
    """After `load` took the labels beside the scan."""
    ctx.console.print(f"labels from {labels_path(scan)}: {summary(ctx.state.volume.voxels.labels)}")


def write_beside(labels: Labels, scan: Path | str) -> None:
    """A scan's labels beside the file it is saved to. A labels file there is the scan's: with no label painted,
    one left from before is written again as clear, not left to paint old labels over the scan when it loads."""
    path = labels_path(scan)
    if labels.data is not None:
        write_labels(path, labels.data, labels.colours)
    elif path.exists():
        w, h, d = labels.size
        write_labels(path, np.zeros((d, h, w), np.uint8), labels.colours)


def say_saved(ctx: Ctx, target: Path, as_scalars: bool) -> None:
    """What `save` did with the scan's labels."""
    labels = ctx.state.volume.voxels.labels
    if labels is None:
        return
    path = labels_path(target)
    if as_scalars and labels.data is not None:
        ctx.console.print(f"saved its labels beside it: {path}, {summary(labels)}")
    elif as_scalars and path.exists():
        ctx.console.print(f"saved {path} beside it with no label: none is painted now")
    elif labels.data is not None:
        ctx.console.print(f"the labels are not kept: save the scan as .nrrd, .npy or .tif to keep them beside it "
                          f"({path.name})")


def pick_label(ctx: Ctx, x: int, y: int, z: int) -> None:
    """The eyedropper on a scan: the label under it becomes the brush's."""
    label = ctx.state.volume.voxels.label_at(x, y, z)
    ctx.console.registry.cvars[BRUSH_LABEL].set(str(label), trusted=ctx.console.trusted)
    ctx.console.print(f"brush label {label}")


# --- painting labels ------------------------------------------------------------------------------------------


@COMMANDS.check("label.voxel", "volume")
def voxel_args(ctx: Ctx, x: int, y: int, z: int, label: int) -> tuple[int, int, int, int]:
    ctx.state.volume.voxels.pick(x, y, z)  # reading refuses a voxel outside the volume
    return x, y, z, _label(label)


@COMMANDS.command("label.voxel", "x:int y:int z:int label:int", "Label one voxel of a scan (0 clears it)",
                  allow=SCRIPTS)
def voxel(ctx: Ctx, *args: int) -> None:
    ctx.state.volume.paint.set_label(*voxel_args(ctx, *args))


@COMMANDS.check("label.stroke", "volume")
def stroke_args(ctx: Ctx, axis, index, size, label, coords):
    check_brush(ctx.state.volume.voxels, axis, index, size)
    return axis, index, size, _label(label), stroke_points(coords)


@COMMANDS.command("label.stroke", "axis slice:int size:int label:int coords:int...",
                  "Paint a label over a scan: a gap-free brush stroke through the points x1 y1 [x2 y2 ...] of a slice "
                  "(label 0 erases); the scan's values stay as loaded", allow=SCRIPTS)
def stroke(ctx: Ctx, *args) -> None:
    ctx.state.volume.paint.stroke_label(*stroke_args(ctx, *args), round_brush=round_brush(ctx.console))


@COMMANDS.command("label.stroke.preview", "axis slice:int size:int label:int coords:int...",
                  "Show a label stroke in progress (the painter, while the mouse is down); not recorded",
                  recorded=False, quiet=True, allow=SCRIPTS)
def stroke_preview(ctx: Ctx, *args) -> None:
    ctx.state.volume.paint.stroke_label(*stroke_args(ctx, *args), round_brush=round_brush(ctx.console),
                                        preview=True)


@COMMANDS.check("label.fill", "volume")
def fill_args(ctx: Ctx, axis: str, index: int, u: int, v: int, label: int, tolerance: int = 0):
    ctx.state.volume.voxels.voxel_of(axis, index, u, v)  # refuses a point outside the slice
    return axis, index, u, v, _label(label), check_tolerance(tolerance)


@COMMANDS.command("label.fill", "axis slice:int x:int y:int label:int [tolerance:int]",
                  "Flood a label over the region around (x, y) within a scan's slice that has the label found at "
                  "(x, y) and whose window colours are within tolerance (0..255, default 0: one exact colour; 255: "
                  "the labels alone bound it) of those at (x, y); label 0 erases", allow=SCRIPTS)
def fill(ctx: Ctx, *args) -> None:
    ctx.state.volume.paint.fill_label(*fill_args(ctx, *args))


@COMMANDS.check("label.color")
def colour_args(ctx: Ctx, label: int, r: int, g: int, b: int) -> tuple[int, tuple[int, int, int]]:
    try:
        return _label(label, least=1), check_rgb((r, g, b))
    except VolumeError as exc:
        raise CommandError(str(exc)) from None


@COMMANDS.command("label.color", "label:int r:int g:int b:int", "Set a label's colour (1..255; components 0..255)",
                  allow=SCRIPTS)
def colour(ctx: Ctx, *args: int) -> None:
    ctx.state.volume.set_label_colour(*colour_args(ctx, *args))


@COMMANDS.command("label.list", "", "Say which labels a scan has painted, their voxels and colours", recorded=False,
                  allow=SCRIPTS)
def list_(ctx: Ctx) -> None:
    labels = ctx.state.volume.voxels.require_labels()
    counts = labels.counts()
    present = np.flatnonzero(counts[1:]) + 1
    if not len(present):
        ctx.console.print("no label painted")
    for n in present:
        ctx.console.print(f"label {n}: {counts[n]} voxels, colour {' '.join(map(str, labels.colours[n]))}")
