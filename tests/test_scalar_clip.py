"""The clip box (app/gl/volume/clip_box.py): a scalar mode's rays sample only the box of bricks that can change its
picture, and draw exactly the picture of the whole volume's rays with fewer samples."""
import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.volume.clip_box import NOTHING, box_over
from app.gl.volume.raytracer import RayTracer
from app.model.camera3d import OrbitCamera
from app.model.volume.phantom import ct_phantom
from app.model.volume.render_modes import TraceSettings
from app.model.volume.scalar_modes import BRICK, brick_maxima
from app.model.volume.scalars import TransferFunction
from app.model.volume.view import VolumeView
from app.model.volume.volume import Volume
from app.resources import SHADERS

SIZE = (40, 40)
VIEW = VolumeView(camera=OrbitCamera(yaw=25, pitch=20, distance=3.5))
CT = TransferFunction(-200.0, 1200.0, "bone", points=((-200.0, 0.0), (1200.0, 0.3)))
ABOVE_ALL = TransferFunction(5000.0, 6000.0, "bone", points=((5000.0, 0.0), (6000.0, 0.3)))  # every ray below


@pytest.fixture(scope="module")
def tracer(gl):
    return RayTracer(gl, ShaderLibrary(gl, [SHADERS]))


@pytest.fixture(scope="module")
def padded():
    """The 24^3 phantom in 48^3 of air: most of each ray crosses nothing a mode shows."""
    return np.pad(ct_phantom(24), 12, constant_values=-1000)


def draw(gl, tracer, volume, mode: str, clip: bool, debug: bool = False) -> np.ndarray:
    """The picture (0..255) or, with `debug`, each pixel's texture samples (float framebuffer)."""
    tracer.clip.enabled = clip
    settings = TraceSettings(scalar_mode=mode, steps=40, iso=-500.0, slice_planes=False, debug_samples=debug)
    try:
        if debug:
            fbo = gl.framebuffer([gl.renderbuffer(SIZE, 4, dtype="f4")])
            tracer.render(fbo, volume.voxels, VIEW, settings)
            counts = np.frombuffer(fbo.read(components=4, dtype="f4"), "f4")[0::4].copy()
            fbo.release()
            return counts
        target = OffscreenTarget(gl, SIZE, samples=0)
        tracer.render(target.fbo, volume.voxels, VIEW, settings)
        image = target.read()[..., :3].copy()
        target.release()
        return image
    finally:
        tracer.clip.enabled = True


@pytest.mark.parametrize("mode", ["mip", "attenuated_mip", "iso", "translucent"])
def test_clipped_rays_draw_the_same_picture_with_fewer_samples(gl, tracer, padded, mode):
    volume = Volume.new(1, 1, 1)
    volume.replace_scalars(padded, CT)
    clipped, whole = draw(gl, tracer, volume, mode, True), draw(gl, tracer, volume, mode, False)
    assert np.array_equal(clipped, whole)
    assert (clipped != clipped[0, 0]).any(-1).sum() > 100  # a picture, not the background
    fewer, all_samples = draw(gl, tracer, volume, mode, True, True), draw(gl, tracer, volume, mode, False, True)
    assert fewer.sum() < 0.8 * all_samples.sum()
    assert (fewer <= all_samples).all()


@pytest.mark.parametrize("mode", ["mip", "translucent"])
def test_rays_below_the_level_everywhere_draw_what_the_whole_rays_draw(gl, tracer, padded, mode):
    volume = Volume.new(1, 1, 1)
    volume.replace_scalars(padded, ABOVE_ALL)  # mip: the low's colour; translucent: clear, the background
    assert np.array_equal(draw(gl, tracer, volume, mode, True), draw(gl, tracer, volume, mode, False))
    assert draw(gl, tracer, volume, mode, True, True).sum() == 0  # no ray samples anything


def test_the_box_holds_the_bricks_over_the_level_and_nothing_when_none_is():
    values = np.zeros((40, 32, 24), np.int16)  # (d, h, w)
    values[20, 9, 16] = 100  # in brick (z 2, y 1, x 2) and, on its side, in the rim of brick x 1
    maxima = brick_maxima(values)
    lo, hi = box_over(maxima, (24, 32, 40), 50.0, 0.0)
    assert np.allclose(lo, (BRICK / 24, 8 / 32, 16 / 40)) and np.allclose(hi, (24 / 24, 16 / 32, 24 / 40))
    assert box_over(maxima, (24, 32, 40), 100.0, 0.0) == NOTHING
    assert box_over(maxima, (24, 32, 40), -1.0, 0.0) == ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
