"""An autosave folder's manifest: which workspace each scene saved there belongs to, and the file it was edited
from, so a crashed session's work can be offered back:
{"format": "shadelab.autosave", "version": 1,
 "scenes": [{"workspace": "lighting2d", "file": "lighting2d.json", "original": "/home/me/a.json" or null}]}."""
from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

from app.io import json_file as jf
from app.io.atomic import write_text

FORMAT = "shadelab.autosave"
VERSION = 1
MANIFEST = "autosave.json"
MAX_SCENES = 64
MAX_PATH = 4096

_SCENE = jf.obj({"workspace": jf.text(64), "file": jf.text(255),
                 "original": {"anyOf": [jf.text(MAX_PATH), {"type": "null"}]}}, required=["workspace", "file"])
VALIDATOR = jf.validator({"scenes": jf.array(_SCENE, MAX_SCENES, title="scenes")}, required=["scenes"])


class AutosaveError(ValueError):
    """A manifest that cannot be read, or names a file outside its folder."""


@dataclass(frozen=True)
class Autosaved:
    workspace: str
    file: Path  # in the autosave folder
    original: str | None  # the file the scene was edited from; None: untitled


def write(folder: Path, scenes: list[Autosaved]) -> None:
    data = {"format": FORMAT, "version": VERSION,
            "scenes": [{"workspace": s.workspace, "file": s.file.name, "original": s.original} for s in scenes]}
    write_text(folder / MANIFEST, json.dumps(data, indent=2) + "\n")


def read(folder: Path) -> list[Autosaved]:
    """The scenes a folder's manifest names, each a file in that folder (a name with a folder in it is refused)."""
    data = jf.read_versioned(folder / MANIFEST, FORMAT, VERSION, AutosaveError, VALIDATOR)
    scenes = []
    for item in data["scenes"]:
        name = item["file"]
        if os.path.basename(name) != name or name in (".", ".."):
            raise AutosaveError(f"{folder / MANIFEST}: {name!r} is not a file name")
        scenes.append(Autosaved(item["workspace"], folder / name, item.get("original")))
    return scenes
