"""Commands every workspace shares: switching workspaces, scene files, digests, help."""
from __future__ import annotations

from typing import TYPE_CHECKING

from app.console.registry import CommandError
from app.io import scene2d, snowflake_scene
from app.model.snowflake import SceneError
from app.model.workspace import NAMES, WORKSPACES

if TYPE_CHECKING:
    from app.editor import Editor


def register(editor: "Editor") -> None:
    console = editor.console
    reg = console.registry

    @reg.command("workspace", "[name]", "Show or switch the workspace: " + ", ".join(NAMES),
                 completer=lambda prefix: [n for n in NAMES if n.startswith(prefix)])
    def workspace(name: str | None = None) -> None:
        if name is None:
            console.print(f"workspace is {editor.workspace}")
            return
        if name not in NAMES:
            raise CommandError(f"no workspace {name!r}; choose one of {', '.join(NAMES)}")
        if not WORKSPACES[NAMES.index(name)].built:
            raise CommandError(f"the {name} workspace is not built yet")
        editor.workspace = name

    @reg.command("scene.load", "path", "Load the current workspace's scene file (checked before anything changes)")
    def scene_load(path: str) -> None:
        if editor.workspace == "lighting2d":
            editor.load_lighting(path)
            return
        if editor.workspace != "snowflake":
            raise CommandError(f"the {editor.workspace} workspace has no scene files yet")
        try:
            flakes, level = snowflake_scene.load(path)
        except SceneError as exc:
            raise CommandError(str(exc)) from None
        editor.snowflake.replace(flakes, level)
        console.print(f"loaded {len(flakes)} flakes from {path}")

    @reg.command("scene.save", "path", "Save the current workspace's scene (atomically)", recorded=False)
    def scene_save(path: str) -> None:
        if editor.workspace not in ("snowflake", "lighting2d"):
            raise CommandError(f"the {editor.workspace} workspace has no scene files yet")
        try:
            if editor.workspace == "lighting2d":
                cam = editor.lighting_camera
                editor.lighting.view = (cam.cx, cam.cy, cam.height)
                scene2d.save(path, editor.lighting)
            else:
                snowflake_scene.save(path, editor.snowflake)
        except OSError as exc:
            raise CommandError(f"cannot write {path}: {exc.strerror}") from None
        console.print(f"saved {path}")

    @reg.command("digest", "", "Print a digest of every workspace's model state", recorded=False)
    def digest() -> None:
        for name, value in editor.digest().items():
            console.print(f"{name} {value}")

