"""Where the console finds and keeps files: the user's config folder and the shipped resources."""
from __future__ import annotations

import os
from pathlib import Path

from app.console.console import Console
from app.console.registry import CommandError
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


def sandbox_dir() -> Path:
    """Where what scripts, demos, configs, binds and aliases write lands: a folder of the user folder that holds
    nothing the editor reads with trust (config.cfg, window.ini, the history, autosaves and caches live elsewhere)."""
    return config_dir() / SANDBOX


SANDBOX = "from-scripts"

# The file policy (docs/architecture.md rule 6, docs/console.md "Files"). What the user types may read and write any
# file. What a Lua script, a demo, a config, a bind or an alias runs may write only into the sandbox folder (a
# relative name lands there) and read only there, in the shipped resources, and beside the file that runs (the
# folder of the demo or script the user opened, not below it). Paths are compared after resolving `..` and
# symbolic links. Commands declare their file parameters (`path:read`, `path:write`) and the console resolves
# them here before the command sees them (Console.file_policy).


def _real(path: Path) -> Path:
    return Path(os.path.realpath(path))


def _inside(path: Path, root: Path) -> bool:
    return path == root or root in path.parents


def _who(console: Console) -> str:
    return console.origins[-1].who()


def may_read(console: Console, path: Path) -> bool:
    if console.trusted:
        return True
    real = _real(path)
    if any(_inside(real, _real(root)) for root in (sandbox_dir(), RESOURCES)):
        return True
    return any(real.parent == _real(o.home) for o in console.origins if o.home is not None)


def readable(console: Console, name: str) -> Path:
    """`name` as given, if the commands running now may read it; else CommandError."""
    path = Path(name).expanduser()
    if not may_read(console, path):
        raise CommandError(f"{_who(console)} may not read {name}: only the sandbox {sandbox_dir()}, the "
                           "resources and files beside it (type the command yourself to read it)")
    return path


def writable(console: Console, name: str) -> Path:
    """Where a command may write `name`: as given for the user's own lines; else inside the sandbox folder, where
    a relative name lands, or CommandError. Either way into a folder that exists (check_folder)."""
    path = Path(name).expanduser()
    if not console.trusted:
        root = _sandbox()
        path = _real(root / path)  # an absolute path stays as it is
        if not _inside(path, root):
            raise CommandError(f"{_who(console)} may write only inside the sandbox {root}, not {name} "
                               "(type the command yourself to write there)")
    check_folder(path, name)
    return path


def _sandbox() -> Path:
    """The sandbox folder, made on first use: a real folder, never a link someone planted to send writes
    elsewhere."""
    root = sandbox_dir()
    if root.is_symlink() or (root.exists() and not root.is_dir()):
        raise CommandError(f"{root} is not a folder Shadelab made (a link or a file): scripts cannot write now")
    root.mkdir(parents=True, exist_ok=True)
    return _real(root)


def resolve(console: Console, kind: str, name: str) -> str:
    """A declared file parameter (registry.FILE_KINDS) as the command gets it: checked, or moved into the sandbox."""
    return str(readable(console, name) if kind == "read" else writable(console, name))


def check_folder(path: Path, name: str) -> None:
    """CommandError unless `path`'s folder exists: a save never makes folders, so a mistyped one is refused
    rather than made. The user folder itself is the exception, made when first written: it is Shadelab's."""
    folder = path.parent
    if not folder.is_dir() and _real(folder) not in (_real(config_dir()), _real(sandbox_dir())):
        raise CommandError(f"cannot write {name}: there is no folder {folder} (make it first)")


def find(name: str, console: Console | None = None) -> Path | None:
    """The file as given, else (for a script, demo or config) beside the file that runs, else the user's
    config folder (the sandbox, for those), else the shipped resources of its kind. With a console, one its
    commands may not read is refused (CommandError) rather than not found."""
    path = Path(name).expanduser()
    candidates = [path]
    if not path.is_absolute():
        if console is not None:
            candidates += [o.home / path for o in reversed(console.origins) if o.home is not None]
        mine = console is None or console.trusted
        candidates.append((config_dir() if mine else sandbox_dir()) / path)
        if path.suffix in SEARCH:
            candidates.append(SEARCH[path.suffix] / path)
    found = [c for c in candidates if c.is_file()]
    allowed = [c for c in found if console is None or may_read(console, c)]
    if found and not allowed:
        readable(console, str(found[0]))  # says why
    return allowed[0] if allowed else None


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
            elif entry.name.endswith(suffixes):  # .nii.gz as well as .nii
                found.add(f"{head + '/' if head else ''}{entry.name}")
    return sorted(found)
