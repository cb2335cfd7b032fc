"""Undo and redo by snapshots: a copy of the state before each edit. A run of edits with the same key
(the moves of one drag) keeps the first snapshot only, so the whole drag is one step."""
from __future__ import annotations

from typing import Any, Callable

LIMIT = 200


class SnapshotHistory:
    """`snapshot()` copies the state an edit may change; `restore(copy)` puts one back."""

    def __init__(self, snapshot: Callable[[], Any], restore: Callable[[Any], None]) -> None:
        self._snapshot, self._restore = snapshot, restore
        self._undo: list = []
        self._redo: list = []
        self._last_key = None

    def checkpoint(self, key=None) -> None:
        if key is not None and key == self._last_key:
            return
        self._last_key = key
        self._undo.append(self._snapshot())
        del self._undo[:-LIMIT]
        self._redo.clear()

    def undo(self) -> bool:
        return self._step(self._undo, self._redo)

    def redo(self) -> bool:
        return self._step(self._redo, self._undo)

    def _step(self, source: list, target: list) -> bool:
        """Restore the newest state of `source`, keeping the present in `target`."""
        if not source:
            return False
        target.append(self._snapshot())
        self._restore(source.pop())
        self._last_key = None
        return True
