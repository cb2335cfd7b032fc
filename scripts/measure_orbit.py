"""Measure orbiting in the editor: a real mouse drag (QTest) over the 3D view of a 128^3 Cornell box in
Phong mode (F5), for 5 seconds; prints updates per second and how soon full quality follows the release.

    xvfb-run -a -s '-screen 0 1900x1000x24' .venv/bin/python scripts/measure_orbit.py
"""
import time
from app.views.application import set_surface_format
set_surface_format()
from PySide6.QtWidgets import QApplication
from PySide6.QtCore import Qt, QPoint
from PySide6.QtTest import QTest
app = QApplication([])
from app.views.main_window import MainWindow
w = MainWindow(); w.show()
for cmd in ("workspace volume", "sample cornell_box 128", "mode 5"):
    w.run(cmd)
w.resize(1780, 850)
for _ in range(50): app.processEvents(); time.sleep(0.01)
vp = w.viewport
print("viewport", vp.width(), vp.height())
c = QPoint(vp.width() // 2, vp.height() // 2)
QTest.mousePress(vp, Qt.MouseButton.LeftButton, pos=c)
f0 = vp.frames; t0 = time.perf_counter(); x = 0
while time.perf_counter() - t0 < 5.0:
    x += 4
    QTest.mouseMove(vp, c + QPoint(x % 300, 0))
    app.processEvents()
n = vp.frames - f0; dt = time.perf_counter() - t0
QTest.mouseRelease(vp, Qt.MouseButton.LeftButton, pos=c + QPoint(x % 300, 0))
stop = time.perf_counter()
print(f"drag: {n} frames in {dt:.1f} s = {n/dt:.1f} updates/s at level {vp.renderer.level}; ladder {[None if m is None else round(m,1) for m in vp.renderer.ladder.ms]}")
while time.perf_counter() - stop < 2.0:
    app.processEvents(); time.sleep(0.005)
    if vp._last_frame > stop + 0.05 and vp.renderer.level == 0:
        print(f"full quality {vp._last_frame - stop:.2f} s after release ({vp.frame_ms[-1]:.0f} ms)"); break
