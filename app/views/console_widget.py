"""The console dock: the log above, a command line below; Enter runs, Up/Down walk the history."""
from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtGui import QColor, QFont, QTextCharFormat
from PySide6.QtWidgets import QLineEdit, QPlainTextEdit, QVBoxLayout, QWidget

from app.console.console import Console, LogLine

COLOURS = {"input": "#8ecae6", "info": "#d0d4dc", "error": "#ff6b6b"}


class CommandLine(QLineEdit):
    def __init__(self, console: Console, parent=None) -> None:
        super().__init__(parent)
        self.console = console
        self.history: list[str] = []
        self._index = 0
        self.setPlaceholderText("command (help lists them)")
        self.returnPressed.connect(self._run)

    def _run(self) -> None:
        line = self.text().strip()
        self.clear()
        if not line:
            return
        if not self.history or self.history[-1] != line:
            self.history.append(line)
        self._index = len(self.history)
        self.console.execute(line)

    def keyPressEvent(self, event) -> None:
        step = {Qt.Key.Key_Up: -1, Qt.Key.Key_Down: 1}.get(event.key())
        if step is None or not self.history:
            super().keyPressEvent(event)
            return
        self._index = max(0, min(len(self.history), self._index + step))
        self.setText(self.history[self._index] if self._index < len(self.history) else "")


class ConsoleWidget(QWidget):
    def __init__(self, console: Console, parent=None) -> None:
        super().__init__(parent)
        self.log = QPlainTextEdit(readOnly=True)
        self.log.setMaximumBlockCount(5000)
        font = QFont("monospace")
        font.setStyleHint(QFont.StyleHint.TypeWriter)
        self.log.setFont(font)
        self.log.setStyleSheet("QPlainTextEdit { background: #14161c; }")  # the log's colours are for a dark ground
        self.input = CommandLine(console)
        self.input.setFont(font)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(self.log)
        layout.addWidget(self.input)
        for line in console.log:
            self.append(line)
        console.log_listeners.append(self.append)

    def append(self, line: LogLine) -> None:
        fmt = QTextCharFormat()
        fmt.setForeground(QColor(COLOURS.get(line.level, COLOURS["info"])))
        cursor = self.log.textCursor()
        cursor.movePosition(cursor.MoveOperation.End)
        if not self.log.document().isEmpty():
            cursor.insertBlock()
        cursor.insertText(line.text, fmt)
        self.log.verticalScrollBar().setValue(self.log.verticalScrollBar().maximum())
