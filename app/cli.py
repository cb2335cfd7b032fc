"""Command line: `shadelab` starts the editor; `render` and `bench` run headless on EGL."""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from app.model.workspace import NAMES

HEADLESS = ("render", "bench")


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 640x480, got {text!r}") from None
    if not (1 <= w <= 16384 and 1 <= h <= 16384):
        raise argparse.ArgumentTypeError(f"size must be within 1..16384 on each side, got {text}")
    return w, h


def parser() -> argparse.ArgumentParser:
    from app.bench import TECHNIQUES

    p = argparse.ArgumentParser(prog="shadelab", description="Shadelab: a workbench for real-time lighting and volume techniques.")
    sub = p.add_subparsers(dest="verb", metavar="{render,bench}")
    r = sub.add_parser("render", help="draw one frame of a workspace headless (EGL) into a PNG")
    r.add_argument("workspace", choices=NAMES)
    r.add_argument("--scene", metavar="FILE", help="scene file to load first (scene.load)")
    r.add_argument("--cmd", action="append", default=[], metavar="COMMAND",
                   help="console command to run before drawing (repeatable, in order)")
    r.add_argument("--size", type=_size, default=(640, 480), metavar="WxH")
    r.add_argument("--out", required=True, metavar="PNG")
    b = sub.add_parser("bench", help="measure speed against accuracy; write DIR/<technique>.csv and .png")
    b.add_argument("technique", choices=sorted(TECHNIQUES))
    b.add_argument("--quick", action="store_true", help="fewer settings and runs, small images (under a minute)")
    b.add_argument("--out", default="bench-out", metavar="DIR")
    return p


def render(args) -> int:
    from app.editor import Editor
    from app.gl.headless import OffscreenTarget, create_context
    from app.gl.workspace_renderer import WorkspaceRenderer
    from app.io.png import write_png

    editor = Editor()
    editor.console.log_listeners.append(lambda line: print(line.text, file=sys.stderr if line.level == "error" else sys.stdout))
    commands = [f"workspace {args.workspace}"]
    if args.scene:
        commands.append(f'scene.load "{args.scene}"')
    commands += args.cmd
    failed = [c for c in commands if not editor.execute(c)]
    if failed:
        print(f"shadelab render: {len(failed)} command(s) failed; no image written", file=sys.stderr)
        return 1
    ctx = create_context()
    errors = []
    renderer = WorkspaceRenderer(ctx, on_shader_error=errors.append)
    target = OffscreenTarget(ctx, args.size)
    renderer.render(editor, target.fbo)
    write_png(args.out, target.read())
    print(f"wrote {args.out} ({args.size[0]}x{args.size[1]}, {ctx.info['GL_RENDERER']})")
    return 0


def bench(args) -> int:
    from app.bench import TECHNIQUES
    from app.bench import harness, report
    from app.gl.headless import create_context

    ensure_qt_app(offscreen=True)  # the chart is painted by pyqtgraph
    tech = TECHNIQUES[args.technique]()
    ctx = create_context()
    print(f"bench {tech.name} on {ctx.info['GL_RENDERER']}{' (quick)' if args.quick else ''}")
    start = time.perf_counter()
    rows = harness.run(ctx, tech, quick=args.quick, progress=print)
    out = Path(args.out)
    csv_path, png_path = out / f"{tech.name}.csv", out / f"{tech.name}.png"
    report.write_csv(csv_path, rows)
    report.save_chart(png_path, report.read_csv(csv_path))
    print(f"wrote {csv_path} and {png_path} in {time.perf_counter() - start:.1f} s")
    return 0


def ensure_qt_app(offscreen: bool = False):
    """A QApplication for QtGui/pyqtgraph work; off screen when there is no display to use."""
    from PySide6.QtWidgets import QApplication

    app = QApplication.instance()
    if app is None:
        if offscreen:
            os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
        app = QApplication(sys.argv[:1])
    return app


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] and argv[0] in HEADLESS + ("-h", "--help"):
        args = parser().parse_args(argv)
        return {"render": render, "bench": bench}[args.verb](args)
    from app.views.application import run_editor

    return run_editor(argv)
