"""Commands every workspace shares: switching workspaces, scene files, undo, digests. Each acts on the
current workspace through what every workspace has (app/model/workspace.py), never on one by name."""
from __future__ import annotations

import hashlib

from app.console import files
from app.console.console import Console
from app.console.registry import CommandError
from app.model.workspace import Workspaces
from app.model.workspaces import names


def digest(console: Console, workspaces: Workspaces) -> dict[str, str]:
    """Every workspace's parts (models and cameras), the cvars, and which workspace is current."""
    cvars = console.registry.cvars
    parts: dict[str, str] = {}
    for state in workspaces:
        parts.update(state.digest())
    parts["cvars"] = hashlib.sha256("".join(f"{n}={c.serialise()};" for n, c in sorted(cvars.items()))
                                    .encode()).hexdigest()[:16]
    parts["workspace"] = workspaces.name
    return parts


def register(console: Console, workspaces: Workspaces) -> None:
    reg = console.registry
    reg.scope = workspaces.name  # bare command names resolve in the current workspace first

    @reg.command("workspace", "[name]", "Show or switch the workspace: " + ", ".join(names()),
                 completer=lambda prefix: [n for n in names() if n.startswith(prefix)])
    def workspace(name: str | None = None) -> None:
        if name is None:
            console.print(f"workspace is {workspaces.name}")
            return
        if name not in names():
            raise CommandError(f"no workspace {name!r}; choose one of {', '.join(names())}")
        workspaces.name = reg.scope = name

    def scene_files():
        state = workspaces.current
        if state.files is None:
            raise CommandError(f"the {state.name} workspace has no scene files")
        return state.files

    @reg.command("scene.load", "path", "Load the current workspace's scene file (checked before anything changes)")
    def scene_load(path: str) -> None:
        scene_files().load(str(files.readable(console, path)))

    @reg.command("scene.save", "path", "Save the current workspace's scene (atomically)", recorded=False)
    def scene_save(path: str) -> None:
        save = scene_files().save
        target = files.writable(console, path)
        try:
            save(target)
        except OSError as exc:
            raise CommandError(f"cannot write {path}: {exc.strerror}") from None
        console.print(f"saved {target}")

    @reg.command("undo", "", "Undo the last edit of the current workspace")
    def undo() -> None:
        if not workspaces.current.history.undo():
            raise CommandError("nothing to undo")

    @reg.command("redo", "", "Redo the last undone edit of the current workspace")
    def redo() -> None:
        if not workspaces.current.history.redo():
            raise CommandError("nothing to redo")

    @reg.command("digest", "", "Print a digest of every workspace's model and camera, and the cvars",
                 recorded=False)
    def digest_() -> None:
        for name, value in digest(console, workspaces).items():
            console.print(f"{name} {value}")
