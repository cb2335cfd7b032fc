"""The clouds workspace's commands and state: parameters, camera, sun, weather, clock, files, undo and a
demo's opening lines; every refusal changes nothing."""
from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from app.editor import Editor
from app.model.clouds.exposure import ToneSettings
from app.model.clouds.scene import PARAMS, CloudParams
from app.model.clouds.workspace import MAX_TIME


@pytest.fixture
def editor():
    editor = Editor()
    assert editor.execute("workspace clouds")
    return editor


def state(editor):
    return editor.workspaces["clouds"]


def test_clouds_set_changes_one_parameter_and_undo_restores_it(editor):
    assert editor.execute("clouds.set coverage 0.5")
    assert state(editor).params.coverage == 0.5
    assert editor.execute("undo")
    assert state(editor).params == CloudParams()


def test_a_slider_drag_of_one_parameter_is_one_undo_step(editor):
    for value in (0.5, 0.6, 0.7):
        assert editor.execute(f"clouds.set density {value}")
    assert editor.execute("undo")
    assert state(editor).params.density == CloudParams().density


@pytest.mark.parametrize("line", ["clouds.set nonsense 1", "clouds.set coverage 3", "clouds.set coverage nan",
                                  "clouds.set light_samples 7", "clouds.set shape_noise 0.5",
                                  "clouds.set shape_min 0.9", "clouds.set octave_scattering 0.8",
                                  "clouds.set phase_max 2", "r_cloudFurnace maybe", "camera.alt 0", "camera.alt 1e9",
                                  "camera.look 0 91", "sun.dir 0 95", "sun.time 25", "weather.new -1",
                                  "clouds.time -1", "r_cloudSteps 0", "r_cloudDownsample 5",
                                  "r_cloudIntegration exact", "r_cloudExposure 11", "r_cloudExposure nan",
                                  "r_cloudToneMap filmic"])
def test_bad_arguments_are_refused_and_change_nothing(editor, line):
    before = editor.digest()
    assert not editor.execute(line)
    assert editor.digest() == before


def test_clouds_list_names_every_parameter(editor):
    lines = []
    editor.console.log_listeners.append(lambda line: lines.append(line.text))
    assert editor.execute("clouds.list")
    text = "\n".join(lines)
    assert all(p.name in text for p in PARAMS)


def test_camera_and_sun_commands(editor):
    assert editor.execute("camera.alt 3000")
    assert editor.execute("camera.look 370 -20")
    assert editor.execute("sun.dir -90 10")
    view = state(editor).view
    assert (view.altitude, view.yaw, view.pitch) == (3000, 10, -20)
    assert (view.sun_azimuth, view.sun_elevation) == (270, 10)
    assert editor.execute("sun.time 12")
    assert state(editor).view.sun_elevation == pytest.approx(65)
    assert editor.execute("sun.time 0")
    assert state(editor).view.sun_elevation < 0  # night: finite, handled by the renderer's tests


def test_a_new_weather_blends_in_over_the_blend_time(editor):
    s = state(editor)
    assert editor.execute("weather.blend 30")
    assert editor.execute("weather.new 5")
    assert s.weather_source == "new 5"
    assert s.blend() == 0.0
    s.advance(15.0)
    assert s.blend() == pytest.approx(0.5)
    s.advance(30.0)
    assert s.blend() == 1.0


def test_a_new_weather_during_a_blend_starts_from_what_is_on_screen(editor):
    s = state(editor)
    assert editor.execute("weather.new 5")
    s.advance(12.0)
    old, new = s.weather.maps
    shown = old + (new - old) * s.blend()
    assert editor.execute("weather.new 6")
    old2, _new2 = s.weather.maps
    assert np.abs(old2 + (_new2 - old2) * s.blend() - shown).max() < 1e-6


def test_weather_new_without_a_seed_takes_the_next_one(editor):
    assert editor.execute("weather.new 41")
    assert editor.execute("weather.new")
    assert state(editor).weather_source == "new 42"


