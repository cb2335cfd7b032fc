"""r_scalarMode, r_mipAttenuation and vol.iso through the console: a scan opens in mip and an RGBA volume in colour,
vol.iso sets the surface and shows it, bad values change nothing, the editor's render settings carry them, and a demo
keeps them."""
import numpy as np
from nibabel.testing import data_path

from app.console.demo import VirtualClock
from app.editor import Editor
from app.model.volume.phantom import ct_phantom
from app.model.volume.scalar_modes import SCALAR_MODES


def cvar(editor: Editor, name: str):
    return editor.console.registry.cvars[name].value


def load_scan(editor: Editor, tmp_path, name="scan.npy"):
    np.save(tmp_path / name, ct_phantom(16))
    assert editor.execute(f"load {tmp_path / name}")


def test_a_scan_opens_in_mip_and_an_rgba_volume_in_colour(volume_editor, tmp_path):
    assert cvar(volume_editor, "r_scalarMode") == "colour"
    load_scan(volume_editor, tmp_path)
    assert cvar(volume_editor, "r_scalarMode") == "mip"
    assert "drawn as mip" in volume_editor.console.log[-1].text
    assert volume_editor.render_settings().scalar_mode == "mip"
    assert volume_editor.execute("sample coords3d 16")
    assert cvar(volume_editor, "r_scalarMode") == "colour"


def test_an_8_bit_mri_opens_as_a_scan_in_mip(volume_editor):
    """nibabel's own 8-bit NIfTI (as MRI templates are written): a scan, windowed, in mip; not painted grey."""
    assert volume_editor.execute(f"load {data_path}/standard.nii.gz")
    assert volume_editor.current.volume.voxels.scalars is not None
    assert cvar(volume_editor, "r_scalarMode") == "mip"


def test_every_mode_is_taken_and_others_refused(volume_editor, tmp_path):
    load_scan(volume_editor, tmp_path)
    for mode in SCALAR_MODES:
        assert volume_editor.execute(f"r_scalarMode {mode}")
        assert volume_editor.render_settings().scalar_mode == mode
    assert not volume_editor.execute("r_scalarMode MIP")
    assert not volume_editor.execute("r_mipAttenuation -1")
    assert cvar(volume_editor, "r_scalarMode") == "translucent"
    assert volume_editor.execute("r_mipAttenuation 0.5")
    assert volume_editor.render_settings().mip_attenuation == 0.5


def test_vol_iso_sets_the_surface_in_data_units_and_shows_it(volume_editor, tmp_path):
    load_scan(volume_editor, tmp_path)
    low, high = (volume_editor.current.volume.voxels.scalars.transfer.low,
                 volume_editor.current.volume.voxels.scalars.transfer.high)
    assert volume_editor.render_settings().iso == (low + high) / 2  # unset: the window's middle
    assert volume_editor.execute("vol.iso")
    assert "the window's middle" in volume_editor.console.log[-1].text
    assert volume_editor.execute("vol.iso 300")
    assert cvar(volume_editor, "r_scalarMode") == "iso" and volume_editor.render_settings().iso == 300.0
    assert volume_editor.execute("vol.iso") and "iso 300 (set)" in volume_editor.console.log[-1].text
    digest = volume_editor.digest()
    assert not volume_editor.execute("vol.iso nan") and not volume_editor.execute("vol.iso 1 2")
    assert volume_editor.digest() == digest
    assert volume_editor.execute("vol.iso 1e6")
    assert "no value exceeds" in volume_editor.console.log[-1].text
    load_scan(volume_editor, tmp_path, "other.npy")  # another scan: its own window's middle again
    assert volume_editor.current.view.iso is None and cvar(volume_editor, "r_scalarMode") == "mip"


def test_a_scalar_mode_on_an_rgba_volume_says_the_f_modes_draw_it(volume_editor):
    assert volume_editor.execute("r_scalarMode mip")
    assert "no scalars" in volume_editor.console.log[-1].text
    assert volume_editor.execute("vol.iso 0.5") and "no scalars" in volume_editor.console.log[-1].text


def test_the_view_digest_without_an_iso_value_is_the_one_recorded_before_it(volume_editor, tmp_path):
    view = volume_editor.current.view
    assert len(view.key()) == 14  # the fields a digest took before vol.iso: old demos replay to their digests
    load_scan(volume_editor, tmp_path)
    assert volume_editor.execute("vol.iso 200")
    assert view.key()[-1] == 200.0


def test_a_demo_keeps_the_mode_and_the_iso_value(volume_editor, tmp_path):
    load_scan(volume_editor, tmp_path)
    assert volume_editor.execute("vol.iso 250; r_scalarMode translucent; r_mipAttenuation 0.2")
    assert volume_editor.execute("record scan")
    volume_editor.demos.clock.advance(0.5)
    assert volume_editor.execute("orbit 40 10")
    assert volume_editor.execute("stop")
    fresh = Editor(clock=VirtualClock())
    assert fresh.execute(f"timedemo {tmp_path / 'scan'}")
    assert fresh.digest() == volume_editor.digest()
    assert fresh.render_settings() == volume_editor.render_settings()
    assert fresh.render_settings().scalar_mode == "translucent" and fresh.render_settings().iso == 250.0
