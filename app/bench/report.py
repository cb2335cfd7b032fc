"""Bench results as CSV and as a chart: error against time, one curve per method (pyqtgraph)."""
from __future__ import annotations

import csv
import io
import math
import os
from collections import defaultdict
from pathlib import Path

import numpy as np

from app.bench.harness import CSV_COLUMNS, Row
from app.io.atomic import write_text
from app.io.regular_file import read_regular_bytes

ERROR_FLOOR = 1e-9  # zero error still needs a place on a log axis
MAX_CSV_BYTES = 16 << 20  # a full bench writes a few hundred rows: some 100 KiB
_NUMBERS = ("knob", "ms_median", "gpu_ms_median", "rmse", "max_abs_error")
_FINITE = ("knob", "ms_median")
LEGEND_ROWS = 12    # a legend with more entries than this lays them out in two columns
PALETTE = ("#4cc9f0", "#f72585", "#ffd166", "#06d6a0", "#b388ff", "#ff9f1c", "#8ecae6", "#ef476f",
           "#90be6d", "#f8961e", "#c77dff", "#e9ecef")


def write_csv(path: str | os.PathLike, rows: list[Row]) -> None:
    out = io.StringIO()
    extra = list(dict.fromkeys(k for row in rows for k in row.extra))
    writer = csv.DictWriter(out, fieldnames=[*CSV_COLUMNS, *extra], lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow(row.as_csv())
    write_text(path, out.getvalue())


def read_csv(path: str | os.PathLike) -> list[dict]:
    """Rows with numbers parsed. A bench CSV, the editor's own in its cache included, is input: a file that is
    not a regular one (a FIFO would wait for ever), is over MAX_CSV_BYTES, lacks the contract's columns or has a
    row cut short or holding no number where one goes is refused with a ValueError (an OSError for the file
    itself) that says where."""
    try:
        text = read_regular_bytes(path, MAX_CSV_BYTES).decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path} is not UTF-8 text (byte {exc.start})") from None
    reader = csv.DictReader(io.StringIO(text, newline=""))
    missing = set(CSV_COLUMNS) - set(reader.fieldnames or ())
    if missing:
        raise ValueError(f"{path} is not a bench CSV (missing {', '.join(sorted(missing))})")
    rows = []
    try:
        for r in reader:
            rows.append(_row(r))
    except (csv.Error, ValueError) as exc:  # csv.Error: a field over csv's size limit, a NUL
        raise ValueError(f"{path}:{reader.line_num}: {exc}") from None
    return rows


def _row(r: dict) -> dict:
    """A CSV row with its numbers parsed: every column of the contract there, finite where a curve needs it (a
    time, a knob), and NaN allowed where a method measured nothing (a CPU method's GPU time)."""
    short = [k for k in CSV_COLUMNS if r.get(k) is None]
    if short:
        raise ValueError(f"the row is cut short (no {', '.join(short)})")
    for key in _NUMBERS:
        try:
            r[key] = float(r[key])
        except ValueError:
            raise ValueError(f"{key} is not a number: {r[key][:40]!r}") from None
        if key in _FINITE and not math.isfinite(r[key]):
            raise ValueError(f"{key} must be a finite number, got {r[key]}")
    return r


def curves(rows: list[dict], scene: str | None = None) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """method -> (ms, RMSE, knob) for one scene (the first one if None), sorted by knob. RMSE rather than
    the max: one silhouette pixel sets the max for every method alike."""
    scene = scene or (rows[0]["scene"] if rows else None)
    grouped: dict[str, list[tuple[float, float, float]]] = defaultdict(list)
    for r in rows:
        if r["scene"] == scene:
            grouped[r["method"]].append((r["knob"], r["ms_median"], max(r["rmse"], ERROR_FLOOR)))
    result = {}
    for method, points in grouped.items():
        knob, ms, err = np.array(sorted(points)).T
        result[method] = (ms, err, knob)
    return result


def add_plots(layout, stacked: bool = False):
    """The chart's two plots (RMSE against time, time against the knob) in a pyqtgraph GraphicsLayout, side by
    side or stacked, on axes that print plain numbers (no SI prefix) and no label over another."""
    from app.bench.chart_axis import ChartAxis

    def axes():
        return {side: ChartAxis(side) for side in ("left", "bottom")}

    return layout.addPlot(row=0, col=0, axisItems=axes()), layout.addPlot(row=int(stacked), col=int(not stacked),
                                                                          axisItems=axes())


