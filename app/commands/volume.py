"""The raster editor's verbs (seed 003, Tex3Dtrace). Names and arguments are fixed: scripts and outside
tests rely on them. Colour components are 0-255 integers; slices are (axis, index) with (u, v) inside."""
from __future__ import annotations

import math
from dataclasses import replace as replaced
from functools import partial
from pathlib import Path

import numpy as np

from app.console import files
from app.console.command_set import CommandSet, Context
from app.console.console import Console
from app.console.demo import ArgChecks
from app.console.registry import SCRIPTS, CommandError, Cvar
from app.commands import volume_labels
from app.commands.volume_args import check_axis as _axis, check_brush, check_rgba as _rgba, round_brush
from app.commands.volume_args import check_tolerance as _tolerance, stroke_points as _points
from app.io.volume_formats import (READ_ONLY, SCALAR_SUFFIXES, SPACING_SUFFIXES, SUPPORTED, WINDOW_SUFFIXES,
                                   FormatError, is_volume_source, read_dicom_files, read_volume_file,
                                   suffix_of, write_volume)
from app.io.volume_labels import LABELS_SUFFIX
from app.model.camera3d import OrbitCamera
from app.model.volume import voxels as voxels_model
from app.model.volume.labels import Labels
from app.model.volume.render_modes import LIGHTS, MODES, TraceSettings
from app.model.volume.samples import SAMPLES, make
from app.model.volume.scalar_modes import ISO_MODE, MIP_ATTENUATION, SCALAR_DEFAULT, SCALAR_MODES
from app.console.text import count, number
from app.model.volume.scalars import (COLORMAPS, PERCENTILES, OpacityPoints, TransferFunction, check_colormap,
                                      check_opacity_points, check_window, default_window, value_range)
from app.model.volume.transfer_presets import PRESETS, check_preset
from app.model.volume.voxels import AXES, DEFAULT_SPACING, Spacing, VolumeError, check_spacing, transparent
from app.model.volume.workspace import VolumeWorkspace
from app.model.workspace import SceneFiles

MAX_SAMPLE = 512
COMMANDS = CommandSet("volume")
Ctx = Context[VolumeWorkspace]
# The seed's ray-tracer variables (default.cfg sets them too): typed and bounded here.
TRACER_CVARS = (
    ("cl_steps", int, 128, 1, 4096, "minimum ray steps across the volume (S = cl_steps * |AB|)"),
    ("cl_shadowSteps", int, 20, 1, 1024, "constant shadow steps"),
    ("cl_distanceScale", float, 1.0, 0.1, 16.0, "distance-function step multiplier"),
    ("cl_sampleRange", float, 1.0, 0.25, 8.0, "normal sampling radius, in voxels"))
QUALITY_LADDER = (32, 64, 128, 256, 512)


def _window_text(transfer: TransferFunction) -> str:
    return _span(transfer.low, transfer.high)


def _span(low: float, high: float) -> str:
    return f"{low:g}..{high:g}"


def _spacing_text(spacing: Spacing) -> str:
    return " ".join(f"{s:g}" for s in spacing)


def _switched(current: bool, on: int | None) -> bool:
    """A flag command's new value: toggled without an argument."""
    return (not current) if on is None else bool(on)


