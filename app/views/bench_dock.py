"""The "Speed vs accuracy" dock: the bench chart of the current technique, run or loaded from CSV.

Before any measurement it says how to get one; a quick bench runs in its own process with a progress bar and
can be cancelled, while the editor's view draws no frame (`measuring`: the main window pauses the viewport), so
that the editor's own frames do not slow the one measured. Hovering a point names its method, scene and knob.
Nothing in it widens the window: long texts wrap or are cut, in full in their tooltips."""
from __future__ import annotations

import os
import re
import sys
from pathlib import Path

import pyqtgraph as pg
from PySide6.QtCore import QProcess, Qt, Signal
from PySide6.QtWidgets import (QFileDialog, QLabel, QProgressBar, QPushButton, QSizePolicy, QStackedWidget, QVBoxLayout,
                               QWidget)

from app.bench import TECHNIQUES, WORKSPACE_TECHNIQUE, report
from app.io.cache import cache_root
from app.views.bench_chart import BenchChart
from app.views.form_widgets import left_row

# a line of the bench's output that reports one measurement (a CSV row): "... 12.34 ms  rmse ..." (or "mean"
# for the clouds' CPU rows)
MEASURED = re.compile(r"\bms\s+(rmse|mean)\b")


def bench_dir() -> Path:
    return cache_root() / "bench"


def wrapping_label(**kwargs) -> QLabel:
    """A label whose text wraps and never asks for more width than the dock has."""
    label = QLabel(wordWrap=True, **kwargs)
    label.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
    label.setMinimumWidth(1)
    return label


