"""A program specialised at compile time: ShaderLibrary.program(name, defines=...) puts `#define`s after each stage's
#version, one program for each set (what raytrace.prg's modes are: SCALAR_MODE)."""
from pathlib import Path

from app.gl.core.shader_source import GSLimits, Origin, load_stage
from app.gl.core.shaders import ShaderLibrary

LIMITS = GSLimits(max_output_vertices=1024, max_total_output_components=1024)
FS = ["// a comment", "#version 330 core", "out vec4 frag_color;",
      "void main() { frag_color = vec4(float(LEVEL) / 4.0, 0.0, 0.0, 1.0); }"]
VS = ["#version 330 core", "void main() { gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }"]


def shader_dir(tmp_path: Path) -> Path:
    (tmp_path / "level_FS.glsl").write_text("\n".join(FS) + "\n")
    (tmp_path / "level_VS.glsl").write_text("\n".join(VS) + "\n")
    (tmp_path / "level.prg").write_text("VS: level_VS.glsl\nFS: level_FS.glsl\n")
    return tmp_path


def test_defines_follow_the_version_line_and_point_at_it(tmp_path):
    source = load_stage(shader_dir(tmp_path) / "level_FS.glsl", LIMITS, defines=(("LEVEL", "3"), ("X", "1.5")))
    assert [line.text for line in source.lines] == [*FS[:2], "#define LEVEL 3", "#define X 1.5", *FS[2:]]
    assert source.origin(3) == Origin(tmp_path / "level_FS.glsl", 2)


def test_each_set_of_defines_is_its_own_program(gl, tmp_path):
    library = ShaderLibrary(gl, [shader_dir(tmp_path)], cache_dir=tmp_path / "cache")
    one, three = library.program("level", defines={"LEVEL": 1}), library.program("level", defines={"LEVEL": 3})
    assert one is not three and one.glo != three.glo
    assert library.program("level", defines={"LEVEL": 1}) is one  # compiled once