def register(console: Console, state: VolumeWorkspace, checks: ArgChecks) -> None:
    """The commands and cvars, and their checks for demos (`checks`)."""
    ctx = Ctx(console, state)
    # Their voxel and slice checks read the volume's size: after any of these a demo's checker cannot know it.
    checks.reshaped_by("volume", "new", "load", "sample", "rotate", "undo", "redo")
    reg = console.registry
    for name, kind, default, lo, hi, text in TRACER_CVARS:
        reg.add_cvar(Cvar(name, kind, default, text, min=lo, max=hi, archive=True))
    reg.add_cvar(Cvar("brush_round", bool, True, "Round brush (0: square)", archive=True))
    reg.add_cvar(Cvar("brush_size", int, 1, "Brush size in voxels (keys 1-4)", min=1, max=64, archive=True))
    reg.add_cvar(Cvar("fill_tolerance", int, 0, "The painter's fill takes in voxels whose every channel is within "
                      "this of the clicked one's (0: one exact colour)", min=0, max=255, archive=True))
    volume_labels.add_cvars(reg)
    mode = Cvar("r_scalarMode", str, "colour", "How a scalar volume is drawn: " + ", ".join(SCALAR_MODES) + " (colour: "
                "the F-modes, on the window's colours); a scalar volume opens in " + SCALAR_DEFAULT,
                choices=SCALAR_MODES)
    mode.on_change.append(partial(_scalar_mode_changed, ctx))
    reg.add_cvar(mode)
    reg.add_cvar(Cvar("r_mipAttenuation", float, MIP_ATTENUATION, "attenuated_mip: how fast the values behind a "
                      "bright one fade, per voxel of window-high value passed (vispy's attenuation)", min=0.0,
                      max=10.0, archive=True))
    console.batch_listeners.append(ScriptSteps(state))
    # scene.load and scene.save in this workspace are load and save; a demo's snapshot is an .r3 (an .npy of a
    # scalar volume, its labels beside it); an autosave of a scalar volume keeps its window in a .nrrd; File > New
    # makes an empty volume of the same size
    state.files = SceneFiles(partial(load, ctx), partial(write, ctx), (".r3", *(s for s in SUPPORTED if s != ".r3")),
                             new=partial(new_same_size, ctx), replacing=("new", "sample"), verbs=("load", "save"),
                             keeping=partial(kept_suffix, ctx), read_only=READ_ONLY,
                             claims=partial(is_volume_source, max_bytes=voxels_model.MAX_BYTES),
                             beside=(LABELS_SUFFIX,))
    COMMANDS.register(console.registry, ctx, checks)
    volume_labels.COMMANDS.register(console.registry, ctx, checks)


class ScriptSteps:
    """A console batch listener: the volume's edits of one script undo as one step."""

    def __init__(self, state: VolumeWorkspace) -> None:
        self.state = state
        self.mark = 0  # the history's edit count when the script started

    def __call__(self, starting: bool) -> None:
        history = self.state.volume.history
        if starting:
            self.mark = history.edits
        else:
            history.group_since(self.mark)


# --- replacing the volume: new, load, sample --------------------------------------------------------------------


def _replace(ctx: Ctx, data: np.ndarray, what: str, step: str, transfer: TransferFunction | None = None,
             loaded: bool = True, spacing: Spacing | None = None, notes: tuple[str, ...] = (),
             labels: Labels | None = None) -> None:
    """An RGBA volume, or the scalars of a 16-bit or float file, coloured through `transfer` (the file's) or
    the default window, with `labels` over them (its labels file's), as the undo step `step`, its voxels
    `spacing` apart (1 1 1 if None). `data` is the command's own (a fresh array) to hand over. A loaded volume
    (a file, a sample) opens the painter on its middle slice; a new one keeps the slice. `notes`: what the reader
    says of the file."""
    state, volume = ctx.state, ctx.state.volume
    spacing = spacing or DEFAULT_SPACING
    if data.ndim == 3:
        volume.replace_scalars(data, transfer, name=step, copy=False, spacing=spacing, labels=labels)
    else:
        volume.replace(data, step, spacing)
    state.view.iso = None  # the new values' window middle
    mode = ctx.console.registry.cvars.get("r_scalarMode")  # a bare context (a command run alone) has no cvars
    if mode is not None:
        mode.set(SCALAR_DEFAULT if volume.voxels.scalars is not None else "colour", trusted=ctx.console.trusted)
    if loaded:
        state.middle_slice()
    else:
        state.clamp_slice()
    shown = "" if spacing == DEFAULT_SPACING else f", spacing {_spacing_text(spacing)}"
    ctx.console.print(f"{what}: {'x'.join(map(str, volume.voxels.size))}{shown}")
    for note in notes:
        ctx.console.print(f"  {note}")
    if (scalars := volume.voxels.scalars) is not None:
        chosen = ("kept in the file" if transfer is not None else
                  "percentiles {:g}..{:g} of the values above the minimum".format(*PERCENTILES))
        ctx.console.print(f"{scalars.values.dtype} scalars, window {_window_text(scalars.transfer)} ({chosen}), "
                          f"{scalars.transfer.colormap}; vol.window and vol.colormap change it; drawn as "
                          f"{SCALAR_DEFAULT} (r_scalarMode; vol.iso VALUE draws a surface)")


def volume_files(ctx: Ctx, prefix: str) -> list[str]:
    return files.complete(prefix, SUPPORTED)


