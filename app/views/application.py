"""Starting the editor: the GL surface format, the QApplication and the main window."""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from PySide6.QtCore import QTimer
from PySide6.QtGui import QSurfaceFormat
from PySide6.QtWidgets import QApplication

from app.console.quoting import quote
from app.gl.core.headless import SAMPLES

SCREENSHOT_DELAY_MS = 1500  # let docks settle and the first frames land
# then wait for the picture to settle (temporal histories; the clouds' TAA converging takes some 80 frames), at most
# this long
SCREENSHOT_WAIT_MS = 300000


def set_surface_format() -> None:
    """GL 3.3 core with the headless host's sample count: same code, same pixels. Before the app exists."""
    fmt = QSurfaceFormat()
    fmt.setVersion(3, 3)
    fmt.setProfile(QSurfaceFormat.OpenGLContextProfile.CoreProfile)
    fmt.setDepthBufferSize(24)
    fmt.setStencilBufferSize(8)
    fmt.setSamples(SAMPLES)
    QSurfaceFormat.setDefaultFormat(fmt)


def editor_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="shadelab", formatter_class=argparse.RawDescriptionHelpFormatter,
                                description="Start the Shadelab editor (on its embedded default scene).")
    p.add_argument("file", nargs="?", help="a .cfg, .lua or .demo to run after start-up, or a file (or a folder "
                   "of DICOM slices) to open")
    p.add_argument("--cmd", action="append", default=[], metavar="COMMAND",
                   help="console command to run at start (repeatable, in order, after FILE)")
    p.add_argument("--size", metavar="WxH", help="window size (default: as the last run left it)")
    p.add_argument("--screenshot", metavar="PNG", help="save a picture of the window once drawn, then quit")
    return p


def startup_command(path: str) -> str:
    """As Tex3Dtrace's first argument: a config runs after start-up, anything else is opened in the workspace
    its format belongs to."""
    verb = {".cfg": "exec", ".lua": "lua", ".demo": "play"}.get(Path(path).suffix, "open")
    return f"{verb} {quote(path)}"


def run_editor(args: argparse.Namespace) -> int:
    """The editor on `args` from editor_parser (app/cli.py checks them, and the display, first)."""
    from app.views.main_window import MainWindow

    set_surface_format()
    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("Shadelab")
    window = MainWindow()
    if args.size:
        window.resize(*(int(v) for v in args.size.lower().split("x")))
    window.show()
    # after the window shows: a long script or demo then runs in a window that answers (and shows its progress)
    lines = ([startup_command(args.file)] if args.file else []) + args.cmd
    QTimer.singleShot(0, lambda: [window.run(line) for line in lines])
    if args.screenshot:
        deadline = time.monotonic() + (SCREENSHOT_DELAY_MS + SCREENSHOT_WAIT_MS) / 1e3

        def shoot() -> None:
            if window.viewport.settled() or time.monotonic() > deadline:
                window.grab().save(args.screenshot)
                window.editor.documents.confirm = None  # a picture run quits without asking to save
                app.quit()
            else:
                QTimer.singleShot(100, shoot)
        QTimer.singleShot(SCREENSHOT_DELAY_MS, shoot)
    return app.exec()
