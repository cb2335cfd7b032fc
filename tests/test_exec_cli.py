"""`shadelab exec`: files and commands in order, headless, with an honest exit status."""
import os
import subprocess
import sys
import time
from pathlib import Path

import app

ROOT = str(Path(app.__file__).parent.parent)  # the `app` under test, not an installed one, whatever the cwd


def shadelab_exec(tmp_path, *args):
    env = {**os.environ, "SHADELAB_CONFIG_DIR": str(tmp_path / "config"), "PYTHONPATH": ROOT}
    return subprocess.run([sys.executable, "-m", "app", "exec", *args], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path, env=env)


def test_items_run_in_order_and_print_the_log(tmp_path):
    (tmp_path / "a.cfg").write_text("snow.clear\nsnow.add 0 0 1\n")
    (tmp_path / "b.lua").write_text("cmd.snow.level(3)\nprint('from lua', cvar.cl_steps)\n")
    r = shadelab_exec(tmp_path, "a.cfg", "-c", "snow.level 1", "b.lua", "-c", "snow.list")
    assert r.returncode == 0, r.stderr
    assert "from lua\t128" in r.stdout
    assert r.stdout.rstrip().endswith("1 flake, level 3")


def test_a_failure_sets_the_status_and_later_items_still_run(tmp_path):
    r = shadelab_exec(tmp_path, "-c", "snow.level 42", "-c", "echo still here", "missing.cfg", "notes.txt")
    assert r.returncode == 1
    assert "within 0..8" in r.stderr and "cannot find missing.cfg" in r.stderr
    assert "not a .cfg, .lua or .demo file" in r.stderr
    assert "still here" in r.stdout


def test_a_demo_plays_at_its_times_before_the_next_item(tmp_path):
    (tmp_path / "t.demo").write_text("shadelab-demo 1\n0 snow.level 1\n0.4 snow.level 2\n0.8 snow.level 3\n")
    start = time.monotonic()
    r = shadelab_exec(tmp_path, "t.demo", "-c", "snow.level")
    assert r.returncode == 0, r.stderr
    assert r.stdout.rstrip().endswith("snow.level is 3")
    assert "demo finished: 3 commands" in r.stdout
    assert time.monotonic() - start >= 0.8


def test_a_lua_error_names_script_and_line(tmp_path):
    (tmp_path / "oops.lua").write_text("cmd.snow.clear()\nlocal x = nil\nx.y = 1\n")
    r = shadelab_exec(tmp_path, "oops.lua")
    assert r.returncode == 1
    assert "oops.lua:3:" in r.stderr


def test_timedemo_headless_draws_frames(tmp_path):
    r = shadelab_exec(tmp_path, "-c", "timedemo snowflake_tour")
    assert r.returncode == 0, r.stderr
    assert "timedemo snowflake_tour.demo: 14 frames in" in r.stdout and "frames/s" in r.stdout
    assert "nothing drawn" not in r.stdout


def test_quit_stops_the_items(tmp_path):
    r = shadelab_exec(tmp_path, "-c", "echo one", "-c", "quit", "-c", "echo two")
    assert r.returncode == 0 and "one" in r.stdout and "two" not in r.stdout
