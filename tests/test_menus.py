"""The menu bar under Xvfb: every action runs a console command; Edit's Undo and Redo name the step and answer
Ctrl+Z, Ctrl+Shift+Z and Ctrl+Y in every workspace; View brings closed docks back and resets the layout,
which is kept between runs; Help shows the workspace's keys, its documentation and what this build is."""
from pathlib import Path

import pytest
from PySide6.QtCore import QPoint, Qt, QUrl
from PySide6.QtGui import QDesktopServices, QTextDocument
from PySide6.QtWidgets import QMessageBox

from app.model.workspaces import names
from dialogs import answer, said

Ctrl, Shift = Qt.KeyboardModifier.ControlModifier, Qt.KeyboardModifier.ShiftModifier
Right, Left, Bottom = (Qt.DockWidgetArea.RightDockWidgetArea, Qt.DockWidgetArea.LeftDockWidgetArea,
                       Qt.DockWidgetArea.BottomDockWidgetArea)


def texts(menu):
    return [a.text() for a in menu.actions() if not a.isSeparator()]


def inputs(window):
    return [line.text for line in window.editor.console.log if line.level == "input"]


def test_the_menus_and_what_each_action_runs(window):
    menus = window.menus.menus
    assert texts(menus["file"]) == ["&New", "&Open...", "Open &Folder...", "Open &Recent", "&Save", "Save &As...",
                                    "&Quit"]
    assert texts(menus["edit"]) == ["&Undo", "&Redo"]
    assert texts(menus["view"]) == ["Editor", "Console", "Speed vs accuracy", "Transfer function", "&Frame All",
                                    "Reset &Layout"]
    assert texts(menus["help"]) == ["&Keys", "&Documentation", "&About Shadelab"]
    shortcuts = {a.text(): [k.toString() for k in a.shortcuts()] for m in menus.values() for a in m.actions()}
    assert shortcuts["&New"] == ["Ctrl+N"] and shortcuts["&Open..."] == ["Ctrl+O"] and shortcuts["&Quit"] == ["Ctrl+Q"]
    assert shortcuts["&Save"] == ["Ctrl+S"] and shortcuts["Save &As..."] == ["Ctrl+Shift+S"]
    assert shortcuts["&Undo"] == ["Ctrl+Z"] and shortcuts["&Redo"] == ["Ctrl+Shift+Z", "Ctrl+Y"]
    menus["view"].actions()[1].trigger()  # Console: shows or hides it
    menus["view"].actions()[-1].trigger()
    menus["file"].actions()[0].trigger()
    assert inputs(window)[-3:] == ["] ui.dock console", "] ui.resetlayout", "] scene.new"]


@pytest.mark.parametrize("workspace, edit, step", [
    ("snowflake", "snow.add 0.5 0.5", "Add Flake"),
    ("lighting2d", "light.add point 0 0", "Add Light"),
    ("volume", "voxel 1 1 1 255 0 0 255", "Paint Voxel"),
    ("clouds", "clouds.set coverage 0.9", "Set coverage"),
    ("lights3d", "object.move 0 1 2 3", "Move Object"),
])
def test_undo_and_redo_are_named_and_keyed_in_every_workspace(window, qtbot, workspace, edit, step):
    assert set(names()) == {"snowflake", "lighting2d", "volume", "clouds", "lights3d"}  # each one is here
    undo, redo = window.menus.undo, window.menus.redo
    window.run(f"workspace {workspace}")
    window.windowHandle().requestActivate()  # the clouds' first showing has a progress dialog: under Xvfb no
    qtbot.waitUntil(window.isActiveWindow)   # window manager gives the window the focus back after it
    state = window.editor.current
    before = state.document_digest()  # the clouds' full digest moves with the wind
    window.run(edit)
    edited = state.document_digest()
    assert undo.text() == f"&Undo {step}" and undo.isEnabled()
    assert redo.text() == "&Redo" and not redo.isEnabled()
    window.viewport.setFocus()
    qtbot.keyClick(window.viewport, Qt.Key.Key_Z, Ctrl)
    assert state.document_digest() == before
    assert redo.text() == f"&Redo {step}"
    qtbot.keyClick(window.viewport, Qt.Key.Key_Z, Ctrl | Shift)
    assert state.document_digest() == edited
    qtbot.keyClick(window.viewport, Qt.Key.Key_Z, Ctrl)
    qtbot.keyClick(window.viewport, Qt.Key.Key_Y, Ctrl)
    assert state.document_digest() == edited
    assert inputs(window)[-4:] == ["] undo", "] redo", "] undo", "] redo"]


