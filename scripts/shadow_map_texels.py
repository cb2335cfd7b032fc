"""The shadow maps before and after fitting them to the view (issue 29), on its hard cases (app/bench/map_texels.py):
per case, the texels a screen pixel gets (median over the pixels the light faces and reaches) and the mask's
mismatch against the CPU reference (all the judged pixels wrong, and those off the shadow's edges, each as a share
of the reference's shadowed pixels), with the maps fitted to the scene's bounds as they were (`before`, drawn by
the same renderer and shader) and fitted to the view (`after`).

    PYTHONPATH=. .venv/bin/python scripts/shadow_map_texels.py [WIDTH HEIGHT]     (default 320 240)
"""
import contextlib
import math
import sys
from unittest import mock

import numpy as np

from app.bench.map_texels import hard_cases, texels_per_pixel
from app.bench.shadows import shadow_edge
from app.gl.core.headless import create_context, release_context
from app.gl.core.shaders import ShaderLibrary
from app.gl.lights3d import renderer as renderer_module
from app.gl.lights3d.light_reach import box_corners
from app.gl.lights3d.renderer import Lights3DRenderer
from app.gl.lights3d.shadow_map import CUBE, CUBE_FACES, NEAR_SHARE, ONE, MapViews, widening
from app.model.lights3d.render_settings import Lights3DRenderSettings
from app.model.transforms import look_at, orthographic, perspective
from app.reference import lights3d as reference
from app.resources import SHADERS


def scene_wide(bounds):
    """The views as the map had them before: fitted to every object's bounds, whatever the view sees."""
    corners = box_corners(*bounds)

    def fit(light, _receivers, _casters, _view_proj, size, pcf, _cascades) -> MapViews:
        wider = widening(size, pcf)
        if light.kind == "point":
            far = light.range
            faces = tuple(perspective(1.0 / wider, 1.0, NEAR_SHARE * far, far) @ look_at(light.position, d)
                          for d in CUBE_FACES)
            return MapViews(CUBE, faces, (True,) * 6, (3, 2), 0.0, far)
        if light.kind == "spot":
            far = max(float(np.linalg.norm(corners - light.position, axis=1).max()), 1e-6)
            tan_half = math.tan(math.radians(light.angle)) * wider
            view = perspective(1.0 / tan_half, 1.0, NEAR_SHARE * far, far) @ look_at(light.position, light.direction)
            return MapViews(ONE, (view,), (True,), (1, 1), 0.0, far)
        centre = (corners.min(0) + corners.max(0)) / 2
        view = look_at(centre, light.direction)
        local = corners @ view[:3, :3].T + view[:3, 3]
        half = np.maximum(np.abs(local[:, :2]).max(0), 1e-6) * wider
        depth = -local[:, 2]
        margin = 1e-3 * max(depth.max() - depth.min(), 1e-6)
        box = orthographic((-half[0], -half[1], depth.min() - margin), (half[0], half[1], depth.max() + margin))
        return MapViews(ONE, (box @ view,), (True,), (1, 1))
    return fit


def main(size=(320, 240)) -> None:
    settings = Lights3DRenderSettings()
    ctx = create_context()
    holder = ctx.simple_framebuffer((8, 8))
    holder.use()
    renderer = Lights3DRenderer(ctx, ShaderLibrary(ctx, [SHADERS]))
    print(f"{size[0]} x {size[1]}, map {settings.map_size}, PCF {settings.pcf}, bias {settings.bias}, "
          f"{settings.cascades} cascades")
    print(f"{'case':24} {'shadowed px':>11}  {'texels/px before':>16} {'after':>8}   "
          f"{'wrong % before':>14} {'after':>6}   {'off edge % before':>17} {'after':>6}")
    for case in hard_cases():
        ref = reference.render(case.scene, case.camera, size)
        judged = ref.facing[case.light]
        truth = judged & ~ref.visible[case.light]
        edge = shadow_edge(truth)
        lo = np.min([o.bounds[0] for o in case.scene.objects], axis=0)
        hi = np.max([o.bounds[1] for o in case.scene.objects], axis=0)
        row = {}
        for when, patch in (("before", mock.patch.object(renderer_module, "fit_views", scene_wide((lo, hi)))),
                            ("after", contextlib.nullcontext())):
            with patch:
                mask, _ = renderer.shadow_mask(case.scene, case.camera, size, case.light, "map", settings)
            wrong = (mask != truth) & judged
            light = case.scene.lights[case.light]
            row[when] = (texels_per_pixel(renderer.mask_map.views, light.position, settings.map_size, ref.position,
                                          ref.object_id, judged),
                         100 * wrong.sum() / truth.sum(), 100 * (wrong & ~edge).sum() / truth.sum())
        (t0, w0, e0), (t1, w1, e1) = row["before"], row["after"]
        print(f"{case.name:24} {truth.sum():11d}  {t0:16.4g} {t1:8.4g}   {w0:14.2f} {w1:6.2f}   {e0:17.2f} {e1:6.2f}")
    renderer.release()
    holder.release()
    release_context(ctx)


if __name__ == "__main__":
    main(tuple(map(int, sys.argv[1:3])) if len(sys.argv) > 2 else (320, 240))
