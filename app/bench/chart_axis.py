"""The bench chart's axis (pyqtgraph): plain numbers, and no tick label drawn over another."""
from __future__ import annotations

import pyqtgraph as pg

LABEL_GAP_PX = 4.0  # the least room between two tick labels


class ChartAxis(pg.AxisItem):
    def __init__(self, orientation: str) -> None:
        super().__init__(orientation)
        # pyqtgraph works out an SI scale even while auto prefixes are off, from the range shown when they are
        # turned off, and keeps it: turned off here, before any label shows, it stays 1 whatever is plotted later
        self.enableAutoSIPrefix(False)

    def generateDrawSpecs(self, p):
        """pyqtgraph drops a tick level only when its labels crowd the axis as a whole: the minor labels of a
        log axis (0.7, 0.8, 0.9 before 1) still overlap each other. Keep each label, major ones first, only
        where it has room."""
        specs = super().generateDrawSpecs(p)
        if specs is None:
            return None
        axis, ticks, texts = specs
        kept = []
        for rect, flags, text in texts:
            room = rect.adjusted(-LABEL_GAP_PX, -LABEL_GAP_PX, LABEL_GAP_PX, LABEL_GAP_PX)
            if not any(room.intersects(other) for other, _f, _t in kept):
                kept.append((rect, flags, text))
        return axis, ticks, kept
