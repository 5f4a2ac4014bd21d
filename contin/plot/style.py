"""One look for every figure of the project: the command line's diagrams and shapes, ``contin plot``, the studies.

A figure is drawn inside :func:`context` (the rcParams below: Times-like STIX text and symbols, 9-point labels, thin axes, ticks inside, a colour-blind-safe colour cycle) on a :func:`figure` (a
matplotlib Figure with its own Agg canvas: no pyplot state, no GUI backend) and written by :func:`save`
(``<stem>.png``, and ``<stem>.pdf`` beside it when asked, atomically) or :func:`write` (one format into
an open file).  The command line writes PNG unless PDF is asked for (:data:`DEFAULT_FORMATS`); the
studies write both (:data:`FORMATS`).  A figure is laid out by matplotlib's constrained layout, or, for
panels in one column with their legends beside them (the command line's diagrams and shapes), by
:func:`beside_layout`, which places them alike in one pass; :func:`write` lays a figure out once, at the
resolution it is written at.  A study, a process of its own, may instead call :func:`use` once to make the style the
process-wide default.

The special points of a bifurcation diagram have one marker each (:data:`MARKERS`): shapes, sizes and
z-orders chosen so that coinciding points stay visible (the larger hollow marks above, the smaller
filled ones inside them).  Stable branches are solid and unstable ones dashed (:data:`STABLE`,
:data:`UNSTABLE`).

matplotlib is imported inside the functions only: importing this module costs nothing.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

__all__ = ["COLORS", "RED", "GREY", "MARKERS", "STABLE", "UNSTABLE", "UNKNOWN", "DPI", "FORMATS", "DEFAULT_FORMATS",
           "PAD", "beside_layout", "in_one_column", "WIDTH", "HEIGHT", "RC", "context", "use", "figure", "save", "write", "marker_style"]

#: Branch colours (Okabe and Ito's colour-blind-safe set; black is kept for the special points).
COLORS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#332288", "#999933")
#: The colour of bifurcations into other modes.
RED = "#C0143C"
#: Reference lines and annotations.
GREY = "0.45"

#: Line styles by stability.
STABLE = {"ls": "-", "lw": 1.5}
UNSTABLE = {"ls": (0, (4.0, 2.2)), "lw": 1.2}
UNKNOWN = {"ls": "-", "lw": 0.9}

#: Marker of each kind of special point: ``marker``, size, face (``"w"`` hollow, ``"k"`` filled), z-order.
#: Hollow marks are larger and drawn above the filled ones, so a fold on top of a limit point shows both.
MARKERS: dict[str, dict[str, Any]] = {
    "fold": {"marker": "o", "ms": 6.5, "mfc": "w", "mec": "k", "mew": 1.0, "zorder": 6},          # the path turns back in x
    "limit point": {"marker": "^", "ms": 5.0, "mfc": "k", "mec": "k", "mew": 0.8, "zorder": 7},   # a limit load of another quantity
    "branch_point": {"marker": "s", "ms": 6.5, "mfc": "w", "mec": "k", "mew": 1.0, "zorder": 6},
    # smaller than the fold's circle and above it: an event where the path folds shows inside the circle
    "event": {"marker": "d", "ms": 5.5, "mfc": "w", "mec": "0.25", "mew": 0.9, "zorder": 6.5},
    "jump": {"marker": "x", "ms": 6.0, "mfc": "none", "mec": "k", "mew": 1.1, "zorder": 8},
    # the largest mark, so the lowest: a fold or limit point on a bifurcation shows inside the star
    "bifurcation": {"marker": "*", "ms": 11.0, "mfc": RED, "mec": RED, "mew": 0.6, "zorder": 5.5},
}

#: Resolution of the PNG (the PDF is vector).
DPI = 200
#: Every format a figure is written in: the studies write both.
FORMATS = ("png", "pdf")
#: What the command line writes unless PDF is asked for: a PDF costs as much again as the PNG (its fonts
#: are embedded), and a picture to look at needs none.
DEFAULT_FORMATS = ("png",)
#: Size of a one-panel figure in inches, its legend beside the axes (a page's width; fonts are 9 pt at this size).
WIDTH, HEIGHT = 6.0, 3.7

RC: dict[str, Any] = {
    "font.family": "serif",
    "font.serif": ["STIXGeneral", "DejaVu Serif"],
    "mathtext.fontset": "stix",  # Times-like text and symbols (matplotlib's own STIX fonts: no font to install)
    "axes.formatter.use_mathtext": False,  # plain tick labels: mathtext ones cost a tenth of a second a figure
    "font.size": 9.0,
    "axes.titlesize": 9.0,
    "figure.titlesize": 9.5,
    "axes.labelsize": 9.5,
    "legend.fontsize": 7.5,
    "legend.title_fontsize": 7.5,
    "xtick.labelsize": 8.0,
    "ytick.labelsize": 8.0,
    "axes.linewidth": 0.7,
    "xtick.direction": "in",
    "ytick.direction": "in",
    "xtick.top": True,
    "ytick.right": True,
    "xtick.major.width": 0.6,
    "ytick.major.width": 0.6,
    "xtick.minor.visible": False,  # minor ticks double the tick artists: a tenth of a second a figure
    "ytick.minor.visible": False,
    "xtick.minor.width": 0.5,
    "ytick.minor.width": 0.5,
    "lines.linewidth": 1.4,
    "lines.markersize": 5.0,
    "axes.prop_cycle": None,  # filled in by _rc(): a cycler needs matplotlib
    "legend.frameon": True,
    "legend.framealpha": 0.9,
    "legend.edgecolor": "0.8",
    "legend.fancybox": False,
    "legend.handlelength": 2.6,
    "legend.borderaxespad": 0.4,
    "figure.dpi": 100,
    "savefig.dpi": DPI,
    "pdf.fonttype": 42,  # TrueType in the PDF: editable text that journals accept (no Type 3 fonts)
    "pdf.compression": 6,
}


def _rc() -> dict[str, Any]:
    from cycler import cycler

    return {**RC, "axes.prop_cycle": cycler(color=list(COLORS))}


@contextmanager
def context() -> Iterator[None]:
    """The project's rcParams for the figures drawn and saved inside (the global ones are restored after)."""
    import matplotlib

    with matplotlib.rc_context(_rc()):
        yield


