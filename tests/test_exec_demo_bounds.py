"""`shadelab exec` with demo times and speeds a host could not sleep until: refused, nothing crashes,
and a recording in progress is still saved."""
from test_exec_cli import shadelab_exec


def test_far_times_and_tiny_speeds_are_refused_and_the_recording_survives(tmp_path):
    (tmp_path / "far.demo").write_text("shadelab-demo 1\n0 snow.clear\n1e308 snow.level 1\n")
    (tmp_path / "one.demo").write_text("shadelab-demo 1\n0 snow.level 2\n0.5 snow.level 3\n")
    r = shadelab_exec(tmp_path, "-c", "record rec", "-c", "snow.level 5", "far.demo", "-c", "play one 1e-300",
                      "-c", "echo still here")
    assert r.returncode == 1
    assert "Traceback" not in r.stderr and "internal error" not in r.stderr
    assert "time 1e308 must be within 0..86400 s" in r.stderr
    assert "speed must be within 1/64..64, got 1e-300" in r.stderr
    assert "still here" in r.stdout and "recorded" in r.stdout
    assert "snow.level 5" in (tmp_path / "rec.demo").read_text()
