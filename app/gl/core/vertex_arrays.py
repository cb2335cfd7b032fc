"""Vertex arrays per program object, for renderers whose programs hot-reload."""
from __future__ import annotations

from typing import Callable

import moderngl


class VertexArrays:
    """Keyed by the Program object, not its GL name: GL may hand a reloaded program the old name."""

    def __init__(self, make: Callable[[moderngl.Program], moderngl.VertexArray]) -> None:
        self._make = make
        self._arrays: dict[moderngl.Program, moderngl.VertexArray] = {}

    def get(self, program: moderngl.Program) -> moderngl.VertexArray:
        vao = self._arrays.get(program)
        if vao is None:
            for old in [p for p in self._arrays if type(p.mglo).__name__ == "InvalidObject"]:
                self._arrays.pop(old).release()  # its program was released by a reload
            vao = self._arrays[program] = self._make(program)
        return vao

    def release(self) -> None:
        """Release every vertex array made (the buffers they read belong to the caller)."""
        for vao in self._arrays.values():
            vao.release()
        self._arrays.clear()
