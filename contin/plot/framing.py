"""Where to look on a bifurcation diagram: the part of the path with its snaps, when the rest would
bury it.

A structure that stiffens after its snaps (a cap once it has everted) can take the last stretch of
its path to a hundred times the snap loads, and axes that hold all of it leave the folds in a smudge
at the origin. :func:`frame` finds the part of a diagram a reader needs: the path from its start to
its last snap under the diagram's own control (the last fold in a branch's parameter, the last
landing of a jump), with every point on it. When the whole path reaches :data:`SPREAD` times farther
in x or in y, :attr:`Frame.layout` says how to show that part: as a detail panel under the whole
path (:func:`show_detail`, the panel's box marked grey on the whole path: the studies' detail panels
use it too), or, when the part spans the whole path in one direction, by limiting the axes to it in
the other (:func:`limit_to`, which says where the path goes off the axes).

Only the branches' stored data are read: nothing is computed again. matplotlib is imported by the
functions that draw.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..results.branch import Branch
from .branches import _axis_name, _coordinate, _folds_in, _jump_parameter

__all__ = ["Box", "Frame", "frame", "combine", "show_detail", "limit_to", "SPREAD", "MARGIN", "COVER"]

#: ``((x0, x1), (y0, y1))``: a rectangle of a diagram, in the units its axes show.
Box = tuple[tuple[float, float], tuple[float, float]]
#: The whole path reaching this many times farther than its part up to the last snap (in x or in y)
#: buries the snaps: the figure shows that part on its own.
SPREAD = 2.5
#: Room around the part shown, a fraction of its size on each side.
MARGIN = 0.1
#: A part spanning this fraction of the whole path in one direction is shown by limiting the axes in
#: the other (one panel); a part smaller in both gets a detail panel.
COVER = 0.7


@dataclass(frozen=True)
class Frame:
    """The part of a diagram with its snaps (:attr:`region`) and all of it (:attr:`whole`).

    Attributes
    ----------
    region : Box
        The path from its start to its last snap under its control, with the points marked on it;
        the whole diagram when no snap is marked.
    whole : Box
        Every stored point drawn and every snap's ends.
    farthest : dict of str to (float, float)
        The point of the whole path farthest ``"left"``, ``"right"``, ``"bottom"`` and ``"top"``.
    """

    region: Box
    whole: Box
    farthest: dict[str, tuple[float, float]]

    @property
    def layout(self) -> str | None:
        """``"detail"`` (a second panel), ``"limits"`` (one panel, its axes limited) or None (the whole path
        shows the snaps well)."""
        spans = [(r[1] - r[0], w[1] - w[0]) for r, w in zip(self.region, self.whole)]
        if any(r <= 0.0 or not math.isfinite(r) for r, _ in spans):
            return None
        if all(w <= SPREAD * r for r, w in spans):
            return None
        return "limits" if any(r >= COVER * w for r, w in spans) else "detail"

    @property
    def detail(self) -> Box:
        """:attr:`region` with :data:`MARGIN` around it: the limits of a detail panel or of limited axes."""
        return tuple((lo - MARGIN * (hi - lo), hi + MARGIN * (hi - lo)) for lo, hi in self.region)


def _hull(xs: Sequence[np.ndarray], ys: Sequence[np.ndarray]) -> tuple[Box, dict[str, tuple[float, float]]]:
    x, y = np.concatenate([np.ravel(v) for v in xs]), np.concatenate([np.ravel(v) for v in ys])
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    if not x.size:
        return ((0.0, 0.0), (0.0, 0.0)), {}
    at = {side: int(f(v)) for side, f, v in (("left", np.argmin, x), ("right", np.argmax, x),
                                             ("bottom", np.argmin, y), ("top", np.argmax, y))}
    return ((float(x.min()), float(x.max())), (float(y.min()), float(y.max()))), \
        {side: (float(x[i]), float(y[i])) for side, i in at.items()}


def frame(branches: Sequence[Branch], x: str, y: str,
          jumps: Iterable[tuple[Any, Mapping[str, float], Mapping[str, float]]] = (),
          scale: Mapping[str, float] | None = None) -> Frame:
    """The :class:`Frame` of a diagram of :func:`contin.plot_branches`, from the same arguments.

    The snaps under the diagram's control are the folds in each branch's own parameter and the ends
    of the jumps (a branch after the first starts where the jump before it lands, when there are
    jumps).  The region is the path, in the order the branches were traced, from its start to the
    last of them.
    """
    jumps = list(jumps)
    scale = dict(scale or {})
    live = [br for br in branches if len(br)]
    if not live:
        return Frame(((0.0, 0.0), (0.0, 0.0)), ((0.0, 0.0), (0.0, 0.0)), {})
    ref = live[0]
    fx, fy = scale.get(_axis_name(x, ref), 1.0), scale.get(_axis_name(y, ref), 1.0)
    paths = [(br.observable(x) * fx, br.observable(y) * fy) for br in branches]
    marks: list[tuple[float | None, float | None]] = []
    last = None
    for bi, br in enumerate(branches):
        if not len(br):
            continue
        control = br.meta.get("parameter_name", "p")
        snaps = [spt for spt in br.special_points if _folds_in(spt, br) == control]
        marks += [(_coordinate(x, s.p, s.observables, br), _coordinate(y, s.p, s.observables, br)) for s in snaps]
        ends = [min(max(s.index, 0), len(br) - 1) for s in snaps] + ([0] if 1 <= bi <= len(jumps) else [])
        if ends:
            last = (bi, max(ends))
    for jump, obs_from, obs_to in jumps:
        p = _jump_parameter(jump)
        marks += [(_coordinate(x, p, dict(obs), ref), _coordinate(y, p, dict(obs), ref)) for obs in (obs_from, obs_to)]
    marks_x = np.array([mx * fx for mx, my in marks if mx is not None and my is not None])
    marks_y = np.array([my * fy for mx, my in marks if mx is not None and my is not None])
    whole, farthest = _hull([*(px for px, _ in paths), marks_x], [*(py for _, py in paths), marks_y])
    if last is None:
        return Frame(whole, whole, farthest)
    b, i = last
    upto = [(px, py) for px, py in paths[:b]] + [(paths[b][0][:i + 1], paths[b][1][:i + 1])]
    region, _ = _hull([*(px for px, _ in upto), marks_x], [*(py for _, py in upto), marks_y])
    return Frame(region, whole, farthest)


def combine(frames: Sequence[Frame]) -> Frame:
    """One frame for diagrams drawn on one axes (an overlay of runs): the hull of their regions and of
    their wholes, where the region of a diagram whose whole path shows its snaps well (no
    :attr:`~Frame.layout` of its own) is its whole path: none of it may be cut off."""
    def hull(boxes: Sequence[Box]) -> Box:
        return ((min(b[0][0] for b in boxes), max(b[0][1] for b in boxes)),
                (min(b[1][0] for b in boxes), max(b[1][1] for b in boxes)))

    sides = {"left": (0, min), "right": (0, max), "bottom": (1, min), "top": (1, max)}
    farthest = {}
    for side, (k, pick) in sides.items():
        points = [f.farthest[side] for f in frames if side in f.farthest]
        if points:
            farthest[side] = pick(points, key=lambda pt: pt[k])
    return Frame(hull([f.region if f.layout else f.whole for f in frames]), hull([f.whole for f in frames]), farthest)


def show_detail(ax: Any, detail: Any, box: Box, title: str = "detail of the grey box",
                scale: tuple[float, float] = (1.0, 1.0)) -> None:
    """Make ``detail`` (an Axes drawn like ``ax``) the detail of the rectangle ``box`` of ``ax``: its limits
    are ``box``, the rectangle is drawn grey on ``ax`` (below the curves), and ``detail`` is titled
    ``title``.  ``scale``: the factors ``detail`` shows x and y with (``(1e3, 1)`` for an abscissa in units
    of 1e-3 there)."""
    from matplotlib.patches import Rectangle

    from . import style

    (x0, x1), (y0, y1) = box
    ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ec=style.GREY, lw=0.7, zorder=1.5))
    detail.set_xlim(scale[0] * x0, scale[0] * x1)
    detail.set_ylim(scale[1] * y0, scale[1] * y1)
    detail.set_title(title, fontsize="small")


def limit_to(ax: Any, fr: Frame) -> None:
    """Limit the axes of ``ax`` to the frame's :attr:`~Frame.detail` in each direction where the whole path
    reaches much farther (:data:`SPREAD`), and say at the edge where the path goes off them and how far
    it goes (an arrow and the farthest value)."""
    from . import style

    box = fr.detail
    for k, (set_lim, lo_side, hi_side) in enumerate(((ax.set_xlim, "left", "right"), (ax.set_ylim, "bottom", "top"))):
        (r0, r1), (w0, w1) = fr.region[k], fr.whole[k]
        if w1 - w0 <= SPREAD * (r1 - r0):
            continue
        lo, hi = box[k]
        set_lim(lo, hi)
        for side, edge, beyond in ((lo_side, lo, w0 < lo), (hi_side, hi, w1 > hi)):
            if not beyond or side not in fr.farthest:
                continue
            point = fr.farthest[side]
            value = point[k]
            at = (point[0], edge) if k == 1 else (edge, point[1])
            ax.annotate(_exit_text(side, value, at, ax), xy=at, xytext=_exit_offset(side, at, ax), textcoords="offset points",
                        ha=_exit_align(side, at, ax)[0], va=_exit_align(side, at, ax)[1], fontsize="small",
                        color=style.GREY, annotation_clip=False,
                        bbox={"boxstyle": "square,pad=0.1", "fc": "w", "ec": "none", "alpha": 0.8})


_ARROWS = {"right": r"$\rightarrow$", "left": r"$\leftarrow$", "top": r"$\uparrow$", "bottom": r"$\downarrow$"}


def _exit_offset(side: str, at: tuple[float, float], ax: Any) -> tuple[float, float]:
    """Where the text sits from the path's exit point, in points: inside the axes, beside the path."""
    if side in ("top", "bottom"):
        return (-3.0 if _past_middle(at, ax) else 3.0), (-3.0 if side == "top" else 3.0)
    return (-3.0 if side == "right" else 3.0), 0.0


def _past_middle(at: tuple[float, float], ax: Any) -> bool:
    lo, hi = ax.get_xlim()
    return at[0] > 0.5 * (lo + hi)


def _exit_text(side: str, value: float, at: tuple[float, float], ax: Any) -> str:
    """The arrow pointing off the axes and how far the path goes; at the top or bottom the arrow is beside
    the path, on the side of the text that faces the path."""
    if side in ("top", "bottom") and _past_middle(at, ax):
        return f"to {value:.3g} {_ARROWS[side]}"
    return f"{_ARROWS[side]} to {value:.3g}"


def _exit_align(side: str, at: tuple[float, float], ax: Any) -> tuple[str, str]:
    if side in ("top", "bottom"):
        return ("right" if _past_middle(at, ax) else "left"), ("top" if side == "top" else "bottom")
    return ("right" if side == "right" else "left"), "center"
