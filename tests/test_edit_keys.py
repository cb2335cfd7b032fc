"""Edit > Undo and Redo's keys (Ctrl+Z, Ctrl+Shift+Z, Ctrl+Y) while a text field has the focus (issue 25): the
console's command line once its line ran, and a panel's spin box, give them to the editor, through real key
presses in the real window; a field with typing of its own to undo keeps them for it."""
import pytest
from PySide6.QtCore import Qt

CTRL, SHIFT = Qt.KeyboardModifier.ControlModifier, Qt.KeyboardModifier.ShiftModifier
Z, Y = Qt.Key.Key_Z, Qt.Key.Key_Y


def focus(qtbot, widget) -> None:
    widget.setFocus()
    qtbot.waitUntil(widget.hasFocus)


def flakes(window) -> int:
    return len(window.editor.workspaces["snowflake"].scene.flakes)


def test_the_console_line_gives_undo_and_redo_to_the_editor_once_its_line_ran(window, qtbot):
    field = window.console_widget.input
    focus(qtbot, field)
    n = flakes(window)
    qtbot.keyClicks(field, "snow.add 0.1 0.1")
    qtbot.keyClick(field, Qt.Key.Key_Return)
    assert flakes(window) == n + 1 and field.text() == ""
    qtbot.keyClick(field, Z, CTRL)
    assert flakes(window) == n and field.text() == ""  # the editor's step, not the line's typing back
    qtbot.keyClick(field, Z, CTRL | SHIFT)
    assert flakes(window) == n + 1
    qtbot.keyClick(field, Z, CTRL)
    qtbot.keyClick(field, Y, CTRL)
    assert flakes(window) == n + 1 and window.menus.undo.text() == "&Undo Add Flake"
    qtbot.keyClicks(field, "snow.li")  # typing of its own: the line undoes and redoes it, the scene stays
    qtbot.keyClick(field, Z, CTRL)
    assert field.text() == "" and flakes(window) == n + 1
    qtbot.keyClick(field, Z, CTRL | SHIFT)
    assert field.text() == "snow.li" and flakes(window) == n + 1


# A panel's spin box per workspace (the snowflake's own QDoubleSpinBox, the 3D lights' form_widgets.spin), the
# value typed into it, and the model value it sets.
SPIN_BOXES = {"snowflake": (lambda panels: panels["snowflake"].spin, "3", lambda state: state.scene.level),
              "lights3d": (lambda panels: panels["lights3d"].widget().shininess, "50",
                           lambda state: state.scene.shininess)}


@pytest.mark.parametrize("workspace", sorted(SPIN_BOXES))
def test_a_spin_box_gives_undo_and_redo_to_the_editor_unless_it_has_typing_of_its_own(window, qtbot, workspace):
    widget, typed, value = SPIN_BOXES[workspace]
    window.run(f"workspace {workspace}")
    state = window.editor.workspaces[workspace]
    box = widget(window.workspace_panels)
    before = value(state)
    focus(qtbot, box)
    box.lineEdit().selectAll()
    qtbot.keyClicks(box, typed)
    qtbot.keyClick(box, Qt.Key.Key_Return)
    assert value(state) == float(typed) != before
    qtbot.keyClick(box, Z, CTRL)
    assert value(state) == before and box.value() == before  # undone, and the panel shows it
    qtbot.keyClick(box, Y, CTRL)
    assert value(state) == float(typed)
    qtbot.keyClick(box, Z, CTRL)
    qtbot.keyClick(box, Z, CTRL | SHIFT)
    assert value(state) == float(typed) and box.value() == float(typed)
    shown = box.lineEdit().text()
    box.lineEdit().selectAll()
    qtbot.keyClicks(box, "1")  # typed, not yet entered: Ctrl+Z takes back the typing, the scene stays
    qtbot.keyClick(box, Z, CTRL)
    assert box.lineEdit().text() == shown and value(state) == float(typed)
