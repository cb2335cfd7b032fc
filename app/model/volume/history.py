"""A volume's undo history: steps that take its voxels back and forth (a changed sub-box of the colours or of a
scan's labels, a quarter turn, a whole image swapped, a window, a label's colour, a spacing), capped by count and
bytes, and the preview of a stroke in progress, kept out of it."""
from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from app.model.volume.labels import Labels
from app.model.volume.scalars import Scalars, TransferFunction
from app.model.volume.voxels import DEFAULT_SPACING, Box, Spacing, Voxels

UNDO_STEPS = 256
UNDO_BYTES = 512 << 20


@dataclass
class Patch:
    """A changed sub-box of the colours, or of a scan's `labels`; `other` holds its contents in the state not
    currently shown (swapped on undo/redo). `allocated`: the edit painted the scan's first label, so undone the
    labels hold none again (as before it), and redone they are made again."""

    box: Box
    other: np.ndarray
    serial: int = 0  # when it was pushed: a batch groups the steps pushed after its mark
    name: str = ""  # what Edit > Undo calls it ("Stroke")
    labels: bool = False
    allocated: bool = False

    @property
    def nbytes(self) -> int:
        return self.other.nbytes

    def apply(self, voxels: Voxels, undo: bool) -> None:
        target = voxels.labels if self.labels else voxels
        if self.allocated and not undo:
            target.allocate()
        view = target.data[self.box.slices()]
        shown = view.copy()
        view[...] = self.other
        self.other = shown
        if self.allocated and undo:
            target.release()
        target.changed(self.box)


@dataclass
class Turn:
    axis: str
    turns: int
    nbytes: int = 0  # stores no voxels: undo is the inverse turn
    serial: int = 0
    name: str = "Rotate"

    def apply(self, voxels: Voxels, undo: bool) -> None:
        voxels.turn(self.axis, -self.turns if undo else self.turns)


@dataclass
class Swap:
    other: np.ndarray  # the whole image not currently shown
    scalars: Scalars | None  # and its scalars
    nbytes: int  # what the replaced image held: fixed, as undo and redo swap images of other sizes in and out
    serial: int = 0
    name: str = ""
    labels: Labels | None = None  # and its labels
    spacing: Spacing = DEFAULT_SPACING  # and its spacing

    @classmethod
    def of(cls, voxels: Voxels, name: str) -> Swap:
        """The step that brings back what `voxels` show now."""
        data, scalars, labels = voxels.data, voxels.scalars, voxels.labels
        held = data.nbytes + (scalars.nbytes if scalars else 0) + (labels.nbytes if labels else 0)
        return cls(data, scalars, held, name=name, labels=labels, spacing=voxels.spacing)

    def apply(self, voxels: Voxels, undo: bool) -> None:
        self.other, self.scalars, self.spacing = voxels.swap(self.other, self.scalars, self.spacing)
        voxels.labels, self.labels = self.labels, voxels.labels


@dataclass
class Respace:
    spacing: Spacing  # the spacing not currently shown
    nbytes: int = 0
    serial: int = 0
    name: str = "Set Spacing"

    def apply(self, voxels: Voxels, undo: bool) -> None:
        self.spacing = voxels.respace(self.spacing)


@dataclass
class Window:
    transfer: TransferFunction  # the scalars' transfer function not currently shown
    nbytes: int = 0  # the colours are made again from the scalars
    serial: int = 0
    name: str = "Set Window"

    def apply(self, voxels: Voxels, undo: bool) -> None:
        shown = voxels.scalars.transfer
        voxels.recolour(self.transfer)
        self.transfer = shown


@dataclass
class LabelColour:
    label: int
    rgb: tuple[int, int, int]  # the label's colour not currently shown
    nbytes: int = 0
    serial: int = 0
    name: str = "Label Colour"

    def apply(self, voxels: Voxels, undo: bool) -> None:
        self.rgb = voxels.labels.set_colour(self.label, self.rgb)


@dataclass
class Group:
    """Steps undone and redone together (the edits of one script)."""

    steps: list
    serial: int = 0
    name: str = ""

    @property
    def nbytes(self) -> int:
        return sum(s.nbytes for s in self.steps)

    def apply(self, voxels: Voxels, undo: bool) -> None:
        for inner in reversed(self.steps) if undo else self.steps:
            inner.apply(voxels, undo)


Step = Patch | Turn | Swap | Window | LabelColour | Respace | Group


