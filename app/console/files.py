"""Where the console finds and keeps files: the user's config folder and the shipped resources."""
from __future__ import annotations

import os
from pathlib import Path

from app.resources import RESOURCES

# Shipped files by kind, searched after the path as given (relative to the working folder).
SEARCH = {".cfg": RESOURCES / "config", ".lua": RESOURCES / "scripts", ".demo": RESOURCES / "demos"}


def config_dir() -> Path:
    """$SHADELAB_CONFIG_DIR, else $XDG_CONFIG_HOME/shadelab, else ~/.config/shadelab."""
    if os.environ.get("SHADELAB_CONFIG_DIR"):
        return Path(os.environ["SHADELAB_CONFIG_DIR"])
    base = os.environ.get("XDG_CONFIG_HOME") or Path.home() / ".config"
    return Path(base) / "shadelab"


def user_config() -> Path:
    return config_dir() / "config.cfg"


def history_file() -> Path:
    return config_dir() / "history"


def find(name: str) -> Path | None:
    """The file as given, else the user's config folder, else the shipped resources of its kind."""
    path = Path(name).expanduser()
    candidates = [path]
    if not path.is_absolute():
        candidates.append(config_dir() / path)
        if path.suffix in SEARCH:
            candidates.append(SEARCH[path.suffix] / path)
    return next((c for c in candidates if c.is_file()), None)


def complete(prefix: str, suffixes: tuple[str, ...]) -> list[str]:
    """File names starting with `prefix` (folders end in '/'), in the working folder and the resources."""
    head, _, tail = prefix.rpartition("/")
    folders = [Path(head or ".")]
    if not head:
        folders += [config_dir(), *{SEARCH[s] for s in suffixes if s in SEARCH}]
    found = set()
    for folder in folders:
        try:
            entries = list(folder.iterdir())
        except OSError:
            continue
        for entry in entries:
            if not entry.name.startswith(tail) or entry.name.startswith("."):
                continue
            if entry.is_dir() and folder == Path(head or "."):
                found.add(f"{head + '/' if head else ''}{entry.name}/")
            elif entry.suffix in suffixes:
                found.add(f"{head + '/' if head else ''}{entry.name}")
    return sorted(found)
