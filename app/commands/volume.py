"""The raster editor's verbs (seed 003, Tex3Dtrace). Names and arguments are fixed: scripts and outside
tests rely on them. Colour components are 0-255 integers; slices are (axis, index) with (u, v) inside."""
from __future__ import annotations

import math
from dataclasses import replace as replaced
from pathlib import Path

from app.console import files
from app.console.console import Console
from app.console.demo import ArgChecks
from app.console.registry import SCRIPTS, CommandError, Cvar
from app.io.volume_formats import (SCALAR_SUFFIXES, SUPPORTED, WINDOW_SUFFIXES, FormatError, read_volume_file,
                                   write_volume)
from app.model.volume import volume as volume_model
from app.model.camera3d import OrbitCamera
from app.model.volume.render_modes import LIGHTS, MODES, TraceSettings
from app.model.volume.volume import AXES, MAX_COORD, MAX_SIDE, Volume
from app.model.volume.samples import SAMPLES, make
from app.model.volume.scalars import (COLORMAPS, PERCENTILES, TransferFunction, check_colormap, check_window,
                                      default_window, value_range)
from app.model.volume.workspace import VolumeWorkspace
from app.model.workspace import SceneFiles

MAX_SAMPLE = 512


def _rgba(r: int, g: int, b: int, a: int) -> tuple[int, int, int, int]:
    rgba = (r, g, b, a)
    if not all(0 <= c <= 255 for c in rgba):
        raise CommandError(f"colour components must be 0..255, got {' '.join(map(str, rgba))}")
    return rgba


def _axis(axis: str) -> str:
    if axis not in AXES:
        raise CommandError(f"axis must be x, y or z, got {axis!r}")
    return axis


def _tolerance(tolerance: int) -> int:
    if not 0 <= tolerance <= 255:
        raise CommandError(f"fill tolerance must be within 0..255, got {tolerance}")
    return tolerance


def _points(coords: list[int]) -> list[tuple[int, int]]:
    if not coords or len(coords) % 2:
        raise CommandError("give the stroke's points as x1 y1 [x2 y2 ...]")
    if max(map(abs, coords)) > MAX_COORD:
        raise CommandError(f"stroke points must be within -{MAX_COORD}..{MAX_COORD}")
    return list(zip(coords[0::2], coords[1::2]))


