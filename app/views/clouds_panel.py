"""The clouds workspace's panel: every parameter of the seed's demo UI, the sun and a time-of-day slider,
the weather, and the renderer's cvars. Each change is a console command, so demos, undo and Lua see it."""
from __future__ import annotations


from PySide6.QtCore import Qt
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDoubleSpinBox, QFileDialog, QFormLayout, QGridLayout, QGroupBox,
                               QHBoxLayout, QLabel, QPushButton, QSlider, QVBoxLayout, QWidget)

from app.commands.clouds import SWITCHES
from app.console.quoting import quote
from app.model.clouds.exposure import EV_RANGE, TONE_MAPS
from app.model.clouds.scene import INTEGRATIONS, PARAM, Param

SLIDER_STEPS = 1000
GROUPS = (
    ("Coverage and shape", ("coverage", "density", "shape_scale", "detail_scale", "shape_min", "shape_max",
                            "detail_modifier", "curl_scale", "curl_amount", "weather_scale")),
    ("High clouds", ("high_coverage", "high_coverage_scale", "high_scale")),
    ("Light", ("ambient", "direct", "hg_forward", "hg_back", "hg_back_weight", "light_step", "cone_radius",
               "octave_scattering", "octave_extinction", "octave_eccentricity")),
    ("Wind", ("wind_speed", "wind_dir", "weather_wind_speed", "weather_wind_dir", "high_wind_speed", "high_wind_dir",
              "time_scale")),
)
TOGGLES = ("shape_noise", "detail_noise", "curl_noise", "multiscatter", "ground_shadows", "physical_sky")


class ValueRow(QWidget):
    """A slider and a number field over lo..hi; `send(value)` runs when the user changes either."""

    def __init__(self, lo: float, hi: float, decimals: int, send) -> None:
        super().__init__()
        self.lo, self.hi, self.send = lo, hi, send
        self.slider = QSlider(Qt.Orientation.Horizontal, minimum=0, maximum=SLIDER_STEPS)
        self.spin = QDoubleSpinBox(minimum=lo, maximum=hi, decimals=decimals, singleStep=(hi - lo) / 100,
                                   keyboardTracking=False)
        row = QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        row.addWidget(self.slider, 1)
        row.addWidget(self.spin)
        self.slider.valueChanged.connect(lambda v: self.send(round(lo + (hi - lo) * v / SLIDER_STEPS, decimals)))
        self.spin.valueChanged.connect(self.send)

    def show_value(self, value: float) -> None:
        for widget, v in ((self.slider, round((value - self.lo) / (self.hi - self.lo) * SLIDER_STEPS)),
                          (self.spin, value)):
            widget.blockSignals(True)
            widget.setValue(v)
            widget.blockSignals(False)


def _decimals(p: Param) -> int:
    return 0 if p.hi - p.lo >= 100 else 3 if p.hi - p.lo <= 2 else 2


