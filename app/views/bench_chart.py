"""The bench chart drawn with pyqtgraph (what it shows comes from app.bench.report.chart): RMSE against frame
time and frame time against the knob, side by side (the PNG) or stacked (the dock), a note above them, and the
legend beside or under them, never over a point: methods by colour, scenes by marker."""
from __future__ import annotations

import html
import math
import os
from pathlib import Path

import pyqtgraph as pg
from PySide6.QtCore import QRectF, Qt
from PySide6.QtWidgets import QSizePolicy

from app.bench.report import Chart, Line, chart, number_text

LABEL_GAP_PX = 4.0  # the least room between two tick labels
LEGEND_ROW_PX = 20  # the height of a legend entry (pyqtgraph's sample is 20 px)
MUTED = "#8a909c"   # the legend's headings and the scene markers' neutral colour
PNG_SIZE = (1400, 600)
MAX_KNOB_TICKS = 16  # a knob with up to this many settings has a tick at each (else pyqtgraph's own)


class ChartAxis(pg.AxisItem):
    """Plain numbers (20, 0.001, no SI prefix), powers of ten only when very small or large, and no tick label
    drawn over another."""

    def __init__(self, orientation: str) -> None:
        super().__init__(orientation)
        # pyqtgraph works out an SI scale even while auto prefixes are off, from the range shown when they are
        # turned off, and keeps it: turned off here, before any label shows, it stays 1 whatever is plotted later
        self.enableAutoSIPrefix(False)
        # a level's labels are drawn while they fill less of the axis than this (generateDrawSpecs then drops
        # each that would touch another); past 6 labels, a level (a log axis' 3, 4, 6...) only while they are few
        self.setStyle(textFillLimits=[(0, 0.9), (6, 0.45)])

    def logTickStrings(self, values, scale, spacing):
        """pyqtgraph's own read '2·10¹' for 20."""
        return [number_text(10 ** v * scale) for v in values]

    def logTickValues(self, minVal, maxVal, size, stdTicks):
        """pyqtgraph's minor level (2..9 in each decade) split in two: 2 and 5 first (20, 50, 100), the rest
        after, so that a crowded axis still labels 1-2-5 rather than powers of ten alone."""
        ticks = super().logTickValues(minVal, maxVal, size, stdTicks)
        if not ticks or ticks[-1][0] is not None:
            return ticks
        major = {round(v, 6) for _spacing, values in ticks[:-1] for v in values}
        minor = [(v, round(10 ** (v - math.floor(v)))) for v in ticks[-1][1] if round(v, 6) not in major]
        return [*ticks[:-1], (None, [v for v, m in minor if m in (1, 2, 5)]),
                (None, [v for v, m in minor if m not in (1, 2, 5)])]

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


class ShrinkingLabel(pg.LabelItem):
    """A label that asks for its text's height but not its width: a long one is cut at the chart's edge rather
    than widening the chart past its view (a plot's own title did: a narrow dock showed only the left of each
    plot). The chart's titles and note are these, laid out above the plots."""

    def updateMin(self):
        super().updateMin()
        self.setMinimumWidth(1)

    def resizeEvent(self, ev):
        super().resizeEvent(ev)
        overflow = self.itemRect()
        if overflow.width() > self.width():  # cut at its end, its start readable
            self.item.moveBy(-overflow.left(), 0)


class Legend(pg.LegendItem):
    """A legend laid out by the chart's layout, beside the plots rather than floating over one."""

    def __init__(self) -> None:
        super().__init__(frame=False, labelTextColor="#d0d4dc")

    def updateSize(self):
        self.updateGeometry()  # pyqtgraph would set its geometry at its parent's corner; the layout places it

    def fit_width(self, width: float) -> None:
        """The most columns (up to one an entry) whose entries fit side by side in `width`."""
        for columns in range(len(self.items), 0, -1):
            self.setColumnCount(columns)
            if self.layout.effectiveSizeHint(Qt.SizeHint.PreferredSize).width() <= width:
                return


