"""Commands every workspace shares: switching workspaces, scene files, undo, digests, help. A workspace
plugs its scene files into `editor.scene_files` and its history into `editor.histories`."""
from __future__ import annotations

from typing import TYPE_CHECKING

from app.console import files
from app.console.registry import CommandError
from app.io import snowflake_scene
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

    def load_snowflakes(path: str) -> None:
        try:
            flakes, level = snowflake_scene.load(path)
        except SceneError as exc:
            raise CommandError(str(exc)) from None
        editor.snowflake.replace(flakes, level)
        console.print(f"loaded {len(flakes)} flakes from {path}")

    editor.scene_files["snowflake"] = (load_snowflakes, lambda path: snowflake_scene.save(path, editor.snowflake))

    def scene_file(which: int):
        handlers = editor.scene_files.get(editor.workspace)
        if handlers is None:
            raise CommandError(f"the {editor.workspace} workspace has no scene files yet")
        return handlers[which]

    @reg.command("scene.load", "path", "Load the current workspace's scene file (checked before anything changes)")
    def scene_load(path: str) -> None:
        scene_file(0)(str(files.readable(console, path)))

    @reg.command("scene.save", "path", "Save the current workspace's scene (atomically)", recorded=False)
    def scene_save(path: str) -> None:
        save = scene_file(1)
        target = files.writable(console, path)
        try:
            save(target)
        except OSError as exc:
            raise CommandError(f"cannot write {path}: {exc.strerror}") from None
        console.print(f"saved {target}")

    def history_step(which: int, nothing: str) -> None:
        # a workspace without its own history (the snowflake) undoes the volume, as before there were two
        step = editor.histories.get(editor.workspace, editor.histories["volume"])[which]
        if not step():
            raise CommandError(nothing)

    @reg.command("undo", "", "Undo the last edit of the current workspace (the volume's where it has none)")
    def undo() -> None:
        history_step(0, "nothing to undo")

    @reg.command("redo", "", "Redo the last undone edit of the current workspace")
    def redo() -> None:
        history_step(1, "nothing to redo")

    @reg.command("digest", "", "Print a digest of every workspace's model state", recorded=False)
    def digest() -> None:
        for name, value in editor.digest().items():
            console.print(f"{name} {value}")

