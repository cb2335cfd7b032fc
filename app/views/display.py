"""Whether the editor has a display to open its window on, asked before Qt is: Qt aborts the process when
its platform plugin finds none, with a message about a missing xcb-cursor0 library."""
from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys
from collections.abc import Mapping
from pathlib import Path

# Qt platforms that draw without a display server (QT_QPA_PLATFORM, before any ':options').
NO_SERVER = frozenset({"offscreen", "minimal", "minimalegl", "eglfs", "linuxfb", "vnc", "vkkhrdisplay"})
XVFB_HINT = ("On a machine without a screen, run it under a virtual X server:\n"
             "  xvfb-run -a -s '-screen 0 1600x1000x24' shadelab [FILE] [--cmd COMMAND]...\n"
             "or use the headless verbs: shadelab render | bench | exec (shadelab --help).")


def display_problem(env: Mapping[str, str] = os.environ) -> str | None:
    """Why no window can open, in a sentence ending with how to run anyway; None when one can (or when this
    platform is not one that uses X11 or Wayland, where Qt finds its own way)."""
    if not sys.platform.startswith(("linux", "freebsd", "openbsd", "netbsd")):
        return None
    platform = env.get("QT_QPA_PLATFORM", "").split(":")[0]
    if platform in NO_SERVER:
        return None
    if platform.startswith("wayland"):
        return None if _wayland_socket(env) else f"no Wayland display to open a window on.\n{XVFB_HINT}"
    if platform != "xcb" and _wayland_socket(env):
        return None
    x_display = env.get("DISPLAY", "")
    if not x_display:
        wanted = "DISPLAY is unset" if platform == "xcb" else "DISPLAY and WAYLAND_DISPLAY are unset"
        return f"no display to open a window on ({wanted}).\n{XVFB_HINT}"
    if _x_display_opens(x_display) is False:
        return f"cannot open the X display {x_display!r} (is its server running?).\n{XVFB_HINT}"
    return None


def _wayland_socket(env: Mapping[str, str]) -> bool:
    name = env.get("WAYLAND_DISPLAY", "")
    if not name:
        return False
    path = Path(name) if Path(name).is_absolute() else Path(env.get("XDG_RUNTIME_DIR", "/nonexistent")) / name
    return path.is_socket()


def _x_display_opens(name: str) -> bool | None:
    """Connect to the X server as Qt's xcb plugin will; None when libxcb is not there to ask."""
    library = ctypes.util.find_library("xcb")
    if library is None:
        return None
    xcb = ctypes.CDLL(library)
    xcb.xcb_connect.restype = ctypes.c_void_p
    xcb.xcb_connect.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_int)]
    xcb.xcb_connection_has_error.argtypes = [ctypes.c_void_p]
    xcb.xcb_disconnect.argtypes = [ctypes.c_void_p]
    connection = xcb.xcb_connect(name.encode(), None)
    try:
        return xcb.xcb_connection_has_error(connection) == 0
    finally:
        xcb.xcb_disconnect(connection)  # an errored connection is freed the same way
