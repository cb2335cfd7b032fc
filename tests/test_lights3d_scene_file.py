"""The 3D lights scene file: a save loads back equal, and a malformed, oversized or wrong-typed file is refused
whole with a message naming the field, before any scene is made."""
import json

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from app.io import json_file, lights3d_scene
from app.io.lights3d_scene import Lights3DSceneError
from app.model.lights3d import scene as lm
from app.model.lights3d.scene import Light3D, Object3D, Scene3D, default_scene


def saved(tmp_path, scene=None) -> dict:
    path = tmp_path / "scene.json"
    lights3d_scene.save(path, scene or default_scene())
    return json.loads(path.read_text())


def test_round_trip(tmp_path):
    scene = default_scene().add_light(Light3D("directional", (0, 300, 0), (0.3, -1, 0.2), (0.5, 0.4, 0.3),
                                              shadow="map"))
    scene = scene.with_settings(ambient=(0.05, 0.1, 0.2), shininess=12.5, specular=0.25)
    path = tmp_path / "scene.json"
    lights3d_scene.save(path, scene)
    assert lights3d_scene.load(path) == scene
    assert [p.name for p in tmp_path.iterdir()] == ["scene.json"]  # written atomically: no temporary left
    lights3d_scene.save(path, default_scene())  # over an existing file
    assert lights3d_scene.load(path) == default_scene()


UNIT = st.floats(0.0, 1.0)
COORD = st.floats(-1e5, 1e5)
OBJECTS = st.one_of(
    st.builds(Object3D, st.just("box"), st.tuples(*[st.floats(0.01, 1e4)] * 3), st.tuples(COORD, COORD, COORD),
              st.tuples(UNIT, UNIT, UNIT)),
    st.builds(Object3D, st.just("sphere"), st.tuples(st.floats(0.01, 1e4), st.integers(3, 40)),
              st.tuples(COORD, COORD, COORD)),
    # from 2 up, a torus's minor radius and hole, and an L's arms, keep to the size floor (0.01) at any ratio
    st.builds(lambda major, ratio, n, m: Object3D("torus", (major, major * ratio, n, m)),
              st.floats(2.0, 1e4), st.floats(0.01, 0.99), st.integers(3, 40), st.integers(3, 40)),
    st.builds(lambda sx, sy, sz, r: Object3D("lprism", (sx, sy, sz, r * min(sx, sy))),
              *[st.floats(2.0, 1e4)] * 3, st.floats(0.01, 0.99)),
    st.builds(Object3D, st.just("plane"), st.tuples(st.floats(0.01, 1e4))),
)
LIGHTS = st.builds(Light3D, st.sampled_from(lm.LIGHT_KINDS), st.tuples(COORD, COORD, COORD),
                   st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(0.01, 1)),
                   st.tuples(*[st.floats(0, lm.MAX_INTENSITY)] * 3), st.floats(1e-3, lm.MAX_SIZE),
                   st.floats(1e-3, lm.MAX_FALLOFF), st.floats(0.01, 89.99), st.sampled_from(lm.SHADOW_METHODS))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(OBJECTS, max_size=6), st.lists(LIGHTS, max_size=lm.MAX_LIGHTS), st.tuples(UNIT, UNIT, UNIT),
       st.floats(1e-3, lm.MAX_SHININESS), st.floats(0, lm.MAX_SPECULAR))
def test_whatever_the_model_holds_saves_and_loads_equal(tmp_path, objects, lights, ambient, shininess, specular):
    scene = Scene3D(tuple(objects), tuple(lights), ambient, shininess, specular)
    path = tmp_path / "any.json"
    lights3d_scene.save(path, scene)
    assert lights3d_scene.load(path) == scene


def test_optional_fields_take_the_models_defaults(tmp_path):
    path = tmp_path / "minimal.json"
    path.write_text(json.dumps({"format": "shadelab.lights3d", "version": 1,
                                "objects": [{"kind": "sphere", "size": [10, 16], "position": [0, 10, 0]}],
                                "lights": [{"kind": "point", "position": [0, 50, 0]}]}))
    scene = lights3d_scene.load(path)
    assert scene == Scene3D((Object3D("sphere", (10, 16), (0, 10, 0)),), (Light3D("point", (0, 50, 0)),))


def with_change(data: dict, keys: tuple, value) -> dict:
    node = data
    for key in keys[:-1]:
        node = node[key]
    node[keys[-1]] = value
    return data


