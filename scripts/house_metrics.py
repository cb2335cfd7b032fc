"""The house's sizes (issue 27's note): the longest functions and the largest files under app/.

    python scripts/house_metrics.py [N]   (N rows of each, 15 unless given)
"""
from __future__ import annotations

import ast
import pathlib
import sys


def functions(root: pathlib.Path):
    """(lines, 'path:name') of every function and method, nested ones too."""
    for path in sorted(root.rglob("*.py")):
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield node.end_lineno - node.lineno + 1, f"{path}:{node.lineno} {node.name}"


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 15
    root = pathlib.Path("app")
    print(f"# {n} longest functions (lines)")
    for lines, where in sorted(functions(root), reverse=True)[:n]:
        print(f"{lines:5d}  {where}")
    print(f"\n# {n} largest files (lines)")
    sizes = sorted(((len(p.read_text().splitlines()), str(p)) for p in root.rglob("*.py")), reverse=True)
    for lines, path in sizes[:n]:
        print(f"{lines:5d}  {path}")
    print(f"\n{len(sizes)} files, {sum(lines for lines, _ in sizes)} lines")


if __name__ == "__main__":
    main()
