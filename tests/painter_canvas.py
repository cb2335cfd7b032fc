"""The volume workspace's slice painter in a real window: opened after some console lines, and where a voxel's
centre lies on it (the painter tests share these)."""
from PySide6.QtCore import QPoint


def open_painter(window, qtbot, lines, refresh: bool = False):
    """The painter's canvas once `lines` ran (each must succeed) and it has drawn (its zoom known)."""
    for line in lines:
        assert window.run(line), line
    if refresh:
        window.refresh()
    canvas = window.workspace_panels["volume"].canvas
    canvas.update()
    qtbot.waitUntil(lambda: canvas.zoom > 0)
    return canvas


def at(canvas, u, v):
    """The widget point over slice voxel (u, v)'s centre."""
    return QPoint(int(canvas.offset.x() + (u + 0.5) * canvas.zoom), int(canvas.offset.y() + (v + 0.5) * canvas.zoom))
