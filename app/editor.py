"""The editor's state without any window: the console, every workspace's model and camera.

Both hosts drive one of these: the Qt main window and the headless `shadelab render/bench`.
"""
from __future__ import annotations


from app.commands import core, snowflake as snowflake_commands
from app.console.console import Console
from app.model.camera2d import Camera2D
from app.model.snowflake import default_scene



class Editor:
    def __init__(self) -> None:
        self.console = Console()
        self.workspace = "snowflake"
        self.snowflake = default_scene()
        self.snowflake_camera = Camera2D()
        core.register(self)
        snowflake_commands.register(self.console, self.snowflake, self.snowflake_camera)

    def execute(self, line: str) -> bool:
        return self.console.execute(line)

    def version(self) -> tuple:
        """Changes whenever anything a host draws changed: redraw when it differs."""
        cam = self.snowflake_camera
        return (self.workspace, self.snowflake.version, cam.cx, cam.cy, cam.height)

    def digest(self) -> dict[str, str]:
        return {"snowflake": self.snowflake.digest()}
