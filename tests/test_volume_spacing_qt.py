"""The editor's window with scans: the painter draws voxels in their physical aspect (and paints where it draws
them), File > Open Folder opens a DICOM series, and Save asks where for a file Shadelab only reads."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt
from pydicom.data import get_testdata_file

from dialogs import answer, said
from painter_canvas import open_painter

SERIES = Path(get_testdata_file("CT_small.dcm", download=False)).parent / "dicomdirtests" / "98892001" / "CT5N"


def volume(editor):
    return editor.workspaces["volume"].volume


def test_the_painter_shows_thick_slices_tall_and_paints_where_it_shows(window, qtbot):
    canvas = open_painter(window, qtbot, ("workspace volume", "new 16 12 6", "vol.spacing 0.5 0.5 2", "slice y 5",
                                          "brush.color 255 0 0 255", "brush_size 1"))
    cu, cv = canvas.cell()
    assert cv == pytest.approx(4 * cu)  # a side view: voxels 0.5 mm wide, 2 mm tall
    centre = QPoint(int(canvas.offset.x() + 3.5 * cu), int(canvas.offset.y() + 4.5 * cv))
    qtbot.mouseClick(canvas, Qt.MouseButton.LeftButton, pos=centre)
    z, y, x = np.nonzero(volume(window.editor).voxels.data[..., 3])
    assert list(zip(x.tolist(), y.tolist(), z.tolist())) == [(3, 5, 4)]
    image = canvas.grab().toImage()
    assert image.pixelColor(centre).red() > 200  # the painted voxel is drawn where it was clicked
    assert window.run("vol.spacing 1 1 1")
    qtbot.waitUntil(lambda: canvas.zoom > 0)
    cu, cv = canvas.cell()
    assert cv == cu


def test_file_open_folder_opens_a_dicom_series_and_save_asks_where(window, qtbot, tmp_path):
    shutil.copytree(SERIES, tmp_path / "ct")
    seen = answer(tmp_path / "ct")
    assert window.run("ui.openfolder")
    assert window.editor.workspaces.name == "volume"
    assert volume(window.editor).voxels.size == (16, 16, 5)
    assert volume(window.editor).voxels.spacing == (0.488281, 0.488281, 2.5)
    assert window.editor.documents.path(window.editor.current) == str(tmp_path / "ct")
    assert window.editor.documents.save_path(window.editor.current) is None  # a folder of DICOM is read, not written
    seen = answer(None)
    window.run("ui.save")
    assert said(seen)  # Save As asked where
