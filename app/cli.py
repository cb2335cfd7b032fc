"""Command line: `shadelab` starts the editor; `render` and `bench` run headless on EGL."""
from __future__ import annotations

import argparse
import os
import re
import sys
import time
from pathlib import Path

from app.console.quoting import quote

VERBS = {  # the headless verbs and their one-line help (shadelab --help lists them under the editor's options)
    "render": "draw one frame of a workspace headless (EGL) into a PNG",
    "bench": "measure speed against accuracy; write DIR/<technique>.csv and .png",
    "exec": "run .cfg/.lua/.demo files and -c commands headless (shadelab exec -h)",
}
# Control characters but tab and newline: C0, DEL and C1. A script's print or a file's name with ESC in it would
# otherwise drive the terminal that shows the log (retitle it, move the cursor, rewrite what was printed).
_TERMINAL_CONTROLS = re.compile(r"[\x00-\x08\x0b-\x1f\x7f-\x9f]")
# `render` draws a still scene until its renderer says more frames would not change it (the clouds: until TAA has
# converged, with a cap of their own); this only guards against a renderer that never says so
MAX_SETTLING_FRAMES = 1024
EXEC_USAGE = """usage: shadelab exec [FILE | -c COMMAND]...

Run .cfg, .lua and .demo files and single console commands in the order given, without a window,
printing the console log. A demo plays to its end at its recorded times before the next item runs.
The exit status is 1 if any command failed; later items still run."""


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
    from app.model.workspaces import names

    p = argparse.ArgumentParser(prog="shadelab",
                                description="Shadelab: a workbench for real-time lighting and volume techniques.")
    sub = p.add_subparsers(dest="verb", metavar="{" + ",".join(VERBS) + "}")
    sub.add_parser("exec", help=VERBS["exec"])
    r = sub.add_parser("render", help=VERBS["render"])
    r.add_argument("workspace", choices=names())
    r.add_argument("--scene", metavar="FILE", help="scene file to load first (scene.load)")
    r.add_argument("--cmd", action="append", default=[], metavar="COMMAND",
                   help="console command to run before drawing (repeatable, in order)")
    r.add_argument("--size", type=_size, default=(640, 480), metavar="WxH")
    r.add_argument("--out", required=True, metavar="PNG")
    r.add_argument("--overlays", action="store_true",
                   help="draw the editor's marks over the scene too (the volume's slice plane, the 2D light icons "
                        "and hull outlines, the 3D lights' markers and gizmo); without it, the scene alone")
    b = sub.add_parser("bench", help=VERBS["bench"])
    b.add_argument("technique", choices=sorted([*TECHNIQUES, "frames"]),
                   help="a technique's methods against its reference; frames: each workspace's interactive and still "
                        "frames at the editor's view size within r_frameBudget")
    b.add_argument("--quick", action="store_true", help="fewer settings and runs, small images (under a minute)")
    b.add_argument("--out", default="bench-out", metavar="DIR")
    b.add_argument("--in-editor", action="store_true",
                   help="the editor's dock runs it, its view paused: the CSV and chart say so (else: from the CLI)")
    return p


def terminal_progress(stream, width: int = 30):
    """A progress bar on the terminal for each thing a renderer has to make (what is cached says nothing)."""
    building: set[str] = set()

    def report(what: str, fraction: float) -> None:
        if fraction >= 1.0 and what not in building:
            return
        building.add(what)
        filled = int(round(width * fraction))
        stream.write(f"\rmaking the {what} texture [{'#' * filled}{' ' * (width - filled)}] {fraction:4.0%}")
        if fraction >= 1.0:
            stream.write("\n")
            building.discard(what)
        stream.flush()
    return report


def print_log_line(line) -> None:
    """A console log line on stdout, or stderr for an error, with its control characters shown as escapes
    (\\x1b): the log is someone else's text. Flushed, so it keeps its place among the streams' lines."""
    text = _TERMINAL_CONTROLS.sub(lambda m: f"\\x{ord(m.group()):02x}", line.text)
    print(text, file=sys.stderr if line.level == "error" else sys.stdout, flush=True)


