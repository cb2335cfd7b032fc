"""Qt key events to the console's key names (app/console/binds.py), for `bind`."""
from __future__ import annotations

from PySide6.QtCore import Qt

K = Qt.Key
SPECIAL = {
    K.Key_Tab: "TAB", K.Key_Return: "ENTER", K.Key_Enter: "ENTER", K.Key_Escape: "ESCAPE", K.Key_Space: "SPACE",
    K.Key_Backspace: "BACKSPACE", K.Key_Up: "UPARROW", K.Key_Down: "DOWNARROW", K.Key_Left: "LEFTARROW",
    K.Key_Right: "RIGHTARROW", K.Key_Insert: "INS", K.Key_Delete: "DEL", K.Key_PageDown: "PGDN",
    K.Key_PageUp: "PGUP", K.Key_Home: "HOME", K.Key_End: "END", K.Key_Pause: "PAUSE",
    K.Key_QuoteLeft: "`", K.Key_Minus: "-", K.Key_Equal: "=", K.Key_BracketLeft: "[", K.Key_BracketRight: "]",
    K.Key_Backslash: "\\", K.Key_Comma: ",", K.Key_Period: ".", K.Key_Slash: "/", K.Key_Apostrophe: "'",
    **{getattr(K, f"Key_F{i}"): f"F{i}" for i in range(1, 13)},
}


def key_name(key: int) -> str | None:
    """The bind name of a Qt key code, or None for keys that cannot be bound."""
    if K.Key_A <= key <= K.Key_Z:
        return chr(key).lower()
    if K.Key_0 <= key <= K.Key_9:
        return chr(key)
    return SPECIAL.get(key)
