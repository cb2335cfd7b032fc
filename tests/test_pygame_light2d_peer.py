"""pygame-light2d draws a light and a hull's shadow where our coordinates put them (bench extra; skipped
where pygame-light2d is not installed)."""
import numpy as np
import pytest

pytest.importorskip("pygame_light2d")

from app.bench import pygame_light2d_peer as peer  # noqa: E402

reason = peer.available()
pytestmark = pytest.mark.skipif(reason is not None, reason=reason or "")


def test_light_at_the_centre_and_a_shadow_behind_the_hull():
    ambient = 0.1
    light = {"position": (32, 32), "radius": 60.0, "color": (1.0, 1.0, 1.0), "power": 1.0, "casts_shadows": True}
    hull = np.array([(40, 28), (48, 28), (48, 36), (40, 36)], float)  # right of the light, x 40..48
    result = peer.render((64, 64), (ambient,) * 3, [light], [hull], frames=1)
    image = result.image
    assert image.shape == (64, 64, 3) and image.dtype == np.float32
    assert np.isfinite(image).all() and np.isfinite(result.ms_per_frame)
    assert image[32, 34].min() > ambient + 0.5  # beside the light
    # Pixel centres 22.5 px either side of the light, on row 32: behind the hull, and its mirror image.
    behind, mirrored = image[32, 54], image[32, 9]
    assert behind.max() < mirrored.min() - 0.1
    assert np.allclose(behind, ambient, atol=0.02)  # only the ambient reaches the shadow
    # Row 0 is the top: a light near the top edge (pygame's y down) lights the top rows.
    top = peer.render((64, 64), (0, 0, 0), [{**light, "position": (32, 4), "radius": 20.0}], [], frames=1).image
    assert top[:8, 28:36].mean() > 0.5 and top[-8:].max() == 0


def test_scenes_past_the_shader_arrays_are_refused():
    square = np.array([(0, 0), (2, 0), (2, 2), (0, 2)], float)
    with pytest.raises(ValueError, match="at most 256 hulls"):
        peer.render((16, 16), (0, 0, 0), [], [square] * 257)
