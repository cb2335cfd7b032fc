"""Typing into the console dock: completion, history across a restart, errors, Lua, runaway scripts."""

from PySide6.QtCore import Qt


def type_line(qtbot, window, text):
    line = window.console_widget.input
    line.setFocus()
    qtbot.keyClicks(line, text)
    qtbot.keyClick(line, Qt.Key.Key_Return)


def log_text(window):
    return window.console_widget.log.toPlainText()


def test_tab_completes_to_the_common_prefix_and_lists(window, qtbot):
    line = window.console_widget.input
    line.setFocus()
    qtbot.waitUntil(line.hasFocus)
    qtbot.keyClicks(line, "cl_s")
    qtbot.keyClick(line, Qt.Key.Key_Tab)
    assert line.text() == "cl_s"
    assert "cl_sampleRange = 1  cl_shadowSteps = 20  cl_steps = 128" in log_text(window)
    qtbot.keyClicks(line, "h")
    qtbot.keyClick(line, Qt.Key.Key_Tab)
    assert line.text() == "cl_shadowSteps "
    assert line.hasFocus()  # Tab completed instead of moving the focus
    line.clear()
    qtbot.keyClicks(line, "exec defa")
    qtbot.keyClick(line, Qt.Key.Key_Tab)
    assert line.text() == "exec default.cfg "


def test_history_survives_a_restart(make_window, qtbot):
    first = make_window()
    type_line(qtbot, first, "snow.level 2.5")
    type_line(qtbot, first, "echo hello")
    first.close()
    second = make_window()
    line = second.console_widget.input
    qtbot.keyClick(line, Qt.Key.Key_Up)
    assert line.text() == "echo hello"
    qtbot.keyClick(line, Qt.Key.Key_Up)
    assert line.text() == "snow.level 2.5"
    qtbot.keyClick(line, Qt.Key.Key_Down)
    qtbot.keyClick(line, Qt.Key.Key_Down)
    assert line.text() == ""


def test_a_bad_command_is_reported_and_changes_nothing(window, qtbot):
    before = window.editor.digest()
    type_line(qtbot, window, "snow.add 1")
    type_line(qtbot, window, "nosuchthing 3")
    assert "snow.add: missing <y>" in log_text(window)
    assert "unknown command 'nosuchthing'" in log_text(window)
    assert window.editor.digest() == before


def test_a_lua_error_names_the_script_and_line(window, qtbot, tmp_path):
    script = tmp_path / "broken.lua"
    script.write_text("cmd.snow.level(1)\nlocal t = nil\nprint(t.field)\n")
    type_line(qtbot, window, f"lua {script}")
    assert "broken.lua:3:" in log_text(window)
    assert window.editor.workspaces["snowflake"].scene.level == 1  # what ran before the error stays; nothing after it


def test_a_runaway_lua_loop_is_stopped_within_its_budget(window, qtbot, tmp_path):
    script = tmp_path / "spin.lua"
    script.write_text("local n = 0\nwhile true do n = n + 1 end\n")
    type_line(qtbot, window, f"lua {script}")
    assert "spin.lua:2: instruction budget exceeded" in log_text(window)  # the budget stopped it, not a clock
    type_line(qtbot, window, "snow.level 3")  # the editor carries on
    assert window.editor.workspaces["snowflake"].scene.level == 3


def test_page_keys_scroll_the_log_and_escape_closes(window, qtbot):
    for i in range(80):
        window.editor.console.print(f"line {i}")
    bar = window.console_widget.log.verticalScrollBar()
    bottom = bar.value()
    line = window.console_widget.input
    qtbot.keyClick(line, Qt.Key.Key_PageUp)
    assert bar.value() < bottom
    qtbot.keyClick(line, Qt.Key.Key_PageDown)
    assert bar.value() == bottom
    qtbot.keyClick(line, Qt.Key.Key_Escape)
    assert not window.docks["console"].isVisible()


def test_clear_empties_the_log_view(window, qtbot):
    type_line(qtbot, window, "echo something")
    type_line(qtbot, window, "clear")
    assert log_text(window) == ""


def test_binds_from_the_config_drive_the_view(window, qtbot):
    type_line(qtbot, window, "bind F5 snow.level 5")
    window.viewport.setFocus()
    qtbot.keyClick(window.viewport, Qt.Key.Key_F5)
    assert window.editor.workspaces["snowflake"].scene.level == 5
    qtbot.keyClick(window.viewport, Qt.Key.Key_PageDown)  # snowflake:PGDN from default.cfg
    assert window.editor.workspaces["snowflake"].scene.level == 4


def test_demo_plays_in_the_editor_on_its_timer(window, qtbot):
    type_line(qtbot, window, "play snowflake_tour 8")
    assert window.editor.demos.playing
    qtbot.waitUntil(lambda: not window.editor.demos.playing, timeout=5000)
    scene = window.editor.workspaces["snowflake"].scene
    assert scene.level == 6 and len(scene.flakes) == 2
    assert "demo finished: 18 commands" in log_text(window)


def test_quit_closes_and_writes_the_user_config(window, qtbot, user_config_dir):
    type_line(qtbot, window, "seta r_mine 5")
    type_line(qtbot, window, "quit")
    qtbot.waitUntil(lambda: not window.isVisible(), timeout=3000)
    assert "seta r_mine 5" in (user_config_dir / "config.cfg").read_text()
