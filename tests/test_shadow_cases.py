"""The hard shadow cases of tests/shadow_cases.py (EGL, llvmpipe, 160 x 120) against the CPU reference: every
shadow method's mask, judged off the shadow edges as a share of the reference's shadowed pixels, and the lit
frames of the volume methods. The numbers measured are printed (pytest -s); docs/lights3d.md's failure table
quotes them."""
import numpy as np
import pytest

from app.gl.core.stencil import GL
from app.gl.lights3d.shadow_methods import METHODS
from app.reference import lights3d as reference
from tests.shadow_cases import CASES, SIZE, judge, near_a_jump, renderer_and_target, shadow_edge, truth

BOUND = 0.01        # of the reference's shadowed pixels, off the shadow edges
RIGHT = ("onepass", "zpass", "zfail")  # exact there: the eye outside every volume in these cases
# the seed's open prisms: a vertex at the light (the sphere's, the box's), a light on the mesh, a view along its rays
SEED_FAILS = {"light on a box corner", "light on the sphere's pole", "light on a sphere vertex", "light on a box edge",
              "light on a box face", "looking along a light's rays"}
OFF = 4 / 255       # a lit frame's pixel further than this from the reference's is wrong


@pytest.fixture(scope="module")
def host(gl):
    yield from renderer_and_target(gl, SIZE)


@pytest.mark.parametrize("name", list(CASES))
def test_each_method_shadows_the_case_as_the_reference_does(host, name):
    case, ref = CASES[name], truth(name)
    judged = {m: judge(host[0].shadow_mask(case.scene, case.camera, SIZE, 0, m)[0], ref)
              for m, method in METHODS.items() if method.shadows}
    assert GL.glGetError() == GL.GL_NO_ERROR
    print(f"\n{name}: {judged['zfail'].shadowed} px in shadow; wrong off the edges "
          + ", ".join(f"{m} {j.share:.2%} ({j.wrong_off_edge}, {j.wrong} with the edges)" for m, j in judged.items()))
    assert judged["zfail"].shadowed > 400  # a shadow to judge
    for m in RIGHT:
        assert judged[m].share <= BOUND, m
    if name in SEED_FAILS:
        assert judged["onepass-seed"].share > 0.02


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("method", ["onepass", "zfail"])
def test_the_lit_frame_is_the_references(host, name, method):
    """The whole frame, every light shadowed `method`'s way: off silhouettes and shadow edges no pixel strays
    from the reference by over 4/255 (a vertex at (0, 0, 0, 0) made the frame dark; a face level with the light
    was lit by noise in the facing test)."""
    renderer, target = host
    case = CASES[name]
    scene = case.scene
    for i in range(len(scene.lights)):
        scene = scene.with_light(i, shadow=method)
    ref = reference.render(scene, case.camera, SIZE)
    renderer.forget_shadows()
    renderer.render(target.fbo, scene, case.camera, marks=False)
    error = np.abs(target.read()[..., :3] / 255.0 - ref.rgb).max(axis=-1)
    edges = near_a_jump(ref, case.camera.position())
    for i in range(len(scene.lights)):
        edges |= shadow_edge(ref.facing[i] & ~ref.visible[i])
    print(f"\n{name}, {method}: {(error[~edges] > OFF).sum()} px over 4/255 off the edges, the most "
          f"{error[~edges].max() * 255:.1f}/255")
    assert (ref.object_id >= 0).mean() > 0.5 and edges.mean() < 0.2
    # onepass: the odd speck where the light grazes a mesh's inner edge (docs/lights3d.md), 3 of 19,200 at most
    assert (error[~edges] > OFF).sum() <= (0 if method == "zfail" else 5)
