"""Pure-text shader framework: templates, .prg containers, GS headers, logs."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.gl.core.shader_source import (GSLimits, Origin, ShaderError, Stage, components_per_vertex, default_cache_dir,
                                       load_stage, parse_driver_log, parse_prg, preprocess, stage_from_path, write_prs)

LIMITS = GSLimits(max_output_vertices=1024, max_total_output_components=1024)


def write(path: Path, *lines: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("".join(line + "\n" for line in lines))
    return path


def texts(lines) -> list[str]:
    return [line.text for line in lines]


# ------------------------------------------------------------------ templates


def seed_example(tmp_path: Path) -> Path:
    write(tmp_path / "test.shl", "//#DEFINE test", "//#INSERT test", "c", "//#END")
    shd = ("a", "//#DEFINE test", "b", "//#END", "//#INCLUDE test.shl", "//#INSERT test", "d")
    return write(tmp_path / "test.shd", *shd)


def test_seed_example_outputs_a_b_c_d(tmp_path):
    assert texts(preprocess(seed_example(tmp_path))) == ["a", "b", "c", "d"]


def test_origins_map_through_templates_and_includes(tmp_path):
    lines = preprocess(seed_example(tmp_path))
    shd, shl = tmp_path / "test.shd", tmp_path / "test.shl"
    assert [line.origin for line in lines] == [Origin(shd, 1), Origin(shd, 3), Origin(shl, 3), Origin(shd, 7)]


def test_later_definition_extends_earlier(tmp_path):
    src = write(
        tmp_path / "x.shd",
        "//#DEFINE body",
        "one",
        "//#END",
        "  //#DEFINE body  ",
        "//#INSERT body",
        "two",
        "//#END",
        "//#INSERT body",
        "//#INSERT body",
    )
    assert texts(preprocess(src)) == ["one", "two", "one", "two"]


def test_plain_lines_of_an_include_are_emitted_and_deps_tracked(tmp_path):
    lib = write(tmp_path / "lib" / "common.shl", "shared", "//#DEFINE t", "x", "//#END")
    src = write(tmp_path / "s.shd", "//#INCLUDE lib/common.shl", "//#INSERT t")
    deps: set[Path] = set()
    assert texts(preprocess(src, deps)) == ["shared", "x"]
    assert lib in deps


@pytest.mark.parametrize(
    ("lines", "bad_line", "needle"),
    [
        (["a", "//#FROB x"], 2, "unknown directive"),
        (["//#INSERT nope"], 1, "unknown template"),
        (["a", "//#INCLUDE missing.shl"], 2, "not found"),
        (["//#DEFINE a", "//#DEFINE b", "//#END"], 2, "nested"),
        (["x", "//#DEFINE a", "y"], 2, "without //#END"),
        (["//#END"], 1, "without //#DEFINE"),
        (["//#DEFINE two words", "//#END"], 1, "single template name"),
    ],
)
def test_template_errors_name_file_and_line(tmp_path, lines, bad_line, needle):
    src = write(tmp_path / "bad.shd", *lines)
    with pytest.raises(ShaderError, match=needle) as info:
        preprocess(src)
    assert (info.value.file, info.value.line) == (src, bad_line)


def test_error_inside_include_reports_the_included_file(tmp_path):
    lib = write(tmp_path / "lib.shl", "//#DEFINE t", "//#INSERT missing", "//#END")
    src = write(tmp_path / "s.shd", "//#INCLUDE lib.shl")
    with pytest.raises(ShaderError) as info:
        preprocess(src)
    assert (info.value.file, info.value.line) == (lib, 2)


def test_include_cycle_refused(tmp_path):
    write(tmp_path / "a.shl", "//#INCLUDE b.shl")
    b = write(tmp_path / "b.shl", "x", "//#INCLUDE a.shl")
    src = write(tmp_path / "s.shd", "//#INCLUDE a.shl")
    with pytest.raises(ShaderError, match="cycle") as info:
        preprocess(src)
    assert (info.value.file, info.value.line) == (b, 2)


def test_diamond_include_is_not_a_cycle(tmp_path):
    write(tmp_path / "leaf.shl", "//#DEFINE t", "leaf", "//#END")
    write(tmp_path / "mid.shl", "//#INCLUDE leaf.shl")
    src = write(tmp_path / "s.shd", "//#INCLUDE leaf.shl", "//#INCLUDE mid.shl", "//#INSERT t")
    assert texts(preprocess(src)) == ["leaf"]


@settings(max_examples=30, deadline=None, database=None)
@given(st.lists(st.text(alphabet="ab xy;{}()=019/*#", max_size=20).filter(lambda t: "//#" not in t)))
def test_text_without_directives_passes_through(tmp_path_factory, body):
    src = write(tmp_path_factory.mktemp("p") / "p.shd", *body)
    lines = preprocess(src)
    assert texts(lines) == body
    assert [line.origin.line for line in lines] == list(range(1, len(body) + 1))


# ----------------------------------------------------------------- file names


@pytest.mark.parametrize(
    ("name", "stage"),
    [("snowflake_GS.glsl", Stage.GEOMETRY), ("a_b_VS.vert", Stage.VERTEX), ("x_FS", Stage.FRAGMENT)],
)
def test_stage_from_name(name, stage):
    assert stage_from_path(Path(name)) is stage


@pytest.mark.parametrize("name", ["shader.glsl", "x_vs.glsl", "x_TS.glsl", "VS.glsl"])
def test_bad_stage_name_refused(name):
    with pytest.raises(ShaderError, match="_VS, _GS or _FS"):
        stage_from_path(Path(name))


# ------------------------------------------------------------------------ .prg


def stage_files(tmp_path: Path, *names: str) -> None:
    for name in names:
        write(tmp_path / name, "#version 330")


def test_prg_with_comments_blank_lines_and_optional_gs(tmp_path):
    stage_files(tmp_path, "v_VS.glsl", "f_FS.glsl", "g_GS.glsl")
    plain = write(tmp_path / "plain.prg", "# a comment", "", "  VS :  v_VS.glsl  ", "FS:f_FS.glsl")
    spec = parse_prg(plain)
    assert spec.stages == {Stage.VERTEX: tmp_path / "v_VS.glsl", Stage.FRAGMENT: tmp_path / "f_FS.glsl"}
    full = write(tmp_path / "full.prg", "FS: f_FS.glsl", "GS: g_GS.glsl", "VS: v_VS.glsl")
    assert list(parse_prg(full).stages) == [Stage.VERTEX, Stage.GEOMETRY, Stage.FRAGMENT]


@pytest.mark.parametrize(
    ("lines", "bad_line", "needle"),
    [
        (["# c", "VS: v_VS.glsl", "FS: gone_FS.glsl"], 3, "gone_FS.glsl"),
        (["VS: v_VS.glsl", "TS: t.glsl", "FS: f_FS.glsl"], 2, "unknown key"),
        (["VS: v_VS.glsl", "VS: v_VS.glsl", "FS: f_FS.glsl"], 2, "duplicate"),
        (["VS: f_FS.glsl", "FS: f_FS.glsl"], 1, "not a VS file"),
        (["VS v_VS.glsl"], 1, "expected"),
        (["VS: v_VS.glsl"], None, "missing FS"),
    ],
)
def test_prg_errors_name_prg_and_line(tmp_path, lines, bad_line, needle):
    stage_files(tmp_path, "v_VS.glsl", "f_FS.glsl")
    prg = write(tmp_path / "p.prg", *lines)
    with pytest.raises(ShaderError, match=needle) as info:
        parse_prg(prg)
    assert (info.value.file, info.value.line) == (prg, bad_line)


# ------------------------------------------------------------------ GS header

GS_BODY = ("in vec3 v[];", "void main() {}")


def gs_file(tmp_path: Path, *header: str, body=GS_BODY) -> Path:
    return write(tmp_path / "flake_GS.glsl", "// leading comment", "#version 330", *header, *body)


def test_gs_header_becomes_layout_after_version(tmp_path):
    path = gs_file(tmp_path, "#GS_input: LINES_ADJACENCY_EXT", "#GS_output: TRIANGLE_STRIP", "#GS_count: 12")
    source = load_stage(path, LIMITS)
    assert texts(source.lines) == [
        "// leading comment",
        "#version 330",
        "layout(lines_adjacency) in;",
        "layout(triangle_strip, max_vertices = 12) out;",
        *GS_BODY,
    ]
    # The generated lines point at the header lines they replace; the body keeps its lines.
    assert [o.line for o in source.source_map] == [1, 2, 3, 4, 6, 7]
    assert source.origin(3) == Origin(path, 3)


def test_gs_header_may_precede_version(tmp_path):
    header = ("#GS_count: 1", "#GS_input: POINTS", "#GS_output: POINTS")
    path = write(tmp_path / "p_GS.glsl", *header, "#version 330")
    assert texts(load_stage(path, LIMITS).lines)[:2] == ["#version 330", "layout(points) in;"]


def test_gs_header_missing(tmp_path):
    path = gs_file(tmp_path, "#GS_input: POINTS", "#GS_output: POINTS")
    with pytest.raises(ShaderError, match="#GS_count") as info:
        load_stage(path, LIMITS)
    assert info.value.file == path


def test_gs_bad_enum(tmp_path):
    path = gs_file(tmp_path, "#GS_input: QUADS", "#GS_output: POINTS", "#GS_count: 1")
    with pytest.raises(ShaderError, match="QUADS") as info:
        load_stage(path, LIMITS)
    assert (info.value.file, info.value.line) == (path, 3)


def test_gs_count_over_max_output_vertices(tmp_path):
    path = gs_file(tmp_path, "#GS_input: POINTS", "#GS_output: POINTS", "#GS_count: 2000")
    expected = "GS_count 2000 exceeds GL_MAX_GEOMETRY_OUTPUT_VERTICES 1024"
    with pytest.raises(ShaderError, match=expected) as info:
        load_stage(path, LIMITS)
    assert info.value.line == 5


def test_gs_count_over_total_components(tmp_path):
    body = ("layout(points) out;", "out vec4 color;", "void main() {}")
    path = gs_file(tmp_path, "#GS_input: POINTS", "#GS_output: POINTS", "#GS_count: 200", body=body)
    expected = "GS_count 200 x 8 components = 1600 exceeds GL_MAX_GEOMETRY_TOTAL_OUTPUT_COMPONENTS 1024"
    with pytest.raises(ShaderError, match=expected):
        load_stage(path, LIMITS)


@pytest.mark.parametrize("count", ["0", "-3", "many"])
def test_gs_count_must_be_positive(tmp_path, count):
    path = gs_file(tmp_path, "#GS_input: POINTS", "#GS_output: POINTS", f"#GS_count: {count}")
    with pytest.raises(ShaderError, match="positive"):
        load_stage(path, LIMITS)


def test_version_must_come_first(tmp_path):
    header = ("#GS_input: POINTS", "#GS_output: POINTS", "#GS_count: 1")
    path = write(tmp_path / "g_GS.glsl", "/* block", "comment */", *header, "float x;", "#version 330")
    with pytest.raises(ShaderError, match="#version") as info:
        load_stage(path, LIMITS)
    assert info.value.line == 6


def test_gs_header_in_vertex_shader_refused(tmp_path):
    path = write(tmp_path / "v_VS.glsl", "#version 330", "#GS_count: 3")
    with pytest.raises(ShaderError, match="vertex") as info:
        load_stage(path, LIMITS)
    assert info.value.line == 2


def test_components_per_vertex_counts_out_declarations(tmp_path):
    path = write(
        tmp_path / "g_GS.glsl",
        "layout(line_strip, max_vertices = 4) out;",
        "out vec3 normal;",
        "flat out int id, ids[2];",
        "out mat3 frame;",
        "layout(location = 1) out uvec2 tag;",
        "// out vec4 commented;",
        "in vec4 not_an_output[];",
    )
    assert components_per_vertex(preprocess(path)) == 4 + 3 + 1 + 2 + 9 + 2


# ------------------------------------------------------------ logs and errors


@pytest.mark.parametrize(
    ("log", "line", "message"),
    [
        ("0:12(5): error: syntax error, unexpected x\n0:14(1): error: later", 12, "syntax error, unexpected x"),
        ("0(7) : warning C7050: meh\n0(12) : error C0000: syntax error", 12, "C0000: syntax error"),
        ("WARNING: 0:3: x\nERROR: 0:9: 'foo' : undeclared identifier\n", 9, "'foo' : undeclared identifier"),
        ("error: unresolved reference\n  to function f\n", None, "error: unresolved reference to function f"),
    ],
)
def test_parse_driver_log(log, line, message):
    assert parse_driver_log(log) == (line, message)


def test_shader_error_str():
    assert str(ShaderError("boom", Path("a/b_FS.glsl"), 3)) == "a/b_FS.glsl:3: boom"
    assert str(ShaderError("boom", Path("p.prg"))) == "p.prg: boom"
    assert str(ShaderError("boom")) == "boom"


def test_default_cache_dir(monkeypatch, tmp_path):
    monkeypatch.setenv("SHADELAB_CACHE_DIR", str(tmp_path / "explicit"))
    assert default_cache_dir() == tmp_path / "explicit" / "shaders"
    monkeypatch.delenv("SHADELAB_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_dir() == tmp_path / "xdg" / "shadelab" / "shaders"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert default_cache_dir() == tmp_path / "home" / ".cache" / "shadelab" / "shaders"


def test_write_prs_replaces_atomically(tmp_path):
    src = write(tmp_path / "src" / "v_VS.glsl", "#version 330", "void main() {}")
    cache = tmp_path / "cache" / "shaders"
    first = write_prs(load_stage(src, LIMITS), cache)
    src.write_text("#version 330\n")
    second = write_prs(load_stage(src, LIMITS), cache)
    assert first == second == cache / "v_VS.prs"
    assert second.read_text() == "#version 330\n"
    assert os.listdir(cache) == ["v_VS.prs"]  # no temp files left behind
