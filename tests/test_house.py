"""The house's rules that a reader would otherwise check by eye (issue 27)."""
from __future__ import annotations

import ast
from pathlib import Path

import app

ROOT = Path(app.__file__).parent.parent
MAX_COMMAND_LINES = 60  # a command is a function you can read whole; registering them is a short list


def long_functions(root: Path, paths: list[Path], limit: int) -> list[str]:
    """'path:line name (N lines)' of every function or method in `paths` (named from `root`), nested ones too,
    longer than `limit` lines as scripts/house_metrics.py counts them (from `def` to its last line)."""
    found = []
    for path in paths:
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1
                if lines > limit:
                    found.append(f"{path.relative_to(root)}:{node.lineno} {node.name} ({lines} lines)")
    return found


def test_no_command_function_is_over_60_lines():
    paths = [*sorted((ROOT / "app" / "commands").rglob("*.py")), ROOT / "app" / "console" / "builtins.py"]
    assert len(paths) > 2  # the folder was found
    offenders = long_functions(ROOT, paths, MAX_COMMAND_LINES)
    assert not offenders, f"over {MAX_COMMAND_LINES} lines: " + "; ".join(offenders)


def test_long_functions_names_each_offender(tmp_path):
    body = "".join(f"    x{i} = {i}\n" for i in range(60))
    nested = "".join(f"    {line}\n" for line in body.splitlines())
    (tmp_path / "sample.py").write_text(f"def short():\n    pass\n\n\ndef long():\n{body}\n\n"
                                        f"def outer():\n    def inner():\n{nested}")
    assert long_functions(tmp_path, [tmp_path / "sample.py"], MAX_COMMAND_LINES) == [
        "sample.py:5 long (61 lines)", "sample.py:68 outer (62 lines)", "sample.py:69 inner (61 lines)"]