class BenchChart:
    """The chart's items in a pyqtgraph GraphicsLayout, laid out again for each chart shown: the error plot is
    left out when the errors are exact to float32."""

    def __init__(self, layout: pg.GraphicsLayout, stacked: bool = False) -> None:
        self.layout = layout
        self.stacked = stacked
        self.error_plot = pg.PlotItem(axisItems=self._axes())
        self.time_plot = pg.PlotItem(axisItems=self._axes())
        self.note = ShrinkingLabel(justify="left")
        self.titles = {plot: ShrinkingLabel(size="11pt") for plot in (self.error_plot, self.time_plot)}
        self.methods_heading = pg.LabelItem("methods (colour)", justify="left", color=MUTED, size="8pt")
        self.scenes_heading = pg.LabelItem("scenes (marker)", justify="left", color=MUTED, size="8pt")
        self.method_legend, self.scene_legend = Legend(), Legend()
        self.legend = pg.GraphicsLayout()  # the headings and both legends, one above the other
        for row, item in enumerate((self.methods_heading, self.method_legend, self.scenes_heading,
                                    self.scene_legend)):
            self.legend.addItem(item, row=row, col=0)
        self.legend.layout.setContentsMargins(4, 4, 4, 4)
        self.legend.layout.setVerticalSpacing(0)
        fixed = QSizePolicy.Policy.Fixed  # as big as its entries, at the top of its cell: the plots take the rest
        for item in (self.legend, self.method_legend, self.scene_legend, self.methods_heading, self.scenes_heading):
            item.setSizePolicy(fixed, fixed)
        if stacked:  # under the plots its width is the chart's, never more: fit_legend fits its columns to it
            self.legend.setSizePolicy(QSizePolicy.Policy.Ignored, fixed)
            self.legend.setMinimumWidth(1)
        # Each item the layout's child for good, laid out or hidden: one that Python alone owned would be deleted
        # by Python while a layout still held it (a crash as the window closed). Set after construction, so that
        # pyqtgraph hears of its scene (a view box in one from birth never fits its range to its lines).
        for item in (self.error_plot, self.time_plot, self.note, *self.titles.values(), self.legend):
            item.setParentItem(layout)
        self.shown = Chart()
        self.lines: dict[pg.PlotDataItem, Line] = {}  # every drawn line and what it draws
        # each legend entry's sample, by method and by scene: clicking one hides (or shows) its lines
        self.method_samples: dict[str, pg.PlotDataItem] = {}
        self.scene_samples: dict[str, pg.PlotDataItem] = {}
        for legend in (self.method_legend, self.scene_legend):
            legend.sigSampleClicked.connect(self._sample_clicked)
        layout.geometryChanged.connect(self.fit_legend)
        self._arrange()

    @staticmethod
    def _axes() -> dict[str, ChartAxis]:
        return {side: ChartAxis(side) for side in ("left", "bottom")}

    def plots(self) -> list[pg.PlotItem]:
        """The plots laid out now."""
        return [self.time_plot] if self.shown.exact else [self.error_plot, self.time_plot]

    def _arrange(self) -> None:
        """The note above the plots, each plot under its title, the legend beside them (side by side) or under
        them (stacked); what is not shown is hidden, out of the grid."""
        grid = self.layout.layout
        while grid.count():
            grid.removeAt(grid.count() - 1)
        for item in (self.note, self.error_plot, self.time_plot, *self.titles.values(), self.legend):
            item.hide()

        def place(item, row: int, col: int, colspan: int = 1) -> None:
            grid.addItem(item, row, col, 1, colspan)
            item.show()

        plots = self.plots()
        top = int(bool(self.note.text))
        if top:
            place(self.note, 0, 0, colspan=1 if self.stacked else len(plots))
        for i, plot in enumerate(plots):
            row, col = (top + 2 * i, 0) if self.stacked else (top, i)
            if self.titles[plot].text:
                place(self.titles[plot], row, col)
            place(plot, row + 1, col)
        if self.shown.colours:
            place(self.legend, *((top + 2 * len(plots), 0) if self.stacked else (top + 1, len(plots))))
            grid.setAlignment(self.legend, Qt.AlignmentFlag.AlignLeft | Qt.AlignmentFlag.AlignTop)

    def show(self, rows: list[dict]) -> Chart:
        """Draw the chart of these bench rows (read_csv's) and return what it shows."""
        self.shown = shown = chart(rows)
        self._clear_items()
        self.note.setText("<br>".join(html.escape(note) for note in shown.notes))
        err, tim = self.error_plot, self.time_plot
        if not shown.exact:
            err.setLogMode(x=True, y=True)
            err.setLabel("bottom", "frame time (ms)")
            err.setLabel("left", "RMSE (0..1)")
            self.titles[err].setText(shown.error_title)
            for line in shown.error_lines:
                self._draw(err, line, line.ms, line.error, width=2)
        tim.setLogMode(x=False, y=True)
        tim.setLabel("bottom", shown.knob_name)
        settings = sorted({float(k) for line in shown.time_lines for k in line.knob})
        if len(settings) <= MAX_KNOB_TICKS:  # ticks at the settings measured, not at levels between them
            tim.getAxis("bottom").setTicks([[(k, number_text(k)) for k in settings]])
        tim.setLabel("left", "frame time (ms)")
        self.titles[tim].setText(shown.time_title)
        for line in shown.time_lines:
            self._draw(tim, line, line.knob, line.ms, width=1.5)
        for method, colour in shown.colours.items():
            self.method_samples[method] = sample = pg.PlotDataItem(pen=pg.mkPen(colour, width=2))
            self.method_legend.addItem(sample, method)
        for scene, marker in shown.markers.items():
            self.scene_samples[scene] = sample = pg.PlotDataItem(pen=None, symbol=marker, symbolSize=7,
                                                                 symbolBrush=MUTED, symbolPen=MUTED)
            self.scene_legend.addItem(sample, scene)
        self._arrange()
        self.fit_legend()
        return shown

    def _draw(self, plot: pg.PlotItem, line: Line, x, y, width: float) -> None:
        colour = self.shown.colours[line.method]
        item = plot.plot(x, y, pen=pg.mkPen(colour, width=width), symbol=self.shown.markers[line.scene],
                         symbolSize=6, symbolBrush=colour, name=line.method, data=line.tips)
        self.lines[item] = line

    def clear(self) -> None:
        """Nothing drawn: no lines, titles, axis labels, note or legend."""
        self.shown = Chart()
        self._clear_items()
        self.note.setText("")
        self._arrange()

    def _clear_items(self) -> None:
        for plot in (self.error_plot, self.time_plot):
            plot.clear()
            self.titles[plot].setText("")
            for axis in ("left", "bottom"):
                plot.setLabel(axis, "")
            plot.showGrid(x=True, y=True, alpha=0.3)
            plot.getAxis("bottom").setTicks(None)
        for legend in (self.method_legend, self.scene_legend):
            legend.clear()
        self.lines.clear()
        self.method_samples.clear()
        self.scene_samples.clear()

    def legend_entries(self) -> dict[str, list[str]]:
        """The legend's names: {'methods': [...], 'scenes': [...]}, in its order."""
        return {"methods": [label.text for _s, label in self.method_legend.items],
                "scenes": [label.text for _s, label in self.scene_legend.items]}

    def fit_legend(self) -> None:
        """As many columns as the room allows: under stacked plots, as many entries side by side as fit the
        width; beside them, a second column only when one would run past the chart's height."""
        room = self.layout.contentsRect()
        margins = [self.layout.layout.getContentsMargins(), self.legend.layout.getContentsMargins()]
        width = room.width() - sum(left + right for left, _top, right, _bottom in margins)
        for legend in (self.method_legend, self.scene_legend):
            count = len(legend.items)
            if not count:
                continue
            if self.stacked:
                legend.fit_width(width)
            else:
                legend.setColumnCount(min(count, math.ceil(count * LEGEND_ROW_PX / max(room.height() / 2,
                                                                                        LEGEND_ROW_PX))))

    def _sample_clicked(self, _sample) -> None:
        """Clicking a legend entry hides (or shows again) its method's or its scene's lines."""
        for item, line in self.lines.items():
            item.setVisible(self.method_samples[line.method].isVisible() and self.scene_samples[line.scene].isVisible())


