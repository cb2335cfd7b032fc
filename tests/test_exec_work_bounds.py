"""Limits that bound the work a shared scene, demo or script can ask for, not only the count of things in it, each
through `shadelab exec` (and `render`): refused with a message that names the limit, nothing written, no internal
error. And what the headless CLI prints and records comes back as it was said: no terminal escapes reach the
terminal, and a recorded line replays word for word."""
import json
import os
import shlex
import subprocess
import sys

from app.model.clouds.workspace import MAX_TIME
from app.model.snowflake import MAX_SEGMENTS
from test_exec_cli import ROOT, shadelab_exec


def clean(r) -> None:
    assert "Traceback" not in r.stderr and "internal error" not in r.stderr + r.stdout


def test_a_lights3d_box_below_the_size_floor_is_refused_by_the_file_and_the_commands(tmp_path):
    """A box of 1e-200 loaded and then every frame failed (its normals came out NaN)."""
    scene = {"format": "shadelab.lights3d", "version": 1, "lights": [],
             "objects": [{"kind": "box", "size": [1e-200, 1, 1], "position": [0, 0, 0]}]}
    (tmp_path / "tiny.json").write_text(json.dumps(scene))
    r = shadelab_exec(tmp_path, "-c", "open tiny.json", "-c", "object.add box 0 0 0 1 1e-200 1",
                      "-c", "object.add torus 0 0 0 1 0.995 16 8", "-c", "object.list")
    assert r.returncode == 1
    clean(r)
    assert "tiny.json: objects[0]: box sx must be within 0.01..10000, got 1e-200" in r.stderr
    assert "box sy must be within 0.01..10000, got 1e-200" in r.stderr
    assert "torus minor radius must be below its major radius by at least 0.01" in r.stderr
    assert r.stdout.rstrip().endswith("5 objects, 2530 triangles")  # the default scene, untouched
    # the smallest box there may be draws: its frames do not fail
    png = tmp_path / "floor.png"
    smallest = [f"object.add box {x} 5 0 0.01 0.01 0.01" for x in (0, 99990)]  # float32 there: a unit in 128
    drawn = subprocess.run([sys.executable, "-m", "app", "render", "lights3d", "--cmd", smallest[0], "--cmd",
                            smallest[1], "--size", "64x48", "--out", str(png)], capture_output=True, text=True,
                           timeout=120, cwd=tmp_path, env={**os.environ, "PYTHONPATH": ROOT,
                                                           "SHADELAB_CONFIG_DIR": str(tmp_path / "config")})
    assert drawn.returncode == 0, drawn.stderr
    clean(drawn)
    assert png.is_file()


