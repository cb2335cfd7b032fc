"""Reading what an editor window's viewport shows, once it has drawn all it was asked to."""
from __future__ import annotations

import time

import numpy as np


def frame_image(window) -> np.ndarray:
    """The viewport's last frame as RGBA uint8, top row first."""
    image = window.viewport.grabFramebuffer()
    image = image.convertToFormat(image.Format.Format_RGBA8888)
    h, w = image.height(), image.width()
    pixels = np.frombuffer(image.constBits(), np.uint8).reshape(h, image.bytesPerLine())[:, : 4 * w].reshape(h, w, 4)
    return pixels.copy()  # a view would outlive the QImage that owns the memory


def wait_until_drawn(window, qtbot, quiet_s: float = 0.3, timeout_ms: int = 20000) -> None:
    """Until the viewport has drawn all it was asked to (the first resizes, an idle refinement, a temporal
    history filling): no new frame for quiet_s and nothing owed. A slow machine just waits longer."""
    vp = window.viewport
    last = {"frames": -1, "at": time.monotonic()}

    def drawn():
        if vp.frames != last["frames"] or not vp.settled():
            last.update(frames=vp.frames, at=time.monotonic())
        return time.monotonic() - last["at"] > quiet_s

    qtbot.waitUntil(drawn, timeout=timeout_ms)
