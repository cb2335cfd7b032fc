"""The snowflake workspace's panel: the level (slider and field) and the flake count."""
from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox, QFormLayout, QHBoxLayout, QLabel, QPushButton, QSlider, QWidget

from app.console.text import count
from app.gl.snowflake.renderer import chunk_layout
from app.model.snowflake import MAX_LEVEL

SLIDER_STEPS_PER_LEVEL = 20


class SnowflakePanel(QWidget):
    def __init__(self, state, run, parent=None) -> None:
        super().__init__(parent)
        self.state = state
        self.run = run
        self.slider = QSlider(Qt.Orientation.Horizontal)
        self.slider.setRange(0, int(MAX_LEVEL * SLIDER_STEPS_PER_LEVEL))
        self.spin = QDoubleSpinBox(decimals=2, minimum=0.0, maximum=MAX_LEVEL, singleStep=0.25)
        self.spin.setKeyboardTracking(False)
        self.info = QLabel()
        self.info.setWordWrap(True)
        clear = QPushButton("Remove all flakes")
        clear.clicked.connect(lambda: self.run("snow.clear"))
        row = QHBoxLayout()
        row.addWidget(self.slider, 1)
        row.addWidget(self.spin)
        form = QFormLayout(self)
        form.addRow("Level (w/s)", row)
        form.addRow(self.info)
        form.addRow(clear)
        form.addRow(QLabel("Click: add · drag: move · right click: remove\n"
                           "right/middle drag: pan · wheel: zoom"))
        self.slider.valueChanged.connect(lambda v: self._set_level(v / SLIDER_STEPS_PER_LEVEL))
        self.spin.valueChanged.connect(self._set_level)
        self.sync()

    def _set_level(self, level: float) -> None:
        if abs(level - self.state.scene.level) > 1e-9:
            self.run(f"snow.level {level:g}")

    def sync(self) -> None:
        """Show the model's values without sending them back as commands."""
        scene = self.state.scene
        for widget, value in ((self.slider, round(scene.level * SLIDER_STEPS_PER_LEVEL)), (self.spin, scene.level)):
            widget.blockSignals(True)
            widget.setValue(value)
            widget.blockSignals(False)
        m, _t, depth, chunks = chunk_layout(scene.level)
        n = len(scene.flakes)
        self.info.setText(f"{count(n, 'flake')} · {3 * 4 ** m + 1} vertices each\n"
                          f"{n * chunks} geometry-shader invocations of ≤ {4 ** depth + 1} vertices")
