"""The "Speed vs accuracy" dock: the bench chart of the current technique, run or loaded from CSV."""
from __future__ import annotations

import sys
from pathlib import Path

import pyqtgraph as pg
from PySide6.QtCore import QProcess
from PySide6.QtWidgets import QFileDialog, QHBoxLayout, QLabel, QPushButton, QVBoxLayout, QWidget

from app.bench import TECHNIQUES, WORKSPACE_TECHNIQUE, report
from app.gl.shader_source import default_cache_dir


def bench_dir() -> Path:
    return default_cache_dir().parent / "bench"


class BenchDock(QWidget):
    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.technique = "snowflake"
        self.chart = pg.GraphicsLayoutWidget()
        self.error_plot = self.chart.addPlot(row=0, col=0)
        self.time_plot = self.chart.addPlot(row=1, col=0)  # stacked: the dock is tall and narrow
        self.status = QLabel()
        self.run_button = QPushButton("Run quick bench")
        self.run_button.clicked.connect(self.run_quick)
        open_button = QPushButton("Open CSV…")
        open_button.clicked.connect(self._open)
        buttons = QHBoxLayout()
        buttons.addWidget(self.run_button)
        buttons.addWidget(open_button)
        buttons.addWidget(self.status, 1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(buttons)
        layout.addWidget(self.chart, 1)
        self.process: QProcess | None = None

    def show_workspace(self, workspace: str) -> None:
        name = WORKSPACE_TECHNIQUE.get(workspace, workspace)
        self.technique = name
        self.run_button.setEnabled(name in TECHNIQUES)
        csv_path = bench_dir() / f"{name}.csv"
        if csv_path.exists():
            self.load(csv_path)
        else:
            report.clear_chart(self.error_plot, self.time_plot)
            self.status.setText(f"{name}: no measurements yet" if name in TECHNIQUES
                                else f"{workspace} has no bench yet")

    def load(self, path: Path) -> None:
        try:
            rows = report.read_csv(path)
        except (OSError, ValueError, KeyError) as exc:
            self.status.setText(f"cannot read {path}: {exc}")
            return
        report.plot(self.error_plot, self.time_plot, rows)
        self.status.setText(f"{path.name}: {len(rows)} measurements")

    def run_quick(self) -> None:
        """The bench runs in its own process (its own EGL context), the editor stays responsive."""
        if self.process is not None:
            return
        self.process = QProcess(self)
        self.process.setProcessChannelMode(QProcess.ProcessChannelMode.MergedChannels)
        self.process.readyReadStandardOutput.connect(self._progress)
        self.process.finished.connect(self._finished)
        self.status.setText("running…")
        self.run_button.setEnabled(False)
        self.process.start(sys.executable, ["-m", "app", "bench", self.technique, "--quick", "--out", str(bench_dir())])

    def _progress(self) -> None:
        text = bytes(self.process.readAllStandardOutput()).decode(errors="replace").strip().splitlines()
        if text:
            self.status.setText(text[-1].strip())

    def _finished(self, code: int, _status) -> None:
        self.process = None
        self.run_button.setEnabled(True)
        if code == 0:
            self.load(bench_dir() / f"{self.technique}.csv")
        else:
            self.status.setText(f"bench failed (exit {code})")

    def _open(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Open bench CSV", str(bench_dir()), "CSV (*.csv)")
        if path:
            self.load(Path(path))