@COMMANDS.command("new", "w:int h:int d:int", "Make an empty (transparent) 3D raster image", allow=SCRIPTS)
def new(ctx: Ctx, w: int, h: int, d: int) -> None:
    _replace(ctx, transparent(w, h, d), "new volume", "New Volume", loaded=False)


def new_same_size(ctx: Ctx) -> None:
    """File > New: an empty volume of the size shown."""
    new(ctx, *ctx.state.volume.voxels.size)


@COMMANDS.command("load", "path [more...]", "Open a 3D raster image (.r3, name_%i.png series, .npy, .npz, .tif, "
                  ".nrrd, .nii, .nii.gz, DICOM: a series' folder or files; 16-bit and float ones through a window); "
                  "`load FILE.npz NAME` opens one of the file's arrays, `load FILE FILE...` the files of one DICOM "
                  "series", completer=volume_files, allow=SCRIPTS)
def load(ctx: Ctx, path: str, more: list[str] | None = None) -> str:
    more = more or []
    found = files.find(path, ctx.console) if "%" not in path else None  # a series names its slices
    source = found or files.readable(ctx.console, path)
    if source.is_dir():  # a DICOM series: its files lie below the folder, which a script may read only in its places
        files.readable(ctx.console, str(source / "*"))
    npz = suffix_of(source) == ".npz"
    if npz and len(more) > 1:
        raise CommandError(f"an .npz file's array is chosen by one name: load {path} NAME")
    try:  # the model's limit, before reading
        if more and not npz:
            others = [files.readable(ctx.console, name) for name in more]
            read = read_dicom_files([source, *others], max_bytes=voxels_model.MAX_BYTES)
        else:
            read = read_volume_file(source, max_bytes=voxels_model.MAX_BYTES, array=more[0] if more else None)
    except FormatError as exc:
        raise CommandError(str(exc)) from None
    labels = volume_labels.beside(ctx, source, read.data.shape) if read.data.ndim == 3 else None
    what = f"loaded {source}" + (f" and {len(more)} more" if more and not npz else "")
    _replace(ctx, read.data, what, "Load Volume", read.transfer, spacing=read.spacing, notes=read.notes,
             labels=labels)
    if labels is not None:
        volume_labels.say_loaded(ctx, source)
    return str(source)


def _as_scalars(ctx: Ctx, path: str) -> bool:
    """A scalar volume saves its scalars in the formats that hold them, its colours in the others."""
    return ctx.state.volume.voxels.scalars is not None and Path(path).suffix.lower() in SCALAR_SUFFIXES


def kept_suffix(ctx: Ctx) -> str:
    """What an autosave keeps the volume in: a scalar volume's window in a .nrrd."""
    return WINDOW_SUFFIXES[0] if ctx.state.volume.voxels.scalars is not None else ".r3"


def write(ctx: Ctx, path: str) -> None:
    voxels = ctx.state.volume.voxels
    try:
        if _as_scalars(ctx, path):
            write_volume(path, voxels.scalars.values, voxels.scalars.transfer, spacing=voxels.spacing)
            volume_labels.write_beside(voxels.labels, path)
        else:
            write_volume(path, voxels.data, spacing=voxels.spacing)
    except FormatError as exc:
        raise CommandError(str(exc)) from None


@COMMANDS.command("save", "path", "Save the 3D raster image (format from the name; atomically); a scalar volume "
                  "saves its scalars to .npy, .nrrd and .tif (and its labels beside them, name.seg.nrrd), its "
                  "colours to .r3 and image series", recorded=False,
                  completer=volume_files, allow=SCRIPTS)
def save(ctx: Ctx, path: str) -> str:
    target = files.writable(ctx.console, path)
    try:
        write(ctx, target)
    except OSError as exc:
        raise CommandError(str(exc)) from None
    voxels, say = ctx.state.volume.voxels, ctx.console.print
    scalars = voxels.scalars
    if voxels.spacing != DEFAULT_SPACING and suffix_of(target) not in SPACING_SUFFIXES:
        say(f"the spacing {_spacing_text(voxels.spacing)} is not kept in {target.name} "
            f"({', '.join(SPACING_SUFFIXES)} keeps it)")
    if scalars is None:
        say(f"saved {target}")
    elif target.suffix.lower() in WINDOW_SUFFIXES:
        say(f"saved {target}: the {scalars.values.dtype} scalars and their window "
            f"{_window_text(scalars.transfer)}, {scalars.transfer.colormap}")
    elif _as_scalars(ctx, target):
        say(f"saved {target}: the {scalars.values.dtype} scalars (the window is not kept in the file; "
            f"{', '.join(WINDOW_SUFFIXES)} keeps it)")
    else:
        say(f"saved {target}: the colours of window {_window_text(scalars.transfer)} (the scalars "
            "are not kept in the file)")
    volume_labels.say_saved(ctx, target, _as_scalars(ctx, target))
    return str(target)


