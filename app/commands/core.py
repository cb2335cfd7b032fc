"""Commands every workspace shares: switching workspaces, scene files, undo, digests. Each acts on the
current workspace (or, for `open`, the one a file belongs to) through what every workspace has
(app/model/workspace.py), never on one by name."""
from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

from app.commands.documents import Documents
from app.console import files
from app.console.command_set import CommandSet, Context
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


@dataclass(frozen=True)
class Shared:
    """What the shared commands reach: every workspace, and their documents (the files their scenes are)."""
    workspaces: Workspaces
    documents: Documents


COMMANDS = CommandSet(None)
Ctx = Context[Shared]


def register(console: Console, workspaces: Workspaces) -> Documents:
    """The shared commands; returns the workspaces' documents (track() them once every workspace's commands
    are registered)."""
    reg = console.registry
    reg.scope = workspaces.name  # bare command names resolve in the current workspace first
    documents = Documents(console, workspaces)
    reg.add_cvar(Cvar("r_frameBudget", float, FRAME_BUDGET_MS, "While you drag, orbit or play, each workspace "
                      "draws its most accurate measured level whose frame fits this many ms, and refines when still",
                      min=5.0, max=2000.0, archive=True))
    COMMANDS.register(reg, Ctx(console, Shared(workspaces, documents)))
    return documents


@COMMANDS.command("workspace", "[name]", "Show or switch the workspace: " + ", ".join(names()),
                  completer=lambda ctx, prefix: [n for n in names() if n.startswith(prefix)], allow=SCRIPTS)
def workspace(ctx: Ctx, name: str | None = None) -> None:
    workspaces = ctx.state.workspaces
    if name is None:
        ctx.console.print(f"workspace is {workspaces.name}")
        return
    if name not in names():
        raise CommandError(f"no workspace {name!r}; choose one of {', '.join(names())}")
    workspaces.name = ctx.console.registry.scope = name


def _scene_files(ctx: Ctx):
    state = ctx.state.workspaces.current
    if state.files is None:
        raise CommandError(f"the {state.name} workspace has no scene files")
    return state.files


@COMMANDS.command("view.frame", "[aspect:float]", "Frame All: put the view where it shows the whole scene (keys F "
                  "and View > Frame All); `aspect`, the view's width over its height, defaults to the view's own",
                  recorded=False, allow=SCRIPTS)
def view_frame(ctx: Ctx, aspect: float | None = None) -> None:
    if aspect is not None and not (math.isfinite(aspect) and 0.01 <= aspect <= 100.0):
        raise CommandError(f"the aspect must be within 0.01..100, got {aspect:g}")
    if not ctx.state.documents.frame(ctx.state.workspaces.current, aspect):
        ctx.console.print(f"the {ctx.state.workspaces.name} scene is empty: nothing to frame")


@COMMANDS.command("scene.load", "path:read", "Load the current workspace's scene file (checked before anything "
                  "changes)", allow=SCRIPTS)
def scene_load(ctx: Ctx, path: str) -> None:
    documents, state = ctx.state.documents, ctx.state.workspaces.current
    load = _scene_files(ctx).load
    documents.may_replace(state, f"scene.load {quote(path)}")
    documents.named(state, load(path))
    documents.frame_loaded(state)


def _load_in_its_workspace(ctx: Ctx, path: str, line: str) -> tuple[Workspace, str]:
    """Load `path` (resolved by the file policy) into the workspace it belongs to (asking first if that drops
    unsaved changes there) and switch to it; that workspace and the file read."""
    state = ctx.state.documents.owner(path)
    ctx.state.documents.may_replace(state, line)
    read = state.files.load(path)
    workspace(ctx, state.name)
    return state, read


@COMMANDS.command("open", "path:read", "Open a scene or volume file in the workspace it belongs to (by its "
                  "suffix, and a JSON file's format), and switch to it",
                  completer=lambda ctx, p: files.complete(p, ctx.state.documents.suffixes()), allow=SCRIPTS)
def open_(ctx: Ctx, path: str) -> None:
    state, read = _load_in_its_workspace(ctx, path, f"open {quote(path)}")
    ctx.state.documents.named(state, read)
    ctx.state.documents.frame_loaded(state)


@COMMANDS.command("recover", "autosave:read [original]", "Open an autosaved scene in its workspace as unsaved "
                  "changes to the file `original` (untitled without it); its first save names its file (Save As "
                  "offers `original`): a plain scene.save does not write there")
def recover(ctx: Ctx, autosave: str, original: str | None = None) -> None:
    state, _read = _load_in_its_workspace(ctx, autosave, f"recover {quote(autosave)}")
    ctx.state.documents.named(state, original, recovered=True)


@COMMANDS.command("scene.new", "", "Put an empty (or the default) scene in the current workspace, untitled",
                  allow=SCRIPTS)
def scene_new(ctx: Ctx) -> None:
    documents, state = ctx.state.documents, ctx.state.workspaces.current
    new = _scene_files(ctx).new
    if new is None:
        raise CommandError(f"the {state.name} workspace has no empty scene")
    documents.may_replace(state, "scene.new")
    new()
    documents.named(state, None)


@COMMANDS.command("scene.save", "[path:write]", "Save the current workspace's scene (atomically); without a path, "
                  "to the file it was opened from or last saved to", recorded=False, allow=SCRIPTS)
def scene_save(ctx: Ctx, path: str | None = None) -> None:
    documents, state = ctx.state.documents, ctx.state.workspaces.current
    save = _scene_files(ctx).save
    if path is None and documents.named_by_script(state):
        raise CommandError("a script named this scene's file: give the file to save it to (or File > Save As)")
    target = path or documents.save_path(state)
    if target is None:
        if documents.recovered(state):
            raise CommandError("the scene was recovered from an autosave: give the file to save it to (its first "
                               "save names its file; File > Save asks, offering the file it was edited from)")
        raise CommandError("the scene is untitled or a shipped sample: give the file to save it to")
    if path is None:  # the document's own file, which a script may not write (a given path is resolved already)
        target = str(files.writable(ctx.console, target))
    try:
        save(target)
    except OSError as exc:
        raise CommandError(f"cannot write {target}: {exc.strerror}") from None
    documents.named(state, str(target))
    ctx.console.print(f"saved {target}")


@COMMANDS.command("undo", "", "Undo the last edit of the current workspace", allow=SCRIPTS)
def undo(ctx: Ctx) -> None:
    if not ctx.state.workspaces.current.history.undo():
        raise CommandError("nothing to undo")


@COMMANDS.command("redo", "", "Redo the last undone edit of the current workspace", allow=SCRIPTS)
def redo(ctx: Ctx) -> None:
    if not ctx.state.workspaces.current.history.redo():
        raise CommandError("nothing to redo")


@COMMANDS.command("digest", "", "Print a digest of every workspace's model and camera, and the cvars",
                  recorded=False, allow=SCRIPTS)
def digest_(ctx: Ctx) -> None:
    for name, value in digest(ctx.console, ctx.state.workspaces).items():
        ctx.console.print(f"{name} {value}")
