"""What every workspace's viewport tool is: the mouse and keys over the view, turned into commands."""
from __future__ import annotations


class ViewportTool:
    """Override what the workspace handles; the rest does nothing. `key` returns True when it used the key
    (else the key's `bind` runs)."""

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
