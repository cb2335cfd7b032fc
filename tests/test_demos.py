"""Demos: recorded with their times, replayed on a virtual clock to the same state digest."""
import pytest

from app.console import demo
from app.console.demo import VirtualClock
from app.editor import Editor


@pytest.fixture(autouse=True)
def isolated(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def errors(editor):
    return [line.text for line in editor.console.log if line.level == "error"]


def refused(tmp_path, text: str) -> str:
    """`text` as a demo is refused by play and timedemo before anything runs; the last error says why."""
    (tmp_path / "bad.demo").write_text(text)
    e = Editor(clock=VirtualClock())
    before = e.digest()
    assert not e.execute("play bad") and not e.execute("timedemo bad")
    assert e.digest() == before and not e.demos.playing
    return errors(e)[-1]


def record_session(clock):
    """A session touching cvars and the model, mid-way through a changed state."""
    e = Editor(clock=clock)
    e.execute("snow.add 0.25 0.5 0.125; cl_steps 200")  # before recording: the preamble must carry it
    e.execute("record session")
    clock.advance(0.5)
    e.execute("snow.level 2.75")
    clock.advance(0.25)
    e.execute("set r_fresh 3; snow.move 0 -0.5 0.1")
    e.execute("help snow.add")  # a query: not recorded
    e.execute("snow.level 99")  # refused: not recorded
    clock.advance(1.0)
    e.execute("snow.view 0.1 0.2 1.5; snow.remove 2")
    e.execute("stop")
    return e


def test_record_then_replay_in_a_fresh_editor_gives_the_same_digest(tmp_path):
    recorded = record_session(VirtualClock())
    text = (tmp_path / "session.demo").read_text()
    assert text.startswith("shadelab-demo 1\n")
    assert "help" not in text and "snow.level 99" not in text
    assert "0.500 snow.level 2.75" in text and "1.750 snow.remove 2" in text

    clock = VirtualClock()
    fresh = Editor(clock=clock)
    assert fresh.digest() != recorded.digest()
    assert fresh.execute("play session")
    clock.advance(0.6)
    fresh.demos.update()
    assert fresh.workspaces["snowflake"].scene.level == 2.75 and fresh.demos.playing
    clock.advance(1.2)
    fresh.demos.update()
    assert not fresh.demos.playing
    assert fresh.digest() == recorded.digest()
    cam, rec = fresh.workspaces["snowflake"].camera, recorded.workspaces["snowflake"].camera
    assert (cam.cx, cam.cy, cam.height) == (rec.cx, rec.cy, rec.height)  # the view too


def test_speed_pause_and_stop(tmp_path):
    record_session(VirtualClock())
    clock = VirtualClock()
    e = Editor(clock=clock)
    e.execute("play session 2")
    clock.advance(0.3)  # 0.6 s of demo time at speed 2
    e.demos.update()
    assert e.workspaces["snowflake"].scene.level == 2.75
    e.execute("pause")
    clock.advance(10)
    e.demos.update()
    assert e.demos.playing and len(e.workspaces["snowflake"].scene.flakes) == 8  # the remove at 1.75 s has not run
    e.execute("pause")  # resume
    clock.advance(0.6)
    e.demos.update()
    assert not e.demos.playing and len(e.workspaces["snowflake"].scene.flakes) == 7
    e.execute("play session")
    assert e.execute("stop") and not e.demos.playing


def test_timedemo_runs_everything_now_and_prints_fps():
    record_session(VirtualClock())
    frames = []
    e = Editor(clock=VirtualClock(), frame=lambda: frames.append(1))
    assert e.execute("timedemo session")
    assert "frames/s" in e.console.log[-1].text
    assert len(frames) == 4  # the preamble at 0 s, then 0.5, 0.75 and 1.75 s


@pytest.mark.parametrize("text, needle", [
    ("", "not a demo"),
    ("quake-demo 1\n0 snow.clear\n", "not a demo"),
    ("shadelab-demo 7\n0 snow.clear\n", "unsupported demo version"),
    ("shadelab-demo 1\nsoon snow.clear\n", "expected '<seconds> <command>'"),
    ("shadelab-demo 1\n1.0 snow.clear\n0.5 snow.clear\n", "not before the line above"),
    ("shadelab-demo 1\n0 snow.clear\n1.0\n", "no command"),
    ("shadelab-demo 1\n0 snow.clear\n0.5 snow.frobnicate 1\n", "unknown command 'snow.frobnicate'"),
    ("shadelab-demo 1\n0 snow.clear\n0.5 snow.add 1\n", "missing <y>"),
    ("shadelab-demo 1\n0 snow.clear\n0.5 cl_steps lots\n", "takes a int"),
])
def test_malformed_demo_is_refused_and_nothing_is_applied(tmp_path, text, needle):
    assert needle in refused(tmp_path, text)


def test_truncated_demo_is_refused(tmp_path):
    record_session(VirtualClock())
    data = (tmp_path / "session.demo").read_bytes()
    (tmp_path / "cut.demo").write_bytes(data[: len(data) - 9])  # cut inside the last command
    e = Editor(clock=VirtualClock())
    before = e.digest()
    assert not e.execute("play cut")
    assert e.digest() == before


def test_names_created_by_the_demo_itself_are_accepted():
    events = demo.parse("shadelab-demo 1\n0 set r_new 1\n0.1 r_new 2\n0.2 alias go 'snow.step 1'\n0.3 go\n")
    demo.check(Editor().console, events)


def test_record_refuses_a_second_recording_and_a_missing_folder(tmp_path):
    e = Editor(clock=VirtualClock())
    assert not e.execute("record nowhere/x")
    assert "no folder" in errors(e)[-1]
    assert e.execute("record a")
    assert not e.execute("record b")
    e.demos.stop_all()
    assert (tmp_path / "a.demo").exists()


def test_shipped_demo_plays():
    e = Editor(clock=VirtualClock())
    assert e.execute("timedemo snowflake_tour")
    assert errors(e) == []
    assert e.workspaces["snowflake"].scene.level == 6 and len(e.workspaces["snowflake"].scene.flakes) == 2


def test_preamble_quotes_text_and_keeps_floats_exact(tmp_path):
    clock = VirtualClock()
    e = Editor(clock=clock)
    e.execute('set greeting "hello world"; cl_distanceScale 1.23456789; mode 3; shadows 0; light 0.1 0.2 0.3')
    e.execute("record exact")
    e.execute("stop")
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute("timedemo exact")
    reg = fresh.console.registry
    assert reg.cvars["greeting"].value == "hello world" and reg.cvars["cl_distanceScale"].value == 1.23456789
    assert fresh.digest() == e.digest()
    view = fresh.workspaces["volume"].view
    assert (view.mode, view.shadows, view.light) == (3, False, (0.1, 0.2, 0.3))


@pytest.mark.parametrize("line, needle", [
    ("1e308 snow.clear", "time 1e308 must be within 0..86400 s"),
    ("86400.5 snow.clear", "time 86400.5 must be within 0..86400 s"),
    ("nan snow.clear", "time nan must be within"),
    ("inf snow.clear", "time inf must be within"),
])
def test_a_demo_time_beyond_a_day_is_refused_at_parse_time(tmp_path, line, needle):
    assert needle in refused(tmp_path, f"shadelab-demo 1\n0 snow.clear\n{line}\n")


@pytest.mark.parametrize("speed", ["1e-300", "0.01", "65", "1e308", "0", "-1"])
def test_a_speed_outside_1_64th_to_64_is_refused(tmp_path, speed):
    (tmp_path / "ok.demo").write_text("shadelab-demo 1\n0 snow.clear\n86400 snow.add 0 0\n")
    e = Editor(clock=VirtualClock())
    before = e.digest()
    assert not e.execute(f"play ok {speed}")
    assert "speed must be within 1/64..64" in errors(e)[-1]
    assert e.digest() == before and not e.demos.playing
    with pytest.raises(demo.DemoError, match="speed must be within"):
        demo.Player(e.console, VirtualClock(), [], float(speed))
    assert e.execute("play ok 0.015625") and e.demos.player.next_due() == 86400 * 64  # the slowest end


@pytest.mark.parametrize("line, needle", [
    ("set cl_steps not_a_number", "cl_steps takes a int, got 'not_a_number'"),
    ("seta cl_steps 99999", "cl_steps must be within 1..4096"),
    ("set r_shadowMethod magic", "r_shadowMethod must be one of"),
    ("voxel 9999 0 0 255 0 0 255", "voxel (9999, 0, 0) is outside the 64 x 64 x 64 volume"),
    ("slice z 100000", "slice 100000 is outside 0..63 along z"),
    ("stroke z 64 1 255 0 0 255 0 0", "slice z = 64 is outside 0..63"),
    ("fill x 0 70 0 255 0 0 255", "(70, 0) is outside the 64 x 64 slice"),
    ("brush.color 0 0 0 300", "colour components must be 0..255"),
    ("snow.move 99 0 0", "no flake 99"),
    ("snow.level 9", "level must be within 0..8"),
    ("light.set 7 radius 1", "no light 7"),
    ("light.set 0 radius -1", "light radius must be >= 0"),
    ("hull.vertex 0 99 0 0", "hull 0 has no vertex 99"),
    ("hull.set 0 scale -1 1", "hull scale must be >= 0"),
    ("orbit 0 90", "pitch must be within"),
])
def test_a_value_the_model_would_refuse_refuses_the_demo_before_anything_runs(tmp_path, line, needle):
    error = refused(tmp_path, f"shadelab-demo 1\n0 snow.level 3\n0 cl_steps 300\n0.5 {line}\n1 snow.add 0 0\n")
    assert f"bad.demo: at 0.500 s: {line!r}: " in error and needle in error, error


def test_checks_of_a_shape_the_demo_changed_are_left_to_playback_which_stops_at_the_first_failure(tmp_path):
    (tmp_path / "grow.demo").write_text("shadelab-demo 1\n0 new 4 4 4\n0.1 voxel 3 3 3 255 0 0 255\n"
                                        "0.2 voxel 5 0 0 255 0 0 255\n0.3 slice z 1\n")
    clock = VirtualClock()
    e = Editor(clock=clock)
    assert e.execute("play grow")  # voxel 5 fits the 64-voxel volume the check sees
    clock.advance(1)
    e.demos.update()
    volume = e.workspaces["volume"]
    assert not e.demos.playing and volume.volume.voxels.size == (4, 4, 4)
    assert volume.view.index != 1  # the slice never ran
    assert errors(e)[-1] == ("grow.demo: stopped at 0.200 s, command 3 of 4 ('voxel 5 0 0 255 0 0 255') failed; "
                             "the 1 after it did not run")
    assert not e.execute("timedemo grow")
    assert "grow.demo: stopped at 0.200 s, command 3 of 4" in errors(e)[-1]


def test_indices_made_by_the_demo_itself_are_not_refused(tmp_path):
    (tmp_path / "build.demo").write_text(
        "shadelab-demo 1\n0 workspace lighting2d\n0 light.add point 0 0\n0 light.set 3 radius 7\n"
        "0 light.set 3 texture builtin:flame\n0 light.set 3 kind textured\n0 light.move 3 1 2\n"
        "0 snow.add 0 0\n0 snow.move 7 1 1\n0 new 8 8 128\n0 slice z 100\n")
    e = Editor(clock=VirtualClock())
    assert len(e.workspaces["lighting2d"].scene.lights) == 3 and len(e.workspaces["snowflake"].scene.flakes) == 7
    assert e.execute("timedemo build"), errors(e)
    assert e.workspaces["lighting2d"].scene.lights[3].kind == "textured" and e.workspaces["volume"].view.index == 100