@pytest.mark.parametrize("keys, value, needle", [
    (("objects", 1, "kind"), "cone", "objects[1].kind: must be one of box, sphere, torus, lprism, plane, got 'cone'"),
    (("objects", 2, "size"), [], "objects[2].size: expected 1 to 4 numbers, got 0"),
    (("objects", 2, "size"), [1, 2, 3, 4, 5], "objects[2].size: expected 1 to 4 numbers, got 5"),
    (("objects", 2, "size"), [18, "32"], "objects[2].size[1]: expected a number, got a string"),
    (("objects", 1, "size"), [30, 30], r"objects[1]: a box's size (sx, sy, sz) must be 3 numbers, got 2"),
    (("objects", 3, "size"), [20, 30, 48, 16], "objects[3]: torus minor radius must be below its major radius"),
    (("objects", 2, "size"), [18, 32.5], "objects[2]: sphere segments must be a whole number"),
    (("objects", 1, "position"), [0, 0], "objects[1].position: expected 3 numbers, got 2"),
    (("objects", 1, "position"), [0, 1e300, 0], "objects[1].position[1]: must be within -100000..100000"),
    (("objects", 1, "colour"), [1, 2, 0], "objects[1].colour[1]: must be within 0..1, got 2"),
    (("objects", 1, "spin"), 1, "objects[1]: unknown keys: spin"),
    (("lights", 0, "kind"), "area", "lights[0].kind: must be one of point, spot, directional, got 'area'"),
    (("lights", 0, "shadow"), 3,
     "lights[0].shadow: must be one of onepass, onepass-seed, zpass, zfail, map, none, got 3"),
    (("lights", 1, "angle"), 0, "lights[1].angle: must be > 0 and <= 90, got 0"),
    (("lights", 1, "angle"), 90, "lights[1]: spot angle must be below 90 degrees"),
    (("lights", 1, "direction"), [0, 0, 0], "lights[1]: spot light direction must not be zero"),
    (("lights", 0, "range"), -1, "lights[0].range: must be > 0 and <= 10000, got -1"),
    (("lights", 0, "colour"), "white", "lights[0].colour: expected a list, got a string"),
    (("lights",), [{"kind": "point", "position": [0, 0, 0]}] * 9, "lights: expected at most 8 lights, got 9"),
    (("objects",), [{"kind": "box", "size": [1, 1, 1], "position": [0, 0, 0]}] * 65,
     "objects: expected at most 64 objects, got 65"),
    (("objects",), [{"kind": "sphere", "size": [1, 400], "position": [0, 0, 0]}] * 2,
     "scene: the scene's objects have 318400 triangles, more than 200000"),
    (("ambient",), [0.1, 0.1], "ambient: expected 3 numbers, got 2"),
    (("shininess",), 0, "shininess: must be > 0 and <= 4096, got 0"),
    (("version",), 2, "unsupported version 2 (this build reads 1)"),
    (("format",), "shadelab.clouds", "is not a shadelab.lights3d file"),
])
def test_bad_fields_refused_by_their_path(tmp_path, keys, value, needle):
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(with_change(saved(tmp_path), keys, value)))
    with pytest.raises(Lights3DSceneError) as refusal:
        lights3d_scene.load(path)
    assert needle in str(refusal.value), str(refusal.value)
    assert str(refusal.value).startswith(str(path))


@pytest.mark.parametrize("text, needle", [
    ("{", "is not valid JSON"),
    ('{"format": "shadelab.lights3d", "version": 1, "objects": [], "lights": [], "shininess": NaN}',
     "NaN is not a finite number"),
    ("[" * 100_000, "nested too deeply"),
    ('{"format": "shadelab.lights3d", "version": 1, "lights": []}', "(top level): missing objects"),
    ("\xff\xfe", "is not valid JSON"),
])
def test_malformed_files_refused(tmp_path, text, needle):
    path = tmp_path / "bad.json"
    path.write_bytes(text.encode("latin-1"))
    with pytest.raises(Lights3DSceneError) as refusal:
        lights3d_scene.load(path)
    assert needle in str(refusal.value)


def test_oversized_and_irregular_files_refused(tmp_path):
    big = tmp_path / "big.json"
    big.write_bytes(b" " * (json_file.MAX_BYTES + 1))
    with pytest.raises(Lights3DSceneError, match="cannot read"):
        lights3d_scene.load(big)
    with pytest.raises(Lights3DSceneError, match="cannot read"):
        lights3d_scene.load(tmp_path)  # a folder
    with pytest.raises(Lights3DSceneError, match="cannot read"):
        lights3d_scene.load(tmp_path / "missing.json")