def test_snowflakes_past_the_segment_budget_are_refused_by_the_file_and_the_commands(tmp_path):
    """4,096 flakes at level 8 (805 million segments) loaded and took minutes a frame."""
    many = {"format": "shadelab.snowflake", "version": 1, "level": 8,
            "flakes": [{"x": i % 64, "y": i // 64} for i in range(4096)]}
    (tmp_path / "many.json").write_text(json.dumps(many))
    (tmp_path / "grow.lua").write_text("for i = 1, 15 do cmd.snow.add(i, 0) end\n")  # 7 + 15 = 22 flakes at level 8
    r = shadelab_exec(tmp_path, "-c", "open many.json", "-c", "snow.level 8", "grow.lua", "-c", "snow.list")
    assert r.returncode == 1
    clean(r)
    assert (f"many.json: 4096 flakes at level 8 draw 805,306,368 segments, more than the budget of "
            f"{MAX_SEGMENTS:,} (flakes x 3 x 4^level)") in r.stderr
    assert f"22 flakes at level 8 draw 4,325,376 segments, more than the budget of {MAX_SEGMENTS:,}" in r.stderr
    assert r.stdout.rstrip().endswith("21 flakes, level 8")  # up to the budget, and not one more
    r = shadelab_exec(tmp_path, "grow.lua", "-c", "snow.level 8", "-c", "snow.level")
    assert r.returncode == 1 and "snow.level is 4" in r.stdout  # refused whole: the level is as it was
    assert "22 flakes at level 8 draw" in r.stderr


def test_the_clouds_clock_is_bounded_the_same_in_the_command_and_in_what_is_recorded(tmp_path):
    """`clouds.time 1e308` was taken (the clouds vanished) and a demo recorded then refused its own line."""
    r = shadelab_exec(tmp_path, "-c", "workspace clouds", "-c", "clouds.time 1e308", "-c", "clouds.time 10 -1e9",
                      "-c", "clouds.set time_scale 25", "-c", f"clouds.time {MAX_TIME:g}", "-c", "clouds.time")
    assert r.returncode == 1
    clean(r)
    assert f"the clock must be within 0..{MAX_TIME:g} s, got 1e+308" in r.stderr
    assert f"the wind's time must be within -{MAX_TIME:g}..{MAX_TIME:g} s, got -1e+09" in r.stderr
    assert f"the wind's time must be within -{MAX_TIME:g}..{MAX_TIME:g} s, got 2.16e+06" in r.stderr  # 25 x clock
    assert "clock 0 s, wind time 0 s" in r.stdout
    r = shadelab_exec(tmp_path, "-c", "workspace clouds", "-c", f"clouds.time {MAX_TIME:g} -{MAX_TIME:g}",
                      "-c", "record edge", "-c", "stop", "edge.demo", "-c", "clouds.time")
    assert r.returncode == 0, r.stderr
    assert f"clouds.time {MAX_TIME!r} {-MAX_TIME!r}" in (tmp_path / "edge.demo").read_text()
    assert "demo finished" in r.stdout and "clock 86400 s, wind time -86400 s" in r.stdout


def test_a_record_name_too_long_for_the_file_system_is_refused_at_record(tmp_path):
    """A 245-character name passed `record` and lost the recording with an internal error at `stop`."""
    r = shadelab_exec(tmp_path, "-c", f"record {'d' * 245}", "-c", "snow.add 0 0", "-c", "stop")
    assert r.returncode == 1
    clean(r)
    assert "record: too long a name: with .start.seg.nrrd" in r.stderr  # a scan's labels beside its snapshot
    assert "(a snapshot it may write beside the demo) it has 260 bytes, more than the 255 a file name may have " \
           "here; give at most 240 bytes before .demo" in r.stderr
    assert "nothing is recording" in r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # not even its snapshot
    r = shadelab_exec(tmp_path, "-c", f"record {'d' * 240}", "-c", "workspace lights3d", "-c", "object.add box",
                      "-c", "stop", "-c", f"record {'e' * 240}", "-c", "stop", "-c", f"play {'e' * 240}")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / f"{'d' * 240}.demo").is_file()  # the longest name there may be, with its temporary file's
    assert (tmp_path / f"{'e' * 240}.start.json").is_file() and "demo finished" in r.stdout  # and its snapshot


def test_terminal_escapes_in_printed_text_do_not_reach_the_terminal(tmp_path):
    (tmp_path / "title.lua").write_text('print("a\\27]0;pwned\\7b\\27[2Jc\\194\\155d\\re")\n')
    r = shadelab_exec(tmp_path, "title.lua", "-c", "exec 'bad\x1bname.cfg'")
    out = r.stdout + r.stderr
    assert not any(c in out for c in "\x1b\x07\x9b\r")
    assert "a\\x1b]0;pwned\\x07b\\x1b[2Jc\\x9bd\\x0de" in r.stdout  # shown, as escapes


def test_a_recorded_line_replays_word_for_word(tmp_path):
    """`//` outside quotes starts a comment: a path holding it was recorded bare and cut short on playback."""
    (tmp_path / "flakes.json").write_text(json.dumps({"format": "shadelab.snowflake", "version": 1, "level": 3,
                                                      "flakes": [{"x": 0, "y": 0}, {"x": 1, "y": 1}]}))
    value = """a//b; c 'd' "e" \\f // g;"""
    r = shadelab_exec(tmp_path, "-c", "record words", "-c", "open './/flakes.json'", "-c",
                      f"set note {shlex.quote(value)}", "-c", "stop")
    assert r.returncode == 0, r.stderr
    recorded = (tmp_path / "words.demo").read_text()
    assert "open './/flakes.json'" in recorded
    r = shadelab_exec(tmp_path, "words.demo", "-c", "note", "-c", "snow.list")
    assert r.returncode == 0, r.stderr
    assert "] open './/flakes.json'\nloaded 2 flakes" in r.stdout
    assert f'"note" is "{value}"' in r.stdout
    assert r.stdout.rstrip().endswith("2 flakes, level 3")
