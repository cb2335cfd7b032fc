"""The 2D lighting workspace's panel: the scene (sample, ambient, shadow method), adding lights and
hulls, and the selected light's or hull's properties. Every change is sent as a console command;
`sync` shows the model without sending anything back."""
from __future__ import annotations

import math

from PySide6.QtWidgets import (QCheckBox, QComboBox, QFormLayout, QGroupBox, QHBoxLayout, QLabel, QLineEdit,
                               QPushButton, QVBoxLayout, QWidget)

from app.commands.lighting2d import sample_names
from app.model.lighting2d.scene import LIGHT_KINDS, SHADOW_METHODS, SHADOW_TYPES
from app.views.form_widgets import ColorButton, rgb_words, spin


class _Placement:
    """A light's or hull's position, rotation (degrees) and scale in spin boxes; each edit is sent as
    `send(key, value)` with the property's console syntax."""

    def __init__(self, send, scale_max: float, scale_step: float) -> None:
        self.x, self.y = spin(-1e7, 1e7, 5), spin(-1e7, 1e7, 5)
        self.rot = spin(-3600, 3600, 5, 1)
        self.sx, self.sy = spin(0, scale_max, scale_step), spin(0, scale_max, scale_step)
        for box in (self.x, self.y):
            box.valueChanged.connect(lambda _=0: send("position", f"{self.x.value()} {self.y.value()}"))
        self.rot.valueChanged.connect(lambda v: send("rotation", repr(math.radians(v))))
        for box in (self.sx, self.sy):
            box.valueChanged.connect(lambda _=0: send("scale", f"{self.sx.value()} {self.sy.value()}"))

    def rows(self, scale_label: str) -> list:
        return [("x", self.x), ("y", self.y), ("Rotation °", self.rot), (f"{scale_label} x", self.sx),
                (f"{scale_label} y", self.sy)]

    def show(self, item) -> None:
        values = (*item.position, math.degrees(item.rotation), *item.scale)
        for box, value in zip((self.x, self.y, self.rot, self.sx, self.sy), values):
            box.setValue(value)


