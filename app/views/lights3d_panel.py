"""The 3D lights workspace's panel: the scene's objects and lights (select, add, remove), the selected one's
properties, the scene's lighting settings and the shadow maps' cvars. Every change is sent as one console
command; `sync` shows the model without sending anything back."""
from __future__ import annotations

from PySide6.QtWidgets import (QAbstractSpinBox, QComboBox, QFormLayout, QGroupBox, QHBoxLayout, QListWidget, QMenu,
                               QPushButton, QSizePolicy, QVBoxLayout, QWidget)

from app.model.lights3d.scene import (LIGHT_KINDS, MAX_COORD, MAX_FALLOFF, MAX_SHININESS, MAX_SIZE, MAX_SPECULAR,
                                      OBJECT_KINDS, SHADOW_METHODS, SIZE_NAMES)
from app.model.lights3d.render_settings import MAX_BIAS, MAX_CASCADES, MAX_MAP_SIZE, MIN_MAP_SIZE, PCF_KERNELS
from app.views.form_widgets import ColorButton, rgb_words, spin
from app.views.lights3d_tool import REMOVE_VERBS

MAP_SIZES = tuple(str(1 << k) for k in range(MIN_MAP_SIZE.bit_length() - 1, MAX_MAP_SIZE.bit_length()))
MAX_SIZE_FIELDS = max(len(names) for names in SIZE_NAMES.values())


def _combo(words) -> QComboBox:
    box = QComboBox()
    box.addItems(list(words))
    return box


class _Vector:
    """x, y, z spin boxes in one row; `send("x y z")` on each finished edit."""

    def __init__(self, send, step: float = 5, decimals: int = 1) -> None:
        self.widget = QWidget()
        row = QHBoxLayout(self.widget)
        row.setContentsMargins(0, 0, 0, 0)
        self.boxes = [spin(-MAX_COORD, MAX_COORD, step, decimals) for _ in range(3)]
        for box in self.boxes:
            # Three in a row fit the dock only without arrows and without the width the range's longest text wants.
            box.setButtonSymbols(QAbstractSpinBox.ButtonSymbols.NoButtons)
            box.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Fixed)
            row.addWidget(box)
            box.valueChanged.connect(lambda _=0: send(" ".join(repr(b.value()) for b in self.boxes)))

    def show(self, xyz) -> None:
        for box, v in zip(self.boxes, xyz):
            box.setValue(v)


