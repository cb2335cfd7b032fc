"""Shader source handling: stage naming, .prg containers, the //# template
preprocessor, geometry-shader headers and driver-log parsing.

Pure text processing so it can be tested and reused without a GL context.
Every produced line remembers where it came from, so a driver error on line N
of the compiled text can be reported against the file the user actually edits
(a stage file or an included .shl template library).
"""

from __future__ import annotations

import enum
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path

from app.io.cache import cache_root


class ShaderError(Exception):
    """A shader problem located (when possible) at a source file and line."""

    def __init__(self, message: str, file: Path | None = None, line: int | None = None):
        super().__init__(message)
        self.message = message
        self.file = Path(file) if file is not None else None
        self.line = line

    def __str__(self) -> str:
        location = [str(part) for part in (self.file, self.line) if part is not None]
        return ":".join([*location, f" {self.message}"]) if location else self.message


class Stage(enum.Enum):
    VERTEX = "VS"
    GEOMETRY = "GS"
    FRAGMENT = "FS"

    @property
    def label(self) -> str:
        return self.name.lower()


def stage_from_path(path: Path) -> Stage:
    """The stage a file holds, from the `_VS` / `_GS` / `_FS` suffix of its stem."""
    _, underscore, suffix = Path(path).stem.rpartition("_")
    try:
        return Stage(suffix if underscore else "")
    except ValueError:
        raise ShaderError(
            "shader file name must end in _VS, _GS or _FS (before the extension)", path
        ) from None


def default_cache_dir() -> Path:
    """Where preprocessed (.prs) files go; never beside the (possibly read-only) sources."""
    return cache_root() / "shaders"


# --------------------------------------------------------------------------- .prg


@dataclass(frozen=True)
class ProgramSpec:
    path: Path
    stages: dict[Stage, Path]  # in pipeline order: VS, optional GS, FS


def parse_prg(path: Path, deps: set[Path] | None = None) -> ProgramSpec:
    """Parse a `.prg` container. `deps` collects every file looked at, even
    missing ones, so a later fix (creating the file) can be noticed."""
    path = Path(path)
    _track(deps, path)
    lines = _read_lines(path)
    found: dict[Stage, Path] = {}
    for lineno, raw in enumerate(lines, 1):
        text = raw.strip()
        if not text or text.startswith("#"):
            continue
        key, colon, value = text.partition(":")
        key, value = key.strip().upper(), value.strip()
        if not colon or not value:
            raise ShaderError("expected 'VS: path', 'GS: path' or 'FS: path'", path, lineno)
        try:
            stage = Stage(key)
        except ValueError:
            raise ShaderError(f"unknown key {key!r} (expected VS, GS or FS)", path, lineno) from None
        if stage in found:
            raise ShaderError(f"duplicate {key} entry", path, lineno)
        stage_path = path.parent / value
        _track(deps, stage_path)
        if not stage_path.is_file():
            raise ShaderError(f"{key} file not found: {stage_path}", path, lineno)
        if not stage_path.stem.endswith(f"_{key}"):
            raise ShaderError(f"{key} entry names {stage_path.name}, which is not a {key} file", path, lineno)
        found[stage] = stage_path
    missing = [s.value for s in (Stage.VERTEX, Stage.FRAGMENT) if s not in found]
    if missing:
        raise ShaderError(f"missing {' and '.join(missing)} entry", path)
    return ProgramSpec(path, {s: found[s] for s in Stage if s in found})


# ------------------------------------------------------------------ preprocessor


@dataclass(frozen=True)
class Origin:
    file: Path
    line: int  # 1-based


@dataclass(frozen=True)
class SourceLine:
    text: str
    origin: Origin


def preprocess(path: Path, deps: set[Path] | None = None) -> list[SourceLine]:
    """Expand //#DEFINE, //#END, //#INSERT and //#INCLUDE directives of one file."""
    return _Preprocessor(deps).run(Path(path), include_chain=())


class _Preprocessor:
    def __init__(self, deps: set[Path] | None):
        self.templates: dict[str, list[SourceLine]] = {}
        self.deps = deps

    def run(self, path: Path, include_chain: tuple[Path, ...]) -> list[SourceLine]:
        out: list[SourceLine] = []
        defining: tuple[str, int, list[SourceLine]] | None = None  # name, line, body
        for lineno, raw in enumerate(_read_lines(path), 1):
            stripped = raw.strip()
            target = defining[2] if defining else out
            if not stripped.startswith("//#"):
                target.append(SourceLine(raw, Origin(path, lineno)))
                continue
            keyword, _, arg = stripped[3:].partition(" ")
            keyword, arg = keyword.upper(), arg.strip()
            if keyword == "DEFINE":
                if defining:
                    raise ShaderError(f"nested //#DEFINE (inside {defining[0]!r})", path, lineno)
                defining = (_name(arg, path, lineno), lineno, [])
            elif keyword == "END":
                if not defining:
                    raise ShaderError("//#END without //#DEFINE", path, lineno)
                # The body was expanded as it was read, so an //#INSERT of the same
                # name inside it used the earlier definition: this is how extension works.
                self.templates[defining[0]] = defining[2]
                defining = None
            elif keyword == "INSERT":
                name = _name(arg, path, lineno)
                if name not in self.templates:
                    raise ShaderError(f"//#INSERT of unknown template {name!r}", path, lineno)
                target.extend(self.templates[name])
            elif keyword == "INCLUDE":
                target.extend(self._include(arg, path, lineno, include_chain))
            else:
                raise ShaderError(f"unknown directive //#{keyword}", path, lineno)
        if defining:
            raise ShaderError(f"//#DEFINE {defining[0]} without //#END", path, defining[1])
        return out

    def _include(self, arg: str, path: Path, lineno: int, chain: tuple[Path, ...]) -> list[SourceLine]:
        if not arg:
            raise ShaderError("//#INCLUDE needs a file name", path, lineno)
        target = path.parent / arg.strip("\"'")
        _track(self.deps, target)
        if not target.is_file():
            raise ShaderError(f"//#INCLUDE file not found: {target}", path, lineno)
        chain = (*chain, path.resolve())
        if target.resolve() in chain:
            raise ShaderError(f"//#INCLUDE cycle: {target.name} is already being included", path, lineno)
        return self.run(target, chain)


