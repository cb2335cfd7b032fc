"""The console dock, as Quake's: the log above, a command line below.

Enter runs; Up/Down walk the history (kept in the user's config folder between runs); Tab completes
to the longest common prefix and lists the candidates; PageUp/PageDown scroll the log; Esc closes.
"""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor, QFont, QTextCharFormat
from PySide6.QtWidgets import QLineEdit, QPlainTextEdit, QVBoxLayout, QWidget

from app.console.completion import complete
from app.console.console import MAX_LINE, MAX_LOG, Console, LogLine
from app.console.registry import CommandError, check_text
from app.io.atomic import write_text
from app.io.regular_file import read_regular_bytes
from app.views.weak_callback import weak_callback

COLOURS = {"input": "#8ecae6", "info": "#d0d4dc", "error": "#ff6b6b"}
HISTORY_LINES = 500
MAX_HISTORY_BYTES = 8 << 20  # 500 lines of a long stroke each


def _typable(line: str) -> bool:
    try:
        check_text("a line", line)
    except CommandError:
        return False
    return len(line) <= MAX_LINE


class CommandLine(QLineEdit):
    closed = Signal()
    page = Signal(int)  # -1 PageUp, +1 PageDown

    def __init__(self, console: Console, history_path: Path, parent=None) -> None:
        super().__init__(parent)
        self.console = console
        self.history_path = history_path
        self.history = self._read_history()
        self._index = len(self.history)
        self.setPlaceholderText("command (help, Tab completes)")
        self.returnPressed.connect(self._run)

    def _read_history(self) -> list[str]:
        """The lines typed in earlier runs. The file is input like any other: one that is not a regular file (a
        FIFO would hang the start), too big or not UTF-8 is said and passed over (the next line typed writes a new
        one), and a line no console line could be (too long, a control character) is dropped."""
        try:
            text = read_regular_bytes(self.history_path, MAX_HISTORY_BYTES).decode("utf-8")
        except FileNotFoundError:
            return []
        except (OSError, UnicodeDecodeError) as exc:
            reason = exc.strerror if isinstance(exc, OSError) else f"not UTF-8 text (byte {exc.start})"
            self.console.error(f"the console history {self.history_path} is not read: {reason}")
            return []
        return [line for line in text.split("\n") if line and _typable(line)][-HISTORY_LINES:]

    def _run(self) -> None:
        line = self.text().strip()
        self.clear()
        if not line:
            return
        if not self.history or self.history[-1] != line:
            self.history.append(line)
            try:
                write_text(self.history_path, "\n".join(self.history[-HISTORY_LINES:]) + "\n")
            except OSError as exc:
                self.console.error(f"cannot keep the history in {self.history_path}: {exc.strerror}")
        self._index = len(self.history)
        self.console.execute(line)

    def event(self, event) -> bool:
        # Tab would move the focus before keyPressEvent saw it.
        if event.type() == event.Type.KeyPress and event.key() == Qt.Key.Key_Tab:
            self._complete()
            return True
        return super().event(event)

    def _complete(self) -> None:
        result = complete(self.console.registry, self.text())
        if len(result.candidates) > 1:
            self.console.print("  ".join(result.candidates))
        self.setText(result.line)

    def keyPressEvent(self, event) -> None:
        key = event.key()
        if key in (Qt.Key.Key_Up, Qt.Key.Key_Down) and self.history:
            step = -1 if key == Qt.Key.Key_Up else 1
            self._index = max(0, min(len(self.history), self._index + step))
            self.setText(self.history[self._index] if self._index < len(self.history) else "")
        elif key in (Qt.Key.Key_PageUp, Qt.Key.Key_PageDown):
            self.page.emit(-1 if key == Qt.Key.Key_PageUp else 1)
        elif key == Qt.Key.Key_Escape:
            self.closed.emit()
        elif key == Qt.Key.Key_QuoteLeft and not self.text():
            self.closed.emit()  # ` toggles the console, also from inside it
        else:
            super().keyPressEvent(event)


class ConsoleWidget(QWidget):
    def __init__(self, console: Console, history_path: Path, parent=None) -> None:
        super().__init__(parent)
        self.console = console
        self.log = QPlainTextEdit(readOnly=True)
        self.log.setMaximumBlockCount(5000)
        font = QFont("monospace")
        font.setStyleHint(QFont.StyleHint.TypeWriter)
        self.log.setFont(font)
        self.log.setStyleSheet("QPlainTextEdit { background: #14161c; }")  # the log's colours are for a dark ground
        self.input = CommandLine(console, history_path)
        self.input.setFont(font)
        self.input.page.connect(self._page)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(self.log)
        layout.addWidget(self.input)
        self.log.setMaximumBlockCount(MAX_LOG)  # the view keeps no more than the console does
        self._seen = self._clears = 0  # console.printed and console.clears when last synced
        console.log_listeners.append(weak_callback(self, "sync", drop_args=True))
        self.sync()

    def sync(self) -> None:
        """Show log lines printed since the last sync (the oldest may have left the log); follow `clear`."""
        new = self.console.printed - self._seen
        if self.console.clears != self._clears:
            self.log.clear()
            self._clears = self.console.clears
        for line in self.console.log[len(self.console.log) - min(new, len(self.console.log)):] if new else ():
            self._append(line)
        self._seen = self.console.printed

    def _append(self, line: LogLine) -> None:
        fmt = QTextCharFormat()
        fmt.setForeground(QColor(COLOURS.get(line.level, COLOURS["info"])))
        cursor = self.log.textCursor()
        cursor.movePosition(cursor.MoveOperation.End)
        if not self.log.document().isEmpty():
            cursor.insertBlock()
        cursor.insertText(line.text, fmt)
        self.log.verticalScrollBar().setValue(self.log.verticalScrollBar().maximum())

    def _page(self, direction: int) -> None:
        bar = self.log.verticalScrollBar()
        bar.setValue(bar.value() + direction * bar.pageStep())
