"""The command line's figures: a traced run's diagram and shapes, saved runs drawn again or overlaid.

Each is drawn once in the project's style (:mod:`contin.style`) and written as PNG and PDF.  The
title is the model's (``plot_options["title"]``, e.g. the scene in a few symbols), else the model's
registered name; a run that did not succeed says its status there too.  matplotlib is imported
inside the functions only.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from . import style

__all__ = ["trace_figure", "shapes_figure", "saved_runs_figure", "once", "figure_files"]


def once(build: Callable[[], Any]) -> Callable[[], Any]:
    """``build`` called on first use only (a figure drawn once, written in two formats)."""
    made: list[Any] = []

    def get() -> Any:
        if not made:
            made.append(build())
        return made[0]
    return get


def figure_files(stem: Path, build: Callable[[], Any]) -> list[tuple[Path, Callable[[Any], None], bool]]:
    """Writers of :func:`contin.io.atomic_write` for ``<stem>.png`` and ``<stem>.pdf`` of one figure drawn once."""
    get = once(build)
    return [(stem.with_name(f"{stem.name}.{fmt}"), (lambda fh, f=fmt: style.write(get(), fh, f)), True)
            for fmt in style.FORMATS]


def trace_figure(model_name: str, result: Any) -> Any:
    """The diagram of a :class:`contin.scene.TraceResult` (its ``plot`` or :meth:`~TraceResult.draw`)."""
    with style.context():
        fig, ax = style.figure()
        if result.plot is not None:
            result.plot(ax)
        else:
            result.draw(ax)
        lines = [t for t in ax.get_title().split("\n") if t]
        if not result.plot_options.get("title"):
            lines.insert(0, model_name)
        if result.status != "ok":
            lines[0] += f" [{result.status}]"
        ax.set_title("\n".join(lines))
    return fig


def shapes_figure(result: Any) -> Any:
    """The model's shapes figure (:attr:`contin.scene.TraceResult.draw_shapes`)."""
    with style.context():
        fig, _ = style.figure(style.WIDTH, style.HEIGHT, nrows=0)
        result.draw_shapes(fig)
        title = result.plot_options.get("title")
        if title:
            fig.suptitle(title)
    return fig


def saved_runs_figure(runs: Sequence[Any], branches: list, x: str, y: str | None, colors: list, labels: list,
                      title: str | None = None) -> Any:
    """Saved runs (:class:`contin.saved.SavedRun`) drawn again: one run as it was drawn, several overlaid.

    An overlay is titled ``title`` (:func:`contin.saved.overlay_labels`), by default by the runs' directories.
    """
    from .diagram import plot_branches

    first = runs[0]
    options = dict(first.plot_options)
    if len(runs) > 1:
        options["title"] = title or " / ".join(str(r.path.name or r.path) for r in runs)
    else:
        options.setdefault("title", f"{first.summary.get('model', '?')}: {first.path.name or first.path}")
    with style.context():
        fig, ax = style.figure()
        plot_branches(branches, x=x, y=y, ax=ax, colors=colors, labels=labels if len(runs) > 1 else None,
                      stability=first.stability, **options)
    return fig
