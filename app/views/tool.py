"""What every workspace's viewport tool is: the mouse and keys over the view, turned into commands."""
from __future__ import annotations

from app.commands.workspaces import COMMANDS


class ViewportTool:
    """Override what the workspace handles; the rest does nothing. `key` returns True when it used the key
    (else the key's `bind` runs)."""

    KEYS = ""  # the mouse and keys it handles, in words (Help > Keys)

    def __init__(self, viewport, state, run) -> None:
        self.viewport = viewport
        self.state = state  # the workspace's (app/model/*_workspace.py)
        self.run = run      # executes one console command line

    def press(self, event) -> None: ...
    def move(self, event) -> None: ...
    def release(self, event) -> None: ...
    def wheel(self, event) -> None: ...
    def double_click(self, event) -> None: ...

    def key(self, event) -> bool:
        return False

    # what the status bar says about the view: keep them cheap, they run on every mouse move or command

    def hover(self, event) -> str:
        """What lies under the cursor: its world or voxel coordinate and its value ("" for nothing)."""
        return ""

    def tool_name(self) -> str:
        """What the mouse does now."""
        return ""

    def render_mode(self) -> str:
        """How the view is drawn (the renderer's method or mode)."""
        return ""

    def settings(self):
        """The workspace's renderer settings, from the cvars and its view."""
        return COMMANDS[self.state.name].render_settings(self.viewport.editor.console, self.state)
