"""The issue's failure cases on the real snowflake shaders: a clear message, the old program keeps running."""
import os
import shutil

import numpy as np
import pytest

from app.gl.core.shaders import ShaderLibrary
from app.gl.snowflake.renderer import SnowflakeRenderer
from app.model.camera2d import Camera2D
from app.model.snowflake import Flake, SnowflakeScene
from app.reference.snowflake import segments
from app.resources import SHADERS


def edit(path, old, new):
    text = path.read_text()
    assert old in text
    path.write_text(text.replace(old, new))
    t = path.stat().st_mtime + 5  # a newer mtime without sleeping
    os.utime(path, (t, t))


BREAKAGES = {
    "prg names a missing file": ("snowflake.prg", "FS: flat_color_FS.glsl", "FS: no_such_FS.glsl",
                                 ("snowflake.prg", 4, "no_such_FS.glsl")),
    "GS header over the limit": ("snowflake_GS.glsl", "#GS_count: 65", "#GS_count: 5000",
                                 ("snowflake_GS.glsl", 4, "GS_count 5000 exceeds")),
    "syntax error in an included template": ("koch.shl", "vec2 p1 = a + d / 3.0;", "vec2 p1 = a + d / 3.0 +;",
                                             ("koch.shl", 9, "error")),
}


@pytest.mark.parametrize("breakage", BREAKAGES, ids=list(BREAKAGES))
def test_broken_edit_keeps_previous_program(gl, tmp_path, breakage):
    shaders = tmp_path / "shaders"
    shutil.copytree(SHADERS, shaders)
    errors = []
    library = ShaderLibrary(gl, [shaders], cache_dir=tmp_path / "cache", on_error=errors.append)
    renderer = SnowflakeRenderer(gl, library)
    scene = SnowflakeScene((Flake(0, 0, 1),), 3)
    before = renderer.capture(scene, Camera2D())

    name, old, new, (file, line, needle) = BREAKAGES[breakage]
    edit(shaders / name, old, new)
    assert library.reload_changed() == []
    err = library.errors["snowflake"]
    assert (err.file.name, err.line) == (file, line) and needle in err.message
    assert errors == [err] and str(err).startswith(f"{shaders / file}:{line}:")

    after = renderer.capture(scene, Camera2D())  # the previous program still runs
    np.testing.assert_array_equal(after, before)
    assert np.abs(after - segments(scene.flakes, 3)).max() < 2e-6

    edit(shaders / name, new, old)
    assert library.reload_changed() == ["snowflake"]
    assert "snowflake" not in library.errors
    np.testing.assert_array_equal(renderer.capture(scene, Camera2D()), before)  # the new program, a fresh VAO