def test_a_painted_stroke_is_undone_by_name(window, qtbot):
    window.run("workspace volume")
    window.run("new 16 12 3")
    canvas = window.workspace_panels["volume"].canvas
    qtbot.waitUntil(lambda: canvas.zoom > 0)
    at = [QPoint(int(canvas.offset.x() + (u + 0.5) * canvas.zoom), int(canvas.offset.y() + 5.5 * canvas.zoom))
          for u in (2, 9)]
    qtbot.mousePress(canvas, Qt.MouseButton.LeftButton, pos=at[0])
    qtbot.mouseMove(canvas, at[1])
    qtbot.mouseRelease(canvas, Qt.MouseButton.LeftButton, pos=at[1])
    assert window.menus.undo.text() == "&Undo Stroke"
    qtbot.keyClick(canvas, Qt.Key.Key_Z, Ctrl)  # the painter has the keyboard: the shortcut still undoes
    assert not window.editor.current.volume.voxels.data.any()
    assert window.menus.undo.text() == "&Undo New Volume"


def test_view_brings_a_closed_dock_back_and_resets_the_layout(window, qtbot):
    console, bench = window.docks["console"], window.docks["bench"]
    menu, view = window.menus.menus["view"], window.menus.dock_actions
    console.close()  # its own close button
    menu.aboutToShow.emit()
    assert not view["console"].isChecked() and view["editor"].isChecked()
    view["console"].trigger()
    assert console.isVisible()
    window.addDockWidget(Left, bench)
    window.run("ui.dock editor 0")
    menu.aboutToShow.emit()
    assert not window.docks["editor"].isVisible() and not view["editor"].isChecked() and view["console"].isChecked()
    window.run("ui.resetlayout")
    qtbot.waitUntil(lambda: window.docks["editor"].isVisible())
    assert window.dockWidgetArea(bench) == Right and window.dockWidgetArea(console) == Bottom
    assert not window.run("ui.dock nothing")


def test_the_layout_is_kept_between_runs(make_window, qtbot):
    first = make_window()
    first.addDockWidget(Right, first.docks["console"])
    first.run("ui.dock bench 0")
    size = (1180, 720)  # not the default 1400 x 860; on the 1280 x 800 screen, above the docks' smallest
    first.resize(*size)
    qtbot.waitUntil(lambda: (first.width(), first.height()) == size)
    first.close()
    second = make_window()
    assert second.dockWidgetArea(second.docks["console"]) == Right
    second.menus.menus["view"].aboutToShow.emit()
    assert not second.docks["bench"].isVisible() and not second.menus.dock_actions["bench"].isChecked()
    assert (second.width(), second.height()) == size
    second.run("ui.dock bench 1")
    assert second.docks["bench"].isVisible()


def test_help_keys_lists_the_current_workspaces_keys(window, qtbot):
    window.menus.menus["help"].actions()[0].trigger()
    dialog = window.menus.keys_dialog
    qtbot.waitExposed(dialog)
    text = window.menus.keys_label.text()
    assert "Click to add a flake" in text and "snow.step 0.25" in text and "Ctrl+Shift+Z" in text
    assert "mode 1" not in text  # another workspace's binds
    window.run("workspace volume")
    window.run("ui.keys")
    text = window.menus.keys_label.text()
    assert "Drag to orbit" in text and "mode 1" in text and "snow.step" not in text


def test_help_shows_the_workspaces_documentation_in_the_editor(window, monkeypatch, qtbot):
    """Broken: it logged "opened docs/snowflake.md" but nothing opened (no desktop launcher under Xvfb)."""
    opened = []
    monkeypatch.setattr(QDesktopServices, "openUrl", lambda url: opened.append(url.toString()) or True)
    window.run("workspace clouds")
    window.menus.menus["help"].actions()[1].trigger()
    viewer = window.menus.docs_viewer
    qtbot.waitExposed(viewer)
    assert Path(viewer.browser.source().toLocalFile()).name == "clouds.md" and not opened
    document = viewer.browser.document()
    assert "Volumetric clouds" in document.toPlainText()[:200]
    images = [f.charFormat().toImageFormat().name() for block in _blocks(document) for f in _fragments(block)
              if f.charFormat().isImageFormat()]
    assert "clouds.png" in images
    picture = document.resource(QTextDocument.ResourceType.ImageResource, QUrl("clouds.png"))
    assert picture is not None and not picture.isNull() and picture.width() > 100  # the picture itself loaded
    viewer.browser.anchorClicked.emit(viewer.browser.source().resolved(QUrl("console.md")))
    assert Path(viewer.browser.source().toLocalFile()).name == "console.md" and not opened  # followed in place
    viewer.browser.anchorClicked.emit(QUrl("https://example.org/"))
    assert opened == ["https://example.org/"]  # outside links go to the desktop


def _blocks(document):
    block = document.begin()
    while block.isValid():
        yield block
        block = block.next()


def _fragments(block):
    it = block.begin()
    while not it.atEnd():
        yield it.fragment()
        it += 1


def test_about_says_which_build_this_is(window):
    seen = answer(QMessageBox.StandardButton.Ok)
    window.menus.menus["help"].actions()[2].trigger()
    assert "Shadelab" in said(seen)[0] and "Qt 6." in said(seen)[0] and "llvmpipe" in said(seen)[0]
