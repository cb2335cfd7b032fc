"""Undo and redo for the 2D scene: a snapshot before each edit. A run of edits with the same key (the
moves of one drag) keeps the first snapshot only, so the whole drag is one step."""
from __future__ import annotations

import copy

from app.model.lighting2d import Scene2D

FIELDS = ("ambient", "lights", "hulls", "background", "normal_map")
LIMIT = 200


class History2D:
    def __init__(self, scene: Scene2D) -> None:
        self.scene = scene
        self._undo: list[dict] = []
        self._redo: list[dict] = []
        self._last_key = None

    def _snapshot(self) -> dict:
        return copy.deepcopy({name: getattr(self.scene, name) for name in FIELDS})

    def _restore(self, state: dict) -> None:
        for name, value in state.items():
            setattr(self.scene, name, value)
        self.scene.touch()

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

    def _step(self, source: list[dict], target: list[dict]) -> bool:
        """Restore the newest state of `source`, keeping the present in `target`."""
        if not source:
            return False
        target.append(self._snapshot())
        self._restore(source.pop())
        self._last_key = None
        return True

    def retarget(self, scene: Scene2D) -> None:
        """Follow a scene object that replaced the old one (history stays: loading can be undone)."""
        self.scene = scene
