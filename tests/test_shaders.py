"""ShaderLibrary against a real (headless EGL) OpenGL 3.3 context."""

from __future__ import annotations

import os
from pathlib import Path

import moderngl
import numpy as np
import pytest

from app.gl.core.shader_source import ShaderError
from app.gl.core.shaders import ShaderLibrary, query_gs_limits

VS = """#version 330
in vec2 in_pos;
out vec2 v_pos;
void main() {
    v_pos = in_pos * 2.0;
    gl_Position = vec4(in_pos, 0.0, 1.0);
}
"""
FS = """#version 330
out vec4 color;
void main() { color = vec4(1.0); }
"""
# POINTS in, LINE_STRIP out: each point becomes a 2-vertex strip (p, p + (1, 10)).
GS = """#version 330
#GS_input: POINTS
#GS_output: LINE_STRIP
#GS_count: 2
in vec2 v_pos[];
out vec2 out_pos;
void main() {
    for (int i = 0; i < 2; ++i) {
        out_pos = v_pos[0] + vec2(float(i), 10.0 * float(i));
        gl_Position = vec4(out_pos, 0.0, 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
"""


@pytest.fixture(scope="module")
def ctx(gl):
    return gl


@pytest.fixture
def shaders(tmp_path):
    root = tmp_path / "shaders"
    root.mkdir()
    return root


@pytest.fixture
def errors():
    return []


@pytest.fixture
def library(ctx, shaders, tmp_path, errors):
    return ShaderLibrary(ctx, [shaders], cache_dir=tmp_path / "cache", on_error=errors.append)


