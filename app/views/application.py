"""Starting the editor: the GL surface format, the QApplication and the main window."""
from __future__ import annotations

import argparse
import sys

from PySide6.QtCore import QTimer
from PySide6.QtGui import QSurfaceFormat
from PySide6.QtWidgets import QApplication

from app.gl.headless import SAMPLES

SCREENSHOT_DELAY_MS = 1500  # let docks settle and the first frames land


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
    p = argparse.ArgumentParser(prog="shadelab", epilog="headless: shadelab render ... | shadelab bench ...",
                                description="Start the Shadelab editor (on its embedded default scene).")
    p.add_argument("scene", nargs="?", help="scene file to open")
    p.add_argument("--cmd", action="append", default=[], metavar="COMMAND", help="console command to run at start")
    p.add_argument("--size", default="1400x860", metavar="WxH", help="window size")
    p.add_argument("--screenshot", metavar="PNG", help="save a picture of the window once drawn, then quit")
    return p


def run_editor(argv: list[str]) -> int:
    from app.views.main_window import MainWindow

    args = editor_parser().parse_args(argv)
    set_surface_format()
    app = QApplication.instance() or QApplication(sys.argv[:1])
    app.setApplicationName("Shadelab")
    window = MainWindow()
    window.resize(*(int(v) for v in args.size.lower().split("x")))
    for line in ([f'scene.load "{args.scene}"'] if args.scene else []) + args.cmd:
        window.run(line)
    window.show()
    if args.screenshot:
        QTimer.singleShot(SCREENSHOT_DELAY_MS, lambda: (window.grab().save(args.screenshot), app.quit()))
    return app.exec()