@COMMANDS.check("sample")
def sample_args(ctx: Ctx, name: str, size: int = 64) -> tuple[str, int]:
    if name not in SAMPLES:
        raise CommandError(f"no sample {name!r}; choose one of {', '.join(SAMPLES)}")
    if not 8 <= size <= MAX_SAMPLE:
        raise CommandError(f"sample size must be within 8..{MAX_SAMPLE}, got {size}")
    return name, size


def sample_names(ctx: Ctx, prefix: str) -> list[str]:
    return [s for s in SAMPLES if s.startswith(prefix)]


@COMMANDS.command("sample", "name [size:int]", "Load a sample volume: " + ", ".join(SAMPLES),
                  completer=sample_names, allow=SCRIPTS)
def sample(ctx: Ctx, *args) -> None:
    name, size = sample_args(ctx, *args)
    _replace(ctx, make(name, size), f"sample {name}", "Sample")


# --- painting -----------------------------------------------------------------------------------------------


@COMMANDS.check("voxel", "volume")
def voxel_args(ctx: Ctx, x: int, y: int, z: int, r: int, g: int, b: int, a: int):
    ctx.state.volume.voxels.pick(x, y, z)  # reading refuses a voxel outside the volume
    return x, y, z, _rgba(r, g, b, a)


@COMMANDS.command("voxel", "x:int y:int z:int r:int g:int b:int a:int", "Set one voxel", allow=SCRIPTS)
def voxel(ctx: Ctx, *args: int) -> None:
    ctx.state.volume.paint.set_voxel(*voxel_args(ctx, *args))


@COMMANDS.check("stroke", "volume")
def stroke_args(ctx: Ctx, axis, index, size, r, g, b, a, coords):
    check_brush(ctx.state.volume.voxels, axis, index, size)
    return axis, index, size, _rgba(r, g, b, a), _points(coords)


def _round_brush(ctx: Ctx) -> bool:
    return round_brush(ctx.console)


@COMMANDS.command("stroke", "axis slice:int size:int r:int g:int b:int a:int coords:int...",
                  "Paint a gap-free brush stroke through the points x1 y1 [x2 y2 ...] of a slice (a = 0 erases)",
                  allow=SCRIPTS)
def stroke(ctx: Ctx, *args) -> None:
    ctx.state.volume.paint.stroke(*stroke_args(ctx, *args), round_brush=_round_brush(ctx))


@COMMANDS.command("stroke.preview", "axis slice:int size:int r:int g:int b:int a:int coords:int...",
                  "Show a stroke in progress (the painter, while the mouse is down); not recorded", recorded=False,
                  quiet=True, allow=SCRIPTS)
def stroke_preview(ctx: Ctx, *args) -> None:
    ctx.state.volume.paint.preview_stroke(*stroke_args(ctx, *args), round_brush=_round_brush(ctx))


@COMMANDS.command("stroke.cancel", "", "Drop a stroke in progress", recorded=False, allow=SCRIPTS)
def stroke_cancel(ctx: Ctx) -> None:
    ctx.state.volume.history.clear_preview()


@COMMANDS.check("fill", "volume")
def fill_args(ctx: Ctx, axis: str, index: int, u: int, v: int, r: int, g: int, b: int, a: int, tolerance: int = 0):
    ctx.state.volume.voxels.voxel_of(_axis(axis), index, u, v)  # refuses a point outside the slice
    return axis, index, u, v, _rgba(r, g, b, a), _tolerance(tolerance)


@COMMANDS.command("fill", "axis slice:int x:int y:int r:int g:int b:int a:int [tolerance:int]",
                  "Flood-fill the region around (x, y) within a slice whose every channel is within tolerance "
                  "(0..255, default 0: one exact colour) of the colour at (x, y)", allow=SCRIPTS)
def fill(ctx: Ctx, *args) -> None:
    ctx.state.volume.paint.fill(*fill_args(ctx, *args))


@COMMANDS.check("rotate")
def rotate_axis(ctx: Ctx, axis: str) -> str:
    return _axis(axis)


