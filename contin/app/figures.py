"""The command line's figures: a traced run's diagram and shapes, saved runs drawn again or overlaid.

Each is drawn once in the project's style (:mod:`contin.plot.style`) and written as PNG, and as PDF too when
asked (:func:`figure_formats`).  The title is the model's (``plot_options["title"]``, e.g. the scene in a
few symbols), else the model's registered name; a run that did not succeed says its status there too.
Where the end of the path would bury its snaps (a structure stiffening after them), the diagram shows
the part with the snaps (:mod:`contin.plot.framing`): a detail panel under the whole path, or axes limited
to that part.  matplotlib is not imported here (the engine imports it in :mod:`contin.plot` only).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..plot import framing, style

__all__ = ["trace_figure", "shapes_figure", "saved_runs_figure", "diagram_figure", "once", "figure_files",
           "figure_formats", "DETAIL_HEIGHT"]

#: Height in inches added to a diagram for its detail panel.
DETAIL_HEIGHT = 2.9
#: Titles longer than this many characters (of their source text) are broken into lines after a comma.
TITLE_LINE = 66


def figure_formats(scene: Mapping[str, Any] | None = None, pdf: bool = False) -> tuple[str, ...]:
    """The formats a run's figures are written in: PNG, and PDF when ``pdf`` (the ``--pdf`` flag) or the
    scene's ``output.pdf`` asks for it."""
    asked = pdf or bool(((scene or {}).get("output") or {}).get("pdf", False))
    return style.FORMATS if asked else style.DEFAULT_FORMATS


def once(build: Callable[[], Any]) -> Callable[[], Any]:
    """``build`` called on first use only (a figure drawn once, written in several formats)."""
    made: list[Any] = []

    def get() -> Any:
        if not made:
            made.append(build())
        return made[0]
    return get


def figure_files(stem: Path, build: Callable[[], Any], formats: Sequence[str] = style.DEFAULT_FORMATS
                 ) -> list[tuple[Path, Callable[[Any], None], bool]]:
    """Writers of :func:`contin.results.io.atomic_write` for ``<stem>.<format>`` of each of ``formats``, of one figure
    drawn once."""
    get = once(build)
    return [(stem.with_name(f"{stem.name}.{fmt}"), (lambda fh, f=fmt: style.write(get(), fh, f)), True)
            for fmt in formats]


def _title(text: str) -> str:
    """``text`` with each of its lines broken after commas to at most :data:`TITLE_LINE` characters."""
    from ..plot.branches import wrapped

    return "\n".join(wrapped(line, TITLE_LINE) for line in text.split("\n"))


def diagram_figure(draw: Callable[[Any], Any], fr: framing.Frame | None = None) -> tuple[Any, Any]:
    """A diagram drawn by ``draw(ax)``, framed by ``fr`` (:attr:`contin.plot.framing.Frame.layout`): on one
    Axes; on one Axes limited to the part with the snaps; or on two, the whole path above with the
    part's box marked, the part below (``draw`` is called for each; the lower one keeps no legend).
    Call inside :func:`contin.plot.style.context`.

    Returns
    -------
    (Figure, Axes)
        The figure and its main Axes (with the title and the legend).
    """
    layout = fr.layout if fr is not None else None
    if layout != "detail":
        fig, ax = style.figure(layout=style.beside_layout())
        draw(ax)
        if layout == "limits":
            framing.limit_to(ax, fr)
        ax.set_title(_title(ax.get_title()))
        return fig, ax
    fig, (ax, detail) = style.figure(style.WIDTH, style.HEIGHT + DETAIL_HEIGHT, nrows=2, layout=style.beside_layout(),
                                     gridspec_kw={"height_ratios": [style.HEIGHT, DETAIL_HEIGHT]})
    draw(ax)
    draw(detail)
    if detail.get_legend() is not None:
        detail.get_legend().remove()
    framing.show_detail(ax, detail, fr.detail, title="the snaps (detail of the grey box)")
    ax.set_title(_title(ax.get_title()))
    return fig, ax


def _frame_of(result: Any) -> framing.Frame:
    """The frame of a :class:`contin.app.scene.TraceResult`'s diagram."""
    y = result.y if result.y is not None else next(iter(result.branches[0].observables), "p") \
        if result.branches else "p"
    jumps = [(j, a, b) for j, (a, b) in zip(result.jumps, result.jump_observables)]
    return framing.frame(result.branches, result.x, y, jumps, result.plot_options.get("scale"))


