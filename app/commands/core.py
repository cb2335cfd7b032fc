"""Commands every workspace shares: switching workspaces, scene files, undo, digests. Each acts on the
current workspace (or, for `open`, the one a file belongs to) through what every workspace has
(app/model/workspace.py), never on one by name."""
from __future__ import annotations

import hashlib
import math

from app.commands.documents import Documents
from app.console import files
from app.console.console import Console
from app.console.quoting import quote
from app.console.registry import SCRIPTS, CommandError, Cvar
from app.model.workspace import Workspace, Workspaces
from app.model.workspaces import names


FRAME_BUDGET_MS = 100.0  # r_frameBudget's default: 10 frames a second while the user works
REPLACING = ("open", "recover", "scene.load", "scene.new")  # the commands here that replace a workspace's scene


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


def register(console: Console, workspaces: Workspaces) -> Documents:
    """The shared commands; returns the workspaces' documents (track() them once every workspace's commands
    are registered)."""
    reg = console.registry
    reg.scope = workspaces.name  # bare command names resolve in the current workspace first
    documents = Documents(console, workspaces)
    reg.add_cvar(Cvar("r_frameBudget", float, FRAME_BUDGET_MS, "While you drag, orbit or play, each workspace "
                      "draws its most accurate measured level whose frame fits this many ms, and refines when still",
                      min=5.0, max=2000.0, archive=True))

    @reg.command("workspace", "[name]", "Show or switch the workspace: " + ", ".join(names()),
                 completer=lambda prefix: [n for n in names() if n.startswith(prefix)], allow=SCRIPTS)
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

    @reg.command("view.frame", "[aspect:float]", "Frame All: put the view where it shows the whole scene (keys F "
                 "and View > Frame All); `aspect`, the view's width over its height, defaults to the view's own",
                 recorded=False, allow=SCRIPTS)
    def view_frame(aspect: float | None = None) -> None:
        if aspect is not None and not (math.isfinite(aspect) and 0.01 <= aspect <= 100.0):
            raise CommandError(f"the aspect must be within 0.01..100, got {aspect:g}")
        if not documents.frame(workspaces.current, aspect):
            console.print(f"the {workspaces.name} scene is empty: nothing to frame")

    @reg.command("scene.load", "path:read", "Load the current workspace's scene file (checked before anything "
                 "changes)", allow=SCRIPTS)
    def scene_load(path: str) -> None:
        load = scene_files().load
        documents.may_replace(workspaces.current, f"scene.load {quote(path)}")
        documents.named(workspaces.current, load(path))
        documents.frame_loaded(workspaces.current)

    def load_in_its_workspace(path: str, line: str) -> tuple[Workspace, str]:
        """Load `path` (resolved by the file policy) into the workspace it belongs to (asking first if that drops
        unsaved changes there) and switch to it; that workspace and the file read."""
        state = documents.owner(path)
        documents.may_replace(state, line)
        read = state.files.load(path)
        workspace(state.name)
        return state, read

    @reg.command("open", "path:read", "Open a scene or volume file in the workspace it belongs to (by its suffix, "
                 "and a JSON file's format), and switch to it",
                 completer=lambda p: files.complete(p, documents.suffixes()), allow=SCRIPTS)
    def open_(path: str) -> None:
        state, read = load_in_its_workspace(path, f"open {quote(path)}")
        documents.named(state, read)
        documents.frame_loaded(state)

    @reg.command("recover", "autosave:read [original]", "Open an autosaved scene in its workspace as unsaved changes "
                 "to the file `original` (untitled without it); its first save names its file (Save As offers "
                 "`original`): a plain scene.save does not write there")
    def recover(autosave: str, original: str | None = None) -> None:
        state, _read = load_in_its_workspace(autosave, f"recover {quote(autosave)}")
        documents.named(state, original, recovered=True)

    @reg.command("scene.new", "", "Put an empty (or the default) scene in the current workspace, untitled",
                 allow=SCRIPTS)
    def scene_new() -> None:
        new = scene_files().new
        if new is None:
            raise CommandError(f"the {workspaces.name} workspace has no empty scene")
        documents.may_replace(workspaces.current, "scene.new")
        new()
        documents.named(workspaces.current, None)

    @reg.command("scene.save", "[path:write]", "Save the current workspace's scene (atomically); without a path, "
                 "to the file it was opened from or last saved to", recorded=False, allow=SCRIPTS)
    def scene_save(path: str | None = None) -> None:
        save = scene_files().save
        if path is None and documents.named_by_script(workspaces.current):
            raise CommandError("a script named this scene's file: give the file to save it to (or File > Save As)")
        target = path or documents.save_path(workspaces.current)
        if target is None:
            if documents.recovered(workspaces.current):
                raise CommandError("the scene was recovered from an autosave: give the file to save it to (its first "
                                   "save names its file; File > Save asks, offering the file it was edited from)")
            raise CommandError("the scene is untitled or a shipped sample: give the file to save it to")
        if path is None:  # the document's own file, which a script may not write (a given path is resolved already)
            target = str(files.writable(console, target))
        try:
            save(target)
        except OSError as exc:
            raise CommandError(f"cannot write {target}: {exc.strerror}") from None
        documents.named(workspaces.current, str(target))
        console.print(f"saved {target}")

    @reg.command("undo", "", "Undo the last edit of the current workspace", allow=SCRIPTS)
    def undo() -> None:
        if not workspaces.current.history.undo():
            raise CommandError("nothing to undo")

    @reg.command("redo", "", "Redo the last undone edit of the current workspace", allow=SCRIPTS)
    def redo() -> None:
        if not workspaces.current.history.redo():
            raise CommandError("nothing to redo")

    @reg.command("digest", "", "Print a digest of every workspace's model and camera, and the cvars",
                 recorded=False, allow=SCRIPTS)
    def digest_() -> None:
        for name, value in digest(console, workspaces).items():
            console.print(f"{name} {value}")

    return documents
