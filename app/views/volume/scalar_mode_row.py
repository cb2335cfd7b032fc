"""The Scalars group's render row: how a scalar volume is drawn (r_scalarMode) and iso mode's value (vol.iso, data
units), each change one console command."""
from __future__ import annotations

import math

from PySide6.QtWidgets import QComboBox, QLabel, QWidget

from app.model.volume.scalar_modes import ISO_MODE, SCALAR_MODES
from app.model.volume.scalars import value_range
from app.views.form_widgets import left_row, spin
from app.views.volume.transfer_panel import number


class ScalarModeRow(QWidget):
    def __init__(self, state, cvars, run) -> None:
        super().__init__()
        self.state, self.cvars, self.run = state, cvars, run
        self.mode = QComboBox(toolTip="How the 3D view draws the values: colour is the F-modes on the window's "
                                      "colours; mip, minip and average the greatest, least and mean value along "
                                      "each ray; iso a lit surface; translucent the opacity curve")
        self.mode.addItems(SCALAR_MODES)
        self.iso = spin(-1.0, 1.0, 0.01)
        self.iso.setToolTip("iso: the surface lies where the values first exceed this (data units)")
        row = left_row(QLabel("draw"), self.mode, QLabel("iso"), self.iso)
        row.setContentsMargins(0, 0, 0, 0)
        self.setLayout(row)
        self.mode.textActivated.connect(lambda name: self.run(f"r_scalarMode {name}"))
        self.iso.valueChanged.connect(lambda v: self.run(f"vol.iso {number(v)}"))
        self._values = None  # the values whose range the iso box spans
        self.sync()

    def sync(self) -> None:
        scalars = self.state.volume.voxels.scalars
        self.setEnabled(scalars is not None)
        mode = self.cvars["r_scalarMode"].value
        self.mode.setCurrentText(mode)
        self.iso.setEnabled(mode == ISO_MODE)
        if scalars is None:
            return
        self.iso.blockSignals(True)
        if scalars.values is not self._values:
            self._values = scalars.values
            self._limits(*value_range(scalars.values), scalars.values.dtype.kind in "iu")
        self.iso.setValue(self.state.iso_value())
        self.iso.blockSignals(False)

    def _limits(self, least: float, most: float, whole: bool) -> None:
        """The values' range, in steps of a hundredth of it, with the decimals that step needs."""
        if not (math.isfinite(least) and math.isfinite(most)) or least >= most:
            least, most = 0.0, 1.0
        step = max(1.0, round((most - least) / 100)) if whole else (most - least) / 100
        self.iso.setDecimals(0 if whole else min(8, max(0, 2 - math.floor(math.log10(step)))))
        self.iso.setRange(least, most)
        self.iso.setSingleStep(step)
