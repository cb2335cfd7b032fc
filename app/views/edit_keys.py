"""Edit > Undo and Redo's keys while a text field has the focus (the console's command line, a panel's spin box).
Qt's fields take Ctrl+Z and Ctrl+Shift+Z for their own typing even with nothing to undo, so the editor's Undo
did nothing there; a field keeps the keys only while it has typing of its own to undo or redo, and an empty one
(the command line once its line ran) gives Undo to the editor."""
from __future__ import annotations

from PySide6.QtCore import QEvent, QObject
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QAbstractSpinBox, QLineEdit


class EditKeys(QObject):
    """Watches every line edit and spin box in `window` (they are all built before the menus)."""

    def __init__(self, window, undo: QAction, redo: QAction) -> None:
        super().__init__(window)
        self.undo, self.redo = undo, redo
        for field in (*window.findChildren(QLineEdit), *window.findChildren(QAbstractSpinBox)):
            field.installEventFilter(self)

    def eventFilter(self, watched: QObject, event: QEvent) -> bool:
        if event.type() != QEvent.Type.ShortcutOverride:
            return False
        keys = QKeySequence(event.keyCombination())
        field = watched.lineEdit() if isinstance(watched, QAbstractSpinBox) else watched
        if keys in self.undo.shortcuts():
            to_editor = not field.text() or not field.isUndoAvailable()
        elif keys in self.redo.shortcuts():
            to_editor = not field.isRedoAvailable()
        else:
            return False
        if to_editor:
            event.ignore()  # not overridden: the window's shortcut, Edit > Undo or Redo, takes the keys
        return to_editor
