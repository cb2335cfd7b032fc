"""Reading the project's versioned JSON files: one place for the checks every format shares."""
from __future__ import annotations

import json
import os


def read_versioned(path: str | os.PathLike, fmt: str, version: int, error: type[Exception]) -> dict:
    """The file's object, once it parsed and names `fmt` at `version`; otherwise `error` saying why."""
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except OSError as exc:
        raise error(f"cannot read {path}: {exc.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise error(f"{path} is not valid JSON: {exc}") from None
    if not isinstance(data, dict) or data.get("format") != fmt:
        raise error(f"{path} is not a {fmt} file")
    if data.get("version") != version:
        raise error(f"{path}: unsupported version {data.get('version')!r} (this build reads {version})")
    return data