def axis_names(ctx: Ctx, prefix: str) -> list[str]:
    return [a for a in AXES if a.startswith(prefix)]


@COMMANDS.command("rotate", "axis", "Rotate the volume 90 degrees about x, y or z (keys 5/6/7)",
                  completer=axis_names, allow=SCRIPTS)
def rotate(ctx: Ctx, axis: str) -> None:
    ctx.state.volume.rotate(_axis(axis))
    ctx.state.clamp_slice()


@COMMANDS.command("smooth", "", "Smooth the volume with a 3x3x3 box filter (key m)", allow=SCRIPTS)
def smooth(ctx: Ctx) -> None:
    ctx.state.volume.paint.smooth()


@COMMANDS.check("pick", "volume")
def picked(ctx: Ctx, x: int, y: int, z: int) -> tuple[int, int, int, int]:
    return ctx.state.volume.voxels.pick(x, y, z)


@COMMANDS.command("pick", "x:int y:int z:int", "Eyedropper: make the voxel's colour the brush colour (on a scan, "
                  "its label the brush label)", allow=SCRIPTS)
def pick(ctx: Ctx, x: int, y: int, z: int) -> None:
    view = ctx.state.view
    colour = picked(ctx, x, y, z)
    if ctx.state.volume.voxels.labels is not None:
        volume_labels.pick_label(ctx, x, y, z)
        return
    view.brush = colour
    ctx.console.print(f"brush colour {' '.join(map(str, view.brush))}")


@COMMANDS.check("brush.color")
def brush_rgba(ctx: Ctx, r: int, g: int, b: int, a: int) -> tuple[int, int, int, int]:
    return _rgba(r, g, b, a)


@COMMANDS.command("brush.color", "r:int g:int b:int a:int", "Set the brush colour (a = 0 erases)", allow=SCRIPTS)
def brush_color(ctx: Ctx, r: int, g: int, b: int, a: int) -> None:
    ctx.state.view.brush = brush_rgba(ctx, r, g, b, a)


# --- the slice and the 3D view ------------------------------------------------------------------------------


@COMMANDS.check("slice", "volume")
def slice_args(ctx: Ctx, axis: str, index: int) -> tuple[str, int]:
    depth = ctx.state.volume.voxels.depth(_axis(axis))
    if not 0 <= index < depth:
        raise CommandError(f"slice {index} is outside 0..{depth - 1} along {axis}")
    return axis, index


@COMMANDS.command("slice", "axis index:int", "Edit this slice in the painter", allow=SCRIPTS)
def slice_(ctx: Ctx, *args) -> None:
    view = ctx.state.view
    view.axis, view.index = slice_args(ctx, *args)


@COMMANDS.command("slice.step", "delta:int", "Move to a neighbouring slice, clamped (keys q/e)", allow=SCRIPTS)
def slice_step(ctx: Ctx, delta: int) -> None:
    view = ctx.state.view
    view.index = min(max(0, view.index + delta), ctx.state.volume.voxels.depth(view.axis) - 1)


@COMMANDS.command("slice.highlight", "[axis] [index:int]", "Highlight a slice in the 3D view (the slice picker)",
                  recorded=False, quiet=True, allow=SCRIPTS)
def slice_highlight(ctx: Ctx, axis: str | None = None, index: int | None = None) -> None:
    ctx.state.view.highlight = None if axis is None or index is None else (_axis(axis), index)


@COMMANDS.check("orbit")
def orbit_camera(ctx: Ctx, yaw: float, pitch: float, distance: float | None = None) -> OrbitCamera:
    cam = ctx.state.view.camera
    return OrbitCamera(yaw % 360.0, pitch, cam.distance if distance is None else distance, cam.fov)


@COMMANDS.command("orbit", "yaw:float pitch:float [distance:float]", "Place the 3D view's camera (left drag; w/s)",
                  quiet=True, allow=SCRIPTS)
def orbit(ctx: Ctx, *args: float) -> None:
    ctx.state.view.camera = orbit_camera(ctx, *args)


@COMMANDS.command("orbit.step", "dyaw:float dpitch:float [ddistance:float]", "Turn the 3D view's camera by steps",
                  allow=SCRIPTS)
def orbit_step(ctx: Ctx, dyaw: float, dpitch: float, ddistance: float = 0.0) -> None:
    cam = ctx.state.view.camera
    pitch = min(max(cam.pitch + dpitch, -85.0), 85.0)
    distance = min(max(cam.distance + ddistance, 1.0), 20.0)
    orbit(ctx, cam.yaw + dyaw, pitch, distance)


