"""The volume panel's scalar group: the window (low and high) and the colour map of a scalar volume's transfer
function, each change one console command (`vol.window`, `vol.window.auto`, `vol.colormap`), so it is recorded,
replayed and undone like any edit."""
from __future__ import annotations

import math

from PySide6.QtWidgets import QComboBox, QGroupBox, QLabel, QPushButton, QVBoxLayout

from app.model.volume.scalars import COLORMAPS, PERCENTILES, value_range
from app.views.form_widgets import left_row, spin

NO_SCALARS = "no scalars to window: load a 16-bit or float NRRD, TIFF or .npy file"


def number(value: float) -> str:
    """As short as it can be written and still read back as the same float."""
    short = f"{value:g}"
    return short if float(short) == value else repr(value)


class TransferPanel(QGroupBox):
    def __init__(self, state, run) -> None:
        super().__init__("Scalars")
        self.state, self.run = state, run
        self.low, self.high = spin(-1.0, 1.0, 0.01), spin(-1.0, 1.0, 0.01)
        self.low.setToolTip("Window low: values here and below are transparent")
        self.high.setToolTip("Window high: values here and above are opaque, the colour map's last colour")
        self.auto = QPushButton("auto", toolTip="The window from percentiles {:g}..{:g} of the values above the minimum"
                                .format(*PERCENTILES))
        self.colormap = QComboBox(toolTip="The colour map across the window")
        self.colormap.addItems(COLORMAPS)
        self.info = QLabel(wordWrap=True)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(left_row(QLabel("window"), self.low, QLabel("to"), self.high, self.auto, self.colormap))
        layout.addWidget(self.info)
        # The box not edited sends the model's own value: a spin box shows it rounded to its decimals.
        self.low.valueChanged.connect(lambda v: self._send(f"vol.window {number(v)} {number(self._transfer.high)}"))
        self.high.valueChanged.connect(lambda v: self._send(f"vol.window {number(self._transfer.low)} {number(v)}"))
        self.auto.clicked.connect(lambda: self._send("vol.window.auto"))
        self.colormap.textActivated.connect(lambda name: self._send(f"vol.colormap {name}"))
        self._values = None  # the values whose range the info line shows
        self._shown = False  # the scalars (a new object at every change) the widgets show; False: none yet
        self.sync()

    @property
    def _transfer(self):
        return self.state.volume.voxels.scalars.transfer

    def _send(self, line: str) -> None:
        if not self.run(line):
            self._shown = False
            self.sync()  # refused (low above high): show the model's window again

    def sync(self) -> None:
        scalars = self.state.volume.voxels.scalars
        if scalars is self._shown:
            return  # the camera moved, a slice changed...: nothing here
        self._shown = scalars
        self.setEnabled(scalars is not None)
        if scalars is None:
            self.info.setText(NO_SCALARS)
            return
        values, transfer = scalars.values, scalars.transfer
        if values is not self._values:
            self._values = values
            self._range = value_range(values)
            self.info.setText(f"{values.dtype} scalars, values {number(self._range[0])}..{number(self._range[1])}")
        self._limits(transfer.low, transfer.high, values.dtype.kind in "iu")
        for widget, value in ((self.low, transfer.low), (self.high, transfer.high)):
            widget.blockSignals(True)
            widget.setValue(value)
            widget.blockSignals(False)
        self.colormap.setCurrentText(transfer.colormap)

    def _limits(self, low: float, high: float, whole: bool) -> None:
        """Room for a window as wide again as the data on either side (and for the current one), in steps of a
        hundredth of the data's span, with the decimals that step needs."""
        least, most = self._range
        if not (math.isfinite(least) and math.isfinite(most)):
            least, most = low, high
        span = max(most - least, high - low)
        step = max(1.0, round(span / 100)) if whole else span / 100
        decimals = 0 if whole else min(8, max(0, 2 - math.floor(math.log10(step))))
        for widget in (self.low, self.high):
            widget.blockSignals(True)
            widget.setDecimals(decimals)
            widget.setRange(min(least - span, low), max(most + span, high))
            widget.setSingleStep(step)
            widget.blockSignals(False)
