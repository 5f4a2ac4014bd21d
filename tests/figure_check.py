"""Shared checks of figures: a study's written files (a PNG and a PDF of the same name), and the command
line's figures read through their data (the Figures it writes, their axes, marks, arrows and legends)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

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


class CapturedFigures:
    """The matplotlib Figures the command line writes, in the order they are first written (the files are
    written as usual): install with :meth:`install` on a pytest ``monkeypatch``."""

    def __init__(self) -> None:
        self.figures: list[Any] = []
        self.formats: list[list[str]] = []

    def install(self, monkeypatch: Any) -> "CapturedFigures":
        """Record every figure :func:`contin.plot.style.write` writes."""
        from contin.plot import style

        original = style.write

        def write(fig: Any, fh: Any, fmt: str) -> None:
            if not any(fig is f for f in self.figures):
                self.figures.append(fig)
                self.formats.append([])
            self.formats[[i for i, f in enumerate(self.figures) if f is fig][0]].append(fmt)
            original(fig, fh, fmt)
        monkeypatch.setattr(style, "write", write)
        return self


def legend_texts(ax: Any) -> list[str]:
    """The texts of ``ax``'s legend (empty without one)."""
    legend = ax.get_legend()
    return [t.get_text() for t in legend.get_texts()] if legend is not None else []


def arrows(ax: Any) -> list[Any]:
    """The annotations of ``ax`` drawn as arrows (the snaps of a diagram, the loads of the shapes figure)."""
    return [t for t in ax.texts if getattr(t, "arrow_patch", None) is not None]


def marker_points(ax: Any, marker: str) -> list[tuple[float, float]]:
    """The points ``ax`` marks with ``marker`` (lines of single marked points: the special points)."""
    return [tuple(map(float, ln.get_xydata()[0])) for ln in ax.lines
            if ln.get_marker() == marker and len(ln.get_xydata()) == 1]


def inside_with_margin(ax: Any, points: Sequence[tuple[float, float]], margin: float) -> bool:
    """Whether every point lies inside ``ax``'s limits, at least ``margin`` (a fraction of the range) from
    each edge."""
    (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
    mx, my = margin * (x1 - x0), margin * (y1 - y0)
    return all(x0 + mx <= x <= x1 - mx and y0 + my <= y <= y1 - my for x, y in points)


def span_fraction(ax: Any, points: Sequence[tuple[float, float]]) -> tuple[float, float]:
    """The fraction of ``ax``'s x and y ranges that the points span."""
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    return (max(xs) - min(xs)) / abs(x1 - x0), (max(ys) - min(ys)) / abs(y1 - y0)


def write_saved_run(out: Path, summary: dict[str, Any], columns: dict[str, Sequence[float]]) -> Path:
    """A directory that :func:`contin.app.saved.load_run` reads as a saved run: ``summary.json`` and ``branch.csv``
    (``columns``: name -> values, one row per point)."""
    import csv
    import json

    out.mkdir(parents=True, exist_ok=True)
    (out / "summary.json").write_text(json.dumps(summary))
    names = list(columns)
    with open(out / "branch.csv", "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(names)
        writer.writerows(zip(*(columns[n] for n in names)))
    return out