class Lighting2DPanel(QWidget):
    def __init__(self, editor, state, run, tool=None, parent=None) -> None:
        super().__init__(parent)
        self.editor, self.state = editor, state
        self.run = run
        self.tool = tool
        self._syncing = False
        layout = QVBoxLayout(self)
        layout.addWidget(self._scene_box())
        layout.addWidget(self._light_box())
        layout.addWidget(self._hull_box())
        self.help = QLabel("Click: select · drag: move · round handle: rotate · square: scale\n"
                           "hull vertices: drag, double-click edge: insert, right click: delete\n"
                           "Delete: remove · empty drag / right drag: pan · wheel: zoom · h: draw a hull")
        self.help.setWordWrap(True)
        layout.addWidget(self.help)
        layout.addStretch(1)
        self.sync()

    def _scene_box(self) -> QGroupBox:
        scene_box = QGroupBox("Scene")
        form = QFormLayout(scene_box)
        self.sample = QComboBox()
        self.sample.addItems(["(load a sample)", *sample_names()])
        self.sample.activated.connect(self._load_sample)
        form.addRow("Sample", self.sample)
        self.ambient = ColorButton("Ambient colour", lambda c: self.run(f"ambient {rgb_words(c)}"))
        form.addRow("Ambient", self.ambient)
        self.method = QComboBox()
        self.method.addItems(SHADOW_METHODS)
        self.method.currentTextChanged.connect(lambda m: self._send(f"r_shadowMethod {m}"))
        form.addRow("Shadows", self.method)
        self.debug = QCheckBox("wireframe")
        self.debug.toggled.connect(lambda on: self._send(f"r_debug2d {int(on)}"))
        form.addRow("Debug", self.debug)
        add = QHBoxLayout()
        for kind in LIGHT_KINDS:
            button = QPushButton(f"+ {kind}")
            button.setToolTip(f"Add a {kind} light at the view's centre")
            button.clicked.connect(lambda _=False, k=kind: self._add_light(k))
            add.addWidget(button)
        form.addRow(add)
        self.draw = QPushButton("Draw a hull (h)")
        self.draw.setToolTip("Click points in the view; click the first point, double-click or Enter to close")
        self.draw.clicked.connect(lambda: self.tool and self.tool.start_drawing())
        form.addRow(self.draw)
        return scene_box

    def _light_box(self) -> QGroupBox:
        self.light_box = QGroupBox("Light")
        lf = QFormLayout(self.light_box)
        self.l_kind = QComboBox()
        self.l_kind.addItems(LIGHT_KINDS)
        self.l_kind.currentTextChanged.connect(lambda v: self._light("kind", v))
        self.l_place = _Placement(self._light, 1e7, 10)
        self.l_color = ColorButton("Light colour", lambda c: self._light("color", rgb_words(c)))
        self.l_intensity = spin(0, 100, 0.1)
        self.l_intensity.valueChanged.connect(lambda v: self._light("intensity", repr(v)))
        self.l_radius = spin(0, 1e6, 1)
        self.l_radius.valueChanged.connect(lambda v: self._light("radius", repr(v)))
        self.l_decay = spin(0, 100, 0.1)
        self.l_decay.valueChanged.connect(lambda v: self._light("cone_decay", repr(v)))
        self.l_height = spin(0, 1e6, 5)
        self.l_height.valueChanged.connect(lambda v: self._light("height", repr(v)))
        self.l_enabled, self.l_shadows = QCheckBox("enabled"), QCheckBox("casts shadows")
        self.l_enabled.toggled.connect(lambda on: self._light("enabled", str(int(on))))
        self.l_shadows.toggled.connect(lambda on: self._light("casts_shadows", str(int(on))))
        self.l_type = QComboBox()
        self.l_type.addItems(SHADOW_TYPES)
        self.l_type.currentTextChanged.connect(lambda v: self._light("shadow_type", v))
        self.l_ignored = QLineEdit()
        self.l_ignored.setPlaceholderText("hull numbers, e.g. 0 2")
        self.l_ignored.editingFinished.connect(
            lambda: self._light("ignored_hulls", self.l_ignored.text().strip() or "none"))
        for label, widget in (("Kind", self.l_kind), *self.l_place.rows("Size"), ("Colour", self.l_color),
                              ("Intensity", self.l_intensity), ("Radius", self.l_radius), ("Cone decay", self.l_decay),
                              ("Height", self.l_height), ("", self.l_enabled), ("", self.l_shadows),
                              ("Hulls", self.l_type), ("Ignores", self.l_ignored)):
            lf.addRow(label, widget)
        return self.light_box

    def _hull_box(self) -> QGroupBox:
        self.hull_box = QGroupBox("Hull")
        hf = QFormLayout(self.hull_box)
        self.h_place = _Placement(self._hull, 1e6, 0.1)
        self.h_enabled = QCheckBox("enabled")
        self.h_enabled.toggled.connect(lambda on: self._hull("enabled", str(int(on))))
        self.h_state = QLabel()
        self.h_state.setWordWrap(True)
        for label, widget in (*self.h_place.rows("Scale"), ("", self.h_enabled), ("", self.h_state)):
            hf.addRow(label, widget)
        return self.hull_box

    # ---- sending -----------------------------------------------------------------------------------

    def _send(self, line: str) -> None:
        if not self._syncing:
            self.run(line)

    def _load_sample(self, index: int) -> None:
        if index > 0:
            self.run(f"lighting.sample {self.sample.itemText(index)}")

    def _add_light(self, kind: str) -> None:
        cam = self.state.camera
        self.run(f"light.add {kind} {cam.cx:.3f} {cam.cy:.3f}")
        self.state.selection = ("light", len(self.state.scene.lights) - 1)
        self.sync()

    def _selected(self, kind: str):
        sel = self.state.selection
        if sel is None or sel[0] != kind:
            return None
        items = self.state.scene.lights if kind == "light" else self.state.scene.hulls
        return sel[1] if 0 <= sel[1] < len(items) else None

    def _light(self, key: str, value: str) -> None:
        i = self._selected("light")
        if i is not None:
            self._send(f"light.set {i} {key} {value}")

    def _hull(self, key: str, value: str) -> None:
        i = self._selected("hull")
        if i is not None:
            self._send(f"hull.set {i} {key} {value}")

    # ---- showing -----------------------------------------------------------------------------------

    def sync(self) -> None:
        self._syncing = True
        try:
            scene = self.state.scene
            cvars = self.editor.console.registry.cvars
            self.ambient.show_color(scene.ambient)
            self.method.setCurrentText(cvars["r_shadowMethod"].value)
            self.debug.setChecked(cvars["r_debug2d"].value)
            li, hi = self._selected("light"), self._selected("hull")
            self.light_box.setVisible(li is not None)
            self.hull_box.setVisible(hi is not None)
            if li is not None:
                self.light_box.setTitle(f"Light {li}")
                light = scene.lights[li]
                self.l_kind.setCurrentText(light.kind)
                self.l_place.show(light)
                for box, value in ((self.l_intensity, light.intensity),
                                   (self.l_radius, light.radius), (self.l_decay, light.cone_decay),
                                   (self.l_height, light.height)):
                    box.setValue(value)
                self.l_color.show_color(light.color)
                self.l_enabled.setChecked(light.enabled)
                self.l_shadows.setChecked(light.casts_shadows)
                self.l_type.setCurrentText(light.shadow_type)
                self.l_ignored.setText(" ".join(map(str, light.ignored_hulls)))
                self.l_decay.setEnabled(light.kind == "spot")
            if hi is not None:
                hull = scene.hulls[hi]
                self.hull_box.setTitle(f"Hull {hi} · {len(hull.points)} points")
                self.h_place.show(hull)
                self.h_enabled.setChecked(hull.enabled)
                self.h_state.setText("valid" if hull.valid else f"INVALID, ignored: {hull.invalid_reason}")
                self.h_state.setStyleSheet("" if hull.valid else "color: #ff5050")
        finally:
            self._syncing = False