class CloudsPanel(QWidget):
    def __init__(self, editor, state, run, parent=None) -> None:
        super().__init__(parent)
        self.editor, self.state, self.run = editor, state, run
        self.cvars = editor.console.registry.cvars
        layout = QVBoxLayout(self)
        self.values: dict[str, ValueRow] = {}
        self.checks: dict[str, QCheckBox] = {}

        render = self._group(layout, "Rendering")
        self.steps = ValueRow(1, 256, 0, lambda v: self._send(f"r_cloudSteps {int(v)}"))
        render.addRow("Steps", self.steps)
        self.downsample = QComboBox()
        self.downsample.addItems(["1", "1/2", "1/3", "1/4"])
        self.downsample.currentIndexChanged.connect(lambda i: self._send(f"r_cloudDownsample {i + 1}"))
        render.addRow("Cloud buffer", self.downsample)
        self.integration = QComboBox()
        self.integration.addItems(INTEGRATIONS)
        self.integration.currentTextChanged.connect(lambda m: self._send(f"r_cloudIntegration {m}"))
        render.addRow("Integration", self.integration)
        switches = QGridLayout()
        for i, (name, _field, label, text) in enumerate(SWITCHES):
            box = QCheckBox(label, toolTip=f"{name}: {text}")
            box.toggled.connect(lambda on, n=name: self._send(f"{n} {int(on)}"))
            self.checks[name] = box
            switches.addWidget(box, i // 2, i % 2)
        render.addRow(switches)

        exposure = self._group(layout, "Exposure")
        self.exposure = ValueRow(*EV_RANGE, 2, lambda ev: self._send(f"r_cloudExposure {ev:g}"))
        self.exposure.setToolTip(self.cvars["r_cloudExposure"].help)
        exposure.addRow("Exposure (EV)", self.exposure)
        box = QCheckBox("Automatic (the EV above adds to it)", toolTip=self.cvars["r_cloudAutoExposure"].help)
        box.toggled.connect(lambda on: self._send(f"r_cloudAutoExposure {int(on)}"))
        self.checks["r_cloudAutoExposure"] = box
        exposure.addRow(box)
        self.tone_map = QComboBox(toolTip=self.cvars["r_cloudToneMap"].help)
        self.tone_map.addItems(TONE_MAPS)
        self.tone_map.currentTextChanged.connect(lambda name: self._send(f"r_cloudToneMap {name}"))
        exposure.addRow("Tone curve", self.tone_map)

        sun = self._group(layout, "Sun")
        self.hour = ValueRow(0, 24, 2, lambda h: self._send(f"sun.time {h:g}"))
        sun.addRow("Time of day", self.hour)
        self.azimuth = ValueRow(0, 360, 1, lambda a: self._send(f"sun.dir {a:g} {self.state.view.sun_elevation:g}"))
        self.elevation = ValueRow(-10, 90, 1, lambda e: self._send(f"sun.dir {self.state.view.sun_azimuth:g} {e:g}"))
        sun.addRow("Azimuth", self.azimuth)
        sun.addRow("Elevation", self.elevation)

        weather = self._group(layout, "Weather")
        buttons = QHBoxLayout()
        generate = QPushButton("Generate weather")
        generate.clicked.connect(lambda: self._send("weather.new"))
        load = QPushButton("Load PNG...")
        load.clicked.connect(self._load_weather)
        buttons.addWidget(generate)
        buttons.addWidget(load)
        weather.addRow(buttons)
        self._param_row(weather, PARAM["weather_blend"])
        self.clock = QLabel()
        weather.addRow(self.clock)

        for title, names in GROUPS:
            form = self._group(layout, title)
            for name in names:
                self._param_row(form, PARAM[name])
        noise = self._group(layout, "Noise and light march")
        for name in TOGGLES:
            box = QCheckBox(name.replace("_", " ").capitalize(), toolTip=PARAM[name].text)
            box.toggled.connect(lambda on, n=name: self._send(f"clouds.set {n} {int(on)}"))
            self.checks[name] = box
            noise.addRow(box)
        self.light_samples = QComboBox()
        self.light_samples.addItems(["6", "30"])
        self.light_samples.currentTextChanged.connect(lambda n: self._send(f"clouds.set light_samples {n}"))
        noise.addRow("Light samples", self.light_samples)
        self.phase = QComboBox(toolTip=PARAM["phase_max"].text)
        self.phase.addItems(["mix", "max"])  # phase_max 0, 1
        self.phase.currentIndexChanged.connect(lambda i: self._send(f"clouds.set phase_max {i}"))
        noise.addRow("Phase", self.phase)
        layout.addWidget(QLabel("Drag: look around · wheel: altitude (through the layer and above it)"))
        layout.addStretch(1)
        self.sync()

    def _group(self, layout, title: str) -> QFormLayout:
        box = QGroupBox(title)
        layout.addWidget(box)
        return QFormLayout(box)

    def _param_row(self, form: QFormLayout, p: Param) -> None:
        row = ValueRow(p.lo, p.hi, _decimals(p), lambda v, n=p.name: self._set_param(n, v))
        row.setToolTip(p.text)
        self.values[p.name] = row
        form.addRow(p.name.replace("_", " ").capitalize(), row)

    def _set_param(self, name: str, value: float) -> None:
        if value != getattr(self.state.params, name):
            self._send(f"clouds.set {name} {value:g}")

    def _send(self, line: str) -> None:
        self.run(line)
        self.sync()  # a refused value springs back

    def _load_weather(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Load weather map", "", "PNG images (*.png)")
        if path:
            self._send(f"weather.load {quote(path)}")

    def sync(self) -> None:
        """Show the model's and the cvars' values without sending them back as commands."""
        params, view, cvars = self.state.params, self.state.view, self.cvars
        for name, row in self.values.items():
            row.show_value(getattr(params, name))
        self.steps.show_value(min(cvars["r_cloudSteps"].value, 256))
        self.exposure.show_value(cvars["r_cloudExposure"].value)
        self.azimuth.show_value(view.sun_azimuth)
        self.elevation.show_value(min(max(view.sun_elevation, -10.0), 90.0))
        widgets = [(self.downsample, lambda w: w.setCurrentIndex(cvars["r_cloudDownsample"].value - 1)),
                   (self.integration, lambda w: w.setCurrentText(cvars["r_cloudIntegration"].value)),
                   (self.tone_map, lambda w: w.setCurrentText(cvars["r_cloudToneMap"].value)),
                   (self.light_samples, lambda w: w.setCurrentText(str(params.light_samples))),
                   (self.phase, lambda w: w.setCurrentIndex(params.phase_max))]
        widgets += [(box, lambda w, n=name: w.setChecked(bool(cvars[n].value if n in cvars else getattr(params, n))))
                    for name, box in self.checks.items()]
        for widget, show in widgets:
            widget.blockSignals(True)
            show(widget)
            widget.blockSignals(False)
        self.clock.setText(f"Clock {self.state.clock:.0f} s · new weather {self.state.blend():.0%} blended in")
