"""Shared check of a study's written figure: a PNG and a PDF of the same name."""

from __future__ import annotations

from pathlib import Path

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def assert_figure(out: Path, stem: str, min_png_bytes: int = 0) -> None:
    """Assert that ``out/<stem>.png`` is a PNG of more than ``min_png_bytes`` and ``out/<stem>.pdf`` a PDF.

    Parameters
    ----------
    out : Path
        The study's output folder.
    stem : str
        The figure's file name without its extension.
    min_png_bytes : int
        The PNG must be larger than this (0: any size).

    Raises
    ------
    AssertionError
        A file is missing its format's signature or the PNG is too small.
    """
    png, pdf = out / f"{stem}.png", out / f"{stem}.pdf"
    assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > min_png_bytes, png
    assert pdf.read_bytes()[:5] == b"%PDF-", pdf
