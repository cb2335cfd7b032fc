"""The 3D lights' hard shadow cases (issue 29) as scenes of the product, and how a method's shadow is judged
against the CPU reference (app/reference/lights3d.py): a light on a box's corner, on the sphere's pole vertex and
on another of its vertices, on a box's edge, on a face, level with a face (and the default scene's point light,
level with the L-prism's top), and the camera looking along a point light's rays past the casters.

A case's measure is the bench's (app/bench/shadows.py): over the pixels the reference says the light faces and
reaches, the GPU's shadow against the reference's `facing & ~visible`; the mismatches more than a pixel from a
shadow edge of the reference count, as a share of the reference's shadowed pixels."""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from app.bench.shadows import shadow_edge
from app.gl.core.headless import OffscreenTarget
from app.gl.core.shaders import ShaderLibrary
from app.gl.core.stencil import StencilTarget
from app.gl.lights3d.renderer import Lights3DRenderer
from app.gl.lights3d.shadow_volume_pass import ShadowVolumePass
from app.model.lights3d.scene import Light3D, Lights3DCamera, Object3D, Scene3D, default_scene
from app.reference import lights3d as reference
from app.resources import SHADERS

SIZE = (160, 120)
GROUND = Object3D("plane", (400.0,), (0.0, 0.0, 0.0), (0.75, 0.75, 0.72))
BOX = Object3D("box", (30.0, 30.0, 30.0), (-25.0, 15.0, 0.0), (0.85, 0.35, 0.25))     # corners x -40|-10, y 0|30
SPHERE = Object3D("sphere", (18.0, 32), (10.0, 18.0, 0.0), (0.3, 0.55, 0.85))        # its pole vertex (10, 36, 0)


def camera_at(eye, target) -> Lights3DCamera:
    offset = np.subtract(eye, target)
    distance = float(np.linalg.norm(offset))
    return Lights3DCamera(yaw=float(np.degrees(np.arctan2(offset[0], offset[2]))),
                          pitch=float(np.degrees(np.arcsin(offset[1] / distance))), distance=distance,
                          target=tuple(map(float, target)))


def lamp(x, y, z) -> Light3D:
    return Light3D("point", (x, y, z), range=400.0)


@dataclass(frozen=True)
class Case:
    name: str
    scene: Scene3D        # its light 0 is the one judged
    camera: Lights3DCamera


VIEW = camera_at((-20.0, 140.0, 170.0), (-10.0, 5.0, 0.0))  # above the box and the sphere, their shadows in view
SPHERE_VERTEX = tuple(SPHERE.mesh().positions[1 + 3 * 32 + 24])  # 45 degrees from the pole, towards the camera
CASES = {c.name: c for c in (
    Case("light on a box corner", Scene3D((GROUND, BOX, SPHERE), (lamp(-10.0, 30.0, 15.0),)), VIEW),
    Case("light on the sphere's pole", Scene3D((GROUND, BOX, SPHERE), (lamp(10.0, 36.0, 0.0),)), VIEW),
    Case("light on a sphere vertex", Scene3D((GROUND, BOX, SPHERE), (lamp(*SPHERE_VERTEX),)), VIEW),
    Case("light on a box edge", Scene3D((GROUND, BOX, SPHERE), (lamp(-10.0, 30.0, 4.0),)), VIEW),
    # seen from the lit side: all beyond the face's plane is in its shadow (an eye there is inside the volume)
    Case("light on a box face", Scene3D((GROUND, BOX, SPHERE), (lamp(-10.0, 12.0, 3.0),)),
         camera_at((70.0, 150.0, 110.0), (-35.0, 0.0, 0.0))),
    Case("light level with a face", Scene3D((GROUND, BOX, SPHERE), (lamp(30.0, 30.0, 10.0),)), VIEW),
    # the default scene's point light at y = 40, level with the L-prism's top, seen from the default camera
    Case("default point light", default_scene(), Lights3DCamera()),
    # the eye beyond the point light, looking along its rays past the sphere and the box onto their shadows
    Case("looking along a light's rays", Scene3D((GROUND, BOX, SPHERE), (lamp(20.0, 70.0, 0.0),)),
         camera_at((40.0, 95.0, 10.0), (-25.0, 5.0, 0.0))),
)}


@lru_cache(maxsize=None)
def truth(name: str, size: tuple[int, int] = SIZE) -> reference.Result:
    case = CASES[name]
    return reference.render(case.scene, case.camera, size)


@dataclass(frozen=True)
class Judged:
    shadowed: int        # the reference's shadowed pixels (the light faces and reaches them, something blocks it)
    wrong: int           # mismatched pixels in all
    wrong_off_edge: int  # ... of them more than a pixel from a shadow edge of the reference

    @property
    def share(self) -> float:
        """The mismatches off the edges, as a share of the reference's shadowed pixels."""
        return self.wrong_off_edge / max(self.shadowed, 1)


def judge(mask: np.ndarray, ref: reference.Result, light: int = 0) -> Judged:
    region = ref.facing[light]
    shadow = region & ~ref.visible[light]
    wrong = (mask != shadow) & region
    return Judged(int(shadow.sum()), int(wrong.sum()), int((wrong & ~shadow_edge(shadow)).sum()))


def near_a_jump(ref: reference.Result, eye) -> np.ndarray:
    """Pixels beside a silhouette: a 4-neighbour shows another object, or a surface over 5% nearer or farther
    (the torus in front of itself). Their centres lie within a pixel of the edge, where the float32 raster and
    the float64 ray may each pick the triangle on their own side."""
    distance = np.linalg.norm(ref.position - np.asarray(eye), axis=-1)
    jump = np.zeros(ref.object_id.shape, bool)
    before, after = slice(None, -1), slice(1, None)
    for a, b in (((before,), (after,)), ((slice(None), before), (slice(None), after))):  # rows, then columns
        with np.errstate(invalid="ignore"):  # the background's distance is NaN: its id tells
            step = (ref.object_id[a] != ref.object_id[b]) | (
                np.abs(distance[a] - distance[b]) > 0.05 * np.fmin(distance[a], distance[b]))
        jump[a] |= step
        jump[b] |= step
    return jump


def renderer_and_target(gl, size):
    """A module fixture's body: a 3D-lights renderer and an offscreen target of `size`, released after."""
    renderer, target = Lights3DRenderer(gl, ShaderLibrary(gl, [SHADERS])), OffscreenTarget(gl, size)
    yield renderer, target
    renderer.release()
    gl.detect_framebuffer(0).use()  # moderngl binds its last framebuffer again: never a deleted one
    target.release()


def stencil_host(gl, size):
    """A shadow-volume pass and a stencil target of `size` for a module's tests (a fixture's body: released after)."""
    shadow_pass, target = ShadowVolumePass(gl, ShaderLibrary(gl, [SHADERS])), StencilTarget(gl, size)
    yield shadow_pass, target
    target.release()
    shadow_pass.release()
