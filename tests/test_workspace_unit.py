"""A workspace is a unit: one written entirely in this module plugs in through the layers' mappings alone
(docs/architecture.md), and the editor, the switcher, `shadelab render`, `digest`, `undo` and demos serve it
like the built-in ones."""
from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtWidgets import QLabel

from app import cli
from app.console.registry import SCRIPTS
from app.bench import WORKSPACE_TECHNIQUE
from app.commands.workspaces import COMMANDS, WorkspaceCommands
from app.console.demo import VirtualClock
from app.editor import Editor
from app.gl.core.renderer_base import WorkspaceRendererBase
from app.gl.core.workspace_renderer import RENDERERS
from app.io.png import read_png
from app.model.history import SnapshotHistory
from app.model.workspace import Workspace, WorkspaceInfo, short_hash
from app.model.workspaces import WORKSPACES
from app.views.workspace_views import VIEWS, WorkspaceViews


# ---- the dummy workspace: one class or function per layer --------------------------------------------

class DummyState(Workspace):
    """model: a counter, with undo."""
    name = "dummy"

    def __init__(self) -> None:
        self.count = 0
        self.history = SnapshotHistory(lambda: self.count, lambda count: setattr(self, "count", count))

    def version(self) -> tuple:
        return (self.count,)

    def digest(self) -> dict[str, str]:
        return {"dummy": short_hash(self.count)}

    def opening_commands(self, snapshot) -> list[str]:
        return [f"sample {self.count}"]


def register(console, state: DummyState, checks) -> None:
    """commands: its own `sample`, a word the volume workspace has too."""
    reg = console.registry.scoped(state.name)

    @reg.command("sample", "count:int", "Set the dummy's counter", allow=SCRIPTS)
    def sample(count: int) -> None:
        state.history.checkpoint("Set Count")
        state.count = count


class DummyRenderer(WorkspaceRendererBase):
    """gl: clears to a colour that shows the counter."""

    def render(self, fbo, state, settings, interactive=False) -> bool:
        fbo.use()
        fbo.clear(state.count / 10, 0.5, settings, 1.0)
        return False


class DummyPanel(QLabel):
    """views: one label."""

    def __init__(self, state) -> None:
        super().__init__()
        self.state = state
        self.sync()

    def sync(self) -> None:
        self.setText(f"count {self.state.count}")


@pytest.fixture
def dummy(monkeypatch):
    """Register the dummy through the mappings, one entry per layer, and nothing else."""
    info = WorkspaceInfo("dummy", "Dummy", DummyState)
    WORKSPACES.append(info)
    monkeypatch.setitem(COMMANDS, "dummy", WorkspaceCommands(register, lambda console, state: 0.25))
    monkeypatch.setitem(RENDERERS, "dummy", DummyRenderer)
    monkeypatch.setitem(VIEWS, "dummy", WorkspaceViews(panel=lambda window, state, tool: DummyPanel(state)))
    assert "dummy" not in WORKSPACE_TECHNIQUE  # a workspace needs no bench to plug in
    yield
    WORKSPACES.remove(info)


def test_the_editor_serves_a_workspace_it_knows_only_through_the_mappings(dummy, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    clock = VirtualClock()
    editor = Editor(clock=clock, configs=False)
    assert editor.execute("workspace dummy") and editor.workspace == "dummy"

    # its `sample` in its own workspace; the volume's everywhere else, as before
    volume_before = editor.workspaces["volume"].volume.voxels.digest()
    assert editor.execute("record counted")
    clock.advance(0.5)
    assert editor.execute("sample 3")
    clock.advance(0.5)
    assert editor.execute("sample 7")
    assert editor.execute("stop")
    assert editor.workspaces["dummy"].count == 7
    assert editor.workspaces["volume"].volume.voxels.digest() == volume_before
    assert editor.execute("volume:sample cornell_box 16")  # the qualified name reaches the volume's
    assert editor.workspaces["volume"].volume.voxels.size == (16, 16, 16)

    # digest: the dummy's part is there and follows its state
    assert editor.digest()["dummy"] == short_hash(7)

    # undo: the dummy's last step, nothing in the volume
    volume_now = editor.workspaces["volume"].volume.voxels.digest()
    assert editor.execute("undo") and editor.workspaces["dummy"].count == 3
    assert editor.workspaces["volume"].volume.voxels.digest() == volume_now
    assert editor.execute("undo") and editor.workspaces["dummy"].count == 0
    assert not editor.execute("undo")  # its history is empty: the volume's sample load is not undone here
    assert editor.workspaces["volume"].volume.voxels.size == (16, 16, 16)

    # a recorded demo replays it in a fresh editor
    fresh_clock = VirtualClock()
    fresh = Editor(clock=fresh_clock, configs=False)
    assert fresh.execute("play counted")
    fresh_clock.advance(10)
    fresh.demos.update()
    assert not fresh.demos.playing and fresh.workspaces["dummy"].count == 7
    assert fresh.workspace == "dummy"
    assert fresh.digest()["dummy"] == short_hash(7)


def test_shadelab_render_draws_it(dummy, tmp_path):
    out = tmp_path / "dummy.png"
    assert cli.main(["render", "dummy", "--cmd", "sample 8", "--size", "64x48", "--out", str(out)]) == 0
    image = read_png(out)
    assert image.shape == (48, 64, 4)
    assert np.abs(image[24, 32, :3].astype(int) - (204, 128, 64)).max() <= 1  # (0.8, 0.5, 0.25) from its state


def test_the_switcher_shows_it_and_its_panel_syncs(dummy, qtbot):
    from app.views.main_window import MainWindow

    window = MainWindow(Editor(configs=False))
    qtbot.addWidget(window)
    action = window.workspace_actions["dummy"]
    assert action.text() == "Dummy" and action.isEnabled()
    action.trigger()
    assert window.editor.workspace == "dummy" and action.isChecked()
    panel = window.workspace_panels["dummy"]
    assert window.panels.currentWidget() is panel
    window.run("sample 5")
    assert panel.text() == "count 5"
    assert window.viewport.tool is None  # no tool: the viewport takes no mouse edits