@COMMANDS.check("mode")
def mode_number(ctx: Ctx, number: int | None = None) -> int | None:
    if number is not None and number not in MODES:
        raise CommandError(f"no mode {number}; modes are 1..{len(MODES)}")
    return number


@COMMANDS.command("mode", "[number:int]", "Show or pick the ray tracer's mode (F1-F11): " +
                  "; ".join(f"{m.number} {m.name}" for m in MODES.values()), allow=SCRIPTS)
def mode(ctx: Ctx, number: int | None = None) -> None:
    view = ctx.state.view
    if mode_number(ctx, number) is None:
        ctx.console.print(f"mode {view.mode}: {MODES[view.mode].name}")
    else:
        view.mode = number


@COMMANDS.command("mode.next", "", "Cycle the ray tracer's modes (key p)", allow=SCRIPTS)
def mode_next(ctx: Ctx) -> None:
    view = ctx.state.view
    view.mode = view.mode % len(MODES) + 1


@COMMANDS.command("shadows", "[on:int]", "Shadows on or off in the Phong modes (key l toggles)", allow=SCRIPTS)
def shadows(ctx: Ctx, on: int | None = None) -> None:
    ctx.state.view.shadows = _switched(ctx.state.view.shadows, on)


@COMMANDS.command("stereo", "[on:int]", "Anaglyph stereo, red/cyan (key t toggles)", allow=SCRIPTS)
def stereo(ctx: Ctx, on: int | None = None) -> None:
    ctx.state.view.stereo = _switched(ctx.state.view.stereo, on)


@COMMANDS.command("magnify", "[on:int]", "Twice the magnification (key x toggles)", allow=SCRIPTS)
def magnify(ctx: Ctx, on: int | None = None) -> None:
    ctx.state.view.magnify = _switched(ctx.state.view.magnify, on)


@COMMANDS.command("wireframe", "[on:int]", "Draw the box's edges (key f toggles)", allow=SCRIPTS)
def wireframe(ctx: Ctx, on: int | None = None) -> None:
    ctx.state.view.wireframe = _switched(ctx.state.view.wireframe, on)


@COMMANDS.command("quality.next", "", "Step cl_steps through 32, 64, 128, 256, 512 (key k)", allow=SCRIPTS)
def quality_next(ctx: Ctx) -> None:
    steps = ctx.console.registry.cvars["cl_steps"]
    steps.set(str(next((s for s in QUALITY_LADDER if s > steps.value), QUALITY_LADDER[0])))
    ctx.console.print(f"cl_steps {steps.value}")


@COMMANDS.command("light", "x:float y:float z:float", "Place the first light (world units; key z moves it)",
                  allow=SCRIPTS)
def light(ctx: Ctx, x: float, y: float, z: float) -> None:
    ctx.state.view.light = (x, y, z)


@COMMANDS.command("light.orbit", "degrees:float", "Turn the first light about the vertical axis (key z)",
                  allow=SCRIPTS)
def light_orbit(ctx: Ctx, degrees: float) -> None:
    view = ctx.state.view
    x, y, z = view.light
    a = math.radians(degrees)
    view.light = (x * math.cos(a) + z * math.sin(a), y, -x * math.sin(a) + z * math.cos(a))


# --- scalar volumes: the transfer function ---------------------------------------------------------------


@COMMANDS.check("vol.window")
def window_args(ctx: Ctx, low: float | None = None, high: float | None = None) -> tuple[float, float] | None:
    if high is None:
        if low is not None:
            raise CommandError("give the window's low and high values, or neither to show it")
        return None
    return check_window(low, high)


@COMMANDS.command("vol.window", "[low:float] [high:float]", "Show or set a scalar volume's window: values at low "
                  "and below are transparent, at high and above opaque, the colour map in between", allow=SCRIPTS)
def window(ctx: Ctx, *args: float) -> None:
    bounds = window_args(ctx, *args)
    volume = ctx.state.volume
    scalars = volume.voxels.require_scalars()
    if bounds is None:
        ctx.console.print(f"window {_window_text(scalars.transfer)} of {scalars.values.dtype} scalars "
                          f"{_span(*value_range(scalars.values))}, colour map {scalars.transfer.colormap}")
    else:
        low, high = bounds
        volume.set_transfer(replaced(scalars.transfer, low=low, high=high))


