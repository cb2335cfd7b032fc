"""Memory of loading a CT: a synthetic 512x512x300 int16 scan (150 MiB of values) written as NIfTI (.nii and
.nii.gz) and as a DICOM series (300 files of uint16 with RescaleIntercept -1024, as scanners write them), then
each read in a fresh process, three ways: the reader alone, `load` (the model: the values and the RGBA colours
they become), and `load` plus the GPU copy (the ray tracer's RGBA texture, uploaded on a headless EGL context; on
Mesa's llvmpipe the texture lives in the process's memory, so its RSS counts it). Each row gives tracemalloc's
peak (numpy's arrays are traced) and the rise of the process's peak RSS over what it held just before reading,
in multiples of the values' size; issue 30's budget is 2.5.

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
import moderngl
from app.gl.volume.texture import VolumeTexture

path, how = sys.argv[1], sys.argv[2]
editor = Editor(clock=VirtualClock())
editor.execute("workspace volume")
ctx = moderngl.create_standalone_context(backend="egl") if how == "gpu" else None
def status(field):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) * 1024 for line in f if line.startswith(field))
with open("/proc/self/clear_refs", "w") as f:  # the peak RSS (VmHWM) starts again from what is resident now
    f.write("5")
before = status("VmRSS:")
tracemalloc.start()
if how == "read":
    kept = read_volume_file(path, max_bytes=8 << 30)
else:
    assert editor.execute(f"load {path}"), path
    if how == "gpu":
        texture = VolumeTexture(ctx).sync(editor.workspaces["volume"].volume.voxels)
        ctx.finish()
peak = tracemalloc.get_traced_memory()[1]
tracemalloc.stop()
rss = status("VmHWM:") - before
gpu = texture.width * texture.height * texture.depth * texture.components if how == "gpu" else 0
print(json.dumps({"traced": peak, "rss": rss, "gpu": gpu}))
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
    print(f"{'file':<12} {'measured':<22} {'traced peak':>12} {'RSS rise':>10}  GPU copy")
    for path in cases:
        for how, what in (("read", "the reader"), ("load", "load (values, colours)"),
                          ("gpu", "load + GPU texture")):
            out = subprocess.run([sys.executable, "-c", MEASURE, str(path), how], capture_output=True, text=True,
                                 check=True)
            m = json.loads(out.stdout.strip().splitlines()[-1])
            gpu = f"{m['gpu'] / size:.2f}x ({m['gpu'] >> 20} MiB RGBA)" if m["gpu"] else ""
            print(f"{path.name:<12} {what:<22} {m['traced'] / size:>11.2f}x {m['rss'] / size:>9.2f}x  {gpu}")


if __name__ == "__main__":
    main()
