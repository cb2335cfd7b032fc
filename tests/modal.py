"""Looking at the editor while a modal dialog's own event loop runs."""
from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QApplication


def while_modal(qtbot, open_it, kind, inspect):
    """Call `open_it()`, which opens a modal dialog of type `kind` and returns once it closes; `inspect(dialog)`
    runs while it is open, then the dialog is cancelled. Returns what inspect returned."""
    seen = []

    def look():
        dialog = QApplication.activeModalWidget()
        if not isinstance(dialog, kind):
            QTimer.singleShot(20, look)
            return
        try:
            qtbot.waitExposed(dialog)
            seen.append(inspect(dialog))
        finally:  # a failed look must not leave the dialog's event loop running
            dialog.reject()
    QTimer.singleShot(0, look)
    open_it()
    assert seen, f"no {kind.__name__} opened"
    return seen[0]