def use() -> None:
    """Make the project's style the process-wide default (for a study, a process of its own)."""
    import matplotlib

    matplotlib.use("Agg")
    matplotlib.rcParams.update(_rc())


def figure(width: float = WIDTH, height: float = HEIGHT, nrows: int = 1, ncols: int = 1, *,
           squeeze: bool = True, **kwargs: Any) -> tuple[Any, Any]:
    """A Figure with its own Agg canvas and a grid of axes, like ``pyplot.subplots`` without pyplot.

    Draw inside :func:`context` (or after :func:`use`): artists read the rcParams when they are made.
    The layout is matplotlib's constrained one unless ``layout=`` says otherwise; ``nrows=0`` gives the
    figure without axes (``(fig, None)``).  Other ``kwargs`` go to ``Figure.subplots`` (``sharex``, ``gridspec_kw``, ...).

    Returns
    -------
    (Figure, Axes or array of Axes)
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout=kwargs.pop("layout", "constrained"))
    FigureCanvasAgg(fig)
    if nrows == 0:  # the caller adds its own axes
        return fig, None
    axes = fig.subplots(nrows, ncols, squeeze=squeeze, **kwargs)
    return fig, axes


#: Room in points between the figure's edge and what is drawn, and between stacked panels (as the
#: constrained layout leaves).
PAD = 3.0


def _tick_labels(axis: Any, renderer: Any) -> tuple[float, float]:
    """The largest width and height (pixels) of the tick labels ``axis`` will draw at its current size and
    the room between them and the axis, from its locator and formatter, measured as its first tick's
    label (no tick is moved: the draw does that once)."""
    lo, hi = sorted(axis.get_view_interval())
    slack = 1e-9 * max(hi - lo, 1e-300)
    locs = [v for v in axis.get_major_locator()() if lo - slack <= v <= hi + slack]
    tick = axis.get_major_ticks(1)[0]
    if not locs or not tick.label1.get_visible():
        return 0.0, 0.0
    label, shown = tick.label1, tick.label1.get_text()
    sizes = []
    for text in axis.get_major_formatter().format_ticks(locs):
        label.set_text(text)
        sizes.append(label.get_window_extent(renderer))
    label.set_text(shown)
    return max(b.width for b in sizes), max(b.height for b in sizes)


def _tick_room(axis: Any) -> float:
    """Points between an axis and its tick labels: the label pad, and the ticks when they point out."""
    return axis.get_major_ticks(1)[0].get_pad() + axis.get_tick_padding()


def _extent(artist: Any, renderer: Any) -> Any:
    """The window extent of a visible artist with something to show, else None."""
    shown = artist is not None and artist.get_visible() and (not hasattr(artist, "get_text") or artist.get_text())
    return artist.get_window_extent(renderer) if shown else None


def _layout_engine_class() -> type:
    from matplotlib.layout_engine import LayoutEngine

    class BesideLayout(LayoutEngine):
        """Panels in one column, each legend beside its panel on the right, titles above: placed in one
        pass from the sizes of their texts, as the constrained layout places them, without its trial
        passes over every tick and artist."""

        _adjust_compatible = False
        _colorbar_gridspec = False

        def execute(self, fig: Any) -> None:
            renderer = fig.canvas.get_renderer()
            pt = fig.dpi / 72.0
            width, height = fig.bbox.width, fig.bbox.height
            pad = PAD * pt
            axes = [ax for ax in fig.axes if ax.get_visible() and ax.axison]
            spec = axes[0].get_subplotspec()
            ratios = list((spec.get_gridspec().get_height_ratios() if spec is not None else None) or [1.0] * len(axes))
            heading = max((b.height for b in (_extent(t, renderer) for t in fig.texts) if b is not None), default=0.0)
            above, below, left, right = [], [], [], []
            for ax in axes:
                box, title = ax.get_window_extent(renderer), _extent(ax.title, renderer)
                above.append(max(title.y1 - box.y1, 0.0) if title is not None else 0.0)
                xlabel, ylabel = _extent(ax.xaxis.label, renderer), _extent(ax.yaxis.label, renderer)
                tick_w, tick_h = _tick_labels(ax.xaxis, renderer)
                below.append((tick_h + _tick_room(ax.xaxis) * pt if tick_h else 0.0)
                             + (xlabel.height + ax.xaxis.labelpad * pt if xlabel is not None else 0.0))
                legend = _extent(ax.get_legend(), renderer)
                right.append(max(legend.width if legend is not None else 0.0, 0.5 * tick_w))
                left.append(ylabel.width + ax.yaxis.labelpad * pt if ylabel is not None else 0.0)
            free = height - heading - 2 * pad - sum(above) - sum(below) - pad * (len(axes) - 1)
            top = height - heading - pad
            spans = []
            for up, down, r in zip(above, below, ratios):
                h = free * r / sum(ratios[:len(axes)])
                spans.append((top - up - h, h))
                top -= up + h + down + pad
            # the tick labels of y depend on the panel's height, known now
            for k, (ax, (y0, h)) in enumerate(zip(axes, spans)):
                ax.set_position([0.0, y0 / height, 1.0, h / height])
                tick_w, _ = _tick_labels(ax.yaxis, renderer)
                left[k] += tick_w + _tick_room(ax.yaxis) * pt if tick_w else 0.0
            x0 = max(left) + pad
            # the legend is anchored at 1.02 of the panel's width: the panel takes what the legend leaves
            w = (width - x0 - max(right) - pad) / (1.02 if any(ax.get_legend() for ax in axes) else 1.0)
            for ax, (y0, h) in zip(axes, spans):
                ax.set_position([x0 / width, y0 / height, w / width, h / height])

    return BesideLayout


def in_one_column(fig: Any) -> bool:
    """Whether the panels of ``fig`` (the Axes with their axis on) stand in one column of one grid, as
    :func:`beside_layout` places them."""
    specs = [ax.get_subplotspec() for ax in fig.axes if ax.axison]
    return bool(specs) and all(spec is not None and spec.get_gridspec().ncols == 1 for spec in specs)


def beside_layout() -> Any:
    """A layout engine for panels in one column with their legends beside them (a diagram, a shapes figure
    without a mode): :class:`matplotlib.layout_engine.LayoutEngine` placing them in one pass."""
    return _layout_engine_class()()


def write(fig: Any, fh: Any, fmt: str) -> None:
    """Write ``fig`` in format ``fmt`` (``"png"`` or ``"pdf"``) into the open binary file ``fh``.

    The PDF carries no creation date, so the same figure gives the same bytes.
    """
    metadata = {"CreationDate": None} if fmt == "pdf" else {"Software": None}
    # zlib level 3 instead of Pillow's 6: the default trace's diagram encodes in 0.05 s instead of 0.08 s,
    # for a file 5 % larger
    extra = {"pil_kwargs": {"compress_level": 3}} if fmt == "png" else {}
    with context():
        _lay_out(fig)
        fig.savefig(fh, format=fmt, dpi=DPI, metadata=metadata, **extra)


def _lay_out(fig: Any) -> None:
    """Place ``fig``'s panels by its layout engine once, at the resolution it is written at, and leave it
    without one: savefig then draws once (with an engine it first draws without rendering, to lay out),
    with the text sizes the layout measured, and every further format keeps the same places."""
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    engine = fig.get_layout_engine()
    if engine is None or isinstance(engine, PlaceHolderLayoutEngine):
        return
    dpi = fig.dpi
    fig.dpi = DPI
    try:
        engine.execute(fig)
    finally:
        fig.dpi = dpi
    fig.set_layout_engine("none")


def save(fig: Any, path: str | os.PathLike, formats: Sequence[str] = FORMATS) -> list[Path]:
    """Write ``fig`` as ``path`` with each suffix of ``formats`` (``x.png`` and ``x.pdf``), atomically.

    ``path`` may carry a suffix or not (``out/diagram`` and ``out/diagram.png`` write the same files).

    Returns
    -------
    list of Path
        The files written.
    """
    from ..results.io import atomic_write

    stem = Path(path)
    if stem.suffix.lower().lstrip(".") in ("png", "pdf", "svg", "eps"):
        stem = stem.with_suffix("")
    return atomic_write([(stem.with_name(f"{stem.name}.{fmt}"), (lambda fh, f=fmt: write(fig, fh, f)))
                         for fmt in formats], binary=True)


def marker_style(kind: str, located: bool = True, color: str | None = None) -> dict[str, Any]:
    """Keyword arguments of ``Axes.plot`` for a special point of ``kind`` (a key of :data:`MARKERS`).

    An unlocated point (only bracketed) is drawn hollow whatever its kind; ``color`` replaces black.
    """
    style = dict(MARKERS[kind])
    if color is not None:
        style["mec"] = color
        if style["mfc"] not in ("w", "none"):
            style["mfc"] = color
    if not located:
        style["mfc"] = "none"
    return style
