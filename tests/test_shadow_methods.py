"""The 3D lights' shadow methods, one object each (app/gl/lights3d/shadow_methods.py): the model's names are the
registry's, and every method in it renders the default scene (EGL, llvmpipe, 96 x 72) doing the work its object
declares and showing the reference's shadows (none: the formulas alone)."""
import numpy as np
import pytest

from app.gl.core.stencil import GL
from app.gl.lights3d.shadow_methods import METHODS
from app.model.lights3d.scene import SHADOW_METHODS, Lights3DCamera, default_scene
from app.reference import lights3d as reference
from tests.shadow_cases import renderer_and_target

SIZE = (96, 72)
CLOSE = Lights3DCamera(distance=250.0)
OFF = 4 / 255  # a pixel further than this from the reference's is wrong


@pytest.fixture(scope="module")
def host(gl):
    yield from renderer_and_target(gl, SIZE)


def test_the_models_method_names_are_the_registrys():
    assert tuple(METHODS) == SHADOW_METHODS  # in order: the commands' help and the scene file's enum list them
    assert [m.name for m in METHODS.values()] == list(METHODS)


def shadowed_by(name: str):
    scene = default_scene()
    for i in range(len(scene.lights)):
        scene = scene.with_light(i, shadow=name)
    return scene


def off_reference(image: np.ndarray, shadow: str) -> float:
    """The share of pixels further than OFF from the reference's picture with every light shadowed `shadow` way."""
    ref = reference.render(shadowed_by(shadow), CLOSE, SIZE)
    return float((np.abs(image - ref.rgb).max(axis=-1) > OFF).mean())


@pytest.mark.parametrize("name", list(METHODS))
def test_every_method_renders_the_default_scene(host, name):
    renderer, target = host
    method = METHODS[name]
    renderer.forget_shadows()  # whatever an earlier test left: this frame builds its own
    stats = renderer.render(target.fbo, shadowed_by(name), CLOSE, marks=False)
    assert GL.glGetError() == GL.GL_NO_ERROR
    assert stats.lights_drawn == 2  # the default scene's point and spot light
    assert (stats.volumes_drawn > 0, stats.volume_triangles > 0) == (method.volumes is not None,) * 2
    assert stats.maps_rendered == (2 if method.shadow_map else 0)

    image = target.read()[..., :3] / 255.0
    # the reference shadows alike whatever the method (zfail's name stands for any), or not at all (none)
    right, other = ("zfail", "none") if method.shadows else ("none", "zfail")
    wrong, unlike = off_reference(image, right), off_reference(image, other)
    print(f"\n{name}: pixels off the reference's by over 4/255: {wrong:.2%}; off it {other}: {unlike:.2%}")
    assert wrong < 0.01  # the map's shadow edges: 0.3 %
    assert unlike > 0.05  # the shadows are there, or not: 10 % of the picture