@COMMANDS.command("vol.window.auto", "", "Set a scalar volume's window to percentiles {:g}..{:g} of its values "
                  "above the minimum (what loading it chose)".format(*PERCENTILES), allow=SCRIPTS)
def window_auto(ctx: Ctx) -> None:
    volume = ctx.state.volume
    scalars = volume.voxels.require_scalars()
    low, high = default_window(scalars.values)
    volume.set_transfer(replaced(scalars.transfer, low=low, high=high))


@COMMANDS.check("vol.colormap")
def colormap_name(ctx: Ctx, name: str) -> str:
    return check_colormap(name)


def colormap_names(ctx: Ctx, prefix: str) -> list[str]:
    return [c for c in COLORMAPS if c.startswith(prefix)]


@COMMANDS.command("vol.colormap", "name", "Colour a scalar volume's window with " + ", ".join(COLORMAPS),
                  completer=colormap_names, allow=SCRIPTS)
def colormap(ctx: Ctx, name: str) -> None:
    volume = ctx.state.volume
    scalars = volume.voxels.require_scalars()
    volume.set_transfer(replaced(scalars.transfer, colormap=name))  # the model checks the name


def _curve_text(points) -> str:
    return " ".join(f"{number(v)} {number(a)}" for v, a in points)


@COMMANDS.check("vol.opacity")
def opacity_args(ctx: Ctx, numbers: list[float] | None = None) -> OpacityPoints | None:
    if not numbers:
        return None
    if len(numbers) % 2:
        raise CommandError("give the opacity curve as pairs, value opacity: v0 a0 [v1 a1 ...]; got "
                           + count(len(numbers), "number"))
    return check_opacity_points(zip(numbers[0::2], numbers[1::2]))


def _translucent_note(ctx: Ctx) -> None:
    mode = ctx.console.registry.cvars.get("r_scalarMode")
    if mode is not None and mode.value != "translucent":
        ctx.console.print(f"the opacity curve draws in r_scalarMode translucent (now {mode.value})")


@COMMANDS.command("vol.opacity", "[points:float...]", "Show or set a scalar volume's opacity curve, the translucent "
                  "mode's: pairs of value (data units, increasing) and opacity per voxel of ray (0..1), linear between "
                  "them and constant beyond the ends; vol.opacity.reset goes back to the ramp over the window",
                  allow=SCRIPTS)
def opacity(ctx: Ctx, numbers: list[float] | None = None) -> None:
    points = opacity_args(ctx, numbers)
    volume = ctx.state.volume
    transfer = volume.voxels.require_scalars().transfer
    if points is None:
        own = "set" if transfer.points is not None else "the ramp over the window, until one is set"
        ctx.console.print(f"opacity {_curve_text(transfer.opacity())} ({own})")
    elif volume.set_transfer(replaced(transfer, points=points), "Set Opacity"):
        _translucent_note(ctx)


@COMMANDS.command("vol.opacity.preview", "points:float...", "Show an opacity curve being dragged in the transfer "
                  "function editor until the next edit; not recorded (vol.opacity sets it)", recorded=False, quiet=True,
                  allow=SCRIPTS)
def opacity_preview(ctx: Ctx, numbers: list[float]) -> None:
    points = opacity_args(ctx, numbers)
    volume = ctx.state.volume
    if points is None:
        raise CommandError("give the curve to show: v0 a0 [v1 a1 ...]")
    volume.preview_transfer(replaced(volume.voxels.require_scalars().transfer, points=points))


@COMMANDS.command("vol.opacity.reset", "", "Set a scalar volume's opacity curve back to the ramp over the window "
                  "(0 at low to 1 at high), what a scan opens with", allow=SCRIPTS)
def opacity_reset(ctx: Ctx) -> None:
    volume = ctx.state.volume
    volume.set_transfer(replaced(volume.voxels.require_scalars().transfer, points=None), "Reset Opacity")


@COMMANDS.check("vol.preset")
def preset_name(ctx: Ctx, name: str) -> str:
    check_preset(name)
    return name


def preset_names(ctx: Ctx, prefix: str) -> list[str]:
    return [p for p in PRESETS if p.startswith(prefix)]


@COMMANDS.command("vol.preset", "name", "Set a scalar volume's window, colour map and opacity curve at once, as 3D "
                  "Slicer's volume-rendering presets: " + ", ".join(PRESETS),
                  completer=preset_names, allow=SCRIPTS)