def drawn_offscreen(rows: list[dict], size: tuple[int, int] = PNG_SIZE) -> tuple[pg.GraphicsLayoutWidget, BenchChart]:
    """The chart of the rows, side by side, laid out at `size` without being shown (needs a QApplication)."""
    from PySide6.QtWidgets import QApplication

    widget = pg.GraphicsLayoutWidget()
    widget.resize(*size)
    drawing = BenchChart(widget.ci)
    drawing.show(rows)
    widget.ci.setGeometry(QRectF(0, 0, *size))  # never shown on screen, so lay it out by hand
    QApplication.processEvents()  # the legend's columns, fitted to that size, laid out
    widget.scene().prepareForPaint()  # the plots' ranges, as a paint would fit them to the lines
    return widget, drawing


def save_chart(path: str | os.PathLike, rows: list[dict], size: tuple[int, int] = PNG_SIZE) -> Chart:
    """Render the chart off screen and write it as a PNG (needs a QApplication; see cli). Returns what it shows."""
    from pyqtgraph.exporters import ImageExporter

    pg.setConfigOptions(antialias=True, background="#14161c", foreground="#d0d4dc")
    widget, drawing = drawn_offscreen(rows, size)
    exporter = ImageExporter(widget.ci)
    exporter.parameters()["width"] = size[0]
    tmp = Path(path).with_suffix(".tmp.png")
    exporter.export(str(tmp))
    os.replace(tmp, path)
    return drawing.shown