class VoxelHistory:
    """The undo and redo steps of one Voxels' edits. An edit changes the voxels, then hands its step here (`record`
    for a painted sub-box, `push` for the others); a preview is shown, but put back before anything else."""

    def __init__(self, voxels: Voxels, max_steps: int = UNDO_STEPS, max_bytes: int = UNDO_BYTES) -> None:
        self.voxels = voxels
        self.max_steps = max_steps
        self.max_bytes = max_bytes
        self._undo: deque[Step] = deque()
        self._redo: list[Step] = []
        self._pushes = 0
        self._preview: Patch | Window | None = None  # painted voxels, or a transfer function, shown unrecorded
        self.nbytes = 0  # what the undo and redo steps hold; a push clears redo, undo/redo only move steps

    @property
    def undo_depth(self) -> int:
        return len(self._undo)

    @property
    def redo_depth(self) -> int:
        return len(self._redo)

    def undo(self) -> bool:
        self.clear_preview()
        if not self._undo:
            return False
        step = self._undo.pop()
        step.apply(self.voxels, undo=True)
        self._redo.append(step)
        return True

    def redo(self) -> bool:
        self.clear_preview()
        if not self._redo:
            return False
        step = self._redo.pop()
        step.apply(self.voxels, undo=False)
        self._undo.append(step)
        return True

    def undo_name(self) -> str | None:
        """What the step undo would take back is called ("Stroke"); None: nothing to undo."""
        return self._undo[-1].name if self._undo else None

    def redo_name(self) -> str | None:
        return self._redo[-1].name if self._redo else None

    @property
    def key(self) -> tuple[int, int, bool]:
        """Changes with every edit pushed, undone or redone and when a preview shows or goes, but not as a preview
        is painted again under the mouse: what the document's digest is kept by (a big volume takes a while to
        hash, and a preview changes the voxels' `version` at every move)."""
        return self._pushes, len(self._undo), self._preview is not None

    @property
    def edits(self) -> int:
        """Undo steps pushed so far, ever: mark it before a batch of edits, then `group_since(mark)`."""
        return self._pushes

    def group_since(self, mark: int, name: str = "Script") -> None:
        """Fold the steps pushed since `edits` was `mark` into one called `name`, so one undo takes them
        all back. Steps from before the mark stay apart, even if the batch undid and redid some of them."""
        steps = []
        while self._undo and self._undo[-1].serial > mark:
            steps.append(self._undo.pop())
        if len(steps) == 1:
            self._undo.append(steps[0])
        elif steps:
            self._undo.append(Group(steps[::-1], serial=steps[0].serial, name=name))

    def record(self, box: Box, before: np.ndarray, name: str, labels: bool = False, allocated: bool = False) -> Box:
        """A sub-box of the colours (of the labels) just written, whose contents were `before`, as one step
        (Patch says what `allocated` is)."""
        self.push(Patch(box, before, name=name, labels=labels, allocated=allocated))
        (self.voxels.labels if labels else self.voxels).changed(box)
        return box

    def push(self, step: Step) -> None:
        """Record an edit; clears redo and drops the oldest steps beyond the count and byte caps."""
        self.nbytes -= sum(s.nbytes for s in self._redo)
        self._redo.clear()
        self._pushes += 1
        step.serial = self._pushes
        self._undo.append(step)
        self.nbytes += step.nbytes
        # A step bigger than the byte cap drops too: that edit cannot be undone, but memory stays bounded.
        while self._undo and (len(self._undo) > self.max_steps or self.nbytes > self.max_bytes):
            self.nbytes -= self._undo.popleft().nbytes

    # --- preview: an edit shown but kept out of the history ----------------------------------

    def preview(self, box: Box, before: np.ndarray, labels: bool = False, allocated: bool = False) -> Box:
        """A sub-box just written, shown (and marked changed) but not recorded: every edit, undo or redo first
        puts the voxels back (`clear_preview`), so it can never mix with the history."""
        self._preview = Patch(box, before, labels=labels, allocated=allocated)
        (self.voxels.labels if labels else self.voxels).changed(box)
        return box

    def preview_transfer(self, transfer: TransferFunction) -> None:
        """A transfer function shown but not recorded (an opacity point being dragged), put back as `preview`'s."""
        self.clear_preview()
        self._preview = Window(self.voxels.scalars.transfer)
        self.voxels.recolour(transfer)

    def clear_preview(self) -> None:
        if isinstance(self._preview, Window):
            window, self._preview = self._preview, None
            window.apply(self.voxels, undo=True)
        elif self._preview is not None:
            patch, self._preview = self._preview, None
            patch.apply(self.voxels, undo=True)
