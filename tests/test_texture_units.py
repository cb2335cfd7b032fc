"""Texture units from one allocator per renderer (app/gl/core/texture_units.py): each named by its sampler
uniform, the same name the same unit, two names never one; bound where the uniforms say; and every sampler of
the renderers' programs at the unit its renderer's allocator gave it, none shared within a program."""
from dataclasses import replace

import pytest

from app.editor import Editor
from app.gl.core import texture_units
from app.gl.core.headless import OffscreenTarget
from app.gl.core.stencil import GL
from app.gl.core.texture_units import TextureUnits
from app.gl.core.workspace_renderer import RENDERERS, WorkspaceRenderer


def test_two_names_never_get_the_same_unit_and_one_name_always_gets_its_own():
    units = TextureUnits()
    names = [f"u_sampler{i}" for i in range(texture_units.LIMIT)]
    given = [units[name] for name in names]
    assert sorted(given) == list(range(texture_units.LIMIT))
    assert [units[name] for name in reversed(names)] == given[::-1]
    assert units.uniforms("u_sampler3", "u_sampler0") == {"u_sampler3": given[3], "u_sampler0": given[0]}
    assert TextureUnits()["u_sampler5"] == 0  # another renderer's allocator: units of its own


def test_a_unit_past_the_limit_is_refused_by_name():
    units = TextureUnits()
    for i in range(texture_units.LIMIT):
        units[f"u_{i}"]
    with pytest.raises(RuntimeError, match="no texture unit left for 'u_more'"):
        units["u_more"]
    assert units["u_0"] == 0  # the named ones keep theirs


def bound_2d(unit: int) -> int:
    GL.glActiveTexture(GL.GL_TEXTURE0 + unit)
    try:
        return int(GL.glGetIntegerv(GL.GL_TEXTURE_BINDING_2D))
    finally:
        GL.glActiveTexture(GL.GL_TEXTURE0)


def test_bind_puts_each_texture_at_its_unit_and_returns_the_uniforms(gl):
    units = TextureUnits()
    units["u_first"]
    a, b = gl.texture((2, 2), 4), gl.texture((2, 2), 4)
    try:
        values = units.bind(u_a=a, u_b=b)
        assert values == {"u_a": 1, "u_b": 2}
        assert (bound_2d(1), bound_2d(2)) == (a.glo, b.glo)
    finally:
        a.release()
        b.release()


SAMPLER_TYPES = {int(getattr(GL, name)) for name in dir(GL) if name.startswith("GL_SAMPLER_")} - {
    int(GL.GL_SAMPLER_BINDING)}


def allocators(owner, depth: int = 3) -> list[TextureUnits]:
    """The TextureUnits an object holds, in its attributes or theirs."""
    if isinstance(owner, TextureUnits):
        return [owner]
    if depth == 0 or not hasattr(owner, "__dict__"):
        return []
    return [units for value in vars(owner).values() for units in allocators(value, depth - 1)]


@pytest.fixture(scope="module")
def host(gl):
    """Every workspace's default scene drawn by one host (the clouds reprojecting: their most samplers; the 3D
    lights' first light through a shadow map), the frame budget's reduced target too."""
    editor = Editor(configs=False)
    host = WorkspaceRenderer(gl)
    target = OffscreenTarget(gl, (48, 32))
    try:
        for name in sorted(RENDERERS):
            assert editor.execute(f"workspace {name}")
            if name == "lights3d":
                assert editor.execute("light3d.set 0 shadow map")
            settings = editor.render_settings()
            if name == "clouds":
                settings = replace(settings, downsample=2, reproject=True)
            host.render(target.fbo, editor.current, settings)
            host.frame_took(1e9)  # too slow: the next frame reduced, its level's pixels stretched (upscale)
            host.render(target.fbo, editor.current, settings, interactive=True, budget_ms=1.0)
        yield host
    finally:
        host.release()
        gl.detect_framebuffer(0).use()
        target.release()


def test_every_sampler_reads_the_unit_its_renderer_gave_it(host):
    owners = [*host.renderers.values(), *(budget.reduced for budget in host.budgets.values())]
    units = [a for owner in owners for a in allocators(owner)]
    checked = set()
    for (name, *_varyings_defines), entry in host.shaders._entries.items():
        program = entry.program
        samplers = {u: program[u].value for u in program if program[u].gl_type in SAMPLER_TYPES}
        if not samplers:
            continue
        assert len(set(samplers.values())) == len(samplers), f"{name} reads two samplers at one unit: {samplers}"
        assert any(all(u in a and a[u] == unit for u, unit in samplers.items()) for a in units), (
            f"{name}'s samplers {samplers} are not the units one renderer's allocator gave")
        checked.add(name)
    assert {"light2d_composite", "raytrace", "clouds_trace", "clouds_resolve", "clouds_composite", "lights3d_light",
            "lights3d_present", "upscale"} <= checked
