"""Our scalar modes against vispy's Volume visual on real scans, in one run (issue 30's measure): `mip` and
`translucent`, each tool's time per frame and its error against the CPU reference (app/reference/volume_scalar.py
at a quarter voxel a step), as docs/volume.md reports them.

Both draw the same scan from the same camera at the same picture size, with steps of the same length in voxels
(vispy's relative_step_size; our cl_steps is steps a unit of texture length, so side / voxels_a_step on the side^3
cube every scan is fitted into), the same window (vispy's clim) and the same colours and opacity
(app/bench/volume_scalar.py `vispy_job`: vispy's translucent alpha is once a step, ours once a voxel of ray, so
vispy is given the curve corrected for its step). vispy runs in its own process (app/bench/vispy_peer.py) and
stores the values as float32 (texture_format "auto"; its default 8 bits adds half or more to its error). Times are
the medians over `--rounds` rounds (ours and vispy's in turn) of the medians of `--runs` frames after one: `draw`
the frame up to glFinish, `frame` with the picture read back (what vispy's `canvas.render()` times; the draw alone
is the fairer figure for both).

    PYTHONPATH=.:/path/to/vispy python scripts/measure_vs_vispy.py SCAN [SCAN ...] [--side 256] [--size 256 256]
        [--steps 1 2] [--runs 15] [--rounds 3] [--opacity 0.1] [--window LOW HIGH] [--out table.md|table.csv]
        [--save-npy DIR] [--images DIR]

SCAN is a (d, h, w) .npy, a .nii/.nii.gz (read with nibabel, which must then be installed; turned upright) or
`phantom` (the CT phantom, app/model/volume/phantom.py). Each is fitted into side^3: shrunk (linear) if a side is
longer, padded centred with its least value; uint8 becomes int16. `--save-npy` writes the fitted scans, to carry
to a machine without nibabel; `--images` the pictures, ours, vispy's and the reference's side by side (Pillow).
The window is the app's default for a loaded scan (percentiles 1 and 99 above the least value), the phantom's
-200..1200 HU, or `--window`; translucent's opacity curve a ramp over it from 0 to `--opacity` a voxel. Needs
numpy, scipy and moderngl (ours) and vispy with PyOpenGL (theirs; without them, ours alone).
"""
from __future__ import annotations

import argparse
import csv
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy.ndimage import zoom

from app.bench import vispy_peer
from app.bench.harness import errors
from app.bench.volume_scalar import VIEW, vispy_job
from app.gl.core.headless import OffscreenTarget, create_context, release_context
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.raytracer import RayTracer
from app.model.volume.phantom import ct_phantom
from app.model.volume.render_modes import TraceSettings
from app.model.volume.scalars import TransferFunction, default_window
from app.model.volume.volume import Volume
from app.reference.volume_scalar import render as reference
from app.resources import SHADERS

PHANTOM_WINDOW = (-200.0, 1200.0)
COLUMNS = ("scan", "mode", "tool", "voxels_a_step", "ms_draw", "ms_frame", "rmse", "max_abs_error",
           "vispy_over_ours")