class Lights3DPanel(QWidget):
    def __init__(self, editor, state, run, parent=None) -> None:
        super().__init__(parent)
        self.state, self.run = state, run
        self.cvars = editor.console.registry.cvars
        self._syncing = False
        self._rows: list[tuple[str, int]] = []  # the list's rows: (kind, index)
        layout = QVBoxLayout(self)
        for box in (self._items_box(), self._object_box(), self._light_box(), self._lighting_box()):
            layout.addWidget(box)
        layout.addStretch(1)
        self.sync()

    def _items_box(self) -> QGroupBox:
        items_box = QGroupBox("Scene")
        items = QVBoxLayout(items_box)
        self.list = QListWidget()
        self.list.setMaximumHeight(150)
        self.list.currentRowChanged.connect(self._select_row)
        items.addWidget(self.list)
        buttons = QHBoxLayout()
        for label, verb, kind, kinds in (("+ Object", "object.add", "object", OBJECT_KINDS),
                                         ("+ Light", "light3d.add", "light", LIGHT_KINDS)):
            button = QPushButton(label)
            menu = QMenu(button)
            for name in kinds:
                menu.addAction(name, lambda v=verb, k=kind, n=name: self._add(v, k, n))
            button.setMenu(menu)
            buttons.addWidget(button)
        self.remove = QPushButton("Remove")
        self.remove.setToolTip("Remove the selection (Delete in the view)")
        self.remove.clicked.connect(self._remove)
        buttons.addWidget(self.remove)
        items.addLayout(buttons)
        return items_box

    def _object_box(self) -> QGroupBox:
        self.object_box = QGroupBox("Object")
        of = QFormLayout(self.object_box)
        self.o_position = _Vector(lambda xyz: self._object("object.move {i} " + xyz))
        of.addRow("Position", self.o_position.widget)
        # Sizes have 1 to 4 numbers by kind (SIZE_NAMES): the rows past the kind's are hidden.
        self.o_size = [spin(0, MAX_SIZE, 1) for _ in range(MAX_SIZE_FIELDS)]
        for box in self.o_size:
            box.valueChanged.connect(lambda _=0: self._object("object.set {i} size " + self._size_words()))
            of.addRow("size", box)  # named by kind in sync
        self.o_colour = ColorButton("Object colour", lambda c: self._object("object.set {i} colour " + rgb_words(c)))
        of.addRow("Colour", self.o_colour)
        return self.object_box

    def _light_box(self) -> QGroupBox:
        self.light_box = QGroupBox("Light")
        lf = QFormLayout(self.light_box)
        self.l_kind = _combo(LIGHT_KINDS)
        self.l_kind.currentTextChanged.connect(lambda k: self._light("kind", k))
        self.l_position = _Vector(lambda xyz: self._light("position", xyz))
        # Where a spot or directional light shines; the command normalises it (a point light has none).
        self.l_direction = _Vector(lambda xyz: self._light("direction", xyz), 0.1, 3)
        self.l_colour = ColorButton("Light colour", lambda c: self._light("colour", rgb_words(c)))
        self.l_range = spin(0.1, MAX_SIZE, 10, 1)
        self.l_range.valueChanged.connect(lambda v: self._light("range", repr(v)))
        self.l_falloff = spin(0.1, MAX_FALLOFF, 1, 1)
        self.l_falloff.valueChanged.connect(lambda v: self._light("falloff", repr(v)))
        self.l_angle = spin(0.5, 89.5, 1, 1)
        self.l_angle.valueChanged.connect(lambda v: self._light("angle", repr(v)))
        self.l_shadow = _combo(SHADOW_METHODS)
        self.l_shadow.currentTextChanged.connect(lambda m: self._light("shadow", m))
        for label, widget in (("Kind", self.l_kind), ("Position", self.l_position.widget),
                              ("Direction", self.l_direction.widget), ("Colour", self.l_colour),
                              ("Range", self.l_range), ("Falloff", self.l_falloff), ("Spot angle °", self.l_angle),
                              ("Shadow", self.l_shadow)):
            lf.addRow(label, widget)
        return self.light_box

    def _lighting_box(self) -> QGroupBox:
        lighting = QGroupBox("Lighting and shadow maps")
        sf = QFormLayout(lighting)
        self.ambient = ColorButton("Ambient colour", lambda c: self._send("lights3d.set ambient " + rgb_words(c)))
        self.shininess = spin(0.1, MAX_SHININESS, 4, 1)
        self.shininess.valueChanged.connect(lambda v: self._send(f"lights3d.set shininess {v!r}"))
        self.specular = spin(0, MAX_SPECULAR, 0.1)
        self.specular.valueChanged.connect(lambda v: self._send(f"lights3d.set specular {v!r}"))
        self.map_size = _combo(MAP_SIZES)
        self.map_size.currentTextChanged.connect(lambda n: self._send(f"r_shadowMapSize {n}"))
        self.pcf = _combo(map(str, PCF_KERNELS))
        self.pcf.currentTextChanged.connect(lambda n: self._send(f"r_shadowPCF {n}"))
        self.bias = spin(0, MAX_BIAS, 0.0001, 4)
        self.bias.valueChanged.connect(lambda v: self._send(f"r_shadowBias {v!r}"))
        self.cascades = _combo(str(n) for n in range(1, MAX_CASCADES + 1))
        self.cascades.currentTextChanged.connect(lambda n: self._send(f"r_shadowCascades {n}"))
        for label, widget in (("Ambient", self.ambient), ("Shininess", self.shininess), ("Specular", self.specular),
                              ("Map size", self.map_size), ("PCF taps", self.pcf), ("Map bias", self.bias),
                              ("Sun cascades", self.cascades)):
            sf.addRow(label, widget)
        return lighting

    # ---- sending -----------------------------------------------------------------------------------

    def _send(self, line: str) -> None:
        if not self._syncing:
            self.run(line)

    def _selected(self, kind: str) -> int | None:
        sel = self.state.selection
        return sel[1] if sel is not None and sel[0] == kind else None

    def _object(self, line: str) -> None:
        """`line` with {i} the selected object's index."""
        i = self._selected("object")
        if i is not None:
            self._send(line.format(i=i))

    def _light(self, field: str, value: str) -> None:
        i = self._selected("light")
        if i is not None:
            self._send(f"light3d.set {i} {field} {value}")

    def _size_words(self) -> str:
        kind = self.state.item(*self.state.selection).kind
        return " ".join(repr(box.value()) for box in self.o_size[:len(SIZE_NAMES[kind])])

    def _select_row(self, row: int) -> None:
        if 0 <= row < len(self._rows):
            self._send("lights3d.select {} {}".format(*self._rows[row]))

    def _add(self, verb: str, kind: str, name: str) -> None:
        if self.run(f"{verb} {name}"):
            self.run(f"lights3d.select {kind} {len(self.state.items(kind)) - 1}")  # the new one, to place it

    def _remove(self) -> None:
        if self.state.selection is not None:
            kind, i = self.state.selection
            self.run(f"{REMOVE_VERBS[kind]} {i}")

    # ---- showing -----------------------------------------------------------------------------------

    def sync(self) -> None:
        self._syncing = True
        try:
            self._show_list()
            oi, li = self._selected("object"), self._selected("light")
            self.object_box.setVisible(oi is not None)
            self.light_box.setVisible(li is not None)
            self.remove.setEnabled(self.state.selection is not None)
            if oi is not None:
                self._show_object(oi)
            if li is not None:
                self._show_light(li)
            scene = self.state.scene
            self.ambient.show_color(scene.ambient)
            self.shininess.setValue(scene.shininess)
            self.specular.setValue(scene.specular)
            self.map_size.setCurrentText(str(self.cvars["r_shadowMapSize"].value))
            self.pcf.setCurrentText(str(self.cvars["r_shadowPCF"].value))
            self.bias.setValue(self.cvars["r_shadowBias"].value)
            self.cascades.setCurrentText(str(self.cvars["r_shadowCascades"].value))
        finally:
            self._syncing = False

    def _show_list(self) -> None:
        scene = self.state.scene
        rows = [("object", i) for i in range(len(scene.objects))] + [("light", i) for i in range(len(scene.lights))]
        labels = [f"object {i}: {o.kind}" for i, o in enumerate(scene.objects)]
        labels += [f"light {i}: {li.kind} · {li.shadow}" for i, li in enumerate(scene.lights)]
        if labels != [self.list.item(r).text() for r in range(self.list.count())]:  # a drag only moves items
            self.list.clear()
            self.list.addItems(labels)
        self._rows = rows
        self.list.setCurrentRow(rows.index(self.state.selection) if self.state.selection in rows else -1)

    def _show_object(self, i: int) -> None:
        obj = self.state.scene.objects[i]
        self.object_box.setTitle(f"Object {i} · {obj.kind}")
        self.o_position.show(obj.position)
        form = self.object_box.layout()
        names = SIZE_NAMES[obj.kind]
        for k, box in enumerate(self.o_size):
            form.setRowVisible(box, k < len(names))
            if k < len(names):
                form.labelForField(box).setText(names[k])
                box.setDecimals(0 if names[k] in ("segments", "sides") else 2)
                box.setValue(obj.size[k])
        self.o_colour.show_color(obj.colour)

    def _show_light(self, i: int) -> None:
        light = self.state.scene.lights[i]
        self.light_box.setTitle(f"Light {i}")
        self.l_kind.setCurrentText(light.kind)
        self.l_position.show(light.position)
        self.l_direction.show(light.direction)
        self.l_direction.widget.setEnabled(light.kind != "point")
        self.l_colour.show_color(light.colour)
        for box, value in ((self.l_range, light.range), (self.l_falloff, light.falloff), (self.l_angle, light.angle)):
            box.setValue(value)
        self.l_range.setEnabled(light.kind == "point")  # the model's spot and directional lights have no reach
        self.l_angle.setEnabled(light.kind == "spot")
        self.l_shadow.setCurrentText(light.shadow)
