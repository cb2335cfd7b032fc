"""Empty-space skipping changes how many samples a ray takes, never the image (issue 13): F7 against F5, and F8
against itself with skipping off (cl_distanceScale 0: every skip is one step), over seeded random sparse
volumes and cameras, and again after strokes and erasures while the distance field is only clamped."""
import numpy as np
import pytest

from app.gl.core.headless import OffscreenTarget
from app.gl.volume.raytracer import RayTracer, TraceSettings
from app.gl.core.shaders import ShaderLibrary
from app.model.volume.volume import Volume
from app.model.volume.voxels import Voxels
from app.model.volume.view import VolumeView
from app.resources import SHADERS
from tests.sparse_volumes import KINDS, random_camera, random_edit, random_steps, sparse_volume

SIZE = (64, 64)
TOLERANCE = 1 / 255 + 1e-9


@pytest.fixture(scope="module")
def tracer(gl):
    return RayTracer(gl, ShaderLibrary(gl, [SHADERS]))


class Renders:
    """One small target; an image or a mean sample count per pixel for each setting."""

    def __init__(self, gl, tracer) -> None:
        self.tracer = tracer
        self.target = OffscreenTarget(gl, SIZE, samples=0)
        self.counts = gl.framebuffer([gl.renderbuffer(SIZE, 4, dtype="f4")])

    def image(self, voxels, view, **settings) -> np.ndarray:
        self.tracer.render(self.target.fbo, voxels, view, TraceSettings(slice_planes=False, **settings))
        return self.target.read()[..., :3] / 255.0

    def samples(self, voxels, view, **settings) -> float:
        self.tracer.render(self.counts, voxels, view, TraceSettings(slice_planes=False, debug_samples=True, **settings))
        return float(np.frombuffer(self.counts.read(components=4, dtype="f4"), "f4")[0::4].mean())

    def release(self) -> None:
        self.target.release()
        self.counts.release()


@pytest.fixture
def renders(gl, tracer):
    r = Renders(gl, tracer)
    yield r
    r.release()


def difference(renders, voxels, view, steps, with_f8: bool) -> float:
    """max |F5 - F7|, and with_f8 also max |F8 - F8 without skipping|, for one camera."""
    pairs = [({"mode": 7}, {"mode": 5})] + [({"mode": 8}, {"mode": 8, "distance_scale": 0.0})] * with_f8
    return max(float(np.abs(renders.image(voxels, view, **skipped, **steps)
                             - renders.image(voxels, view, **plain, **steps)).max()) for skipped, plain in pairs)


def test_skipping_leaves_random_sparse_scenes_unchanged(renders):
    """Isolated voxels, 1-voxel lines and planes at random angles, thin shells and 0.1..5 % noise, random RGBA;
    120 random cameras (inside the box too) at random cl_steps 39..241 and cl_shadowSteps. Enough pairs and
    pixels that the old accumulated stepping (t += dt) failed here, with this seed and each of 6 others tried."""
    rng = np.random.default_rng(1301)
    worst, plain, skipped = 0.0, 0.0, 0.0
    for v in range(12):
        shape = tuple(int(s) for s in rng.integers(8, 65, 3))
        voxels = Voxels(sparse_volume(rng, KINDS[v % len(KINDS)], shape))
        for c in range(10):
            view, steps = VolumeView(camera=random_camera(rng)), random_steps(rng)
            worst = max(worst, difference(renders, voxels, view, steps, c % 3 == 0))
            if c == 0:  # the skipping really happens: fewer samples for the same picture
                plain += renders.samples(voxels, view, mode=5, **steps)
                skipped += renders.samples(voxels, view, mode=7, **steps)
    assert worst <= TOLERANCE
    assert skipped < 0.8 * plain


def test_skipping_after_edits_with_the_clamped_field(renders, tracer):
    """Strokes and erasures only clamp the distance field (refine() has not run): still the same picture."""
    rng = np.random.default_rng(1302)
    worst, clamped = 0.0, 0
    for v in range(6):
        shape = tuple(int(s) for s in rng.integers(12, 49, 3))
        volume = Volume(sparse_volume(rng, KINDS[v % len(KINDS)], shape))
        renders.image(volume.voxels, VolumeView(), mode=7)  # the exact field, before any edit
        for r in range(6):
            for _edit in range(int(rng.integers(1, 4))):
                random_edit(rng, volume)
            view = VolumeView(camera=random_camera(rng))
            worst = max(worst, difference(renders, volume.voxels, view, random_steps(rng), r % 3 == 0))
            clamped += tracer.distance.stale  # the clamped field, not a rebuild
    assert worst <= TOLERANCE
    assert clamped >= 30  # of the 36 pictures
    assert tracer.distance.refine() and not tracer.distance.stale