def register(console: Console, state: VolumeWorkspace, checks: ArgChecks) -> None:
    reg = console.registry.scoped(state.name)
    view = state.view
    # Their voxel and slice checks read the volume's size: after any of these a demo's checker cannot know it.
    checks.reshaped_by("volume", "new", "load", "sample", "rotate", "undo", "redo")
    volume_files = lambda p: files.complete(p, SUPPORTED)  # noqa: E731
    # The seed's ray-tracer variables (default.cfg sets them too): typed and bounded here.
    for name, kind, default, lo, hi, text in (
            ("cl_steps", int, 128, 1, 4096, "minimum ray steps across the volume (S = cl_steps * |AB|)"),
            ("cl_shadowSteps", int, 20, 1, 1024, "constant shadow steps"),
            ("cl_distanceScale", float, 1.0, 0.1, 16.0, "distance-function step multiplier"),
            ("cl_sampleRange", float, 1.0, 0.25, 8.0, "normal sampling radius, in voxels")):
        reg.add_cvar(Cvar(name, kind, default, text, min=lo, max=hi, archive=True))
    brush_round = reg.add_cvar(Cvar("brush_round", bool, True, "Round brush (0: square)", archive=True))
    reg.add_cvar(Cvar("brush_size", int, 1, "Brush size in voxels (keys 1-4)", min=1, max=64, archive=True))
    reg.add_cvar(Cvar("fill_tolerance", int, 0, "The painter's fill takes in voxels whose every channel is within "
                      "this of the clicked one's (0: one exact colour)", min=0, max=255, archive=True))
    batch = {"mark": 0}

    def on_batch(starting: bool) -> None:
        if starting:
            batch["mark"] = volume().edits
        else:
            volume().group_since(batch["mark"])

    console.batch_listeners.append(on_batch)

    def volume() -> Volume:
        return state.volume

    def replace(data, what: str, step: str, transfer: TransferFunction | None = None, loaded: bool = True) -> None:
        """An RGBA volume, or the scalars of a 16-bit or float file, coloured through `transfer` (the file's) or
        the default window, as the undo step `step`. `data` is the command's own (a fresh array) to hand over.
        A loaded volume (a file, a sample) opens the painter on its middle slice; a new one keeps the slice."""
        if data.ndim == 3:
            volume().replace_scalars(data, transfer, name=step, copy=False)
        else:
            volume().replace(data, step)
        if loaded:
            state.middle_slice()
        else:
            state.clamp_slice()
        console.print(f"{what}: {'x'.join(map(str, volume().size))}")
        if (scalars := volume().scalars) is not None:
            chosen = ("kept in the file" if transfer is not None else
                      "percentiles {:g}..{:g} of the values above the minimum".format(*PERCENTILES))
            console.print(f"{scalars.values.dtype} scalars, window {_window_text(scalars.transfer)} ({chosen}), "
                          f"{scalars.transfer.colormap}; vol.window and vol.colormap change it")

    def edit(change, *args, **kwargs) -> None:
        """A voxel edit; on a scalar volume it bakes the window into the colours, which the user should know."""
        scalars = volume().scalars
        change(*args, **kwargs)
        if scalars is None or volume().scalars is not None:
            return
        if volume().undo_depth:  # the edit's step, holding the scalars
            console.print("the edit baked the window into the colours: the scalars are set aside; undo it to "
                          "change the window again")
        else:
            console.print(f"the edit baked the window into the colours, and the scalars ({scalars.nbytes >> 20} MiB) "
                          "do not fit the undo history: load the file again to window it")

    @reg.command("new", "w:int h:int d:int", "Make an empty (transparent) 3D raster image", allow=SCRIPTS)
    def new(w: int, h: int, d: int) -> None:
        replace(Volume.new(w, h, d).data, "new volume", "New Volume", loaded=False)

    @reg.command("load", "path", "Open a 3D raster image (.r3, name_%i.png series, .npy, .tif, .nrrd; 16-bit and "
                 "float ones through a window)",
                 completer=volume_files, allow=SCRIPTS)
    def load(path: str) -> str:
        found = files.find(path, console) if "%" not in path else None  # a series names its slices
        source = found or files.readable(console, path)
        try:
            read = read_volume_file(source, max_bytes=volume_model.MAX_BYTES)  # the model's limit, before reading
        except FormatError as exc:
            raise CommandError(str(exc)) from None
        replace(read.data, f"loaded {source}", "Load Volume", read.transfer)
        return str(source)

    def as_scalars(path: str) -> bool:
        """A scalar volume saves its scalars in the formats that hold them, its colours in the others."""
        return volume().scalars is not None and Path(path).suffix.lower() in SCALAR_SUFFIXES

    def write(path: str) -> None:
        scalars = volume().scalars
        try:
            if as_scalars(path):
                write_volume(path, scalars.values, scalars.transfer)
            else:
                write_volume(path, volume().data)
        except FormatError as exc:
            raise CommandError(str(exc)) from None

    @reg.command("save", "path", "Save the 3D raster image (format from the name; atomically); a scalar volume "
                 "saves its scalars to .npy, .nrrd and .tif, its colours to .r3 and image series", recorded=False,
                 completer=volume_files, allow=SCRIPTS)
    def save(path: str) -> str:
        target = files.writable(console, path)
        try:
            write(target)
        except OSError as exc:
            raise CommandError(str(exc)) from None
        scalars = volume().scalars
        if scalars is None:
            console.print(f"saved {target}")
        elif target.suffix.lower() in WINDOW_SUFFIXES:
            console.print(f"saved {target}: the {scalars.values.dtype} scalars and their window "
                          f"{_window_text(scalars.transfer)}, {scalars.transfer.colormap}")
        elif as_scalars(target):
            console.print(f"saved {target}: the {scalars.values.dtype} scalars (the window is not kept in the file; "
                          f"{', '.join(WINDOW_SUFFIXES)} keeps it)")
        else:
            console.print(f"saved {target}: the colours of window {_window_text(scalars.transfer)} (the scalars "
                          "are not kept in the file)")
        return str(target)

    # scene.load and scene.save in this workspace are load and save; a demo's snapshot is an .r3 (an .npy of a
    # scalar volume); an autosave of a scalar volume keeps its window in a .nrrd; File > New makes an empty volume
    # of the same size
    state.files = SceneFiles(load, write, (".r3", *(s for s in SUPPORTED if s != ".r3")),
                             new=lambda: new(*volume().size), replacing=("new", "sample"), verbs=("load", "save"),
                             keeping=lambda: WINDOW_SUFFIXES[0] if volume().scalars is not None else ".r3")

    @checks.add("sample")
    def sample_args(name: str, size: int = 64) -> tuple[str, int]:
        if name not in SAMPLES:
            raise CommandError(f"no sample {name!r}; choose one of {', '.join(SAMPLES)}")
        if not 8 <= size <= MAX_SAMPLE:
            raise CommandError(f"sample size must be within 8..{MAX_SAMPLE}, got {size}")
        return name, size

    @reg.command("sample", "name [size:int]", "Load a sample volume: " + ", ".join(SAMPLES),
                 completer=lambda p: [s for s in SAMPLES if s.startswith(p)], allow=SCRIPTS)
    def sample(*args) -> None:
        name, size = sample_args(*args)
        replace(make(name, size), f"sample {name}", "Sample")

    @checks.add("voxel", "volume")
    def voxel_args(x: int, y: int, z: int, r: int, g: int, b: int, a: int):
        volume().pick(x, y, z)  # reading refuses a voxel outside the volume
        return x, y, z, _rgba(r, g, b, a)

    @reg.command("voxel", "x:int y:int z:int r:int g:int b:int a:int", "Set one voxel", allow=SCRIPTS)
    def voxel(*args: int) -> None:
        edit(volume().set_voxel, *voxel_args(*args))

    @checks.add("stroke", "volume")
    def stroke_args(axis, index, size, r, g, b, a, coords):
        volume().slice(_axis(axis), index)  # refuses an index past the depth
        if not 1 <= size <= MAX_SIDE:
            raise CommandError(f"brush size must be within 1..{MAX_SIDE}, got {size}")
        return axis, index, size, _rgba(r, g, b, a), _points(coords)

    @reg.command("stroke", "axis slice:int size:int r:int g:int b:int a:int coords:int...",
                 "Paint a gap-free brush stroke through the points x1 y1 [x2 y2 ...] of a slice (a = 0 erases)",
                 allow=SCRIPTS)
    def stroke(axis, index, size, r, g, b, a, coords) -> None:
        edit(volume().stroke, *stroke_args(axis, index, size, r, g, b, a, coords), round_brush=brush_round.value)

    @reg.command("stroke.preview", "axis slice:int size:int r:int g:int b:int a:int coords:int...",
                 "Show a stroke in progress (the painter, while the mouse is down); not recorded", recorded=False,
                 quiet=True, allow=SCRIPTS)
    def stroke_preview(axis, index, size, r, g, b, a, coords) -> None:
        volume().preview_stroke(*stroke_args(axis, index, size, r, g, b, a, coords), round_brush=brush_round.value)

    @reg.command("stroke.cancel", "", "Drop a stroke in progress", recorded=False, allow=SCRIPTS)
    def stroke_cancel() -> None:
        volume().clear_preview()

    @checks.add("fill", "volume")
    def fill_args(axis: str, index: int, u: int, v: int, r: int, g: int, b: int, a: int, tolerance: int = 0):
        volume().voxel_of(_axis(axis), index, u, v)  # refuses a point outside the slice
        return axis, index, u, v, _rgba(r, g, b, a), _tolerance(tolerance)

    @reg.command("fill", "axis slice:int x:int y:int r:int g:int b:int a:int [tolerance:int]",
                 "Flood-fill the region around (x, y) within a slice whose every channel is within tolerance "
                 "(0..255, default 0: one exact colour) of the colour at (x, y); on a scalar volume, of the "
                 "window's colours", allow=SCRIPTS)
    def fill(*args) -> None:
        edit(volume().fill, *fill_args(*args))

    checks.add("rotate")(_axis)

    @reg.command("rotate", "axis", "Rotate the volume 90 degrees about x, y or z (keys 5/6/7)",
                 completer=lambda p: [a for a in AXES if a.startswith(p)], allow=SCRIPTS)
    def rotate(axis: str) -> None:
        volume().rotate(_axis(axis))
        state.clamp_slice()

    @reg.command("smooth", "", "Smooth the volume with a 3x3x3 box filter (key m)", allow=SCRIPTS)
    def smooth() -> None:
        edit(volume().smooth)

    checks.add("pick", "volume")(lambda x, y, z: volume().pick(x, y, z))

    @reg.command("pick", "x:int y:int z:int", "Eyedropper: make the voxel's colour the brush colour", allow=SCRIPTS)
    def pick(x: int, y: int, z: int) -> None:
        view.brush = volume().pick(x, y, z)
        console.print(f"brush colour {' '.join(map(str, view.brush))}")

    checks.add("brush.color")(_rgba)

    @reg.command("brush.color", "r:int g:int b:int a:int", "Set the brush colour (a = 0 erases)", allow=SCRIPTS)
    def brush_color(r: int, g: int, b: int, a: int) -> None:
        view.brush = _rgba(r, g, b, a)

    @checks.add("slice", "volume")
    def slice_args(axis: str, index: int) -> tuple[str, int]:
        depth = volume().depth(_axis(axis))
        if not 0 <= index < depth:
            raise CommandError(f"slice {index} is outside 0..{depth - 1} along {axis}")
        return axis, index

    @reg.command("slice", "axis index:int", "Edit this slice in the painter", allow=SCRIPTS)
    def slice_(*args) -> None:
        view.axis, view.index = slice_args(*args)

    @reg.command("slice.step", "delta:int", "Move to a neighbouring slice, clamped (keys q/e)", allow=SCRIPTS)
    def slice_step(delta: int) -> None:
        view.index = min(max(0, view.index + delta), volume().depth(view.axis) - 1)

    @reg.command("slice.highlight", "[axis] [index:int]", "Highlight a slice in the 3D view (the slice picker)",
                 recorded=False, quiet=True, allow=SCRIPTS)
    def slice_highlight(axis: str | None = None, index: int | None = None) -> None:
        view.highlight = None if axis is None or index is None else (_axis(axis), index)

    @checks.add("orbit")
    def orbit_camera(yaw: float, pitch: float, distance: float | None = None) -> OrbitCamera:
        cam = view.camera
        return OrbitCamera(yaw % 360.0, pitch, cam.distance if distance is None else distance, cam.fov)

    @reg.command("orbit", "yaw:float pitch:float [distance:float]", "Place the 3D view's camera (left drag; w/s)",
                 quiet=True, allow=SCRIPTS)
    def orbit(*args: float) -> None:
        view.camera = orbit_camera(*args)

    @reg.command("orbit.step", "dyaw:float dpitch:float [ddistance:float]", "Turn the 3D view's camera by steps",
                 allow=SCRIPTS)
    def orbit_step(dyaw: float, dpitch: float, ddistance: float = 0.0) -> None:
        cam = view.camera
        pitch = min(max(cam.pitch + dpitch, -85.0), 85.0)
        distance = min(max(cam.distance + ddistance, 1.0), 20.0)
        orbit(cam.yaw + dyaw, pitch, distance)

    @checks.add("mode")
    def mode_number(number: int | None = None) -> int | None:
        if number is not None and number not in MODES:
            raise CommandError(f"no mode {number}; modes are 1..{len(MODES)}")
        return number

    @reg.command("mode", "[number:int]", "Show or pick the ray tracer's mode (F1-F11): " +
                 "; ".join(f"{m.number} {m.name}" for m in MODES.values()), allow=SCRIPTS)
    def mode(number: int | None = None) -> None:
        if mode_number(number) is None:
            console.print(f"mode {view.mode}: {MODES[view.mode].name}")
        else:
            view.mode = number

    @reg.command("mode.next", "", "Cycle the ray tracer's modes (key p)", allow=SCRIPTS)
    def mode_next() -> None:
        view.mode = view.mode % len(MODES) + 1

    @reg.command("shadows", "[on:int]", "Shadows on or off in the Phong modes (key l toggles)", allow=SCRIPTS)
    def shadows(on: int | None = None) -> None:
        view.shadows = (not view.shadows) if on is None else bool(on)

    def flag(name: str, attribute: str, text: str) -> None:
        @reg.command(name, "[on:int]", text, allow=SCRIPTS)
        def toggle(on: int | None = None) -> None:
            setattr(view, attribute, (not getattr(view, attribute)) if on is None else bool(on))

    flag("stereo", "stereo", "Anaglyph stereo, red/cyan (key t toggles)")
    flag("magnify", "magnify", "Twice the magnification (key x toggles)")
    flag("wireframe", "wireframe", "Draw the box's edges (key f toggles)")

    @reg.command("quality.next", "", "Step cl_steps through 32, 64, 128, 256, 512 (key k)", allow=SCRIPTS)
    def quality_next() -> None:
        ladder = (32, 64, 128, 256, 512)
        steps = reg.cvars["cl_steps"]
        steps.set(str(next((s for s in ladder if s > steps.value), ladder[0])))
        console.print(f"cl_steps {steps.value}")

    @reg.command("light", "x:float y:float z:float", "Place the first light (world units; key z moves it)",
                 allow=SCRIPTS)
    def light(x: float, y: float, z: float) -> None:
        view.light = (x, y, z)

    @reg.command("light.orbit", "degrees:float", "Turn the first light about the vertical axis (key z)", allow=SCRIPTS)
    def light_orbit(degrees: float) -> None:
        x, y, z = view.light
        a = math.radians(degrees)
        view.light = (x * math.cos(a) + z * math.sin(a), y, -x * math.sin(a) + z * math.cos(a))

    # --- scalar volumes: the transfer function ---------------------------------------------------------------

    @checks.add("vol.window")
    def window_args(low: float | None = None, high: float | None = None) -> tuple[float, float] | None:
        if high is None:
            if low is not None:
                raise CommandError("give the window's low and high values, or neither to show it")
            return None
        return check_window(low, high)

    @reg.command("vol.window", "[low:float] [high:float]", "Show or set a scalar volume's window: values at low and "
                 "below are transparent, at high and above opaque, the colour map in between", allow=SCRIPTS)
    def window(*args: float) -> None:
        bounds = window_args(*args)
        scalars = volume().require_scalars()
        if bounds is None:
            console.print(f"window {_window_text(scalars.transfer)} of {scalars.values.dtype} scalars "
                          f"{_span(*value_range(scalars.values))}, colour map {scalars.transfer.colormap}")
        else:
            low, high = bounds
            volume().set_transfer(replaced(scalars.transfer, low=low, high=high))

    @reg.command("vol.window.auto", "", "Set a scalar volume's window to percentiles {:g}..{:g} of its values above "
                 "the minimum (what loading it chose)".format(*PERCENTILES), allow=SCRIPTS)
    def window_auto() -> None:
        scalars = volume().require_scalars()
        low, high = default_window(scalars.values)
        volume().set_transfer(replaced(scalars.transfer, low=low, high=high))

    checks.add("vol.colormap")(check_colormap)

    @reg.command("vol.colormap", "name", "Colour a scalar volume's window with " + ", ".join(COLORMAPS),
                 completer=lambda p: [c for c in COLORMAPS if c.startswith(p)], allow=SCRIPTS)
    def colormap(name: str) -> None:
        scalars = volume().require_scalars()
        volume().set_transfer(replaced(scalars.transfer, colormap=name))  # the model checks the name

    checks.add("vol.background")(lambda r, g, b: _rgba(r, g, b, 255))

    @reg.command("vol.background", "r:int g:int b:int", "Background colour of the 3D view (key c)", allow=SCRIPTS)
    def background(r: int, g: int, b: int) -> None:
        view.background = _rgba(r, g, b, 255)[:3]


def _window_text(transfer: TransferFunction) -> str:
    return _span(transfer.low, transfer.high)


def _span(low: float, high: float) -> str:
    return f"{low:g}..{high:g}"


def render_settings(console: Console, state: VolumeWorkspace) -> TraceSettings:
    """The ray tracer's settings from the cvars and the view."""
    cvars, view = console.registry.cvars, state.view
    return TraceSettings(mode=view.mode, steps=cvars["cl_steps"].value, shadow_steps=cvars["cl_shadowSteps"].value,
                         sample_range=cvars["cl_sampleRange"].value, distance_scale=cvars["cl_distanceScale"].value,
                         shadows=view.shadows, lights=(view.light, *LIGHTS[1:]))
