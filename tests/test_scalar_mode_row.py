"""The Scalars group's draw row under Xvfb: the mode list and the iso box send r_scalarMode and vol.iso, and show
what the console set; the row greys out without scalars."""
import numpy as np
import pytest
from PySide6.QtCore import Qt


@pytest.fixture
def row(window, tmp_path):
    values = np.full((12, 14, 16), -1000, np.int16)
    values[3:9, 4:10, 5:11] = 800
    np.save(tmp_path / "scan.npy", values)
    assert window.run("workspace volume")
    modes = window.workspace_panels["volume"].modes
    assert not modes.isEnabled()  # the default sample: no scalars
    assert window.run(f"load {tmp_path / 'scan.npy'}")
    window.refresh()
    return modes


def test_the_row_sends_the_mode_and_the_iso_value_as_commands(window, row, qtbot):
    cvars = window.editor.console.registry.cvars
    assert row.isEnabled() and row.mode.currentText() == "mip" and not row.iso.isEnabled()
    row.mode.textActivated.emit("translucent")  # what picking an entry of the open list sends
    assert cvars["r_scalarMode"].value == "translucent"
    row.mode.textActivated.emit("iso")
    window.refresh()
    assert row.iso.isEnabled() and row.iso.value() == window.editor.workspaces["volume"].iso_value()
    row.iso.setFocus()
    row.iso.lineEdit().selectAll()
    qtbot.keyClicks(row.iso.lineEdit(), "250")
    qtbot.keyClick(row.iso.lineEdit(), Qt.Key.Key_Return)
    assert window.editor.workspaces["volume"].view.iso == 250.0
    assert [line.text for line in window.editor.console.log if line.level == "input"][-1] == "] vol.iso 250"


def test_the_row_shows_what_the_console_set(window, row):
    assert window.run("vol.iso 500")
    window.refresh()
    assert row.mode.currentText() == "iso" and row.iso.value() == 500
    assert window.run("r_scalarMode average")
    window.refresh()
    assert row.mode.currentText() == "average" and not row.iso.isEnabled()
    assert window.run("sample coords3d 16")
    window.refresh()
    assert not row.isEnabled() and row.mode.currentText() == "colour"
