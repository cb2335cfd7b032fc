"""Callbacks that do not keep a widget alive: the editor (and its console) may outlive the window."""
from __future__ import annotations

import weakref
from typing import Any, Callable

import shiboken6
from PySide6.QtCore import QObject


def weak_callback(obj: QObject, method: str, *, drop_args: bool = False, gone: Any = None) -> Callable[..., Any]:
    """obj.method through a weak reference: once obj is gone (its Python wrapper collected, or the C++
    object deleted under it), calling it does nothing and returns `gone`. drop_args: call it without the
    caller's arguments (a listener's log line, say)."""
    ref = weakref.ref(obj)

    def call(*args: Any) -> Any:
        target = ref()
        if target is None or not shiboken6.isValid(target):
            return gone
        bound = getattr(target, method)
        return bound() if drop_args else bound(*args)

    return call
