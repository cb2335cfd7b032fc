"""set_uniforms (app/gl/core/uniforms.py) on the editor's own programs: a uniform a program lacks fails loudly in
debug mode (the tests' mode: tests/conftest.py), naming the program and the uniform, unless the call site says
the program may lack it; outside debug mode it is skipped and the rest are set."""
import pytest

from app.gl.core.shaders import ShaderLibrary
from app.gl.core.uniforms import UniformError, program_name, set_uniforms
from app.resources import SHADERS


@pytest.fixture(scope="module")
def box_edges(gl, tmp_path_factory):
    """The volume's wireframe program: u_view_proj, u_color, u_extent."""
    return ShaderLibrary(gl, [SHADERS], cache_dir=tmp_path_factory.mktemp("cache")).program("box_edges")


def test_set_uniforms_sets_every_value(box_edges):
    set_uniforms(box_edges, {"u_color": (0.25, 0.5, 0.75, 1.0)}, u_extent=(1.0, 2.0, 3.0))
    assert box_edges["u_color"].value == (0.25, 0.5, 0.75, 1.0)
    assert box_edges["u_extent"].value == (1.0, 2.0, 3.0)


def test_a_misspelt_uniform_raises_naming_the_program_and_the_uniform(box_edges):
    assert program_name(box_edges) == "box_edges"
    with pytest.raises(UniformError, match=r"program 'box_edges' has no uniform 'u_colour'"):
        set_uniforms(box_edges, u_colour=(1.0, 0.0, 0.0, 1.0), u_extent=(2.0, 2.0, 2.0))
    assert box_edges["u_extent"].value == (2.0, 2.0, 2.0)  # the others were set before it said so


def test_a_uniform_the_call_site_calls_optional_may_be_missing(box_edges):
    set_uniforms(box_edges, {"u_steps": 8, "u_extent": (3.0, 3.0, 3.0)}, optional={"u_steps"})
    assert box_edges["u_extent"].value == (3.0, 3.0, 3.0)
    with pytest.raises(UniformError, match="'u_stpes'"):  # optional names only those
        set_uniforms(box_edges, {"u_stpes": 8}, optional={"u_steps"})


def test_outside_debug_mode_a_missing_uniform_is_skipped(box_edges, monkeypatch):
    monkeypatch.setenv("SHADELAB_GL_DEBUG", "0")
    set_uniforms(box_edges, u_colour=(1.0, 0.0, 0.0, 1.0), u_extent=(4.0, 4.0, 4.0))
    assert box_edges["u_extent"].value == (4.0, 4.0, 4.0)


def test_a_program_made_elsewhere_is_named_by_its_gl_object(gl):
    program = gl.program(vertex_shader="#version 330\nvoid main() { gl_Position = vec4(0.0); }")
    try:
        with pytest.raises(UniformError, match=rf"program '#{program.glo}' has no uniform 'u_x'"):
            set_uniforms(program, u_x=1.0)
    finally:
        program.release()
