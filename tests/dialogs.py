"""Answering a window's modal dialogs as a person would: once a dialog is up (Qt's own, under Xvfb), a timer
reads it and presses a button or picks a file. Answers are given in the order the dialogs come."""
from __future__ import annotations

import time

from PySide6.QtCore import QTimer
from PySide6.QtWidgets import QApplication, QFileDialog, QMessageBox

POLL_MS = 20
GIVE_UP_S = 30  # a dialog that never came: stop, rather than answer one of a later test


def answer(*answers) -> list:
    """Answer the next modal dialogs in turn: a QMessageBox.StandardButton presses that button, a path picks
    that file in a file dialog, None cancels it. Returns what each dialog said (`said`): a message box's text and
    informative text, a file dialog's name filters; and what else it showed (`showed`): a message box's buttons,
    a file dialog's folder."""
    seen: list = []
    pending = list(answers)
    deadline = time.monotonic() + GIVE_UP_S

    def poll() -> None:
        dialog = QApplication.activeModalWidget()
        if dialog is None or (seen and dialog is seen[-1][0]):  # not up yet, or the last one still closing
            if time.monotonic() < deadline:
                QTimer.singleShot(POLL_MS, poll)
            return
        reply = pending.pop(0)
        if isinstance(dialog, QMessageBox):
            seen.append((dialog, f"{dialog.text()}\n{dialog.informativeText()}", [b.text() for b in dialog.buttons()]))
            dialog.button(reply).click()
        elif isinstance(dialog, QFileDialog):
            seen.append((dialog, dialog.nameFilters(), dialog.directory().absolutePath()))
            if reply is None:
                dialog.reject()
            else:
                dialog.selectFile(str(reply))
                dialog.accept()
        else:
            raise AssertionError(f"an unexpected dialog: {dialog!r}")
        if pending:
            QTimer.singleShot(POLL_MS, poll)

    QTimer.singleShot(0, poll)
    return seen


def said(seen: list) -> list:
    """What the answered dialogs said, in order."""
    return [what for _dialog, what, _showed in seen]


def showed(seen: list) -> list:
    """What else the answered dialogs showed, in order: a message box's button texts, a file dialog's folder."""
    return [more for _dialog, _what, more in seen]


class NoDialogs:
    """While inside, any modal dialog that comes up is cancelled at once and kept in `came` (the window title and
    text of each): a test asserts none came, without waiting forever on one."""

    def __init__(self) -> None:
        self.came: list[str] = []
        self._timer = QTimer(interval=POLL_MS, timeout=self._poll)

    def __enter__(self) -> "NoDialogs":
        self._timer.start()
        return self

    def __exit__(self, *exc) -> None:
        self._timer.stop()

    def _poll(self) -> None:
        dialog = QApplication.activeModalWidget()
        if dialog is not None and dialog.isVisible():
            text = dialog.text() if isinstance(dialog, QMessageBox) else ""
            self.came.append(f"{dialog.windowTitle()}: {text}")
            dialog.reject()
