"""Undo and redo by snapshots: a copy of the state before each edit, with the edit's name ("Move Flake",
what Edit > Undo says). A run of edits with the same key (the moves of one drag) keeps the first snapshot
only, so the whole drag is one step."""
from __future__ import annotations

from typing import Any, Callable

LIMIT = 200


def setting_name(thing: str, field: str) -> str:
    """The name of an edit that sets one field of a thing: "Move Light" for its position, else "Set Light colour"."""
    return f"Move {thing}" if field == "position" else f"Set {thing} {field.replace('_', ' ')}"


class SnapshotHistory:
    """`snapshot()` copies the state an edit may change; `restore(copy)` puts one back."""

    def __init__(self, snapshot: Callable[[], Any], restore: Callable[[Any], None]) -> None:
        self._snapshot, self._restore = snapshot, restore
        self._undo: list = []
        self._redo: list = []
        self._last_key = None

    def checkpoint(self, name: str, key=None) -> None:
        """Before an edit called `name`; one with the key of the edit before it joins that one's step."""
        if key is not None and key == self._last_key:
            return
        self._last_key = key
        self._undo.append((name, self._snapshot()))
        del self._undo[:-LIMIT]
        self._redo.clear()

    def undo(self) -> bool:
        return self._step(self._undo, self._redo)

    def redo(self) -> bool:
        return self._step(self._redo, self._undo)

    def undo_name(self) -> str | None:
        return self._undo[-1][0] if self._undo else None

    def redo_name(self) -> str | None:
        return self._redo[-1][0] if self._redo else None

    def _step(self, source: list, target: list) -> bool:
        """Restore the newest state of `source`, keeping the present in `target` under the same name."""
        if not source:
            return False
        name, state = source.pop()
        target.append((name, self._snapshot()))
        self._restore(state)
        self._last_key = None
        return True
