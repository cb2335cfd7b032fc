"""An autosave folder's manifest: which workspace each scene saved there belongs to, the file it was edited from,
and the SHA-256 of the scene file, so a crashed session's work can be offered back:
{"format": "shadelab.autosave", "version": 2,
 "scenes": [{"workspace": "lighting2d", "file": "lighting2d.json", "original": "/home/me/a.json" or null,
             "sha256": "..."}],
 "signature": "..."}.

The cache is input like any folder: anyone who can write there could plant a manifest whose scene is theirs and
whose `original` names a file of the user's to be overwritten at the next Save. So the editor signs each manifest
(HMAC-SHA256 of its content) with a key of its own, kept private in the user's config folder (signing_key), and
reads back only manifests with a good signature whose scene files are the ones it wrote."""
from __future__ import annotations

import hashlib
import hmac
import json
import os
import secrets
import stat
from dataclasses import dataclass
from pathlib import Path

from app.io import json_file as jf
from app.io.atomic import write_text
from app.io.regular_file import open_regular

FORMAT = "shadelab.autosave"
VERSION = 2  # 1 had no signature: its manifests are not read
MANIFEST = "autosave.json"
KEY_FILE = "autosave.key"  # in the user's config folder
MAX_SCENES = 64
MAX_PATH = 4096
_KEY_BYTES = 32
_HEX = 64  # characters of a key, a digest and a signature

_SCENE = jf.obj({"workspace": jf.text(64), "file": jf.text(255),
                 "original": {"anyOf": [jf.text(MAX_PATH), {"type": "null"}]}, "sha256": jf.text(_HEX)},
                required=["workspace", "file", "sha256"])
VALIDATOR = jf.validator({"scenes": jf.array(_SCENE, MAX_SCENES, title="scenes"), "signature": jf.text(_HEX)},
                         required=["scenes", "signature"])


class AutosaveError(ValueError):
    """A manifest that cannot be read, is not signed by this editor's key, or names a file that is not the one it
    wrote; or a key that cannot be used."""


@dataclass(frozen=True)
class Autosaved:
    workspace: str
    file: Path  # in the autosave folder
    original: str | None  # the file the scene was edited from; None: untitled
    sha256: str  # of `file` as the editor wrote it


def file_digest(path: Path) -> str:
    """The SHA-256 of a regular file (OSError for anything else: a FIFO, a folder)."""
    digest = hashlib.sha256()
    with open_regular(path) as f:
        while chunk := f.read(1 << 20):
            digest.update(chunk)
    return digest.hexdigest()


def signing_key(path: Path) -> bytes:
    """The key manifests are signed with, kept in `path` (owner-only, 0600): made with `secrets` on first use,
    and made again where the file holds no key or others may read it (a key someone else knows signs nothing).
    AutosaveError where it cannot be read or written (a FIFO or a folder in its place)."""
    try:
        with open_regular(path, 4 * _HEX) as f:
            private = stat.S_IMODE(os.fstat(f.fileno()).st_mode) & 0o077 == 0
            text = f.read().decode("ascii", errors="replace").strip()
        if private and len(text) == _HEX and all(c in "0123456789abcdef" for c in text):
            return bytes.fromhex(text)
    except FileNotFoundError:
        pass
    except OSError as exc:
        raise AutosaveError(f"cannot read the autosave key {path}: {exc.strerror or exc}") from None
    key = secrets.token_bytes(_KEY_BYTES)
    try:
        _write_private(path, key.hex() + "\n")
    except OSError as exc:
        raise AutosaveError(f"cannot write the autosave key {path}: {exc.strerror or exc}") from None
    return key


def _write_private(path: Path, text: str) -> None:
    """`text` in a new file only its owner may read (0600 whatever the umask), put in place of `path` at once."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{secrets.token_hex(4)}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o600)
    try:
        with os.fdopen(fd, "w", encoding="ascii") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)  # replaces a link itself, never the file it names
    finally:
        tmp.unlink(missing_ok=True)


def signature(key: bytes, scenes: list[dict]) -> str:
    """The HMAC-SHA256 a manifest listing `scenes` (as JSON objects) is signed with."""
    message = json.dumps({"format": FORMAT, "version": VERSION, "scenes": scenes}, sort_keys=True,
                         separators=(",", ":"))
    return hmac.new(key, message.encode("utf-8"), hashlib.sha256).hexdigest()


def write(folder: Path, scenes: list[Autosaved], key: bytes) -> None:
    items = [{"workspace": s.workspace, "file": s.file.name, "original": s.original, "sha256": s.sha256}
             for s in scenes]
    data = {"format": FORMAT, "version": VERSION, "scenes": items, "signature": signature(key, items)}
    write_text(folder / MANIFEST, json.dumps(data, indent=2) + "\n")


def read(folder: Path, key: bytes) -> list[Autosaved]:
    """The scenes a folder's manifest names, once its signature shows this editor wrote it and each scene file,
    a regular file in that folder (not a link), is the one it wrote; none if it has no manifest (a session that
    crashed before its first autosave). AutosaveError otherwise."""
    manifest = folder / MANIFEST
    if not _no_link(manifest):
        return []
    data = jf.read_versioned(manifest, FORMAT, VERSION, AutosaveError, VALIDATOR)
    if not hmac.compare_digest(data["signature"], signature(key, data["scenes"])):
        raise AutosaveError(f"{manifest} is not signed by this editor's key")
    scenes = []
    for item in data["scenes"]:
        name = item["file"]
        if os.path.basename(name) != name or name in (".", ".."):
            raise AutosaveError(f"{manifest}: {name!r} is not a file name")
        file = folder / name
        try:
            same = _no_link(file) and hmac.compare_digest(file_digest(file), item["sha256"])
        except OSError as exc:
            raise AutosaveError(f"cannot read {file}: {exc.strerror or exc}") from None
        if not same:
            raise AutosaveError(f"{file} is not the file this editor wrote (it is gone, or its SHA-256 differs)")
        scenes.append(Autosaved(item["workspace"], file, item["original"], item["sha256"]))
    return scenes


def _no_link(path: Path) -> bool:
    """Whether something is at `path`; AutosaveError if it is a symbolic link (the editor writes none)."""
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        return False
    except OSError as exc:
        raise AutosaveError(f"cannot read {path}: {exc.strerror or exc}") from None
    if stat.S_ISLNK(mode):
        raise AutosaveError(f"{path} is a symbolic link, not a file this editor wrote")
    return True