def _name(arg: str, path: Path, lineno: int) -> str:
    if not re.fullmatch(r"\w+", arg):
        raise ShaderError(f"expected a single template name, got {arg!r}", path, lineno)
    return arg


def _read_lines(path: Path) -> list[str]:
    try:
        return path.read_text(encoding="utf-8").splitlines()
    except OSError as exc:
        raise ShaderError(f"cannot read file: {exc.strerror or exc}", path) from None


def _track(deps: set[Path] | None, path: Path) -> None:
    if deps is not None:
        deps.add(path)


# ------------------------------------------------------------ geometry headers


@dataclass(frozen=True)
class GSLimits:
    max_output_vertices: int
    max_total_output_components: int


GS_INPUTS = {
    "POINTS": "points",
    "LINES": "lines",
    "LINES_ADJACENCY_EXT": "lines_adjacency",
    "TRIANGLES": "triangles",
    "TRIANGLES_ADJACENCY_EXT": "triangles_adjacency",
}
GS_OUTPUTS = {"POINTS": "points", "LINE_STRIP": "line_strip", "TRIANGLE_STRIP": "triangle_strip"}

_GS_HEADER = re.compile(r"#GS_(\w+)\s*:?\s*(.*)$", re.IGNORECASE)
_OUT_DECL = re.compile(
    r"(?:layout\s*\([^)]*\)\s*)?(?:(?:flat|smooth|noperspective|centroid|invariant)\s+)*"
    r"out\s+(\w+)\s+([^;{]+);"
)
_ARRAY = re.compile(r"\[\s*(\d*)\s*\]")
_SCALARS = ("float", "int", "uint", "bool")


def components(glsl_type: str) -> int:
    """Output components a GLSL type uses; 0 for types we do not size (structs)."""
    if glsl_type in _SCALARS:
        return 1
    if m := re.fullmatch(r"[iub]?vec([234])", glsl_type):
        return int(m[1])
    if m := re.fullmatch(r"mat([234])", glsl_type):
        return int(m[1]) ** 2
    return 0


def components_per_vertex(lines: list[SourceLine]) -> int:
    """gl_Position plus every `out` variable a geometry shader declares."""
    total = 4
    for line in lines:
        if m := _OUT_DECL.match(line.text.strip()):
            for declarator in m[2].split(","):
                size = _ARRAY.search(declarator)
                total += components(m[1]) * (int(size[1]) if size and size[1] else 1)
    return total


def apply_gs_header(lines: list[SourceLine], path: Path, limits: GSLimits) -> list[SourceLine]:
    """Replace `#GS_input/#GS_output/#GS_count` lines by GLSL 330 layout qualifiers
    placed right after `#version`, checking the count against the GL limits."""
    header: dict[str, tuple[str, SourceLine]] = {}
    body: list[SourceLine] = []
    for line in lines:
        m = _GS_HEADER.match(line.text.strip())
        if not m:
            body.append(line)
            continue
        key, value = m[1].lower(), m[2].strip()
        if key not in ("input", "output", "count"):
            expected = "expected GS_input, GS_output, GS_count"
            raise ShaderError(f"unknown header #GS_{m[1]} ({expected})", *_at(line))
        if key in header:
            raise ShaderError(f"duplicate #GS_{key}", *_at(line))
        header[key] = (value, line)
    missing = [f"#GS_{k}" for k in ("input", "output", "count") if k not in header]
    if missing:
        raise ShaderError(f"geometry shader needs {', '.join(missing)}", path)

    layout_in = _enum(header["input"], GS_INPUTS, "GS_input")
    layout_out = _enum(header["output"], GS_OUTPUTS, "GS_output")
    count = _gs_count(header["count"], components_per_vertex(body), limits)
    version = _version_index(body, path)
    layout = [
        SourceLine(f"layout({layout_in}) in;", header["input"][1].origin),
        SourceLine(f"layout({layout_out}, max_vertices = {count}) out;", header["output"][1].origin),
    ]
    return body[: version + 1] + layout + body[version + 1 :]