def preset(ctx: Ctx, name: str) -> None:
    chosen = PRESETS[preset_name(ctx, name)]
    volume = ctx.state.volume
    transfer = chosen.transfer(volume.voxels.require_scalars().values)
    volume.set_transfer(transfer, f"Preset {chosen.title}")
    ctx.console.print(f"{chosen.title}: window {_window_text(transfer)}, {transfer.colormap}, opacity "
                      f"{_curve_text(transfer.points)}")
    _translucent_note(ctx)


@COMMANDS.check("vol.spacing")
def spacing_args(ctx: Ctx, sides: list[float] | None = None) -> Spacing | None:
    if not sides:
        return None
    if len(sides) != 3:
        raise CommandError("give the spacing as three sides, sx sy sz, or none to show it")
    try:
        return check_spacing(*sides)
    except VolumeError as exc:
        raise CommandError(str(exc)) from None


@COMMANDS.command("vol.spacing", "[sides:float...]", "Show or set the voxels' spacing, sx sy sz (x, y, z; in the "
                  "file's unit, mm for scans): the box and the painter take the volume's physical shape; files "
                  "give it where they state it", allow=SCRIPTS)
def spacing(ctx: Ctx, sides: list[float] | None = None) -> None:
    chosen = spacing_args(ctx, sides)
    voxels = ctx.state.volume.voxels
    if chosen is None:
        w, h, d = voxels.size
        sx, sy, sz = voxels.spacing
        ctx.console.print(f"spacing {_spacing_text(voxels.spacing)}: the volume is {w * sx:g} x {h * sy:g} x "
                          f"{d * sz:g}")
    else:
        ctx.state.volume.set_spacing(chosen)


def _scalar_mode_changed(ctx: Ctx, cvar: Cvar) -> None:
    if cvar.value != "colour" and ctx.state.volume.voxels.scalars is None:
        ctx.console.print(f"r_scalarMode {cvar.value}: this volume has no scalars, so the F-modes draw its colours "
                          "(load a 16-bit or float file)")


@COMMANDS.command("vol.iso", "[value:float]", "Show or set a scalar volume's iso value (data units) and draw the "
                  "surface where the values first exceed it (r_scalarMode iso; lit as F5)", allow=SCRIPTS)
def iso(ctx: Ctx, value: float | None = None) -> None:
    scalars = ctx.state.volume.voxels.scalars
    if value is None:
        chosen = "set" if ctx.state.view.iso is not None else "the window's middle"
        of = (f"of {scalars.values.dtype} scalars {_span(*value_range(scalars.values))}" if scalars is not None
              else "(this volume has no scalars)")
        ctx.console.print(f"iso {ctx.state.iso_value():g} ({chosen}) {of}")
        return
    ctx.state.view.iso = value
    ctx.console.registry.cvars["r_scalarMode"].set(ISO_MODE, trusted=ctx.console.trusted)  # says so without scalars
    if scalars is not None and not value < value_range(scalars.values)[1]:
        ctx.console.print(f"no value exceeds {value:g} (the greatest is {value_range(scalars.values)[1]:g}): "
                          "there is no surface to draw")


@COMMANDS.check("vol.background")
def background_rgba(ctx: Ctx, r: int, g: int, b: int) -> tuple[int, int, int, int]:
    return _rgba(r, g, b, 255)


@COMMANDS.command("vol.background", "r:int g:int b:int", "Background colour of the 3D view (key c)", allow=SCRIPTS)
def background(ctx: Ctx, r: int, g: int, b: int) -> None:
    ctx.state.view.background = background_rgba(ctx, r, g, b)[:3]


def render_settings(console: Console, state: VolumeWorkspace) -> TraceSettings:
    """The ray tracer's settings from the cvars and the view."""
    cvars, view = console.registry.cvars, state.view
    return TraceSettings(mode=view.mode, steps=cvars["cl_steps"].value, shadow_steps=cvars["cl_shadowSteps"].value,
                         sample_range=cvars["cl_sampleRange"].value, distance_scale=cvars["cl_distanceScale"].value,
                         shadows=view.shadows, lights=(view.light, *LIGHTS[1:]),
                         scalar_mode=cvars["r_scalarMode"].value, iso=state.iso_value(),
                         mip_attenuation=cvars["r_mipAttenuation"].value,
                         label_opacity=cvars[volume_labels.OPACITY].value)
