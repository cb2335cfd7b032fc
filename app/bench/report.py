"""Bench results as CSV, and what their chart shows: error against time, and time against the knob, one line
per method (and scene), in the order of its knob. app/views/bench_chart.py draws it, in a PNG and in the dock;
everything that chart says is decided here, without Qt."""
from __future__ import annotations

import csv
import io
import math
import os
from collections import defaultdict
from dataclasses import dataclass, field

import numpy as np

from app.bench.harness import CSV_COLUMNS, Row
from app.io.atomic import write_text
from app.io.regular_file import read_regular_bytes

ERROR_FLOOR = 1e-9  # zero error still needs a place on a log axis
# Every error on a 0..1 scale (each technique's value range) below this is float32 rounding, not a method's error:
# float32 steps by 1.2e-7 just below 1, so this is about 8 of its steps. A chart whose every error is below it
# draws no error axis (it would be flat noise) but time alone, and says why.
EXACT_ERROR = 1e-6
MAX_CSV_BYTES = 16 << 20  # a full bench writes a few hundred rows: some 100 KiB
_NUMBERS = ("knob", "ms_median", "gpu_ms_median", "rmse", "max_abs_error")
_FINITE = ("knob", "ms_median")
PALETTE = ("#4cc9f0", "#f72585", "#ffd166", "#06d6a0", "#b388ff", "#ff9f1c", "#8ecae6", "#ef476f",
           "#90be6d", "#f8961e", "#c77dff", "#e9ecef")
MARKERS = ("o", "s", "t", "d", "p", "h", "star", "t1", "+", "x")  # pyqtgraph's symbols, one a scene
# The CSV column that says where the rows were measured, and what the chart says of each value.
MEASURED_IN = "measured_in"
WHERE = {"cli": "from the CLI", "editor": "measured in the editor, view paused"}
PLAIN_RANGE = (1e-4, 1e6)  # numbers written out in full within it (0.001, 20, 1500), else as a power of ten
SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


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


def number_text(value: float, digits: int = 3) -> str:
    """A number as a person reads it: 20, 0.001, 1500; a power of ten only when very small or large (2·10⁻⁸,
    10⁻⁸), to `digits` significant digits."""
    if value == 0 or not math.isfinite(value):
        return f"{value:g}"
    if PLAIN_RANGE[0] <= abs(value) < PLAIN_RANGE[1]:
        return np.format_float_positional(value, precision=digits, fractional=False, trim="-")
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    mantissa = mantissa.rstrip("0").rstrip(".")
    power = "10" + str(int(exponent)).translate(SUPERSCRIPT)
    return power if mantissa == "1" else f"{mantissa}·{power}"


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


def tip(method: str, scene: str, knob_name: str, knob: float, ms: float, rmse: float) -> str:
    """What hovering a point of the chart says about it."""
    return f"{method}\n{scene}\n{knob_name} = {knob:g}\n{ms:.3g} ms/frame, RMSE {rmse:.3g}"


@dataclass
class Line:
    """One method's points in one scene under one knob, joined in the order of the knob's value: the curve of
    that method as its knob moves, whatever order they were run in. Each point has its tip()."""

    method: str
    scene: str
    knob_name: str
    knob: np.ndarray
    ms: np.ndarray
    error: np.ndarray  # RMSE, at least ERROR_FLOOR
    tips: list[str]


@dataclass
class Chart:
    """What the bench chart shows. `error_lines`: RMSE against time in the first scene; none when every error is
    exact to float32. `time_lines`: time against the first row's knob in every scene (rows measured against
    another knob would share that axis meaninglessly: they are in the error panel only). The legend names the
    methods by colour and the scenes by marker; `notes` say what the chart leaves out and where it was measured."""

    scene: str = ""
    knob_name: str = "knob"
    error_lines: list[Line] = field(default_factory=list)
    time_lines: list[Line] = field(default_factory=list)
    colours: dict[str, str] = field(default_factory=dict)  # method -> colour, in the legend's order
    markers: dict[str, str] = field(default_factory=dict)  # scene -> marker, in the legend's order
    exact: bool = False
    notes: list[str] = field(default_factory=list)

    @property
    def error_title(self) -> str:
        return f"Speed vs accuracy — {self.scene}"

    @property
    def time_title(self) -> str:
        return f"Frame time against {self.knob_name}, per scene" if self.exact else "Time against quality, per scene"


def lines(rows: list[dict]) -> list[Line]:
    """The rows' lines: one per method, scene and knob, each sorted by the knob's value."""
    grouped: dict[tuple[str, str, str], list[tuple[float, float, float]]] = defaultdict(list)
    for r in rows:
        grouped[(r["method"], r["scene"], r["knob_name"])].append((r["knob"], r["ms_median"], r["rmse"]))
    result = []
    for (method, scene, knob_name), points in grouped.items():
        points.sort()
        knob, ms, rmse = (np.array(column, dtype=float) for column in zip(*points))
        result.append(Line(method, scene, knob_name, knob, ms, np.maximum(rmse, ERROR_FLOOR),
                           [tip(method, scene, knob_name, *point) for point in points]))
    return result


def exact_to_float32(rows: list[dict]) -> bool:
    """Every error of the rows (RMSE and max) below EXACT_ERROR; an error that is not a number is not exact."""
    return bool(rows) and all(r["rmse"] < EXACT_ERROR and r["max_abs_error"] < EXACT_ERROR for r in rows)


def where_measured(rows: list[dict]) -> str:
    """What the rows' measured_in column says, as the chart's note ('' for a CSV from before the column)."""
    places = list(dict.fromkeys(r.get(MEASURED_IN) or "" for r in rows))
    return " and ".join(WHERE[p] for p in places if p in WHERE)


def chart(rows: list[dict]) -> Chart:
    if not rows:
        return Chart()
    scene, knob_name = rows[0]["scene"], rows[0]["knob_name"]
    exact = exact_to_float32(rows)
    error_lines = [] if exact else sorted(lines([r for r in rows if r["scene"] == scene]),
                                          key=lambda line: line.method)
    time_lines = lines([r for r in rows if r["knob_name"] == knob_name])
    methods = sorted({r["method"] for r in rows})  # colours stay with a method whatever the rows drawn
    colours = {m: PALETTE[i % len(PALETTE)] for i, m in enumerate(methods)}
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    markers = {s: MARKERS[i % len(MARKERS)] for i, s in enumerate(scenes)}
    drawn = error_lines + time_lines
    notes = [f"exact to float32 (error < {number_text(EXACT_ERROR)}): time only"] if exact else []
    notes += [where] if (where := where_measured(rows)) else []
    return Chart(scene, knob_name, error_lines, time_lines,
                 {m: c for m, c in colours.items() if any(line.method == m for line in drawn)},
                 {s: k for s, k in markers.items() if any(line.scene == s for line in drawn)}, exact, notes)