def reject_gs_header(lines: list[SourceLine], stage: Stage) -> None:
    """GS headers would reach the compiler as bogus directives in other stages."""
    for line in lines:
        if _GS_HEADER.match(line.text.strip()):
            raise ShaderError(f"#GS_ header in a {stage.label} shader", *_at(line))


def _enum(entry: tuple[str, SourceLine], allowed: dict[str, str], key: str) -> str:
    value, line = entry
    try:
        return allowed[value.upper()]
    except KeyError:
        raise ShaderError(f"#{key}: {value!r} is not one of {', '.join(allowed)}", *_at(line)) from None


def _gs_count(entry: tuple[str, SourceLine], per_vertex: int, limits: GSLimits) -> int:
    value, line = entry
    if not re.fullmatch(r"\d+", value) or int(value) < 1:
        raise ShaderError(f"#GS_count must be a positive integer, got {value!r}", *_at(line))
    count = int(value)
    if count > limits.max_output_vertices:
        raise ShaderError(
            f"GS_count {count} exceeds GL_MAX_GEOMETRY_OUTPUT_VERTICES {limits.max_output_vertices}",
            *_at(line),
        )
    if count * per_vertex > limits.max_total_output_components:
        raise ShaderError(
            f"GS_count {count} x {per_vertex} components = {count * per_vertex} exceeds "
            f"GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS {limits.max_total_output_components}",
            *_at(line),
        )
    return count


def _version_index(lines: list[SourceLine], path: Path) -> int:
    """Index of `#version`, which must come before anything but blanks and comments."""
    in_block_comment = False
    for index, line in enumerate(lines):
        text = line.text.strip()
        if in_block_comment or text.startswith("/*"):
            in_block_comment = "*/" not in text
            continue
        if not text or text.startswith("//"):
            continue
        if text.startswith("#version"):
            return index
        raise ShaderError("#version must be the first line of a geometry shader", *_at(line))
    raise ShaderError("geometry shader has no #version line", path)


def _at(line: SourceLine) -> tuple[Path, int]:
    return line.origin.file, line.origin.line


# ---------------------------------------------------------------- stage source


@dataclass(frozen=True)
class StageSource:
    stage: Stage
    path: Path
    lines: list[SourceLine]

    @property
    def text(self) -> str:
        return "".join(line.text + "\n" for line in self.lines)

    @property
    def source_map(self) -> list[Origin]:
        """Origin of each line of `text`; index 0 is line 1."""
        return [line.origin for line in self.lines]

    def origin(self, line: int) -> Origin | None:
        return self.lines[line - 1].origin if 1 <= line <= len(self.lines) else None


def load_stage(path: Path, limits: GSLimits, deps: set[Path] | None = None,
               defines: tuple[tuple[str, str], ...] = ()) -> StageSource:
    """Read, preprocess and (for geometry shaders) header-convert one stage file; `defines` (name, value) become
    `#define` lines after its `#version` (a program specialised at compile time)."""
    path = Path(path)
    stage = stage_from_path(path)
    _track(deps, path)
    lines = preprocess(path, deps)
    if defines:
        at = next((i for i, line in enumerate(lines) if line.text.strip().startswith("#version")), None)
        if at is None:
            raise ShaderError("defines need a #version line to follow", path)
        origin = lines[at].origin
        lines[at + 1:at + 1] = [SourceLine(f"#define {name} {value}", origin) for name, value in defines]
    if stage is Stage.GEOMETRY:
        lines = apply_gs_header(lines, path, limits)
    else:
        reject_gs_header(lines, stage)
    return StageSource(stage, path, lines)


def write_prs(source: StageSource, cache_dir: Path) -> Path:
    """Write the preprocessed text as `<stem>.prs`, atomically so a reader never
    sees a half-written file."""
    cache_dir.mkdir(parents=True, exist_ok=True)
    target = cache_dir / f"{source.path.stem}.prs"
    fd, tmp = tempfile.mkstemp(dir=cache_dir, prefix=target.name, suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(source.text)
        os.replace(tmp, target)
    except BaseException:
        os.unlink(tmp)
        raise
    return target


# ------------------------------------------------------------------ driver log

_LOG_PATTERNS = (
    re.compile(r"^\s*\d+:(\d+)\(\d+\):\s*error:\s*(.*)$", re.MULTILINE),  # Mesa
    re.compile(r"^\s*\d+\((\d+)\)\s*:\s*error\s*(.*)$", re.MULTILINE),  # NVIDIA
    re.compile(r"^\s*ERROR:\s*\d+:(\d+):\s*(.*)$", re.MULTILINE),  # AMD / Intel on Windows
)


def parse_driver_log(log: str) -> tuple[int | None, str]:
    """First error's (1-based line, message) in a compiler log; line is None if
    the log names none (then the whole trimmed log is the message)."""
    hits = [m for pattern in _LOG_PATTERNS if (m := pattern.search(log))]
    if not hits:
        return None, " ".join(log.split())
    first = min(hits, key=lambda m: m.start())
    return int(first[1]), first[2].strip()