class BenchDock(QWidget):
    measuring = Signal(bool)  # a quick bench started (True) or ended, however it ended (False)

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.technique = "snowflake"
        self.chart = pg.GraphicsLayoutWidget()
        self.drawing = BenchChart(self.chart.ci, stacked=True)  # the dock is tall
        self.chart.scene().sigMouseMoved.connect(self._hover)
        self.hover_text = ""
        self.hint = wrapping_label(alignment=Qt.AlignmentFlag.AlignCenter, textFormat=Qt.TextFormat.RichText)
        self.hint.setMargin(16)
        self.pages = QStackedWidget()
        self.pages.addWidget(self.hint)
        self.pages.addWidget(self.chart)
        self.status = wrapping_label()
        self.progress = QProgressBar(visible=False)
        self.run_button = QPushButton("Run quick bench")
        self.run_button.clicked.connect(self.run_quick)
        self.cancel_button = QPushButton("Cancel", visible=False)
        self.cancel_button.clicked.connect(self.cancel)
        open_button = QPushButton("Open CSV…")
        open_button.clicked.connect(self._open)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(left_row(self.run_button, self.cancel_button, open_button))
        layout.addWidget(self.progress)
        layout.addWidget(self.status)
        layout.addWidget(self.pages, 1)
        self.process: QProcess | None = None
        self.running = ""  # the technique the quick bench in progress measures
        self._cancelled = False
        self._partial = ""  # the bench's output after its last whole line

    def set_status(self, text: str) -> None:
        self.status.setText(text)
        self.status.setToolTip(text)

    def show_workspace(self, workspace: str) -> None:
        """The last measurement of the workspace's technique in the cache, else how to make one."""
        name = WORKSPACE_TECHNIQUE.get(workspace, workspace)
        self.technique = name
        self.run_button.setEnabled(name in TECHNIQUES and self.process is None)
        csv_path = bench_dir() / f"{name}.csv"
        refused = self.load(csv_path) if os.path.lexists(csv_path) else None  # lexists: a dangling link is said
        if refused == "":
            return
        if name in TECHNIQUES:
            self._show_hint(f"<p>No measurement of <b>{name}</b> yet.</p>"
                            "<p><b>Run quick bench</b> measures each method at a few settings on small images, "
                            "in under a minute.</p>"
                            f"<p>For every setting: <code>shadelab bench {name} --out DIR</code> in a terminal, "
                            "then <b>Open CSV…</b> its <code>.csv</code>.</p>")
        else:
            self._show_hint(f"<p>The {workspace} workspace has no bench.</p>"
                            "<p><b>Open CSV…</b> shows any bench's results.</p>")
        self.set_status(refused or "")  # why the last results are not shown, with the hint for new ones

    def _show_hint(self, html: str) -> None:
        self.drawing.clear()
        self.hint.setText(html)
        self.pages.setCurrentWidget(self.hint)
        self.set_status("")

    def load(self, path: Path) -> str:
        """Show the bench CSV at `path`; "" if it was, else why not (also in the status line). The results in the
        cache are input like any file: one cut short, or a FIFO in its place, is said and never trusted."""
        try:
            rows = report.read_csv(path)
        except (OSError, ValueError) as exc:
            refused = f"cannot read {path.name}: {(exc.strerror or exc) if isinstance(exc, OSError) else exc}"
            self.set_status(refused)
            return refused
        self.drawing.show(rows)
        self.pages.setCurrentWidget(self.chart)
        self.set_status(f"{path.name}: {len(rows)} measurements")
        return ""

    # -- the quick bench ----------------------------------------------------------------------------------

    def run_quick(self) -> None:
        """The bench runs in its own process (its own EGL context), the editor stays responsive."""
        if self.process is not None or self.technique not in TECHNIQUES:
            return
        self._cancelled, self.running, self._partial = False, self.technique, ""
        self.process = QProcess(self)
        self.process.setProcessChannelMode(QProcess.ProcessChannelMode.MergedChannels)
        self.process.readyReadStandardOutput.connect(self._progress)
        self.process.finished.connect(self._finished)
        self.process.errorOccurred.connect(self._error)
        self._start_progress()
        self.set_status(f"quick bench of {self.technique}: starting…")
        self.run_button.setEnabled(False)
        self.cancel_button.setVisible(True)
        self.measuring.emit(True)
        # -u: the child's progress lines arrive as printed, not in blocks when its stdout is a pipe
        self.process.start(sys.executable, ["-u", "-m", "app", "bench", self.technique, "--quick", "--in-editor",
                                            "--out", str(bench_dir())])

    def _start_progress(self) -> None:
        """Counted in measurements; as many as the last quick bench of this technique made, else a busy bar."""
        try:
            expected = len(report.read_csv(bench_dir() / f"{self.technique}.csv"))
        except (OSError, ValueError, KeyError):
            expected = 0
        self.progress.setRange(0, expected)
        self.progress.setValue(0)
        self.progress.setFormat(f"%v of about {expected} measurements" if expected else "%v measurements")
        self.progress.setVisible(True)

    def cancel(self) -> None:
        if self.process is not None:
            self._cancelled = True
            self.process.kill()  # its CSV is written atomically at the end: nothing half written stays

    def _progress(self) -> None:
        if self.process is None:  # output that came after its end
            return
        # Whole lines only: a read can end mid-line, whose rest comes with the next one.
        text = self._partial + bytes(self.process.readAllStandardOutput()).decode(errors="replace")
        *complete, self._partial = text.split("\n")
        lines = [line for line in complete if line.strip()]
        done = sum(1 for line in lines if MEASURED.search(line))
        if done:
            if self.progress.maximum():
                self.progress.setMaximum(max(self.progress.maximum(), self.progress.value() + done))
            self.progress.setValue(self.progress.value() + done)
        if lines:
            self.set_status(f"{self.progress.value()} measured; " + " ".join(lines[-1].split()))

    def _error(self, error) -> None:
        """A bench that never started gets no finished(): end it here (a crash or a kill gets both)."""
        if error == QProcess.ProcessError.FailedToStart and self.process is not None:
            reason = self.process.errorString()
            self._ended()
            self.set_status(f"quick bench of {self.running} could not start: {reason}")

    def _ended(self) -> None:
        """Whatever ended the bench: the dock ready for another, the view drawing again."""
        self.process.deleteLater()
        self.process = None
        self.progress.setVisible(False)
        self.cancel_button.setVisible(False)
        self.run_button.setEnabled(self.technique in TECHNIQUES)
        self.measuring.emit(False)

    def _finished(self, code: int, _status) -> None:
        self._ended()
        if self._cancelled:
            self.set_status(f"quick bench of {self.running} cancelled")
        elif code != 0:
            self.set_status(f"quick bench of {self.running} failed (exit {code}): see its output in a terminal with "
                            f"shadelab bench {self.running} --quick --out DIR")
        elif self.running == self.technique:  # else another workspace is in view: it shows when that one is
            self.load(bench_dir() / f"{self.technique}.csv")
        else:
            self.set_status(f"quick bench of {self.running} done")

    def _open(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Open bench CSV", str(bench_dir()), "CSV (*.csv)")
        if path:
            self.load(Path(path))

    # -- hovering a point ---------------------------------------------------------------------------------

    def _hover(self, scene_pos) -> None:
        """A point under the mouse shows its tip (its method, scene, knob, time and error)."""
        text = ""
        for plot in self.drawing.plots():
            if not plot.vb.sceneBoundingRect().contains(scene_pos):
                continue
            for item in plot.listDataItems():
                points = item.scatter.pointsAt(item.scatter.mapFromScene(scene_pos))
                if len(points):
                    text = points[0].data()
                    break
        if text != self.hover_text:
            self.hover_text = text
            self.chart.setToolTip(text)  # Qt shows it once the mouse rests