def trace_figure(model_name: str, result: Any) -> Any:
    """The diagram of a :class:`contin.app.scene.TraceResult` (its ``plot`` or :meth:`~TraceResult.draw`)."""
    with style.context():
        fig, ax = diagram_figure(result.plot if result.plot is not None else result.draw, _frame_of(result))
        lines = [t for t in ax.get_title().split("\n") if t]
        if not result.plot_options.get("title"):
            lines.insert(0, model_name)
        if result.status != "ok":
            lines[0] += f" [{result.status}]"
        ax.set_title("\n".join(lines))
    return fig


def shapes_figure(result: Any) -> Any:
    """The model's shapes figure (:attr:`contin.app.scene.TraceResult.draw_shapes`)."""
    with style.context():
        fig, _ = style.figure(style.WIDTH, style.HEIGHT, nrows=0)
        result.draw_shapes(fig)
        title = result.plot_options.get("title")
        if style.in_one_column(fig):
            fig.set_layout_engine(style.beside_layout())
            if title:  # a figure text, which the layout keeps above the panels; the title's size of the style
                fig.text(0.5, 1.0 - style.PAD / 72.0 / fig.get_figheight(), _title(title), ha="center", va="top",
                         fontsize=style.RC["figure.titlesize"])
        elif title:
            fig.suptitle(_title(title))
    return fig


def _draw_overlay(ax: Any, runs: Sequence[Any], x: str, y: str, labels: Sequence[str], title: str) -> None:
    """Saved runs on one Axes, one colour each, each styled by its own control and in its own units
    (its ``scale``), its snaps as arrows; the legend names the runs, then what is drawn."""
    from ..plot.branches import (SPECIAL_KINDS, add_legend, axis_label, branch_handle, draw_branch, draw_jumps,
                                 legend_entries, mark_special_points)

    drawn: set[str] = set()
    handles, points, snaps = [], {}, 0
    for k, run in enumerate(runs):
        color = style.COLORS[k % len(style.COLORS)]
        for br in run.branches:
            if len(br):
                drawn |= draw_branch(ax, br, x, y, color=color, stability=run.stability,
                                     scale=run.plot_options.get("scale"))
        handles.append(branch_handle(color, labels[k]))
    for run in runs:
        options = run.plot_options
        for br in run.branches:
            mark_special_points(ax, br, x, y, kinds=options.get("special_kinds", SPECIAL_KINDS),
                                scale=options.get("scale"), symbols=options.get("symbols"),
                                same_as=options.get("same_as"), handles=points)
        if run.branches:
            snaps += draw_jumps(ax, run.jumps, x, y, run.branches[0], scale=options.get("scale"))
    first = runs[0]
    if first.plot_options.get("zero_line"):
        ax.axhline(0.0, color="0.75", lw=0.6, zorder=0)
    ref = first.branches[0]
    names = [ref.meta.get("parameter_name", "p") if axis == "p" else axis for axis in (x, y)]
    ax.set_xlabel(axis_label(names[0], first.plot_options.get("axis_labels")))
    ax.set_ylabel(axis_label(names[1], first.plot_options.get("axis_labels")))
    ax.set_title(title)
    controls = {run.control for run in runs}
    heading = None
    if drawn & {"stable", "unstable"}:
        heading = f"{controls.pop()} control" if len(controls) == 1 and None not in controls else \
            "each run under its own control"
    add_legend(ax, legend_entries(handles, drawn, points, snaps > 0), title=heading)


def saved_runs_figure(runs: Sequence[Any], x: str, y: str | None = None) -> Any:
    """Saved runs (:class:`contin.app.saved.SavedRun`) drawn again: one run as it was drawn (its branches, labels,
    snaps and options), several overlaid (:func:`_draw_overlay`), titled and labelled by
    :func:`contin.app.saved.overlay_labels`."""
    from ..plot.branches import plot_branches
    from .saved import overlay_labels

    first = runs[0]
    y = y if y is not None else next(iter(first.branches[0].observables), "p") if first.branches else "p"
    if len(runs) == 1:
        options = dict(first.plot_options)
        options.setdefault("title", f"{first.summary.get('model', '?')}: {first.path.name or first.path}")
        labels = first.labels if len(first.labels) == len(first.branches) and len(first.branches) > 1 else None

        def draw(ax: Any) -> Any:
            return plot_branches(first.branches, x=x, y=y, ax=ax, jumps=first.jumps, labels=labels,
                                 stability=first.stability, **options)
    else:
        title, run_labels = overlay_labels(runs)

        def draw(ax: Any) -> Any:
            return _draw_overlay(ax, runs, x, y, run_labels, title)
    fr = framing.combine([framing.frame(run.branches, x, y, run.jumps, run.plot_options.get("scale"))
                          for run in runs])
    with style.context():
        fig, _ = diagram_figure(draw, fr)
    return fig