def load(path: str, side: int) -> tuple[str, np.ndarray]:
    """The scan's name and its values fitted into side^3, (d, h, w)."""
    if path == "phantom":
        return f"CT phantom {side}^3", ct_phantom(side)
    if path.endswith((".nii", ".nii.gz")):
        import nibabel

        # (x, y, z) as RAS+ files hold them -> (d, h, w) = (y, -z, x): the head upright in our view (h down)
        values = np.asarray(nibabel.load(path).dataobj).transpose(1, 2, 0)[:, ::-1]
    else:
        values = np.load(path, allow_pickle=False)
    if values.ndim != 3:
        raise SystemExit(f"{path}: a 3D array is needed, got shape {values.shape}")
    name = f"{Path(path).name.split('.')[0]} {'x'.join(map(str, values.shape[::-1]))}"
    values = values.astype(np.int16) if values.dtype == np.uint8 else values
    if max(values.shape) > side:
        values = zoom(values, side / max(values.shape), order=1)
    pad = [((side - n) // 2, side - n - (side - n) // 2) for n in values.shape]
    return name, np.pad(values, pad, constant_values=values.min())


def transfers(name: str, values: np.ndarray, window, opacity: float) -> dict[str, TransferFunction]:
    low, high = window or (PHANTOM_WINDOW if name.startswith("CT phantom") else default_window(values))
    return {"mip": TransferFunction(low, high, "grey"),
            "translucent": TransferFunction(low, high, "grey", points=((low, 0.0), (high, opacity)))}


def ours(ctx, values: np.ndarray, transfer: TransferFunction, mode: str, size, cl_steps: float,
         runs: int) -> tuple[float, float, np.ndarray]:
    """Median ms of a frame drawn (up to glFinish) and drawn and read back, and the picture (0..1)."""
    volume = Volume.new(1, 1, 1)
    volume.replace_scalars(values, transfer, copy=False)
    tracer = RayTracer(ctx, ShaderLibrary(ctx, [SHADERS]))
    target = OffscreenTarget(ctx, size, samples=0)
    settings = TraceSettings(steps=cl_steps, slice_planes=False, scalar_mode=mode)
    try:
        def draw() -> None:
            tracer.render(target.fbo, volume.voxels, VIEW, settings)
            ctx.finish()

        draw()  # uploads the values and compiles the shaders
        draws, frames = [], []
        for _ in range(runs):
            start = time.perf_counter()
            draw()
            drawn = time.perf_counter()
            image = target.read()
            draws.append((drawn - start) * 1e3)
            frames.append((time.perf_counter() - start) * 1e3)
        return statistics.median(draws), statistics.median(frames), image[..., :3] / 255.0
    finally:
        target.release()


def measure(args) -> tuple[list[dict], list[str]]:
    size = tuple(args.size)
    with_vispy = vispy_peer.available()
    tools = ("ours", "vispy") if with_vispy else ("ours",)
    notes = [] if with_vispy else ["vispy is not installed (an optional peer): ours alone"]
    ctx = create_context()
    rows = []
    try:
        camera = VIEW.camera
        notes.append(f"ours on {ctx.info['GL_RENDERER']}; {size[0]}x{size[1]}, yaw {camera.yaw:g} pitch "
                     f"{camera.pitch:g} distance {camera.distance:g}, {args.rounds} rounds of {args.runs} frames, "
                     f"reference at {args.reference_step:g} voxel a step")
        for path in args.scans:
            name, values = load(path, args.side)
            if args.save_npy:
                Path(args.save_npy).mkdir(parents=True, exist_ok=True)
                np.save(Path(args.save_npy) / f"{Path(path).name.split('.')[0]}_{args.side}.npy", values)
            for mode, transfer in transfers(name, values, args.window, args.opacity).items():
                start = time.perf_counter()
                truth = reference(values, transfer, VIEW.camera, size, mode, args.side / args.reference_step)
                notes.append(f"{name} {mode}: window {transfer.low:g}..{transfer.high:g}, CPU reference in "
                             f"{time.perf_counter() - start:.0f} s")
                for step in args.steps:
                    def draw(tool: str) -> tuple[float, float, np.ndarray]:
                        if tool == "ours":
                            return ours(ctx, values, transfer, mode, size, args.side / step, args.runs)
                        result = vispy_peer.run(vispy_job(values, transfer, mode, VIEW.camera, size, step,
                                                          args.runs))
                        if not any(n.startswith("vispy on") for n in notes):
                            notes.append(f"vispy on {result['renderer']}")
                        return float(result["ms"]), float(result["frame_ms"]), result["image"] / 255.0

                    found = [(tool, *times) for tool, times in _rounds(draw, tools, args.rounds).items()]
                    if args.images:
                        _save_images(Path(args.images) / f"{path.split('/')[-1].split('.')[0]}_{mode}_{step:g}.png",
                                     [image for *_, image in found] + [truth])
                    for tool, draw_ms, frame_ms, image in found:
                        rmse, worst = errors(image, truth)
                        rows.append(dict(scan=name, mode=mode, tool=tool, voxels_a_step=step, ms_draw=draw_ms,
                                         ms_frame=frame_ms, rmse=rmse, max_abs_error=worst))
                        print(_line(rows[-1]), flush=True)
                    if with_vispy:
                        rows[-2]["vispy_over_ours"] = rows[-1]["ms_draw"] / rows[-2]["ms_draw"]
    finally:
        release_context(ctx)
    return rows, notes


def _rounds(draw, tools: tuple[str, ...], rounds: int) -> dict[str, tuple[float, float, np.ndarray]]:
    """Each tool's median times over `rounds` rounds of `draw`, the tools in turn (in the opposite order every
    other round), so that a machine busy for a while slows both alike; and its picture."""
    times = {tool: [] for tool in tools}
    for r in range(rounds):
        for tool in tools if r % 2 == 0 else tools[::-1]:
            times[tool].append(draw(tool))
    return {tool: (statistics.median(t[0] for t in found), statistics.median(t[1] for t in found), found[-1][2])
            for tool, found in times.items()}


def _save_images(path: Path, images: list[np.ndarray]) -> None:
    from PIL import Image

    path.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray((np.concatenate(images, 1) * 255).round().astype(np.uint8)).save(path)


def _cells(row: dict) -> list[str]:
    ratio = row.get("vispy_over_ours")
    return [row["scan"], row["mode"], row["tool"], f"{row['voxels_a_step']:g}", f"{row['ms_draw']:.2f}",
            f"{row['ms_frame']:.2f}", f"{row['rmse']:.2e}", f"{row['max_abs_error']:.2e}",
            "" if ratio is None else f"{ratio:.2f}x"]


def _line(row: dict) -> str:
    return "  ".join(_cells(row))


def write(path: Path, rows: list[dict], notes: list[str]) -> None:
    if path.suffix == ".csv":
        with path.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(COLUMNS)
            writer.writerows(_cells(row) for row in rows)
        return
    lines = [f"| {' | '.join(COLUMNS)} |", f"|{'---|' * len(COLUMNS)}"]
    lines += [f"| {' | '.join(_cells(row))} |" for row in rows]
    path.write_text("\n".join([*lines, "", *notes, ""]))


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scans", nargs="+", help="a .npy, .nii or .nii.gz scan, or 'phantom'")
    parser.add_argument("--side", type=int, default=256, help="the cube each scan is fitted into")
    parser.add_argument("--size", type=int, nargs=2, default=(256, 256), metavar=("W", "H"))
    parser.add_argument("--steps", type=float, nargs="+", default=(1.0, 2.0), help="voxels a step")
    parser.add_argument("--reference-step", type=float, default=0.25, help="the reference's voxels a step")
    parser.add_argument("--runs", type=int, default=15, help="frames timed a round, after one")
    parser.add_argument("--rounds", type=int, default=3, help="rounds of ours and vispy's frames, in turn")
    parser.add_argument("--opacity", type=float, default=0.1, help="translucent's opacity a voxel at the high end")
    parser.add_argument("--window", type=float, nargs=2, metavar=("LOW", "HIGH"))
    parser.add_argument("--out", type=Path, help="the table as markdown (.md) or CSV (.csv)")
    parser.add_argument("--save-npy", help="a folder for the fitted scans")
    parser.add_argument("--images", help="a folder for the pictures: ours, vispy's, the reference's")
    args = parser.parse_args(argv)
    rows, notes = measure(args)
    print("\n".join(notes))
    if args.out:
        write(args.out, rows, notes)


if __name__ == "__main__":
    main(sys.argv[1:])