def render(args) -> int:
    from app.console.files import check_folder
    from app.console.registry import CommandError
    from app.editor import Editor
    from app.gl.core.headless import OffscreenTarget, create_context, release_context
    from app.gl.core.workspace_renderer import RENDERERS, WorkspaceRenderer
    from app.io.png import write_png

    try:
        check_folder(Path(args.out), args.out)  # before any work: a save never makes folders
    except CommandError as exc:
        print(f"shadelab render: {exc}", file=sys.stderr)
        return 1
    editor = Editor()
    editor.console.log_listeners.append(print_log_line)
    editor.workspaces.view_aspect = args.size[0] / args.size[1]  # view.frame and a loaded file fit the picture
    commands = [f"workspace {args.workspace}"]
    if args.scene:
        commands.append(f"scene.load {quote(args.scene)}")
    commands += args.cmd
    failed = [c for c in commands if not editor.execute(c)]
    if failed:
        print(f"shadelab render: {len(failed)} command(s) failed; no image written", file=sys.stderr)
        return 1
    RENDERERS[args.workspace].prepare(terminal_progress(sys.stderr))
    ctx = create_context()
    try:
        renderer = WorkspaceRenderer(ctx)
        target = OffscreenTarget(ctx, args.size)
        frames = 0
        while frames < MAX_SETTLING_FRAMES:  # a still scene: let temporal histories fill
            renderer.render(target.fbo, editor.current, editor.render_settings(), overlays=args.overlays)
            frames += 1
            if not renderer.settling():
                break
        write_png(args.out, target.read())
        print(f"wrote {args.out} ({args.size[0]}x{args.size[1]}, {frames} frame{'s' * (frames != 1)}, "
              f"{ctx.info['GL_RENDERER']})")
    finally:
        release_context(ctx)  # leaves none current: a caller in this process may make its own
    return 0


def bench(args) -> int:
    if args.technique == "frames":
        return bench_frames(args)
    from app.bench import TECHNIQUES, WORKSPACE_TECHNIQUE
    from app.bench import harness, report
    from app.gl.core.headless import create_context, release_context
    from app.gl.core.workspace_renderer import RENDERERS
    from app.views.bench_chart import save_chart

    ensure_qt_app(offscreen=True)  # the chart is painted by pyqtgraph
    tech = TECHNIQUES[args.technique](quick=args.quick)
    for workspace, technique in WORKSPACE_TECHNIQUE.items():  # textures made before the first frame, with a bar
        if technique == args.technique:
            RENDERERS[workspace].prepare(terminal_progress(sys.stderr))
    ctx = create_context()
    try:
        print(f"bench {tech.name} on {ctx.info['GL_RENDERER']}{' (quick)' if args.quick else ''}")
        start = time.perf_counter()
        rows = harness.run(ctx, tech, quick=args.quick, progress=print)
        for row in rows:
            row.extra[report.MEASURED_IN] = "editor" if args.in_editor else "cli"
        out = Path(args.out)
        csv_path, png_path = out / f"{tech.name}.csv", out / f"{tech.name}.png"
        report.write_csv(csv_path, rows)
        written = report.read_csv(csv_path)
        save_chart(png_path, written)
        charts = tech.charts(written) if tech.charts is not None else {}
        for name, part in charts.items():
            save_chart(out / name, part)
        if tech.extra_outputs is not None:
            tech.extra_outputs(ctx, out, args.quick, rows, print)
        more = "".join(f", {name}" for name in charts)
        print(f"wrote {csv_path} and {png_path}{more} in {time.perf_counter() - start:.1f} s")
    finally:
        release_context(ctx)  # leaves none current: a caller in this process may make its own
    return 0


def bench_frames(args) -> int:
    from app.bench import frame_budget
    from app.gl.core.headless import create_context, release_context
    from app.gl.core.workspace_renderer import RENDERERS

    RENDERERS["clouds"].prepare(terminal_progress(sys.stderr))
    ctx = create_context()
    try:
        print(f"bench frames on {ctx.info['GL_RENDERER']}{' (quick)' if args.quick else ''}, "
              f"{frame_budget.DEFAULT_VIEW[0]}x{frame_budget.DEFAULT_VIEW[1]}")
        rows = frame_budget.run(ctx, list(RENDERERS), frames=8 if args.quick else 24)
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        frame_budget.write_csv(out / "frames.csv", rows)
        print(f"wrote {out / 'frames.csv'}")
    finally:
        release_context(ctx)
    return 0


