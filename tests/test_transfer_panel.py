"""The volume panel's scalar group under Xvfb: typed windows, the colour map and the auto button become the
window commands; a refused window snaps back; commands typed in the console show in the panel."""
import nrrd
import numpy as np
import pytest
from PySide6.QtCore import Qt

from app.model.volume.scalars import TransferFunction


@pytest.fixture
def panel(window, tmp_path):
    values = np.full((12, 14, 16), -1024, np.int16)
    values[3:9, 4:10, 5:11] = np.arange(6 * 6 * 6).reshape(6, 6, 6) * 10
    nrrd.write(str(tmp_path / "ct.nrrd"), values, {"encoding": "gzip"}, index_order="C")
    assert window.run("workspace volume")
    transfer = window.workspace_panels["volume"].transfer
    assert not transfer.isEnabled() and "no scalars" in transfer.info.text()
    assert window.run(f"load {tmp_path / 'ct.nrrd'}")
    window.refresh()
    return transfer


def transfer_function(window) -> TransferFunction:
    return window.editor.workspaces["volume"].volume.voxels.scalars.transfer


def type_into(qtbot, box, text: str) -> None:
    box.setFocus()
    box.lineEdit().selectAll()
    qtbot.keyClicks(box.lineEdit(), text)
    qtbot.keyClick(box.lineEdit(), Qt.Key.Key_Return)


def commands(window) -> list[str]:
    return [line.text for line in window.editor.console.log if line.level == "input"]


def test_the_panel_shows_the_loaded_window_and_sends_edits_as_commands(window, panel, qtbot):
    start = transfer_function(window)
    assert panel.isEnabled() and panel.info.text() == "int16 scalars, values -1024..2150"
    assert (panel.low.value(), panel.high.value(), panel.colormap.currentText()) == (start.low, start.high, "grey")
    type_into(qtbot, panel.high, "600")
    assert transfer_function(window) == TransferFunction(start.low, 600, "grey")
    type_into(qtbot, panel.low, "-20")
    assert transfer_function(window) == TransferFunction(-20, 600, "grey")
    panel.colormap.textActivated.emit("hot")  # what picking an entry of the open list sends
    assert transfer_function(window) == TransferFunction(-20, 600, "hot")
    qtbot.mouseClick(panel.auto, Qt.MouseButton.LeftButton)
    assert transfer_function(window) == TransferFunction(start.low, start.high, "hot")
    assert commands(window)[-4:] == [f"] vol.window {start.low:g} 600", "] vol.window -20 600", "] vol.colormap hot",
                                     "] vol.window.auto"]
    window.run("undo")
    window.refresh()
    assert (panel.low.value(), panel.high.value()) == (-20, 600)


def test_a_refused_window_snaps_back_and_console_commands_show(window, panel, qtbot):
    start = transfer_function(window)
    type_into(qtbot, panel.low, str(int(start.high) + 50))  # above high: refused
    assert transfer_function(window) == start
    assert "low must be below its high" in [line.text for line in window.editor.console.log][-1]
    assert panel.low.value() == start.low
    window.run("vol.window 100 300; vol.colormap viridis")
    window.refresh()
    assert (panel.low.value(), panel.high.value(), panel.colormap.currentText()) == (100, 300, "viridis")
    window.run("label.stroke z 5 1 2 6 6")  # labels over the scan: it windows as before
    window.refresh()
    assert panel.isEnabled() and panel.colormap.currentText() == "viridis"
    window.run("new 8 8 8")  # RGBA: nothing to window
    window.refresh()
    assert not panel.isEnabled() and "no scalars to window" in panel.info.text()
