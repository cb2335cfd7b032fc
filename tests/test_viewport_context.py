"""The viewport's GL context going and coming back (Qt makes a new one when the widget changes window): the old
one's objects are freed and the new one draws the whole scene."""
import numpy as np

from tests.window_frames import frame_image, wait_until_drawn


def test_a_new_context_after_a_resize_draws_the_scene_and_the_old_one_is_released(window, qtbot):
    window.run("workspace lighting2d")
    wait_until_drawn(window, qtbot)
    for width in (900, 1000):  # the renderer replaces its size-bound targets: released objects are queued
        window.resize(width, 700)
        wait_until_drawn(window, qtbot)
    before = frame_image(window)
    vp, old = window.viewport, window.viewport.ctx
    window.setCentralWidget(window.takeCentralWidget())  # out of the window and back: Qt's context is remade
    vp.show()
    qtbot.waitUntil(lambda: vp.ctx is not None and vp.ctx is not old, timeout=10000)
    wait_until_drawn(window, qtbot)
    assert old.mglo.__class__.__name__ == "InvalidObject"  # the old context was released, not left half-freed
    after = frame_image(window)
    assert after.shape == before.shape and np.abs(after.astype(int) - before.astype(int)).mean() < 1.0