def tip(method: str, scene: str, knob_name: str, knob: float, ms: float, rmse: float) -> str:
    """What hovering a point of the chart says about it."""
    return f"{method}\n{scene}\n{knob_name} = {knob:g}\n{ms:.3g} ms/frame, RMSE {rmse:.3g}"


def plot(error_plot, time_plot, rows: list[dict], scene: str | None = None) -> None:
    """Fill two pyqtgraph PlotItems (from add_plots): RMSE against ms (log-log), and ms against the knob per
    scene. Each point carries its tip() as its data."""
    import pyqtgraph as pg

    for p in (error_plot, time_plot):
        p.clear()
        p.showGrid(x=True, y=True, alpha=0.3)
        p.addLegend(offset=(10, 10), brush=(20, 22, 28, 200))
    scene = scene or (rows[0]["scene"] if rows else None)
    error_plot.setLogMode(x=True, y=True)
    error_plot.setLabel("bottom", "frame time (ms)")
    error_plot.setLabel("left", "RMSE (0..1)")
    error_plot.setTitle(f"Speed vs accuracy — {scene}")
    methods = sorted({r["method"] for r in rows})
    colours = {m: PALETTE[i % len(PALETTE)] for i, m in enumerate(methods)}
    knob_names = {r["method"]: r["knob_name"] for r in rows if r["scene"] == scene}
    for method, (ms, err, knob) in curves(rows, scene).items():
        tips = [tip(method, scene, knob_names[method], *point) for point in zip(knob, ms, err)]
        error_plot.plot(ms, err, pen=pg.mkPen(colours[method], width=2), symbol="o", symbolSize=6,
                        symbolBrush=colours[method], name=method, data=tips)
    time_plot.setLogMode(x=False, y=True)
    knob_name = rows[0]["knob_name"] if rows else "knob"
    time_plot.setLabel("bottom", knob_name)
    time_plot.setLabel("left", "frame time (ms)")
    time_plot.setTitle("Time against quality, per scene")
    # one axis: rows measured against another knob (a method's own, or extra set-ups) would share it
    # meaninglessly, so they appear only on the left
    timed = [r for r in rows if r["knob_name"] == knob_name]
    symbols = "ostd+x"
    scenes = list(dict.fromkeys(r["scene"] for r in timed))
    for method in methods:
        named = False  # one legend entry per method; its scenes differ by symbol
        for si, sc in enumerate(scenes):
            pts = sorted((r["knob"], r["ms_median"], r["rmse"]) for r in timed
                         if r["method"] == method and r["scene"] == sc)
            if pts:
                knob, ms, _rmse = np.array(pts).T
                time_plot.plot(knob, ms, pen=pg.mkPen(colours[method], width=1.5), symbol=symbols[si % len(symbols)],
                               symbolSize=6, symbolBrush=colours[method], name=None if named else method,
                               data=[tip(method, sc, knob_name, *point) for point in pts])
                named = True
    for p in (error_plot, time_plot):
        p.legend.setVisible(bool(p.legend.items))  # an empty legend still draws its box
        p.legend.setColumnCount(2 if len(p.legend.items) > LEGEND_ROWS else 1)


def clear_chart(error_plot, time_plot) -> None:
    """Both plots empty: no curves, titles, axis labels or legend box."""
    for p in (error_plot, time_plot):
        p.clear()
        p.setTitle(None)
        for axis in ("left", "bottom"):
            p.setLabel(axis, "")
        if p.legend is not None:
            p.legend.setVisible(False)


def save_chart(path: str | os.PathLike, rows: list[dict], size: tuple[int, int] = (1400, 600)) -> None:
    """Render the chart off screen and write it as a PNG (needs a QApplication; see cli)."""
    import pyqtgraph as pg
    from pyqtgraph.exporters import ImageExporter

    pg.setConfigOptions(antialias=True, background="#14161c", foreground="#d0d4dc")
    from PySide6.QtCore import QRectF

    widget = pg.GraphicsLayoutWidget()
    widget.resize(*size)
    error_plot, time_plot = add_plots(widget.ci)
    plot(error_plot, time_plot, rows)
    widget.ci.setGeometry(QRectF(0, 0, *size))  # never shown on screen, so lay it out by hand
    exporter = ImageExporter(widget.ci)
    exporter.parameters()["width"] = size[0]
    tmp = Path(path).with_suffix(".tmp.png")
    exporter.export(str(tmp))
    os.replace(tmp, path)