def put(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def bump(path: Path) -> None:
    """Advance mtime explicitly rather than sleeping for the filesystem's clock."""
    t = path.stat().st_mtime + 5
    os.utime(path, (t, t))


def transform(ctx, program, points: np.ndarray, out_vertices: int, varying_floats: int = 2) -> np.ndarray:
    src = ctx.buffer(points.astype("f4").tobytes())
    out = ctx.buffer(reserve=out_vertices * varying_floats * 4)
    vao = ctx.vertex_array(program, [(src, "2f", "in_pos")])
    vao.transform(out, mode=moderngl.POINTS, vertices=len(points))
    result = np.frombuffer(out.read(), dtype="f4").reshape(-1, varying_floats)
    for obj in (vao, out, src):
        obj.release()
    return result


def test_limits_read_from_context(library):
    assert library.limits.max_output_vertices >= 256
    assert library.limits.max_total_output_components >= 1024


def test_geometry_program_runs_and_is_cached(ctx, library, shaders):
    put(shaders / "flake_VS.glsl", VS)
    put(shaders / "flake_GS.glsl", GS)
    put(shaders / "flake_FS.glsl", FS)
    put(shaders / "flake.prg", "# snowflake\nVS: flake_VS.glsl\nGS: flake_GS.glsl\nFS: flake_FS.glsl\n")
    program = library.program("flake", varyings=("out_pos",))
    assert library.program("flake", ("out_pos",)) is program

    points = np.array([[0.0, 0.0], [1.0, 2.0], [-1.0, 0.5]])
    captured = transform(ctx, program, points, out_vertices=2 * len(points))
    expected = np.concatenate([[2 * p, 2 * p + (1.0, 10.0)] for p in points])
    np.testing.assert_allclose(captured, expected)


def test_prs_files_go_to_cache_dir_only(library, shaders, tmp_path):
    put(shaders / "flake_VS.glsl", VS)
    put(shaders / "flake_GS.glsl", GS)
    put(shaders / "flake_FS.glsl", FS)
    put(shaders / "flake.prg", "VS: flake_VS.glsl\nGS: flake_GS.glsl\nFS: flake_FS.glsl\n")
    library.program("flake")
    cache = tmp_path / "cache"
    assert sorted(p.name for p in cache.iterdir()) == ["flake_FS.prs", "flake_GS.prs", "flake_VS.prs"]
    assert "layout(line_strip, max_vertices = 2) out;" in (cache / "flake_GS.prs").read_text()
    assert not list(shaders.glob("*.prs"))


def test_compile_error_in_included_template_names_the_shl(library, shaders, errors):
    lib = put(
        shaders / "helpers.shl",
        "// helpers\n//#DEFINE shade\nfloat shade() {\n    return undeclared_thing;\n}\n//#END\n",
    )
    put(shaders / "p_VS.glsl", VS)
    fs_body = FS.split("\n", 1)[1]
    put(shaders / "p_FS.glsl", "#version 330\n//#INCLUDE helpers.shl\n//#INSERT shade\n" + fs_body)
    put(shaders / "p.prg", "VS: p_VS.glsl\nFS: p_FS.glsl\n")
    with pytest.raises(ShaderError, match="undeclared_thing") as info:
        library.program("p")
    assert (info.value.file, info.value.line) == (lib, 4)
    assert "fragment shader p_FS.glsl" in info.value.message
    assert errors == [info.value] and library.errors["p"] is info.value


def test_compile_error_line_in_geometry_shader_accounts_for_layout_lines(library, shaders):
    put(shaders / "g_VS.glsl", VS)
    put(shaders / "g_FS.glsl", FS)
    gs = put(shaders / "g_GS.glsl", GS.replace("EndPrimitive();", "EndPrimitive(); nope = 1;"))
    put(shaders / "g.prg", "VS: g_VS.glsl\nGS: g_GS.glsl\nFS: g_FS.glsl\n")
    with pytest.raises(ShaderError, match="nope") as info:
        library.program("g")
    assert (info.value.file, info.value.line) == (gs, 13)


def test_link_error_names_the_prg(library, shaders):
    put(shaders / "l_VS.glsl", VS)
    put(shaders / "l_FS.glsl", FS)
    prg = put(shaders / "l.prg", "VS: l_VS.glsl\nFS: l_FS.glsl\n")
    with pytest.raises(ShaderError, match="link failed") as info:
        library.program("l", varyings=("no_such_output",))
    assert (info.value.file, info.value.line) == (prg, None)


def test_broken_edit_keeps_old_program_then_fix_reloads(ctx, library, shaders, errors):
    vs = put(shaders / "r_VS.glsl", VS)
    put(shaders / "r_FS.glsl", FS)
    put(shaders / "r.prg", "VS: r_VS.glsl\nFS: r_FS.glsl\n")
    good = library.program("r", ("v_pos",))
    assert library.reload_changed() == []

    put(vs, VS.replace("in_pos * 2.0", "in_pos * 2.0 +"))
    bump(vs)
    assert library.reload_changed() == []
    assert library.program("r", ("v_pos",)) is good
    assert isinstance(library.errors["r"], ShaderError) and errors == [library.errors["r"]]
    assert library.errors["r"].file == vs
    np.testing.assert_allclose(transform(ctx, good, np.array([[1.0, 2.0]]), 1), [[2.0, 4.0]])
    assert library.reload_changed() == []  # unchanged since the failed attempt: no retry
    assert len(errors) == 1

    put(vs, VS.replace("in_pos * 2.0", "in_pos * 3.0"))
    bump(vs)
    assert library.reload_changed() == ["r"]
    assert "r" not in library.errors
    fresh = library.program("r", ("v_pos",))
    assert fresh is not good
    np.testing.assert_allclose(transform(ctx, fresh, np.array([[1.0, 2.0]]), 1), [[3.0, 6.0]])


def test_edit_to_included_template_triggers_reload(library, shaders):
    lib = put(shaders / "k.shl", "//#DEFINE k\nconst float K = 1.0;\n//#END\n")
    vs = "#version 330\n//#INCLUDE k.shl\n//#INSERT k\nvoid main() { gl_Position = vec4(K); }\n"
    put(shaders / "i_VS.glsl", vs)
    put(shaders / "i_FS.glsl", FS)
    put(shaders / "i.prg", "VS: i_VS.glsl\nFS: i_FS.glsl\n")
    library.program("i")
    put(lib, "//#DEFINE k\nconst float K = 2.0;\n//#END\n")
    bump(lib)
    assert library.reload_changed() == ["i"]


def test_missing_stage_file_is_a_clear_error_until_created(library, shaders, errors):
    put(shaders / "m_VS.glsl", VS)
    prg = put(shaders / "m.prg", "VS: m_VS.glsl\nFS: m_FS.glsl\n")
    with pytest.raises(ShaderError, match="m_FS.glsl") as info:
        library.program("m")
    assert (info.value.file, info.value.line) == (prg, 2)
    with pytest.raises(ShaderError):  # a never-compiled program stays an error, without a retry
        library.program("m")
    assert len(errors) == 1

    put(shaders / "m_FS.glsl", FS)
    assert library.reload_changed() == ["m"]
    assert isinstance(library.program("m"), moderngl.Program)


def test_unknown_program_name(library):
    with pytest.raises(ShaderError, match="nothing.prg not found"):
        library.program("nothing")


def test_gs_count_over_context_limit_refused(ctx, library, shaders):
    put(shaders / "b_VS.glsl", VS)
    put(shaders / "b_FS.glsl", FS)
    gs = put(shaders / "b_GS.glsl", GS.replace("#GS_count: 2", "#GS_count: 5000"))
    put(shaders / "b.prg", "VS: b_VS.glsl\nGS: b_GS.glsl\nFS: b_FS.glsl\n")
    limit = query_gs_limits(ctx).max_output_vertices
    expected = f"GS_count 5000 exceeds GL_MAX_GEOMETRY_OUTPUT_VERTICES {limit}"
    with pytest.raises(ShaderError, match=expected) as info:
        library.program("b")
    assert (info.value.file, info.value.line) == (gs, 4)
