"""The editor's state without any window: the console, every workspace's model and camera.

Both hosts drive one of these: the Qt main window and the headless `shadelab render/exec/bench`.
"""
from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Callable

from app.commands import core, lighting2d as lighting_commands, snowflake as snowflake_commands, \
    volume as volume_commands
from app.console import builtins, files
from app.console.binds import Binds
from app.console.console import Console
from app.console.demo import Clock, MonotonicClock
from app.console.demos import Demos
from app.io import scene2d
from app.model.camera2d import Camera2D
from app.model.lighting2d import Scene2D
from app.model.snowflake import default_scene
from app.model.volume import Volume
from app.model.volume_samples import make
from app.model.volume_view import VolumeView
from app.resources import SCENES

START_CONFIGS = ("default.cfg", "shadelab.cfg")
DEFAULT_2D_SCENE = SCENES / "j_concave_three_lights.json"


class Editor:
    """`clock` times demos (a virtual one in tests); `frame` draws one frame for timedemo."""

    def __init__(self, clock: Clock | None = None, frame: Callable[[], None] | None = None,
                 configs: bool = True) -> None:
        self.console = Console()
        self.binds = Binds()
        self.workspace = "snowflake"
        self.snowflake = default_scene()
        self.snowflake_camera = Camera2D()
        self.volume = Volume(make("coords3d"))  # Tex3Dtrace opened coords3d by default
        self.volume_view = VolumeView()
        self.lighting = scene2d.load(DEFAULT_2D_SCENE)
        self.lighting_camera = Camera2D(*self.lighting.view)
        # what the 2D view draws besides the scene (view state, not model: no command changes it)
        self.lighting_selection: tuple[str, int] | None = None
        self.lighting_pending: list[tuple[float, float]] = []  # the points of a hull being drawn
        # per workspace: (load, save) of its scene files and (undo, redo), filled in by its commands
        self.scene_files: dict[str, tuple[Callable[[str], None], Callable[[str], None]]] = {}
        self.histories: dict[str, tuple[Callable[[], bool], Callable[[], bool]]] = {}
        self.lua = builtins.register(self.console, self.binds)
        self.demos = Demos(self.console, clock or MonotonicClock(), self.state_commands, frame)
        core.register(self)
        snowflake_commands.register(self.console, self.snowflake, self.snowflake_camera, self.demos.arg_checks)
        volume_commands.register(self)
        lighting_commands.register(self)
        if configs:
            self.run_start_configs()

    def run_start_configs(self) -> None:
        """default.cfg and shadelab.cfg from the resources, then the user's archived config."""
        for name in START_CONFIGS:
            builtins.exec_file(self.console, name)
        if files.user_config().is_file():
            builtins.exec_file(self.console, str(files.user_config()))

    def execute(self, line: str) -> bool:
        return self.console.execute(line)

    def version(self) -> tuple:
        """Changes whenever anything a host draws changed: redraw when it differs."""
        cam, cam2 = self.snowflake_camera, self.lighting_camera
        return (self.workspace, self.snowflake.version, cam.cx, cam.cy, cam.height, self.volume.version,
                self.volume_view.key(), self.console.registry.cvar_changes, self.lighting.version,
                cam2.cx, cam2.cy, cam2.height)

    def replace_lighting(self, scene: Scene2D) -> None:
        """Put a loaded 2D scene in place (its view becomes the camera's); version keeps growing."""
        scene.version = self.lighting.version + 1
        self.lighting = scene
        self.lighting_history.retarget(scene)
        cam = self.lighting_camera
        cam.cx, cam.cy, cam.height = scene.view

    def digest(self) -> dict[str, str]:
        cvars = hashlib.sha256("".join(f"{n}={c.serialise()};" for n, c in sorted(self.console.registry.cvars.items()))
                               .encode()).hexdigest()[:16]
        v = self.volume_view
        view = hashlib.sha256(repr((v.key(), self.workspace)).encode()).hexdigest()[:16]
        return {"snowflake": self.snowflake.digest(), "volume": self.volume.digest(), "lighting2d": self.lighting.digest(),
                "cvars": cvars, "view": view}

    def state_commands(self, demo_path: Path) -> list[str]:
        """Commands that rebuild the current state from any other: a demo's opening lines. Each command
        module says its own part (the voxels may go into a snapshot file beside the demo)."""
        lines = volume_commands.state_commands(self, demo_path)
        lines += snowflake_commands.state_commands(self.snowflake, self.snowflake_camera)
        lines += lighting_commands.state_commands(self)
        lines += [c.assignment() for _name, c in sorted(self.console.registry.cvars.items())]
        lines.append(f"workspace {self.workspace}")
        return lines