def test_weather_load_reads_a_png_and_refuses_a_broken_one(editor, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rgb = (np.random.default_rng(0).random((64, 64, 3)) * 255).astype(np.uint8)
    Image.fromarray(rgb).save(tmp_path / "w.png")
    assert editor.execute(f"weather.load {tmp_path / 'w.png'}")
    assert state(editor).weather_source.startswith("load ")
    (tmp_path / "bad.png").write_bytes(b"\x89PNG\r\n\x1a\n broken")
    before = editor.digest()
    assert not editor.execute(f"weather.load {tmp_path / 'bad.png'}")
    assert editor.digest() == before


def test_the_clock_moves_the_wind_by_the_time_scale(editor):
    s = state(editor)
    assert editor.execute("clouds.set time_scale 2")
    s.advance(3.0)
    assert (s.clock, s.wind_time) == (3.0, 6.0)
    assert editor.execute("clouds.time 10")
    assert (s.clock, s.wind_time) == (10.0, 20.0)


def test_scene_save_and_load_round_trip(editor, tmp_path):
    assert editor.execute("clouds.set coverage 0.7")
    assert editor.execute("sun.dir 120 40")
    assert editor.execute("weather.new 9")
    path = tmp_path / "sky.json"
    assert editor.execute(f"scene.save {path}")
    other = Editor()
    assert other.execute("workspace clouds")
    assert other.execute(f"scene.load {path}")
    a, b = state(editor), other.workspaces["clouds"]
    assert a.params == b.params and b.view.sun_azimuth == 120 and b.weather_source == "new 9"


@pytest.mark.parametrize("content", [
    '{"format": "shadelab.clouds", "version": 1, "params": {"coverage": 9}}',
    '{"format": "shadelab.clouds", "version": 1, "params": {"bogus": 1}}',
    '{"format": "shadelab.clouds", "version": 1, "params": {"shape_min": 0.9}}',
    '{"format": "shadelab.clouds", "version": 1, "params": {}, "sun": [0, 120]}',
    '{"format": "shadelab.clouds", "version": 2, "params": {}}',
    '{"format": "shadelab.clouds", "version": 1, "params": {"coverage": NaN}}',
    'not json'])
def test_a_malformed_scene_is_refused_and_changes_nothing(editor, tmp_path, content):
    path = tmp_path / "bad.json"
    path.write_text(content)
    before = editor.digest()
    assert not editor.execute(f"scene.load {path}")
    assert editor.digest() == before


def test_opening_commands_rebuild_the_state(editor, tmp_path):
    for line in ("clouds.set coverage 0.8", "clouds.set light_samples 30", "camera.alt 7000", "camera.look 33 21",
                 "sun.dir 200 15", "weather.new 12", "clouds.set weather_blend 12"):
        assert editor.execute(line)
    state(editor).advance(4.0)
    lines = state(editor).opening_commands(lambda: str(tmp_path / "unused"))
    other = Editor()
    assert other.execute("workspace clouds")
    assert other.execute("clouds.set hg_back 0.1")
    for line in lines:
        assert other.execute(line), line
    assert other.workspaces["clouds"].digest() == state(editor).digest()


def test_render_settings_follow_the_cvars(editor):
    for line in ("r_cloudSteps 64", "r_cloudDownsample 3", "r_cloudTAA 0", "r_cloudIntegration seed",
                 "r_cloudReproject 1", "r_cloudDebugSamples 1", "r_cloudExposure -1.5", "r_cloudAutoExposure 0",
                 "r_cloudToneMap agx"):
        assert editor.execute(line)
    s = editor.render_settings()
    assert (s.steps, s.downsample, s.taa, s.integration, s.reproject, s.debug_samples) == (
        64, 3, False, "seed", True, True)
    assert s.tone == ToneSettings(ev=-1.5, auto=False, curve="agx")


def test_the_scene_file_is_json_with_every_parameter(editor, tmp_path):
    path = tmp_path / "sky.json"
    assert editor.execute(f"scene.save {path}")
    data = json.loads(path.read_text())
    assert data["format"] == "shadelab.clouds" and set(data["params"]) == {p.name for p in PARAMS}


def test_the_clock_left_running_stops_at_the_ends_of_its_range_where_its_line_replays(editor):
    assert editor.execute("clouds.set time_scale -25")
    state(editor).advance(1e308)  # a day and more of blowing wind
    assert (state(editor).clock, state(editor).wind_time) == (MAX_TIME, -MAX_TIME)
    line = state(editor).opening_commands(lambda: "unused")[-1]
    assert line == f"clouds.time {MAX_TIME!r} {-MAX_TIME!r}"
    other = Editor()
    assert other.execute("workspace clouds") and other.execute(line)  # what is recorded is what the command takes
