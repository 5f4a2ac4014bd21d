"""What an install puts into site-packages: only names that are this project's own (issue 14, B6).

A generic top-level name (``models``, ``studies``) would be found by any other project's
``import models``.  The engine installs as ``contin``, the folder ``models/`` as ``contin_models``,
the console script's launcher lives in ``contin.launch``; the studies are not installed.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CONFIG = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]


def test_every_installed_package_is_named_for_the_project() -> None:
    tops = {name.split(".")[0] for name in CONFIG["packages"]}
    assert tops == {"contin", "contin_models"}


@pytest.mark.parametrize("top", ["contin", "contin_models"])
def test_every_package_folder_is_installed(top: str) -> None:
    # a subpackage added under contin/ or models/ but not listed would be missing from the install
    folders = {p.parent for p in (ROOT / CONFIG["package-dir"][top]).rglob("__init__.py")}
    listed = {ROOT / CONFIG["package-dir"][top] / Path(*name.split(".")[1:])
              for name in CONFIG["packages"] if name.split(".")[0] == top}
    assert folders == listed


def test_the_console_script_and_models_resolve_to_installed_names() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["scripts"]["contin"] == "contin.launch:main"
    targets = project["entry-points"]["contin.models"].values()
    assert targets and all(t.startswith("contin_models.") for t in targets)


def test_importing_contin_loads_no_engine_module() -> None:
    # contin.launch must be importable without numpy: an interrupt while the engine loads is its job
    import subprocess
    import sys

    code = "import sys, contin.launch; print(sorted(m for m in sys.modules if m.split('.')[0] in ('numpy', 'scipy')))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd="/")
    assert out.stdout.strip() == "[]"
