"""Shared check of the committed generated kernels: regenerating them gives the same bytes."""

from __future__ import annotations

import importlib
from pathlib import Path

import pytest

from contin.modelkit.codegen import check_generated

ROOT = Path(__file__).resolve().parents[1]


def assert_reproduced(model: str, tmp_path: Path) -> None:
    """Regenerate ``models/<model>/_generated.py`` and compare it byte for byte with the committed file.

    Parameters
    ----------
    model : str
        The model package whose ``codegen`` module writes its ``_generated.py`` (``"shell"``, ``"contact"``).
    tmp_path : Path
        Unused (kept for the callers' signature): the text is compared in memory.

    Raises
    ------
    contin.modelkit.codegen.GeneratedFileOutOfDate
        The committed file differs (an AssertionError); the message gives the first differing line
        and names the command that regenerates it.
    """
    pytest.importorskip("sympy")
    codegen = importlib.import_module(f"contin_models.{model}.codegen")
    check_generated(codegen.generate_source, ROOT / "models" / model / "_generated.py",
                    f"python -m contin_models.{model}.codegen")
