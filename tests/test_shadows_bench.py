"""The shadows bench (app/bench/shadows.py) on a tiny plan: its rows and the columns other tools read, the
volume methods' fill cost against their casters, the scene's size knob, and `shadelab bench shadows`. No
timing is checked, only that the work is done and measured."""
import pytest

from app.bench import TECHNIQUES, WORKSPACE_TECHNIQUE, harness, report, shadows
from app.gl.core.depth_bounds import EXTENSION

TINY = shadows.Plan(size=(64, 48), triangles=(2530,), map_sizes=(256,), biases=(0.0,), cascades=(2,), runs=1)


def test_registered_for_the_lights3d_workspace():
    assert TECHNIQUES["shadows"] is shadows.technique
    assert WORKSPACE_TECHNIQUE["lights3d"] == "shadows"


@pytest.mark.parametrize("triangles", [2530, 10_000, 100_000])
def test_the_scene_grows_to_about_the_triangles_asked(triangles):
    scene = shadows.scene_of(triangles)
    assert triangles <= scene.triangles <= 1.1 * triangles
    assert [o.kind for o in scene.objects] == ["plane", "box", "sphere", "torus", "lprism"]


def test_rows_measure_mismatch_and_fill_cost(gl, tmp_path):
    rows = harness.run(gl, shadows.technique(plan=TINY), quick=True, runs=1)
    by_method = {r.method: r for r in rows}
    assert set(by_method) == {"onepass", "onepass-seed", "zpass", "zfail", "map", "map pcf1", "map pcf3",
                              "map pcf5", "map bias", "map cascades"}
    for row in rows:
        assert 0 <= row.extra["mismatch_off_edge_pct"] <= row.extra["mismatch_pct"] < 5
        assert row.ms_median > 0 and row.extra["still_ms"] > 0 and (row.width, row.height) == TINY.size
        assert row.extra["depth_bounds"] == int(EXTENSION in gl.extensions)
    onepass, seed, zpass, zfail = (by_method[m].extra for m in ("onepass", "onepass-seed", "zpass", "zfail"))
    casters = onepass["caster_triangles"]
    assert seed["volume_triangles"] == 7 * casters  # seed 002: 7 per caster triangle
    # and a far cap, of about half of them: those turned from the light
    assert onepass["volume_triangles"] % 8 == 0 and onepass["volume_triangles"] < 0.7 * seed["volume_triangles"]
    assert zpass["volume_triangles"] == 2 * zpass["extruded_edges"]  # the silhouettes' quads
    assert zfail["volume_triangles"] == 2 * zfail["extruded_edges"] + casters  # and both caps
    assert zfail["mismatch_off_edge_pct"] == 0.0  # what differs lies on the reference's shadow edges
    # the fill: a fragment or more per volume triangle, the seed's quads to infinity the most per triangle
    for row in (onepass, seed, zpass, zfail):
        assert row["fill_px"] > row["volume_triangles"]
    assert seed["fill_px"] / seed["volume_triangles"] > zfail["fill_px"] / zfail["volume_triangles"]
    assert seed["fill_px"] > onepass["fill_px"] > 10 * zfail["fill_px"] and by_method["map"].extra["fill_px"] == 0
    assert by_method["map bias"].extra["bias"] == 0.0 and by_method["map pcf5"].extra["pcf"] == 5
    assert by_method["map cascades"].extra["cascades"] == 2 and "texels_px" not in zfail
    for row in rows:  # a map gives each pixel a footprint of texels (at 64 x 48, many); the stencil has none
        assert row.method not in ("onepass", "zpass", "zfail") or "texels_px" not in row.extra
        assert not row.method.startswith("map") or row.extra["texels_px"] > 1
    sun = shadows.scene_of(2530, sun=True)
    assert len(sun.lights) == 3 and by_method["map cascades"].extra["caster_triangles"] > onepass["caster_triangles"]
    report.write_csv(tmp_path / "shadows.csv", rows)
    header = (tmp_path / "shadows.csv").read_text().splitlines()[0].split(",")
    assert {"mismatch_pct", "mismatch_off_edge_pct", "volume_triangles", "fill_px", "draw_ms"} <= set(header)


def test_cli_bench_writes_the_csv_and_the_chart(tmp_path, monkeypatch, qapp):
    from app import cli

    monkeypatch.setitem(TECHNIQUES, "shadows", lambda quick=False: shadows.technique(plan=TINY))
    assert cli.main(["bench", "shadows", "--quick", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "shadows.csv").is_file() and (tmp_path / "shadows.png").is_file()
