"""`shadelab` without a verb starts the editor: its help, a word that is neither a verb nor a file, and no
display to open a window on, each answered before Qt starts (through the real command line)."""
import os
import subprocess
import sys
from pathlib import Path

from app.views.display import display_problem


def shadelab(*args, env=None):
    return subprocess.run([sys.executable, "-m", "app", *args], capture_output=True, text=True, timeout=120, env=env)


def without_display(**extra) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM")}
    return {**env, **extra}


def free_x_display() -> str:
    """A display number no X server listens on here."""
    n = next(n for n in range(4242, 4300) if not Path(f"/tmp/.X11-unix/X{n}").exists() and
             not Path(f"/tmp/.X{n}-lock").exists())
    return f":{n}"


def test_help_lists_the_editors_options_and_the_verbs():
    r = shadelab("--help")
    assert r.returncode == 0, r.stderr
    for word in ("--cmd COMMAND", "--screenshot PNG", "--size WxH", "file", "shadelab render", "shadelab bench",
                 "shadelab exec"):
        assert word in r.stdout


def test_a_mistyped_verb_is_neither_a_verb_nor_a_file(tmp_path):
    r = shadelab("frobnicate", env=without_display())  # refused before any window is tried
    assert r.returncode == 2
    assert "'frobnicate' is neither a verb (render, bench, exec) nor a file" in r.stderr


def test_no_display_says_so_and_how_to_run_under_xvfb():
    r = shadelab(env=without_display())
    assert r.returncode == 1
    assert "no display to open a window on (DISPLAY and WAYLAND_DISPLAY are unset)" in r.stderr
    assert "xvfb-run -a" in r.stderr and "xcb-cursor0" not in r.stderr


def test_a_display_that_does_not_open_is_named():
    display = free_x_display()
    r = shadelab(env=without_display(DISPLAY=display))
    assert r.returncode == 1
    assert f"cannot open the X display '{display}'" in r.stderr and "xvfb-run -a" in r.stderr


def test_the_test_servers_display_opens_and_offscreen_needs_none():
    assert display_problem(os.environ) is None  # pytest-xvfb's server
    assert display_problem({"DISPLAY": free_x_display()}) is not None
    assert display_problem({"QT_QPA_PLATFORM": "offscreen"}) is None
