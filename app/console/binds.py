"""Key bindings, Quake style: a key name bound to a command line, optionally per workspace.

`bind w "snow.step 0.25"` binds everywhere; `bind snowflake:w ...` only in that workspace, where it
wins over the global one. Key names are the Quake console's, so configs read the same.
"""
from __future__ import annotations

import string

from app.console.quoting import quote
from app.console.registry import check_new_name, check_text

NAMED = ("TAB", "ENTER", "ESCAPE", "SPACE", "BACKSPACE", "UPARROW", "DOWNARROW", "LEFTARROW",
         "RIGHTARROW", "INS", "DEL", "PGDN", "PGUP", "HOME", "END", "PAUSE", "SHIFT", "CTRL", "ALT",
         "KP_PLUS", "KP_MINUS", "MOUSE1", "MOUSE2", "MOUSE3", "MWHEELUP", "MWHEELDOWN")
KEYS = frozenset([*string.ascii_lowercase, *string.digits, *"`-=[]\\,./'", *NAMED,
                  *(f"F{i}" for i in range(1, 13))])


def normalise(key: str) -> str:
    """'W' -> 'w', 'f1' -> 'F1', 'pgup' -> 'PGUP'; refuses names that are no key."""
    if len(key) == 1:
        name = key.lower()
    else:
        name = key.upper()
    if name not in KEYS:
        raise ValueError(f"no key called {key!r} (keys: a-z, 0-9, F1-F12, {', '.join(NAMED[:9])}...)")
    return name


def split(spec: str) -> tuple[str, str]:
    """'snowflake:w' -> ('snowflake', 'w'); 'w' -> ('', 'w')."""
    scope, sep, key = spec.rpartition(":")
    if sep and not scope:  # ':' itself is not a key we bind; keep the message clear
        raise ValueError(f"no key called {spec!r}")
    if scope:
        check_new_name("a bind's workspace", scope)
    return scope, normalise(key)


class Binds:
    """`table`: the binds in force; `kept`: those the user made, which config.cfg keeps. What scripts, demos and
    configs bind or unbind changes the first alone: it lasts the session (docs/console.md, taint)."""

    def __init__(self) -> None:
        self.table: dict[tuple[str, str], str] = {}
        self.kept: dict[tuple[str, str], str] = {}

    def bind(self, spec: str, command: str, trusted: bool = True) -> None:
        key, command = split(spec), check_text(f"bind {spec}", command)
        for table in (self.table, self.kept) if trusted else (self.table,):
            table[key] = command

    def unbind(self, spec: str, trusted: bool = True) -> bool:
        key = split(spec)
        if trusted:
            self.kept.pop(key, None)
        return self.table.pop(key, None) is not None

    def clear(self, trusted: bool = True) -> None:
        self.table.clear()
        if trusted:
            self.kept.clear()

    def lookup(self, workspace: str, key: str) -> str | None:
        return self.table.get((workspace, key)) or self.table.get(("", key))

    def describe(self, workspace: str, spec: str) -> str:
        """What `bind KEY` says: what the key runs in `workspace` (its own bind wins over the global one), and
        the key's binds elsewhere; `scope:KEY` asks for one bind exactly."""
        scope, key = split(spec)
        if scope:
            found = self.table.get((scope, key))
            return f"{scope}:{key} is bound to {found!r}" if found else f"{scope}:{key} is not bound"
        own, everywhere = self.table.get((workspace, key)), self.table.get(("", key))
        if own:
            said = f"{key} is bound to {own!r} in {workspace}"
        elif everywhere:
            said = f"{key} is bound to {everywhere!r}"
        else:
            said = f"{key} is not bound" + (f" in {workspace}" if workspace else "")
        elsewhere = [f"{s}:{key} {c!r}" if s else repr(c) for (s, k), c in sorted(self.table.items())
                     if k == key and s != workspace and (s or own)]  # the global one where this workspace's hides it
        return said + (f" (elsewhere: {'; '.join(elsewhere)})" if elsewhere else "")

    def lines(self, kept: bool = False) -> list[str]:
        """`bind` commands that recreate the table (bindlist), or the user's own binds (`kept`: writeconfig), sorted."""
        table = self.kept if kept else self.table
        return [f"bind {quote(f'{s}:{k}' if s else k)} {quote(c)}" for (s, k), c in sorted(table.items())]
