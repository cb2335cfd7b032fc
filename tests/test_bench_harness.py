"""The bench harness on a tiny technique whose errors are known exactly."""
import numpy as np
import pytest

from app.bench import harness, report
from app.bench.harness import Method, Technique

SPREAD = {"ms_min", "ms_max", "gpu_ms_min", "gpu_ms_max"}  # the columns beside the medians


def flat_grey(ctx):
    return None


def render_grey(_state, target, value, _scene):
    target.fbo.use()
    target.fbo.clear(value, value, value, 1.0)


def output_grey(_state, target, _value, _scene):
    return target.read()[..., :3] / 255.0


def grey_reference(_scene, _value, size):
    return np.full((size[1], size[0], 3), 0.5)


def tiny():
    return Technique("grey", [Method("clear", "level", (0.5, 0.25), flat_grey, render_grey, output_grey)],
                     {"empty": None}, grey_reference, size=(32, 16), quick_size=(16, 8))


def test_errors_against_reference(gl):
    rows = harness.run(gl, tiny(), quick=True, runs=2)
    assert [(r.knob, r.width, r.height, r.runs) for r in rows] == [(0.5, 16, 8, 2), (0.25, 16, 8, 2)]
    exact, off = rows
    assert exact.max_abs_error <= 1 / 255  # 0.5 stores as 127 or 128
    assert off.max_abs_error == pytest.approx(abs(64 / 255 - 0.5), abs=1 / 255)
    assert off.rmse == pytest.approx(off.max_abs_error)  # a uniform error
    assert all(r.ms_median > 0 and r.gpu_ms_median >= 0 for r in rows)
    assert all(SPREAD <= r.extra.keys() for r in rows)  # the spread beside it (test_timing_spread: its values)


def test_timing_spread_and_medians_are_those_of_the_recorded_frames():
    timing = harness.Timing(wall=[3.0, 1.0, 2.0], gpu=[0.5, 0.25, 1.0])
    assert timing.medians() == (2.0, 0.5)
    assert timing.spread() == {"ms_min": 1.0, "ms_max": 3.0, "gpu_ms_min": 0.25, "gpu_ms_max": 1.0}
    assert timing.summary().split() == ["2.00", "(1.00..3.00)", "ms"]


def test_shape_mismatch_is_an_error():
    with pytest.raises(ValueError, match="differs"):
        harness.errors(np.zeros((2, 2)), np.zeros((2, 3)))


def test_csv_round_trip_and_curves(gl, tmp_path):
    rows = harness.run(gl, tiny(), quick=True, runs=1)
    report.write_csv(tmp_path / "grey.csv", rows)
    back = report.read_csv(tmp_path / "grey.csv")
    assert [r["knob"] for r in back] == [0.5, 0.25]
    [line] = report.lines(back)
    assert line.method == "clear" and list(line.knob) == [0.25, 0.5] and line.error[1] >= report.ERROR_FLOOR


def test_read_csv_refuses_other_files(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="not a bench CSV"):
        report.read_csv(path)


def test_chart_right_panel_keeps_to_the_first_knob_and_the_legend_names_each_method_once():
    def row(method, knob_name, knob, scene, ms):
        return {"method": method, "knob_name": knob_name, "knob": knob, "scene": scene, "ms_median": ms,
                "rmse": 0.01 / ms, "max_abs_error": 0.02}

    rows = [row(m, "lightmap_scale", k, s, k * 4 + i) for i, m in enumerate(("exact", "hard"))
            for k in (0.5, 1.0) for s in ("a", "b")]
    rows += [row("jitter", "samples", n, "a", n) for n in (4, 16)]  # another knob: left panel only
    shown = report.chart(rows)
    assert sorted((line.method, line.knob_name) for line in shown.error_lines) == [
        ("exact", "lightmap_scale"), ("hard", "lightmap_scale"), ("jitter", "samples")]  # scene a only
    assert sorted((line.method, line.scene) for line in shown.time_lines) == [
        ("exact", "a"), ("exact", "b"), ("hard", "a"), ("hard", "b")]
    assert list(shown.colours) == ["exact", "hard", "jitter"] and list(shown.markers) == ["a", "b"]
    assert not shown.exact and shown.notes == []  # no measured_in column: nothing said of where


def test_a_method_may_draw_at_its_own_size(gl):
    seen = []

    def reference(_scene, _value, size):
        seen.append(size)
        return np.full((size[1], size[0], 3), 0.5)

    own = Method("own", "level", (0.5,), flat_grey, render_grey, output_grey, size=(24, 12), quick_size=(12, 6),
                 reference=reference)
    tech = tiny()
    tech.methods.append(own)
    rows = harness.run(gl, tech, quick=True, runs=1)
    assert [(r.method, r.width, r.height) for r in rows] == [("clear", 16, 8), ("clear", 16, 8), ("own", 12, 6)]
    assert seen == [(12, 6)] and rows[-1].max_abs_error <= 1 / 255
    full = harness.run(gl, tech, runs=1)
    assert [(r.width, r.height) for r in full] == [(32, 16), (32, 16), (24, 12)]


def test_interleaved_timing_draws_each_in_turn(gl):
    order = []
    draws = {name: (lambda name=name: order.append(name)) for name in ("a", "b")}
    timed = harness.time_interleaved(gl, draws, 3)
    assert order == ["a", "b"] * 4  # one warm-up round, then three timed
    assert set(timed) == {"a", "b"} and all(wall >= 0 and gpu >= 0 for wall, gpu in timed.values())


def test_interleaved_methods_take_turns_and_keep_their_own_rows(gl):
    order = []

    def logged(name):
        def render(state, target, value, scene):
            order.append((name, value))
            render_grey(state, target, value, scene)
        return render

    methods = [Method(name, "level", (0.5, 0.25), flat_grey, logged(name), output_grey) for name in ("a", "b")]
    tech = Technique("grey", methods, {"empty": None}, grey_reference, size=(32, 16), quick_size=(16, 8),
                     interleave=True)
    rows = harness.run(gl, tech, quick=True, runs=2)
    turn = [("a", 0.5), ("a", 0.25), ("b", 0.5), ("b", 0.25)]
    assert order == turn * 3 + turn  # a warm-up round, two timed, then each drawn again for its row
    assert [(r.method, r.knob, r.runs) for r in rows] == [(m, v, 2) for m, v in turn]
    # each row measures its own setting's frame, though another method's was the last one timed
    assert rows[0].max_abs_error <= 1 / 255 and rows[2].max_abs_error <= 1 / 255
    assert rows[1].max_abs_error == pytest.approx(abs(64 / 255 - 0.5), abs=1 / 255)
    assert all(SPREAD <= r.extra.keys() for r in rows)
