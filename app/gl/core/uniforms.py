"""Uniforms set by name, one way for every renderer.

A GLSL compiler drops a uniform its program never reads, so a name the program lacks is one of two things: a
uniform optimised out under some setting (a shader branch compiled away, a pass that reads only some of a
shared set), which the call site names in `optional`; or a mistake (misspelt, renamed in the shader), which in
debug mode (tests, SHADELAB_GL_DEBUG=1) raises, naming the program and the uniform, and otherwise is skipped so
the frame still draws."""
from __future__ import annotations

from collections.abc import Collection, Mapping

import moderngl

from app.gl.core.gl_state import debug_enabled


class UniformError(LookupError):
    """A program was given a uniform it does not have, and the call site did not say it may lack it."""


def set_uniforms(program: moderngl.Program, values: Mapping[str, object] | None = None, /,
                 optional: Collection[str] = (), **named) -> None:
    """Set each of `values` and `named` (uniform name -> value) that `program` has; the others must be in
    `optional`, or debug mode raises UniformError."""
    missing = []
    for name, value in ({**values, **named} if values else named).items():
        if name in program:
            program[name].value = value
        elif name not in optional:
            missing.append(name)
    if missing and debug_enabled():
        _missing(program, missing)


def program_name(program: moderngl.Program) -> str:
    """The name ShaderLibrary compiled it under (its `.prg`), else its GL object number."""
    return program.extra if isinstance(program.extra, str) else f"#{program.glo}"


def _missing(program: moderngl.Program, names: list[str]) -> None:
    raise UniformError(f"program {program_name(program)!r} has no uniform {', '.join(map(repr, names))} "
                       "(misspelt, renamed, or optimised out: a call site that expects that lists it in optional)")
