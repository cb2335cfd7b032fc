"""Five workspaces share one GL context in the real window: what one draws never depends on which was shown
before it (DESIGN.md rule 8). Every ordered pair of workspaces is shown in turn in one MainWindow, and each
frame is compared with the same workspace's frame in a window that started on it; every frame's GL state is
read back (SHADELAB_GL_DEBUG, tests/conftest.py), so a renderer that leaves state or an error behind fails."""
from __future__ import annotations

import numpy as np

from app.editor import Editor
from app.model.workspaces import WORKSPACES
from app.views.main_window import MainWindow
from tests.window_frames import frame_image, wait_until_drawn

NAMES = [info.name for info in WORKSPACES]
# The clouds' picture depends on their clock and, through jitter, TAA, reprojection and automatic exposure
# (adapting over frames), on how many frames
# were drawn before (the frame index picks the noise and the pixels traced): stopped for comparable frames.
STILL = ("clouds.set time_scale 0", "r_cloudJitter 0", "r_cloudTAA 0", "r_cloudReproject 0", "r_cloudAutoExposure 0")
SIZE = (760, 520)
VIEW = (380, 300)


def every_ordered_pair(names: list[str]) -> list[str]:
    """A walk that passes from every name to every other exactly once (an Eulerian circuit of the complete
    directed graph, Hierholzer's algorithm): 20 pairs in 21 workspace switches for five names."""
    unused = {a: [b for b in names if b != a] for a in names}
    stack, walk = [names[0]], []
    while stack:
        if unused[stack[-1]]:
            stack.append(unused[stack[-1]].pop())
        else:
            walk.append(stack.pop())
    return walk[::-1]


def open_window(qtbot, first: str | None = None) -> MainWindow:
    editor = Editor()
    for line in STILL:
        assert editor.execute(line), line
    if first is not None:
        assert editor.execute(f"workspace {first}")
    window = MainWindow(editor)
    editor.documents.confirm = None
    qtbot.addWidget(window)
    window.resize(*SIZE)
    # one picture size in every window: what is compared is what a workspace draws after another, not how the
    # docks of the workspaces shown before share the window (the console's height can drift by a pixel or two)
    window.viewport.setFixedSize(*VIEW)
    window.show()
    qtbot.waitExposed(window)
    wait_until_drawn(window, qtbot, timeout_ms=60000)
    return window


def test_the_walk_covers_every_ordered_pair_once():
    walk = every_ordered_pair(NAMES)
    pairs = list(zip(walk, walk[1:]))
    assert len(pairs) == len(set(pairs)) == len(NAMES) * (len(NAMES) - 1)


def test_each_workspace_after_any_other_draws_as_in_a_fresh_window(qtbot):
    fresh = {}
    for name in NAMES:
        window = open_window(qtbot, name)
        fresh[name] = frame_image(window)
        assert not window.viewport.gl_state_errors
        window.close()
    window = open_window(qtbot)
    walk = every_ordered_pair(NAMES)
    wrong = {}
    for before, name in zip(walk, walk[1:]):
        window.run(f"workspace {name}")
        wait_until_drawn(window, qtbot, timeout_ms=60000)
        image = frame_image(window)
        assert image.shape == fresh[name].shape, (before, name)
        diff = np.abs(image.astype(int) - fresh[name].astype(int))[..., :3]
        if diff.max() > 1:
            wrong[f"{name} after {before}"] = (round(float(diff.mean()), 2), int(diff.max()), int((diff > 1).sum()))
    assert not wrong, f"(mean, max, pixels off by > 1/255): {wrong}"
    assert not window.viewport.gl_state_errors
