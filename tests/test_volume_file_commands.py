"""`load` through the console: special files, impossible patterns, mixed series and volumes over the model's
limit are refused with a clear message, and neither the volume nor its history changes."""
import os

import numpy as np
import pytest
from PIL import Image

from app.io.volume_formats import write_volume
from app.model.volume import voxels as voxels_model


@pytest.fixture
def editor(volume_editor):
    return volume_editor


def fifo(tmp_path) -> str:
    os.mkfifo(tmp_path / "pipe.r3")
    return "pipe.r3"


def device(tmp_path) -> str:
    (tmp_path / "zero.npy").symlink_to("/dev/zero")
    return "zero.npy"


def wide_pattern(tmp_path) -> str:
    return "s_%0500000000i.png"


def mixed_series(tmp_path) -> str:
    write_volume(tmp_path / "s_%i.png", np.zeros((3, 2, 2, 4), np.uint8))
    Image.new("RGBA", (2, 2), (1, 2, 3, 4)).save(tmp_path / "s_1.png")  # as if another save stopped after slice 1
    return "s_%i.png"


def big_file(tmp_path) -> str:
    write_volume(tmp_path / "big.r3", np.zeros((16, 16, 16, 4), np.uint8))
    return "big.r3"


@pytest.mark.parametrize("make, needle", [
    (fifo, "is a FIFO (named pipe), not a regular file"),
    (device, "is a device"),
    (wide_pattern, "padded to 9 digits at most"),
    (mixed_series, "not the ones saved together"),
    (big_file, "over the size limit of 4096 bytes"),
])
def test_a_refused_load_changes_nothing(editor, tmp_path, monkeypatch, make, needle):
    monkeypatch.setattr(voxels_model, "MAX_BYTES", 4096)  # the model's limit is the reader's: refused before reading
    volume = editor.workspaces["volume"].volume
    before = (volume.voxels.digest(), volume.history.undo_depth)
    assert not editor.execute(f"load {make(tmp_path)}")
    assert needle in [line.text for line in editor.console.log if line.level == "error"][-1]
    assert (volume.voxels.digest(), volume.history.undo_depth) == before
