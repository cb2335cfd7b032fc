"""What every workspace's state is, and the editor's list of them in switcher order.

A workspace is one object (docs/architecture.md rule 7): its model, its camera or view, its undo history, its part of
the editor's version and digest, the commands that rebuild it at the start of a demo, and its scene files.
Each layer keeps one mapping from the workspace's name to its part there (app/commands, app/gl,
app/views, app/bench): docs/architecture.md lists them."""
from __future__ import annotations

import hashlib
from pathlib import Path
from dataclasses import dataclass
from typing import Callable, ClassVar, Protocol


class History(Protocol):
    def undo(self) -> bool: ...  # False: nothing to undo
    def redo(self) -> bool: ...
    def undo_name(self) -> str | None: ...  # the step undo would take back ("Stroke"); None: nothing to undo
    def redo_name(self) -> str | None: ...


@dataclass(frozen=True)
class SceneFiles:
    """How a workspace's scene goes to and from a file; its commands fill it in (they know the formats
    and the file policy). `load` returns the file it read, which names the document: a lookup may find it
    elsewhere than as given (the volume's looks beside a running demo and in the user folder).
    `suffixes[0]` names a demo's snapshot of the scene and its autosave, unless `keeping` says otherwise.

    `format`: the "format" its JSON files name, which tells them from other workspaces' JSON files (`open`).
    `new`: puts an empty (or the default) scene in place (File > New, `scene.new`).
    `replacing`: its own verbs that put another document in place (a sample; the volume's `new`, its New): the
    editor asks before they drop unsaved changes, and the scene is untitled after them. An edit that undo takes
    back (clear, reset) is none of them: it never asks, and the scene keeps its file, with unsaved changes.
    `verbs`: its own load and save verbs, if it has any besides scene.load and scene.save (the volume's
    `load` and `save`): they return the file they read or wrote, which names the scene's file as those do.
    `keeping`: the suffix of a file that keeps the scene as it stands, where that depends on the scene (a scalar
    volume's window and colour map only go into .nrrd): its autosave takes it.
    `read_only`: the suffixes it reads but never writes (NIfTI, DICOM): Save asks where, as for an untitled scene.
    `claims`: whether a path of none of its suffixes is its file all the same (a folder of DICOM slices).
    `beside`: the suffixes of files a save may write beside the scene's, in place of its suffix (a scan's labels:
    `ct.nrrd` -> `ct.seg.nrrd`): a demo's snapshot has them beside it too."""
    load: Callable[[str], str]
    save: Callable[[str], None]
    suffixes: tuple[str, ...]
    format: str | None = None
    new: Callable[[], None] | None = None
    replacing: tuple[str, ...] = ()
    verbs: tuple[str, str] | None = None
    keeping: Callable[[], str] | None = None
    read_only: tuple[str, ...] = ()
    claims: Callable[[str], bool] | None = None
    beside: tuple[str, ...] = ()

    def keeping_suffix(self) -> str:
        return self.suffixes[0] if self.keeping is None else self.keeping()

    def suffix(self, path: str) -> str | None:
        """The longest of `suffixes` that `path`'s name ends with (".nii.gz" before ".gz"), else None."""
        name = Path(path).name.lower()
        return max((s for s in self.suffixes if name.endswith(s)), key=len, default=None)

    def writes(self, path: str) -> bool:
        """Whether a save may go to `path`, the file its scene came from: not a format it only reads."""
        return self.suffix(path) not in self.read_only and (self.claims is None or not self.claims(path))


class Workspace:
    """Base of every workspace's state; subclasses name themselves and hold their model."""

    name: ClassVar[str]
    history: History
    files: SceneFiles | None = None

    def version(self) -> tuple:
        """Changes whenever anything the workspace draws changed: hosts redraw when it differs."""
        raise NotImplementedError

    def digest(self) -> dict[str, str]:
        """Short hashes of the model and of the camera, by part name (the `digest` command prints them)."""
        raise NotImplementedError

    def document_digest(self) -> str:
        """A hash of what the scene file holds (not the camera, not the selection): the scene has unsaved
        changes while it differs from the one at the last save or load, so undoing back clears them."""
        return self.digest()[self.name]

    def document_model(self) -> tuple[object, object] | None:
        """The object the scene file holds and its version, where it keeps one: the document digest is worked out
        again only after either changes (hosts ask after every command, a camera drag too). None: every time."""
        return None

    def frame_commands(self, aspect: float) -> list[str]:
        """Commands that put the view where it shows the whole scene, in a view `aspect` wide per unit of height
        (Frame All, `view.frame`); none where there is nothing to frame."""
        return []

    def load_frame_commands(self, aspect: float) -> list[str]:
        """After a file was loaded: the commands that frame it (Frame All), where it is not in view already."""
        return self.frame_commands(aspect)

    def opening_commands(self, snapshot: Callable[..., str]) -> list[str]:
        """Commands that rebuild this state from any other: a demo's opening lines. `snapshot()` saves the
        scene beside the demo and returns its path as one console word (quoted where it must be), for state too
        big for command lines; `snapshot(suffix)` saves it in another of its formats than `files.suffixes[0]`."""
        raise NotImplementedError


def short_hash(*values) -> str:
    return hashlib.sha256(repr(values).encode()).hexdigest()[:16]


@dataclass(frozen=True)
class WorkspaceInfo:
    name: str
    title: str
    state: type[Workspace]


class MissingEntry(LookupError):
    """A workspace a layer's mapping lacks: a mistake in the code (tests/test_workspace_mappings.py), said by name."""


class WorkspaceMapping(dict):
    """A layer's mapping from a workspace's name to its part there; looking up a name it lacks raises MissingEntry
    naming the mapping, where a `.get` would draw an empty background or leave a panel out without a word."""

    def __init__(self, where: str, entries: dict) -> None:
        super().__init__(entries)
        self.where = where  # the mapping's name and file, for the message

    def __missing__(self, name: str):
        raise MissingEntry(f"the {name!r} workspace has no entry in {self.where} "
                           "(docs/architecture.md, \"A workspace is a unit\")")


class Workspaces:
    """The editor's workspaces in switcher order, by name; one of them is current."""

    def __init__(self, states: list[Workspace], current: str) -> None:
        self._states = {state.name: state for state in states}
        self.name = current  # the current workspace's
        self.view_aspect = 1.0  # width / height of the view a host last drew (none headless): Frame All fits it

    def __iter__(self):
        return iter(self._states.values())

    def __getitem__(self, name: str) -> Workspace:
        return self._states[name]

    def __contains__(self, name: str) -> bool:
        return name in self._states

    @property
    def current(self) -> Workspace:
        return self._states[self.name]
