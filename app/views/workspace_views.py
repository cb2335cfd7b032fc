"""The views layer's mapping: each workspace's mouse and key tool in the viewport, and its panel in the
editor dock (with the dock width it wants)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from PySide6.QtGui import QColor
from PySide6.QtWidgets import QColorDialog, QFrame, QScrollArea, QWidget

from app.views.clouds_panel import CloudsPanel
from app.views.clouds_tool import CloudsTool
from app.views.lighting2d_panel import Lighting2DPanel
from app.views.lighting2d_tool import Lighting2DTool
from app.views.lights3d_panel import Lights3DPanel
from app.views.lights3d_tool import Lights3DTool
from app.views.volume.slice_painter import SlicePainter
from app.views.volume.slice_picker import SlicePicker
from app.views.snowflake_panel import SnowflakePanel
from app.views.snowflake_tool import SnowflakeTool
from app.views.volume.tool import VolumeTool
from app.commands.volume_labels import BRUSH_LABEL
from app.views.volume.transfer_editor import TransferEditor
from app.console.registry import SCRIPTS
from app.model.workspace import WorkspaceMapping


DEFAULT_DOCK_WIDTH = 260


@dataclass(frozen=True)
class WorkspaceDock:
    """A dock of the workspace's own, under the bench's, shown while the workspace is current (View lists it,
    `ui.dock KEY` shows it): `make(window, state)` makes its widget, whose `sync()` brings it in line with the
    model."""
    key: str
    title: str
    make: Callable[..., QWidget]


@dataclass(frozen=True)
class WorkspaceViews:
    """`tool(viewport, state, run)` handles the viewport's mouse and keys (press, move, release, wheel;
    optionally double_click and key); `panel(window, state, tool)` makes the dock's widget, whose `sync()`
    brings it in line with the model while the workspace is current; `docks`, the workspace's own docks."""
    tool: Callable | None = None
    panel: Callable[..., QWidget] | None = None
    dock_width: int = DEFAULT_DOCK_WIDTH
    docks: tuple[WorkspaceDock, ...] = ()


class Scrolled(QScrollArea):
    """A panel in a scroll area: showing a selection's properties must not resize the dock (and move the
    view under the mouse in the middle of a drag)."""

    def __init__(self, panel) -> None:
        super().__init__(widgetResizable=True, frameShape=QFrame.Shape.NoFrame)
        self.setWidget(panel)
        self.sync = panel.sync


def lighting2d_panel(window, state, tool) -> QWidget:
    panel = Lighting2DPanel(window.editor, state, window.run, tool)
    window.viewport.view_changed.connect(panel.sync)  # the tool's selection shows in the panel
    return Scrolled(panel)


def volume_panel(window, state, tool) -> QWidget:
    """The slice painter, and the dialogs the volume's binds open (what they choose comes back as commands)."""
    reg = window.editor.console.registry.scoped(state.name)
    view = state.view
    painter = SlicePainter(window.editor, state, window.run)

    def colour_dialog(title: str, rgba, alpha: bool) -> QColor | None:
        options = QColorDialog.ColorDialogOption.ShowAlphaChannel if alpha else QColorDialog.ColorDialogOption(0)
        colour = QColorDialog.getColor(QColor(*rgba), window, title, options)
        return colour if colour.isValid() else None

    @reg.command("ui.brushcolor", "", "Choose the brush colour in a dialog (painter key c); on a scan, the brush's "
                 "label from a menu", recorded=False, allow=SCRIPTS)
    def brush_colour() -> None:
        if state.volume.voxels.labels is not None:
            painter.labels.open_menu()
        elif colour := colour_dialog("Brush colour", view.brush, alpha=True):
            window.run(f"brush.color {colour.red()} {colour.green()} {colour.blue()} {colour.alpha()}")

    @reg.command("ui.labelcolor", "", "Choose the colour of the brush's label in a dialog", recorded=False,
                 allow=SCRIPTS)
    def label_colour() -> None:
        label = window.editor.console.registry.cvars[BRUSH_LABEL].value
        labels = state.volume.voxels.require_labels()
        if label and (colour := colour_dialog(f"Colour of label {label}", labels.colours[label], alpha=False)):
            window.run(f"label.color {label} {colour.red()} {colour.green()} {colour.blue()}")

    @reg.command("ui.background", "", "Choose the 3D view's background colour (key c)", recorded=False, allow=SCRIPTS)
    def background() -> None:
        if colour := colour_dialog("Background colour", view.background, alpha=False):
            window.run(f"vol.background {colour.red()} {colour.green()} {colour.blue()}")

    @reg.command("ui.slicepicker", "", "Open the slice picker (key v)", recorded=False, allow=SCRIPTS)
    def slice_picker() -> None:
        if painter.picker is None:
            painter.picker = SlicePicker(state, tool, window.run, window)
            painter.picker.finished.connect(lambda _r: setattr(painter, "picker", None))
        painter.picker.show()

    return painter


VIEWS: dict[str, WorkspaceViews] = WorkspaceMapping("VIEWS (app/views/workspace_views.py)", {
    "lighting2d": WorkspaceViews(Lighting2DTool, lighting2d_panel, 300),
    "volume": WorkspaceViews(VolumeTool, volume_panel, 520, docks=(
        WorkspaceDock("transfer", "Transfer function", lambda window, state: TransferEditor(state, window.run)),)),
    "clouds": WorkspaceViews(CloudsTool, lambda window, state, tool: Scrolled(CloudsPanel(window.editor, state,
                                                                                          window.run)), 420),
    "lights3d": WorkspaceViews(Lights3DTool, lambda window, state, tool: Scrolled(Lights3DPanel(window.editor, state,
                                                                                               window.run)), 320),
    "snowflake": WorkspaceViews(SnowflakeTool, lambda window, state, tool: SnowflakePanel(state, window.run)),
})