def exec_items(argv: list[str]) -> list[tuple[str, str]]:
    """['a.cfg', '-c', 'echo hi'] -> [('file', 'a.cfg'), ('cmd', 'echo hi')], order kept."""
    items, args = [], list(argv)
    while args:
        arg = args.pop(0)
        if arg in ("-h", "--help"):
            raise SystemExit(print(EXEC_USAGE) or 0)
        if arg == "-c":
            if not args:
                raise SystemExit("shadelab exec: -c needs a command")
            items.append(("cmd", args.pop(0)))
        else:
            items.append(("file", arg))
    return items


def run_exec(argv: list[str]) -> int:
    from app.console.demo import MonotonicClock
    from app.editor import Editor

    items = exec_items(argv)
    clock = MonotonicClock()
    editor = Editor(clock=clock)
    errors = []
    editor.console.log_listeners.append(print_log_line)
    editor.console.log_listeners.append(lambda line: line.level == "error" and errors.append(line))
    quit_requested = []
    editor.console.quit_listeners.append(lambda: quit_requested.append(True))
    editor.demos.frame = HeadlessFrame(editor)
    try:
        _exec_items(editor, clock, items, quit_requested)
    finally:  # whatever happened, a recording in progress is saved
        editor.demos.stop_all()
    return 1 if errors else 0


def _exec_items(editor, clock, items: list[tuple[str, str]], quit_requested: list) -> None:
    runners = {".cfg": "exec", ".lua": "lua", ".demo": "play"}
    for kind, value in items:
        if kind == "cmd":
            editor.execute(value)
        elif Path(value).suffix in runners:
            editor.execute(f"{runners[Path(value).suffix]} {quote(value)}")
        else:
            editor.console.error(f"exec: {value}: not a .cfg, .lua or .demo file")
        while editor.demos.playing or editor.console.waiting:  # finish demos and waits before the next item
            due = editor.demos.player.next_due() if editor.demos.playing else None
            if due is not None:
                time.sleep(max(0.0, due - clock.now()))
            editor.demos.update()
            editor.console.frame()
        if quit_requested:
            break


class HeadlessFrame:
    """timedemo's frame in the headless host: draw the workspace off screen (EGL made on first use)."""

    def __init__(self, editor, size=(640, 480)) -> None:
        self.editor, self.size = editor, size
        self.target = None

    def __call__(self) -> None:
        from app.gl.core.headless import OffscreenTarget, create_context
        from app.gl.core.workspace_renderer import WorkspaceRenderer

        if self.target is None:
            ctx = create_context()
            self.renderer = WorkspaceRenderer(ctx, on_shader_error=lambda e: self.editor.console.error(str(e)))
            self.target = OffscreenTarget(ctx, self.size)
        self.renderer.render(self.target.fbo, self.editor.current, self.editor.render_settings())
        self.target.ctx.finish()


def ensure_qt_app(offscreen: bool = False):
    """A QApplication for QtGui/pyqtgraph work; off screen when there is no display to use."""
    from PySide6.QtWidgets import QApplication

    app = QApplication.instance()
    if app is None:
        if offscreen:
            os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
        app = QApplication(sys.argv[:1])
    return app


def editor(argv: list[str]) -> int:
    """The editor, once its arguments make sense and there is a display to show it on."""
    from app.console.files import find
    from app.views.application import editor_parser, run_editor
    from app.views.display import display_problem

    p = editor_parser()
    p.epilog = "headless verbs (shadelab VERB -h for each one's options):\n" + "\n".join(
        f"  shadelab {verb:<8} {text}" for verb, text in VERBS.items())
    args = p.parse_args(argv)
    # as `exec`, `play`... find it: the resources too; a folder opens as a scan's series of slices
    if args.file is not None and find(args.file) is None and not Path(args.file).is_dir():
        p.error(f"{args.file!r} is neither a verb ({', '.join(VERBS)}) nor a file or folder")
    problem = display_problem()
    if problem is not None:
        print(f"shadelab: {problem}", file=sys.stderr)
        return 1
    return run_editor(args)


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["exec"]:
        return run_exec(argv[1:])
    if argv[:1] and argv[0] in VERBS:
        args = parser().parse_args(argv)
        return {"render": render, "bench": bench}[args.verb](args)
    return editor(argv)
