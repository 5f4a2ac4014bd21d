"""Shared check of the committed generated kernels: regenerating them gives the same bytes."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest

from contin_models.codegen_cli import write_generated

ROOT = Path(__file__).resolve().parents[1]


def assert_reproduced(model: str, tmp_path: Path) -> None:
    """Regenerate ``models/<model>/_generated.py`` into ``tmp_path`` and compare it byte for byte.

    Parameters
    ----------
    model : str
        The model package whose ``codegen`` module writes its ``_generated.py`` (``"shell"``, ``"contact"``).
    tmp_path : Path
        Folder for the regenerated file.

    Raises
    ------
    AssertionError
        The committed file differs; the message names the command that regenerates it.
    """
    pytest.importorskip("sympy")
    codegen = importlib.import_module(f"contin_models.{model}.codegen")
    out = tmp_path / "_generated.py"
    write_generated(codegen.generate_source, out)
    committed = ROOT / "models" / model / "_generated.py"
    assert out.read_bytes() == committed.read_bytes(), (
        f"models/{model}/_generated.py is out of date: run `python -m contin_models.{model}.codegen`")
