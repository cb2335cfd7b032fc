"""GL side of the shader framework: compiles `.prg` programs with moderngl, maps
driver errors back to the edited source line and hot-reloads changed files."""

from __future__ import annotations

import ctypes
import logging
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from pathlib import Path

import moderngl

from app.gl.core.shader_source import (GSLimits, ProgramSpec, ShaderError, Stage, StageSource, default_cache_dir,
                                       load_stage, parse_driver_log, parse_prg, write_prs)

log = logging.getLogger(__name__)

GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS = 0x8DE1
# GL 3.2 spec minimums, used when the driver cannot be asked.
_MIN_OUTPUT_VERTICES = 256
_MIN_TOTAL_OUTPUT_COMPONENTS = 1024
_GL_LIBRARIES = (
    "libOpenGL.so.0",
    "libGL.so.1",
    "opengl32",
    "/System/Library/Frameworks/OpenGL.framework/OpenGL",
)

# moderngl titles each failing stage's log `<stage>_shader` over a `====` rule.
_LOG_TITLE = re.compile(r"^(\w+)\n=+\n", re.MULTILINE)
_STAGE_TITLES = {f"{stage.label}_shader": stage for stage in Stage}


def query_gs_limits(ctx: moderngl.Context) -> GSLimits:
    """Geometry-shader output limits of `ctx`, which must be current."""
    vertices = int(ctx.info.get("GL_MAX_GEOMETRY_OUTPUT_VERTICES") or _MIN_OUTPUT_VERTICES)
    return GSLimits(vertices, _total_output_components())


def _total_output_components() -> int:
    """moderngl's ctx.info lacks this limit, so ask the system GL library directly
    (it answers for the current context)."""
    for name in _GL_LIBRARIES:
        try:
            get_integer = ctypes.CDLL(name).glGetIntegerv
        except (OSError, AttributeError):
            continue
        value = ctypes.c_int(0)
        get_integer(GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS, ctypes.byref(value))
        if value.value > 0:
            return value.value
    return _MIN_TOTAL_OUTPUT_COMPONENTS


def _mtime(path: Path) -> int | None:
    try:
        return path.stat().st_mtime_ns
    except OSError:
        return None  # missing files are dependencies too: creating one is a change


@dataclass
class _Entry:
    name: str
    varyings: tuple[str, ...]
    defines: tuple[tuple[str, str], ...] = ()
    program: moderngl.Program | None = None
    error: ShaderError | None = None
    mtimes: dict[Path, int | None] = field(default_factory=dict)

    def changed(self) -> bool:
        return any(_mtime(path) != stamp for path, stamp in self.mtimes.items())


class ShaderLibrary:
    """Programs built from `<name>.prg` files, compiled on first use and hot-reloaded.

    Fetch `program(name)` whenever drawing: a successful reload releases the old
    program object, while a failed one keeps it so the view keeps rendering."""

    def __init__(
        self,
        ctx: moderngl.Context,
        search_dirs: Iterable[Path],
        cache_dir: Path | None = None,
        on_error: Callable[[ShaderError], None] | None = None,
    ):
        self.ctx = ctx
        self.search_dirs = [Path(d) for d in search_dirs]
        self.cache_dir = Path(cache_dir) if cache_dir is not None else default_cache_dir()
        self.on_error = on_error
        self.errors: dict[str, ShaderError] = {}
        self.limits = query_gs_limits(ctx)
        self._entries: dict[tuple, _Entry] = {}

    def program(self, name: str, varyings: tuple[str, ...] = (), defines: dict | None = None) -> moderngl.Program:
        """`defines`: {name: value} as `#define`s in every stage, one program for each set."""
        key = (name, tuple(varyings), tuple(sorted((k, str(v)) for k, v in (defines or {}).items())))
        entry = self._entries.get(key)
        if entry is None:
            entry = self._entries[key] = _Entry(name, key[1], key[2])
            self._rebuild(entry)
        # A program that never compiled is retried by reload_changed() once its
        # files change, not on every call (callers ask once per frame).
        if entry.program is None:
            assert entry.error is not None
            raise entry.error
        return entry.program

    def reload_changed(self) -> list[str]:
        reloaded: list[str] = []
        for entry in self._entries.values():
            if entry.changed() and self._rebuild(entry) and entry.name not in reloaded:
                reloaded.append(entry.name)
        return reloaded

    def _rebuild(self, entry: _Entry) -> bool:
        deps: set[Path] = set()
        try:
            program = self._compile(entry.name, entry.varyings, deps, entry.defines)
        except ShaderError as error:
            entry.error = self.errors[entry.name] = error
            if self.on_error is not None:
                self.on_error(error)
            return False
        finally:
            entry.mtimes = {path: _mtime(path) for path in deps}
        if entry.program is not None:
            entry.program.release()
        entry.program, entry.error = program, None
        self.errors.pop(entry.name, None)
        return True

    def _compile(self, name: str, varyings: tuple[str, ...], deps: set[Path],
                 defines: tuple[tuple[str, str], ...] = ()) -> moderngl.Program:
        spec = parse_prg(self._find(name, deps), deps)
        sources = {stage: load_stage(path, self.limits, deps, defines) for stage, path in spec.stages.items()}
        self._write_cache(sources.values())
        geometry = sources.get(Stage.GEOMETRY)
        try:
            program = self.ctx.program(
                vertex_shader=sources[Stage.VERTEX].text,
                geometry_shader=geometry.text if geometry else None,
                fragment_shader=sources[Stage.FRAGMENT].text,
                varyings=varyings,
            )
        except moderngl.Error as exc:
            raise _driver_error(str(exc), spec, sources) from None
        program.extra = name  # what set_uniforms' errors call it (app/gl/core/uniforms.py)
        return program

    def _find(self, name: str, deps: set[Path]) -> Path:
        for directory in self.search_dirs:
            candidate = directory / f"{name}.prg"
            deps.add(candidate)  # a file appearing earlier in the search order must trigger a reload
            if candidate.is_file():
                return candidate
        dirs = ", ".join(str(d) for d in self.search_dirs) or "(no search directories)"
        raise ShaderError(f"no program {name!r}: {name}.prg not found in {dirs}")

    def _write_cache(self, sources: Iterable[StageSource]) -> None:
        # The .prs files are a debugging aid; an unwritable cache must not stop rendering.
        try:
            for source in sources:
                write_prs(source, self.cache_dir)
        except OSError as exc:
            log.warning("cannot write preprocessed shaders to %s: %s", self.cache_dir, exc)


def _driver_error(text: str, spec: ProgramSpec, sources: dict[Stage, StageSource]) -> ShaderError:
    """Turn moderngl's compile/link failure text into an error at the origin line."""
    title = _LOG_TITLE.search(text)
    line, message = parse_driver_log(text[title.end() :] if title else text)
    stage = _STAGE_TITLES.get(title[1]) if title else None
    if stage is None or stage not in sources:  # link errors name no stage or line: blame the program
        return ShaderError(f"link failed: {message}", spec.path)
    source = sources[stage]
    origin = source.origin(line) if line is not None else None
    return ShaderError(
        f"{stage.label} shader {source.path.name}: {message}",
        origin.file if origin else source.path,
        origin.line if origin else None,
    )
