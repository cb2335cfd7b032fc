"""The bench chart (app/bench/report.py decides what it shows, app/views/bench_chart.py draws it), as the PNG of
`shadelab bench` lays it out: the legend beside the plots and never over a point, methods by colour and scenes
by marker; each line joined in the order of its knob; no flat error axis when every error is float32 rounding;
log ticks as plain numbers; and where the rows were measured."""
import html
import math
import random

import pytest

from app.bench import report
from app.views.bench_chart import drawn_offscreen

pytestmark = pytest.mark.usefixtures("qapp")


def rows_of(methods=("gs", "cpu"), scenes=("1 flake", "16 flakes"), knobs=range(5), error=1e-3, where=None,
            knob_name="level"):
    """Bench rows as read_csv gives them: each method in each scene at each knob, slower and finer as it rises,
    the second scene four times slower."""
    rows = []
    for m, method in enumerate(methods):
        for s, scene in enumerate(scenes):
            for k in knobs:
                ms = (1 + m) * 4 ** s * 2 ** k
                rows.append({"technique": "t", "method": method, "knob_name": knob_name, "knob": float(k),
                             "scene": scene, "ms_median": float(ms), "rmse": error / (1 + k),
                             "max_abs_error": 2 * error / (1 + k), **({report.MEASURED_IN: where} if where else {})})
    return rows


def test_the_legend_is_beside_the_plots_and_names_the_methods_and_the_scene_markers():
    """Broken: the legend sat in the plot's corner over gs's points; the markers stood for scenes the legend
    never named."""
    _widget, drawing = drawn_offscreen(rows_of())
    assert drawing.legend_entries() == {"methods": ["cpu", "gs"], "scenes": ["1 flake", "16 flakes"]}
    shown = drawing.shown
    assert shown.markers == {"1 flake": "o", "16 flakes": "s"}
    # each scene's lines carry its marker, each method's its colour, in both plots
    for item, line in drawing.lines.items():
        assert item.opts["symbol"] == shown.markers[line.scene]
        assert item.opts["symbolBrush"] == shown.colours[line.method]
    # the scene samples are markers alone (no line), the method samples lines alone (no marker)
    assert all(s.opts["symbol"] is None and s.opts["pen"] is not None for s in drawing.method_samples.values())
    assert [s.opts["symbol"] for s in drawing.scene_samples.values()] == ["o", "s"]
    legend = drawing.legend.sceneBoundingRect()
    assert legend.width() > 0 and legend.height() > 0
    for plot in drawing.plots():
        assert not legend.intersects(plot.vb.sceneBoundingRect()), drawing.titles[plot].text


def test_clicking_a_legend_entry_hides_its_methods_or_its_scenes_lines():
    _widget, drawing = drawn_offscreen(rows_of())
    gs = drawing.method_samples["gs"]
    gs.setVisible(False)  # what clicking its sample does
    drawing._sample_clicked(gs)
    assert {line.method for item, line in drawing.lines.items() if item.isVisible()} == {"cpu"}
    gs.setVisible(True)
    drawing.scene_samples["16 flakes"].setVisible(False)
    drawing._sample_clicked(drawing.scene_samples["16 flakes"])
    assert {(line.method, line.scene) for item, line in drawing.lines.items() if item.isVisible()} == {
        ("gs", "1 flake"), ("cpu", "1 flake")}


def test_each_line_is_joined_in_the_order_of_its_knob_whatever_order_the_rows_came_in():
    """Broken (as it read): lines zig-zagged. A method's points join in knob order, each scene and knob on its
    own line, so that a line is that method's curve as its knob moves."""
    rows = rows_of(knobs=(0.25, 0.5, 1.0, 2.0))
    rows += [{**r, "knob_name": "samples", "knob": r["knob"] * 64} for r in rows if r["method"] == "gs"]
    random.Random(3).shuffle(rows)
    _widget, drawing = drawn_offscreen(rows)
    for item, line in drawing.lines.items():
        assert list(line.knob) == sorted(line.knob)
        assert [tip.splitlines()[2] for tip in line.tips] == [f"{line.knob_name} = {k:g}" for k in line.knob]
        ms = {r["knob"]: r["ms_median"] for r in rows if (r["method"], r["scene"], r["knob_name"])
              == (line.method, line.scene, line.knob_name)}
        assert list(line.ms) == [ms[k] for k in line.knob]
    error_lines = [line for item, line in drawing.lines.items() if item in drawing.error_plot.listDataItems()]
    # the error plot: the first scene, one line per method and knob (gs under both of its knobs)
    assert sorted((line.method, line.knob_name) for line in error_lines) == [
        ("cpu", "level"), ("gs", "level"), ("gs", "samples")]
    assert {line.scene for line in error_lines} == {rows[0]["scene"]}
    # the time plot: the first row's knob, ticks at its settings
    time_items = drawing.time_plot.listDataItems()
    assert {drawing.lines[i].knob_name for i in time_items} == {rows[0]["knob_name"]}
    for item in time_items:
        assert list(item.xData) == sorted(item.xData)


