"""The package layers and the headless core: lint-imports' contracts (pyproject.toml, [tool.importlinter]) hold,
and importing any module of the packages below the views pulls in neither Qt nor pyqtgraph.

Both checks run in subprocesses: this test process has Qt loaded already (pytest-qt, the conftest)."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
HEADLESS = ["app.model", "app.io", "app.reference", "app.gl", "app.console", "app.commands", "app.bench"]
QT = ("PySide6", "pyqtgraph")


def run_python(code: str, timeout: float) -> subprocess.CompletedProcess:
    path = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH")) if p)
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, env={**os.environ, "PYTHONPATH": path},
                          capture_output=True, text=True, timeout=timeout)


@pytest.mark.layers
def test_layer_check_lint_imports_contracts_are_kept():
    """THE LAYER CHECK: cli > views > bench > editor > commands > console > gl > reference > io > model, and no
    Qt below the views. lint-imports lists every import chain that breaks a contract."""
    # Not `-m importlinter.cli`: that module has no __main__ block, so it would exit 0 having checked nothing.
    r = run_python("import sys; from importlinter.cli import lint_imports_command; "
                   "sys.exit(lint_imports_command(['--config', 'pyproject.toml', '--no-cache']))", timeout=300)
    assert "Contracts:" in r.stdout, r.stdout + r.stderr  # it ran and read the contracts
    assert r.returncode == 0, f"lint-imports found broken contracts:\n{r.stdout}{r.stderr}"


# In the subprocess: every module of the package, imported one after another; the first that brings Qt in is named.
IMPORT_ALL = """
import importlib, pkgutil, sys
qt = {qt!r}
package = importlib.import_module({package!r})
names = [package.__name__] + sorted(m.name for m in pkgutil.walk_packages(package.__path__, package.__name__ + "."))
assert len(names) > 1, names
culprits = []
for name in names:
    before = [q for q in qt if q in sys.modules]
    importlib.import_module(name)
    culprits += [(name, q) for q in qt if q in sys.modules and q not in before]
for name, q in culprits:
    print(f"importing {{name}} imports {{q}}")
assert not any(q in sys.modules for q in qt), culprits
print(f"{{len(names)}} modules imported")
"""


@pytest.mark.parametrize("package", HEADLESS)
def test_importing_the_package_pulls_in_no_qt(package):
    r = run_python(IMPORT_ALL.format(qt=QT, package=package), timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "modules imported" in r.stdout


@pytest.mark.layers
def test_no_module_imports_one_that_imports_it_back():
    """No import cycle in app, imports inside functions included (the contracts see only across layers: the
    clouds bench and its report once imported each other, one of them in a function)."""
    import grimp

    graph = grimp.build_graph("app", cache_dir=None)
    cycles = sorted({tuple(sorted((module, imported))) for module in graph.modules
                     for imported in graph.find_modules_directly_imported_by(module)
                     if graph.chain_exists(importer=imported, imported=module)})
    assert not cycles, cycles
