"""Memory of loading a CT: a synthetic 512x512x300 int16 scan (150 MiB of values) written as NIfTI (.nii and
.nii.gz) and as a DICOM series (300 files of uint16 with RescaleIntercept -1024, as scanners write them), then
each read in a fresh process, four ways: the reader alone; `load` (the model: the values, and no colours); `load`
and a frame drawn (the ray tracer's textures, on a headless EGL context: the values, their bricks; drawn in mip, the
mode a scan opens in, then in colour F5, which looks the colours up in the shader); and that with a label painted
(the model's labels, uint8, and the labels' box on the GPU). On Mesa's llvmpipe the textures live in the process's
memory, so its RSS counts them.

Each row gives, in multiples of the values' size: tracemalloc's peak while loading (numpy's arrays are traced); what
is held after: the model's arrays (Voxels.nbytes: values, labels) plus the textures the GL side made
(RayTracer.held_bytes); and the rise of the process's peak RSS over what it held just before reading. Issue 30's
budget for the held bytes is 2.5 (values, labels, GPU copy counted).

    PYTHONPATH=. .venv/bin/python scripts/measure_load_memory.py [WxHxD] [folder]
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import nibabel as nib
import numpy as np

from tests.dicom_files import write_series

SIZE = tuple(int(n) for n in (sys.argv[1] if len(sys.argv) > 1 else "512x512x300").split("x"))

MEASURE = r"""
import json, sys, tracemalloc
from app.console.demo import VirtualClock
from app.editor import Editor
from app.io.volume_formats import read_volume_file

path, how = sys.argv[1], sys.argv[2]
editor = Editor(clock=VirtualClock())
editor.execute("workspace volume")
if how != "read":
    import moderngl
    from app.gl.core.headless import OffscreenTarget
    from app.gl.core.shaders import ShaderLibrary
    from app.gl.volume.raytracer import RayTracer
    from app.model.volume.render_modes import TraceSettings
    from app.resources import SHADERS
    ctx = moderngl.create_standalone_context(backend="egl")
    import numpy as np
    from app.model.volume.volume import Volume
    tracer, target = RayTracer(ctx, ShaderLibrary(ctx, [SHADERS])), OffscreenTarget(ctx, (128, 128), samples=0)
    def draw(voxels, view):
        for scalar in ("mip", "colour"):
            tracer.render(target.fbo, voxels, view, TraceSettings(mode=5, scalar_mode=scalar, steps=64))
        ctx.finish()
    for dtype in ("int16", "uint16"):  # the shaders compiled and llvmpipe's code made before measuring
        tiny = Volume.new(1, 1, 1)
        tiny.replace_scalars(np.arange(512, dtype=dtype).reshape(8, 8, 8))
        draw(tiny.voxels, editor.workspaces["volume"].view)
    tracer.scalars.release()
def status(field):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) * 1024 for line in f if line.startswith(field))
with open("/proc/self/clear_refs", "w") as f:  # the peak RSS (VmHWM) starts again from what is resident now
    f.write("5")
before = status("VmRSS:")
tracemalloc.start()
held = gpu = 0
if how == "read":
    kept = read_volume_file(path, max_bytes=8 << 30)
    held = kept.data.nbytes
else:
    assert editor.execute(f"load {path}"), path
    volume = editor.workspaces["volume"].volume
    if how == "labels":
        w, h, d = volume.voxels.size  # a stroke across the middle slice: an organ's outline, say
        assert editor.execute(f"label.stroke z {d // 2} 9 1 {w // 3} {h // 3} {2 * w // 3} {2 * h // 3}")
    peak = tracemalloc.get_traced_memory()[1]
    if how != "load":
        draw(volume.voxels, editor.workspaces["volume"].view)
        gpu = tracer.held_bytes()
    held = volume.voxels.nbytes
peak = tracemalloc.get_traced_memory()[1] if how in ("read", "load") else peak
tracemalloc.stop()
rss = status("VmHWM:") - before
print(json.dumps({"traced": peak, "held": held, "gpu": gpu, "rss": rss}))
"""


def ct_values(shape: tuple[int, int, int]) -> np.ndarray:
    """(d, h, w) stored values: a disc of soft tissue (1064, i.e. 40 HU) in air (24 = -1000 HU) with noise."""
    d, h, w = shape
    y, x = np.mgrid[0:h, 0:w]
    disc = ((x - w / 2) ** 2 + (y - h / 2) ** 2 < (0.4 * min(w, h)) ** 2)
    rng = np.random.default_rng(0)
    values = np.empty(shape, np.uint16)
    for z in range(d):
        values[z] = np.where(disc, 1064, 24) + rng.integers(0, 30, (h, w))
    return values


def write_nifti(folder: Path, values: np.ndarray) -> list[Path]:
    hu = (values.astype(np.int32) - 1024).astype(np.int16)
    image = nib.Nifti1Image(hu.T, np.diag([0.7, 0.7, 2.0, 1.0]))  # (i, j, k) = (x, y, z)
    paths = [folder / "ct.nii", folder / "ct.nii.gz"]
    for path in paths:
        nib.save(image, path)
    return paths


def write_dicom(folder: Path, values: np.ndarray) -> Path:
    write_series(folder / "ct-series", values, gap=2.0, spacing=(0.7, 0.7))
    return folder / "ct-series"


def main() -> None:
    w, h, d = SIZE
    folder = Path(sys.argv[2]) if len(sys.argv) > 2 else Path(tempfile.mkdtemp(prefix="ct-memory-"))
    folder.mkdir(parents=True, exist_ok=True)
    values = ct_values((d, h, w))
    size = values.nbytes
    cases = [*write_nifti(folder, values), write_dicom(folder, values)]
    del values
    print(f"{w}x{h}x{d} int16: {size / 2**20:.0f} MiB of values; in {folder}")
    print(f"{'file':<12} {'measured':<28} {'traced peak':>11} {'held':>7} {'of it GPU':>10} {'RSS rise':>9}")
    for path in cases:
        for how, what in (("read", "the reader"), ("load", "load (values)"), ("gpu", "load + drawn (GPU textures)"),
                          ("labels", "+ a label painted")):
            out = subprocess.run([sys.executable, "-c", MEASURE, str(path), how], capture_output=True, text=True,
                                 check=True)
            m = json.loads(out.stdout.strip().splitlines()[-1])
            total = m["held"] + m["gpu"]
            gpu = f"{m['gpu'] / size:.3f}x" if m["gpu"] else ""
            print(f"{path.name:<12} {what:<28} {m['traced'] / size:>10.2f}x {total / size:>6.3f}x {gpu:>10} "
                  f"{m['rss'] / size:>8.2f}x")

if __name__ == "__main__":
    main()