@pytest.mark.parametrize("where, note", [("cli", "from the CLI"), ("editor", "measured in the editor, view paused"),
                                         (None, None)])
def test_exact_to_float32_draws_time_alone_and_says_so(where, note):
    """Broken: the snowflake's errors (every one float32 rounding, 9e-9..6.6e-8) drew a flat error axis."""
    rows = rows_of(error=6.6e-8, where=where)
    widget, drawing = drawn_offscreen(rows)
    shown = drawing.shown
    assert shown.exact and not shown.error_lines
    assert drawing.plots() == [drawing.time_plot]
    assert not drawing.error_plot.isVisible()  # not laid out at all
    label = f"exact to float32 (error < {report.number_text(report.EXACT_ERROR)}): time only"
    assert label == "exact to float32 (error < 10⁻⁶): time only"
    assert shown.notes == [label, *([note] if note else [])]
    assert drawing.note.text == "<br>".join(html.escape(n) for n in shown.notes)  # '<' shown, not markup
    assert drawing.titles[drawing.time_plot].text == "Frame time against level, per scene"
    assert drawing.time_plot.vb.sceneBoundingRect().width() > widget.width() * 0.7  # it takes the room
    # one error at EXACT_ERROR (RMSE or max) is a method's error: the error plot is back
    rows[5]["max_abs_error"] = report.EXACT_ERROR
    assert not report.chart(rows).exact
    rows[5]["max_abs_error"] = math.nan
    assert not report.chart(rows).exact


def test_the_note_says_where_the_rows_were_measured_beside_the_errors():
    _widget, drawing = drawn_offscreen(rows_of(where="editor"))
    assert not drawing.shown.exact and drawing.plots() == [drawing.error_plot, drawing.time_plot]
    assert drawing.note.text == "measured in the editor, view paused"
    assert report.where_measured(rows_of(where="cli") + rows_of(where="editor")) == (
        "from the CLI and measured in the editor, view paused")


def test_clearing_leaves_no_line_title_note_or_legend():
    widget, drawing = drawn_offscreen(rows_of(where="cli"))
    drawing.clear()
    assert not any(plot.listDataItems() for plot in (drawing.error_plot, drawing.time_plot))
    assert not drawing.legend.isVisible() and not drawing.note.isVisible() and not drawing.lines
    assert drawing.legend_entries() == {"methods": [], "scenes": []}
    assert not drawing.titles[drawing.time_plot].isVisible() and drawing.time_plot.getAxis("left").labelText == ""


def test_log_ticks_read_as_plain_numbers_and_powers_of_ten_only_far_out():
    """Broken: 20 ms read '2·10¹'."""
    cases = {20: "20", 50: "50", 100: "100", 0.001: "0.001", 0.5: "0.5", 1500: "1500", 0.0001: "0.0001",
             1e-8: "10⁻⁸", 2e-8: "2·10⁻⁸", 6.6e-8: "6.6·10⁻⁸", 3e6: "3·10⁶"}
    assert {v: report.number_text(v) for v in cases} == cases
    _widget, drawing = drawn_offscreen(rows_of(knobs=range(3), error=2e-3))
    axis = drawing.time_plot.getAxis("left")
    assert axis.logTickStrings([math.log10(v) for v in (20, 50, 100)], 1, None) == ["20", "50", "100"]
    error_axis = drawing.error_plot.getAxis("left")
    assert error_axis.logTickStrings([-3, math.log10(2e-8)], 1, None) == ["0.001", "2·10⁻⁸"]
    # the time plot's ticks as drawn: 1..64 ms, plain, and its knob's ticks at the levels measured
    drawn = drawn_texts(drawing.time_plot, "left")
    assert {"1", "10"} <= set(drawn) and not any("·" in t or "⁰" in t or "¹" in t for t in drawn), drawn
    assert drawn_texts(drawing.time_plot, "bottom") == ["0", "1", "2"]


def test_a_crowded_log_axis_labels_one_two_five_before_the_rest():
    """Three decades on a short axis: pyqtgraph labelled the powers of ten alone (1, 10, 100)."""
    rows = rows_of(knobs=range(11), scenes=("a",))
    widget, drawing = drawn_offscreen(rows, size=(700, 300))
    values = {float(t) for t in drawn_texts(drawing.time_plot, "left")}
    assert {2.0, 5.0, 20.0, 50.0} <= values, values


def drawn_texts(plot, side: str) -> list[str]:
    from tests.test_bench_dock import drawn_labels

    return [text for _rect, text in drawn_labels(plot, side)]
