"""app/model/transforms.py against matrices worked out by hand, and the GL layout against GL itself."""
import math

import moderngl
import numpy as np
import pytest

from app.model.transforms import frustum, gl_matrix, least_axis, look_at, orthographic, perspective


def test_perspective_maps_the_near_and_far_planes_to_the_clip_cube():
    # 90 degrees (focal 1), square, planes at 1 and 3: z' = -2 z - 3, w' = -z.
    expected = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -2, -3], [0, 0, -1, 0]]
    m = perspective(1.0, 1.0, 1.0, 3.0)
    np.testing.assert_array_equal(m, expected)
    for z, ndc in ((-1.0, -1.0), (-3.0, 1.0)):
        clip = m @ [0.0, 0.0, z, 1.0]
        assert clip[2] / clip[3] == pytest.approx(ndc)


def test_perspective_narrows_x_by_the_aspect():
    focal = 1 / math.tan(math.radians(30))  # 60 degrees vertically
    m = perspective(focal, 2.0, 0.5, 10.0)
    assert m[0, 0] == pytest.approx(focal / 2) and m[1, 1] == pytest.approx(focal)
    corner = m @ [2 * math.tan(math.radians(30)), math.tan(math.radians(30)), -1.0, 1.0]  # the view's corner at z=-1
    assert corner[:2] / corner[3] == pytest.approx([1.0, 1.0])


def test_a_frustum_maps_its_window_of_tangents_to_the_clip_square():
    np.testing.assert_array_equal(frustum((-1.0, -1.0), (1.0, 1.0), 1.0, 3.0), perspective(1.0, 1.0, 1.0, 3.0))
    m = frustum((0.5, -0.25), (1.5, 0.75), 2.0, 8.0)  # off centre: right of the axis, mostly above it
    for (tx, ty), ndc in (((0.5, -0.25), (-1, -1)), ((1.5, 0.75), (1, 1)), ((1.0, 0.25), (0, 0))):
        for depth in (2.0, 5.0):  # the same tangent at any depth: the same place in the window
            clip = m @ [tx * depth, ty * depth, -depth, 1.0]
            assert clip[:2] / clip[3] == pytest.approx(ndc)
    for z, ndc in ((-2.0, -1.0), (-8.0, 1.0)):
        clip = m @ [0.0, 0.0, z, 1.0]
        assert clip[2] / clip[3] == pytest.approx(ndc)


def test_orthographic_maps_its_box_to_the_clip_cube():
    m = orthographic((-1.0, -2.0, 1.0), (3.0, 2.0, 5.0))
    expected = [[0.5, 0, 0, -0.5], [0, 0.5, 0, 0], [0, 0, -0.5, -1.5], [0, 0, 0, 1]]
    np.testing.assert_array_equal(m, expected)
    np.testing.assert_allclose(m @ [-1.0, -2.0, -1.0, 1.0], [-1, -1, -1, 1])  # lo corner, depth 1 along -z
    np.testing.assert_allclose(m @ [3.0, 2.0, -5.0, 1.0], [1, 1, 1, 1])


def test_look_at_down_minus_z_is_a_translation():
    expected = [[1, 0, 0, -1], [0, 1, 0, -2], [0, 0, 1, -3], [0, 0, 0, 1]]
    np.testing.assert_array_equal(look_at((1.0, 2.0, 3.0), (0.0, 0.0, -1.0), (0.0, 1.0, 0.0)), expected)


def test_look_at_along_plus_x():
    # gluLookAt(eye 0, centre +x, up +y): right is +z, the view's -z is +x.
    expected = [[0, 0, 1, 0], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]]
    np.testing.assert_array_equal(look_at((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)), expected)


@pytest.mark.parametrize("forward", [(0.0, -1.0, 0.0), (0.0, 1.0, 0.0), (0.6, 0.0, -0.8), (0.48, -0.6, 0.64)])
def test_look_at_without_up_is_a_rigid_view_along_forward(forward):
    eye = np.array([1.0, -2.0, 0.5])
    m = look_at(eye, forward)
    rotation = m[:3, :3]
    np.testing.assert_allclose(rotation @ rotation.T, np.identity(3), atol=1e-12)
    assert np.linalg.det(rotation) == pytest.approx(1.0)
    np.testing.assert_allclose(rotation @ forward, [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(m @ [*eye, 1.0], [0, 0, 0, 1], atol=1e-12)
    assert abs(np.dot(least_axis(forward), forward)) == min(abs(np.asarray(forward)))


def test_gl_matrix_is_column_major():
    m = np.arange(16, dtype=np.float32).reshape(4, 4)
    assert gl_matrix(m) == (0, 4, 8, 12, 1, 5, 9, 13, 2, 6, 10, 14, 3, 7, 11, 15)
    assert all(isinstance(v, float) for v in gl_matrix(m))


VERTEX = """#version 330
uniform mat4 u_m;
out vec4 v_out;
void main() { v_out = u_m * vec4(1.0, 2.0, 3.0, 1.0); }
"""


def test_gl_matrix_multiplies_in_glsl_as_in_numpy(gl):
    m = np.array([[1, 2, 3, 4], [5, 6, 7, 8], [9, 10, 11, 12], [0.5, 0.25, 0.125, 1]])
    program = gl.program(vertex_shader=VERTEX, varyings=["v_out"])
    out = gl.buffer(reserve=16)
    vao = gl.vertex_array(program, [])
    try:
        program["u_m"].value = gl_matrix(m)
        vao.transform(out, mode=moderngl.POINTS, vertices=1)
        np.testing.assert_allclose(np.frombuffer(out.read(), "f4"), m @ [1, 2, 3, 1])
    finally:
        for obj in (vao, out, program):
            obj.release()
