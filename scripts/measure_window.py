"""Time loading a scalar volume and changing its window through the console (the model's work: reading, the
default window's percentiles, colouring every voxel; no GL). docs/volume.md quotes it.

    PYTHONPATH=. .venv/bin/python scripts/ct_phantom.py /tmp/ph256.nrrd 256
    PYTHONPATH=. .venv/bin/python scripts/measure_window.py /tmp/ph256.nrrd
"""
import statistics
import sys
import time

from app.console.demo import VirtualClock
from app.editor import Editor

editor = Editor(clock=VirtualClock())
editor.execute("workspace volume")
start = time.perf_counter()
assert editor.execute(f"load {sys.argv[1]}")
load = time.perf_counter() - start
times = []
for i in range(10):
    start = time.perf_counter()
    assert editor.execute(f"vol.window {100 + i} 1200")
    times.append(time.perf_counter() - start)
print(f"load {load * 1000:.0f} ms; vol.window median {statistics.median(times) * 1000:.0f} ms "
      f"(min {min(times) * 1000:.0f}, max {max(times) * 1000:.0f})")
