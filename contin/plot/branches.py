"""Plots of branches and snaps: each branch drawn smooth from its stored tangents, stable solid and
unstable dashed, its special points marked, its snaps as arrows (:func:`plot_branches` and its pieces).

Plotting only reads results; it never computes them.  The graph of branches and jumps is
:func:`contin.diagram` (:mod:`contin.analyses.diagram`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from ..analyses.jump import JumpResult
from ..results.branch import Branch, SpecialPoint

__all__ = ["plot_branches", "smooth_path", "stability_pieces", "draw_branch", "mark_special_points", "draw_jumps",
           "axis_label", "branch_handle", "legend_entries", "add_legend", "wrapped", "comma_parts", "SPECIAL_KINDS"]


def _coordinate(name: str, p: float, observables: dict, br: Branch) -> float | None:
    """A plot coordinate: the parameter (as ``"p"`` or by its name) or a named observable."""
    if name in ("p", br.meta.get("parameter_name")):
        return p
    return observables.get(name)


def _stability_of(br: Branch, stability: str | None) -> np.ndarray | None:
    """Per-point stability under ``stability`` (default: the primary label); None when unknown."""
    if stability is None:
        return br.stable
    return br.stable_under(stability) if stability in br.stability_by else None


#: Points drawn inside each cubic piece between two stored points.
HERMITE_SAMPLES = 8
#: A stored tangent is trusted where it points forward along its piece (cosine with the chord above this)
#: and its length times the arclength is within this factor of the chord (in the plot's own scale).
_MIN_CHORD_COS, _MAX_LENGTH_RATIO = 0.0, 4.0


def hermite_piece(p0: Sequence[float], p1: Sequence[float], m0: Sequence[float], m1: Sequence[float],
                  tau: np.ndarray | float) -> np.ndarray:
    """The cubic Hermite curve from ``p0`` to ``p1`` with end derivatives ``m0``, ``m1`` (per unit ``tau``).

    ``P(0) = p0``, ``P(1) = p1``, ``P'(0) = m0``, ``P'(1) = m1``; with points of a branch and their
    tangents ``dX/ds`` times the arclength ``s1 - s0`` between them this is the branch between the
    stored points to third order in the step.

    Returns
    -------
    ndarray (len(tau), dim)
    """
    t = np.atleast_1d(np.asarray(tau, dtype=float))[:, None]
    p0, p1, m0, m1 = (np.asarray(v, dtype=float)[None, :] for v in (p0, p1, m0, m1))
    t2, t3 = t * t, t * t * t
    return ((2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * p1 + (t3 - t2) * m1)


def _trusted_pieces(x: np.ndarray, y: np.ndarray, dx: np.ndarray | None, dy: np.ndarray | None,
                    s: np.ndarray) -> np.ndarray:
    """Which pieces between consecutive points may be drawn as cubics (:func:`smooth_path`'s rule)."""
    n = x.size
    if n < 2 or dx is None or dy is None:
        return np.zeros(max(n - 1, 0), dtype=bool)
    dx, dy, s = np.asarray(dx, dtype=float), np.asarray(dy, dtype=float), np.asarray(s, dtype=float)
    ds = np.diff(s)
    # the plot's own scale: a tangent is judged against the chord in units of each axis' span
    span_x = float(np.ptp(x[np.isfinite(x)])) if np.isfinite(x).any() else 1.0
    span_y = float(np.ptp(y[np.isfinite(y)])) if np.isfinite(y).any() else 1.0
    sx, sy = 1.0 / (span_x or 1.0), 1.0 / (span_y or 1.0)
    cx, cy = np.diff(x) * sx, np.diff(y) * sy
    chord = np.hypot(cx, cy)

    def along(tx: np.ndarray, ty: np.ndarray) -> np.ndarray:
        length = np.hypot(tx * sx, ty * sy)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            cos = (tx * sx * cx + ty * sy * cy) / (length * chord)
            ratio = length * ds / chord
        return (cos > _MIN_CHORD_COS) & (ratio < _MAX_LENGTH_RATIO) & (ratio > 1.0 / _MAX_LENGTH_RATIO)
    ok = (np.isfinite(dx[:-1]) & np.isfinite(dy[:-1]) & np.isfinite(dx[1:]) & np.isfinite(dy[1:])
          & np.isfinite(ds) & (ds > 0) & (chord > 0))
    return ok & along(dx[:-1], dy[:-1]) & along(dx[1:], dy[1:])


def _densified(x: np.ndarray, y: np.ndarray, dx: np.ndarray | None, dy: np.ndarray | None, s: np.ndarray,
               curved: np.ndarray, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """The points with ``samples - 1`` points of its cubic inside each piece marked ``curved``."""
    if not curved.any():
        return x, y
    dx, dy, s = np.asarray(dx, dtype=float), np.asarray(dy, dtype=float), np.asarray(s, dtype=float)
    ds = np.diff(s)
    n = x.size
    tau = np.linspace(0.0, 1.0, samples + 1)[1:-1]
    h00, h10, h01, h11 = (2 * tau**3 - 3 * tau**2 + 1, tau**3 - 2 * tau**2 + tau, -2 * tau**3 + 3 * tau**2,
                          tau**3 - tau**2)
    i = np.flatnonzero(curved)
    inner_x = (np.outer(x[i], h00) + np.outer(dx[i] * ds[i], h10) + np.outer(x[i + 1], h01)
               + np.outer(dx[i + 1] * ds[i], h11))
    inner_y = (np.outer(y[i], h00) + np.outer(dy[i] * ds[i], h10) + np.outer(y[i + 1], h01)
               + np.outer(dy[i + 1] * ds[i], h11))
    # interleave: point k, then the inner points of piece k (when it is curved)
    count = np.ones(n, dtype=int)
    count[i] += tau.size
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    X, Y = np.empty(int(count.sum())), np.empty(int(count.sum()))
    X[start], Y[start] = x, y
    slots = start[i][:, None] + 1 + np.arange(tau.size)[None, :]
    X[slots], Y[slots] = inner_x, inner_y
    return X, Y


def smooth_path(x: np.ndarray, y: np.ndarray, dx: np.ndarray | None, dy: np.ndarray | None, s: np.ndarray,
                samples: int = HERMITE_SAMPLES) -> tuple[np.ndarray, np.ndarray]:
    """The polyline through the points ``(x, y)`` with each piece between consecutive points a cubic Hermite
    curve (:func:`hermite_piece`) whose end derivatives are the tangents ``(dx, dy)`` (per unit ``s``)
    times ``s[i+1] - s[i]``; straight where a tangent is missing (None or NaN) or does not fit the
    piece (it points backwards, or its length times the arclength is not within a factor 4 of the
    chord, both in the plot's own scale: a tangent stored in other units, a jump between branches).

    Every stored point is on the result; ``samples - 1`` points are added inside each curved piece.
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.size < 2 or dx is None or dy is None or samples < 2:
        return x, y
    return _densified(x, y, dx, dy, s, _trusted_pieces(x, y, dx, dy, np.asarray(s, dtype=float)), samples)


def stability_pieces(x: np.ndarray, y: np.ndarray, dx: np.ndarray | None, dy: np.ndarray | None, s: np.ndarray,
                     stable: Sequence[bool] | np.ndarray | None, cuts: Iterable[float] = (),
                     samples: int = HERMITE_SAMPLES) -> list[tuple[np.ndarray, np.ndarray, bool | None]]:
    """A path drawn smooth (:func:`smooth_path`) and cut into runs of equal stability, for solid and
    dashed lines.

    Parameters
    ----------
    x, y, dx, dy, s, samples
        As for :func:`smooth_path` (the tangents are judged against the whole path's spans).
    stable : sequence of bool, optional
        Stability at each point; None: one run of unknown stability.
    cuts : iterable of float
        Arclengths where the stability may change, e.g. of the located folds and bifurcations: where
        it differs at stored points ``i`` and ``i + 1``, the runs meet at the first cut strictly
        between ``s[i]`` and ``s[i + 1]``, on the piece's cubic; without one, at point ``i + 1``.

    Returns
    -------
    list of (X, Y, stable)
        In path order; each run ends on the sample the next one starts on.
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n = x.size
    if stable is None or n < 2:
        return [(*smooth_path(x, y, dx, dy, s, samples), None)]
    st = [bool(v) for v in stable]
    s = np.asarray(s, dtype=float)
    curved = _trusted_pieces(x, y, dx, dy, s) if samples >= 2 else np.zeros(n - 1, dtype=bool)
    cut = np.sort(np.array([c for c in cuts if c is not None and math.isfinite(c)], dtype=float))

    def through(a: int, b: int) -> tuple[np.ndarray, np.ndarray]:  # stored points a..b, smooth
        sl = slice(a, b + 1)
        return _densified(x[sl], y[sl], None if dx is None else np.asarray(dx)[sl],
                          None if dy is None else np.asarray(dy)[sl], s[sl], curved[a:b], samples)

    def split(i: int, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Piece ``i`` up to its fraction ``t`` (without its start) and from there (without its end)."""
        if curved[i]:
            h = s[i + 1] - s[i]
            ends = ((x[i], y[i]), (x[i + 1], y[i + 1]), (dx[i] * h, dy[i] * h), (dx[i + 1] * h, dy[i + 1] * h))
            k0, k1 = max(1, round(samples * t)), max(1, round(samples * (1.0 - t)))
            return (hermite_piece(*ends, np.linspace(0.0, t, k0 + 1)[1:]),
                    hermite_piece(*ends, np.linspace(t, 1.0, k1 + 1)[:-1]))
        P = np.array([[x[i] + t * (x[i + 1] - x[i]), y[i] + t * (y[i + 1] - y[i])]])
        return P, P

    pieces: list[tuple[np.ndarray, np.ndarray, bool | None]] = []
    start, head = 0, np.empty((0, 2))
    for i in range(n - 1):
        if st[i] == st[i + 1]:
            continue
        inside = cut[(cut > s[i]) & (cut < s[i + 1])]
        if inside.size:
            before, after = split(i, float((inside[0] - s[i]) / (s[i + 1] - s[i])))
            X, Y = through(start, i)
            pieces.append((np.concatenate([head[:, 0], X, before[:, 0]]),
                           np.concatenate([head[:, 1], Y, before[:, 1]]), st[i]))
            head = after
        else:  # no located point inside: the change shows at the next stored point
            X, Y = through(start, i + 1)
            pieces.append((np.concatenate([head[:, 0], X]), np.concatenate([head[:, 1], Y]), st[i]))
            head = np.empty((0, 2))
        start = i + 1
    if start < n - 1 or head.size:  # a last point alone is already the end of the run before
        X, Y = through(start, n - 1)
        pieces.append((np.concatenate([head[:, 0], X]), np.concatenate([head[:, 1], Y]), st[-1]))
    return pieces


# ---------------------------------------------------------------------------------------------------
# drawing: a branch, its special points, its snaps, the axes and the legend; plot_branches puts them together
# ---------------------------------------------------------------------------------------------------
#: The kinds of special points marked unless the caller says otherwise.
SPECIAL_KINDS = ("fold", "branch_point", "event", "bifurcation")
#: Two marks closer than this fraction of the branch's extent (in both directions) are at the same place.
_SAME_PLACE = 2e-3
#: A snap shorter than this fraction of the diagram's extent (in both directions) is drawn as no arrow.
_SHORTEST_ARROW = 5e-3


def _factor(scale: Mapping[str, float] | None, axis: str, br: Branch) -> float:
    """The factor the axis ``axis`` shows its quantity with (:func:`plot_branches`' ``scale``)."""
    return (scale or {}).get(_axis_name(axis, br), 1.0)


def _scaled_tangent(br: Branch, name: str, factor: float) -> np.ndarray | None:
    t = br.tangent(name)
    return None if t is None else t * factor


def draw_branch(ax: Any, br: Branch, x: str, y: str, *, color: str, stability: str | None = None,
                scale: Mapping[str, float] | None = None, smooth: bool = True, zorder: float | None = None) -> set[str]:
    """Draw one branch on ``ax``: one line per run of equal stability, stable solid and unstable dashed (thin
    when unknown), each drawn smooth from the stored tangents and changing style at the located special
    points (:func:`stability_pieces`).

    Parameters
    ----------
    ax : matplotlib Axes
    br : Branch
    x, y : str
        The quantities on the axes (``"p"`` or the parameter's name for the parameter).
    color : str
        The branch's colour.
    stability : str, optional
        The stability label to style by; default the branch's primary label.  A branch without that
        label is drawn thin (stability unknown).
    scale : mapping of str to float, optional
        Factors by quantity name, as :func:`plot_branches` takes them.
    smooth : bool
        Cubic pieces between stored points where tangents are stored (else straight).
    zorder : float, optional
        Where the lines lie among the plot's artists (default: stable above unstable, both above the grid).

    Returns
    -------
    set of str
        The styles drawn: ``"stable"``, ``"unstable"``, ``"unknown"``.
    """
    from . import style

    fx, fy = _factor(scale, x, br), _factor(scale, y, br)
    xs, ys = br.observable(x) * fx, br.observable(y) * fy
    dx = _scaled_tangent(br, x, fx) if smooth else None
    dy = _scaled_tangent(br, y, fy) if smooth else None
    stored_s = br.s.shape == br.p.shape
    s = br.s if stored_s else np.arange(len(br), dtype=float)
    cuts = [spt.s for spt in br.special_points if spt.located] if stored_s else []
    drawn: set[str] = set()
    for px, py, st in stability_pieces(xs, ys, dx, dy, s, _stability_of(br, stability), cuts):
        kind = "unknown" if st is None else ("stable" if st else "unstable")
        line = {"stable": style.STABLE, "unstable": style.UNSTABLE, "unknown": style.UNKNOWN}[kind]
        ax.plot(px, py, color=color, solid_capstyle="round", dash_capstyle="butt",
                zorder=zorder if zorder is not None else (2 if st is not False else 1.9), **line)
        drawn.add(kind)
    return drawn


def _axis_name(axis: str, br: Branch) -> str:
    """The quantity on an axis: the parameter's name for ``"p"``."""
    return br.meta.get("parameter_name", "p") if axis == "p" else axis


def _folds_in(spt: SpecialPoint, br: Branch) -> str | None:
    """The quantity that folds at a special point: the branch's parameter at a fold of the branch, the
    declared quantity at an extremum that declares one (``contin.extremum(..., folds=...)``); else None."""
    if spt.kind == "fold":
        return spt.info.get("folds") or br.meta.get("parameter_name", "p")
    if spt.kind == "event" and spt.info.get("folds") is not None:
        return str(spt.info["folds"])
    return None


#: Legend names of the marker kinds other than folds (whose name says what folds).
_NAMES = {"branch_point": "branch point", "event": "event", "jump": "jump", "bifurcation": "bifurcation into another mode"}


def _fold_marker(folds: str, x_name: str, symbols: Mapping[str, str], same_as: Mapping[str, str]) -> tuple[str, str]:
    """A fold in the quantity on the x axis (the path turns back in it) is an open circle; a fold in any
    other quantity (a limit point of that load under its own control) a filled triangle.  ``same_as``
    names quantities that are another one in other units (``F_norm`` is ``F``), and a ratio ``q_over_u``
    is ``q`` in units of ``u``: a fold in ``w`` is a fold in ``w_over_R``.  Returns the marker kind of
    :data:`contin.plot.style.MARKERS` and the legend name."""
    if folds in (x_name, same_as.get(x_name), x_name.partition("_over_")[0]):
        return "fold", f"fold in {symbols.get(folds) or _math(folds)}"
    return "limit point", f"limit point in {symbols.get(folds) or _math(folds)}"


def _math(name: str) -> str:
    """A quantity's name as a symbol (mathtext): ``w_b`` -> ``$w_b$``; a name that is not one stays text."""
    return f"${name}$" if name.isidentifier() and len(name.split("_")[0]) <= 2 else name


def _extent(br: Branch, x: str, y: str, fx: float, fy: float) -> tuple[float, float]:
    """The branch's extent on the axes (``ptp`` of its finite plotted values; 0 when it has none)."""
    xs, ys = br.observable(x) * fx, br.observable(y) * fy
    return tuple(float(np.ptp(v[np.isfinite(v)])) if np.isfinite(v).any() else 0.0 for v in (xs, ys))


def mark_special_points(ax: Any, br: Branch, x: str, y: str, *, kinds: Sequence[str] = SPECIAL_KINDS,
                        scale: Mapping[str, float] | None = None, symbols: Mapping[str, str] | None = None,
                        same_as: Mapping[str, str] | None = None, handles: dict[str, Any] | None = None) -> dict[str, Any]:
    """Mark the special points of ``br`` of ``kinds`` on ``ax``, each with its marker of
    :data:`contin.plot.style.MARKERS`.

    A fold is marked by the quantity that folds (:func:`_fold_marker`); an extremum that declares a fold is
    marked as that fold; an unlocated point (a bracket's end) hollow.  An event at the place of a located
    fold is not marked again: it only bracketed the fold.

    Parameters
    ----------
    ax : matplotlib Axes
    br : Branch
    x, y : str
        The quantities on the axes.
    kinds : sequence of str
        Which kinds to mark (``"fold"`` includes declared folds).
    scale, symbols, same_as : mapping, optional
        As :func:`plot_branches` takes them.
    handles : dict, optional
        Legend entries already made (name -> artist), e.g. by the branches before this one: a kind
        already there gets no second entry.  Updated in place.

    Returns
    -------
    dict of str to artist
        ``handles``, with an entry for each kind of mark drawn.
    """
    from . import style

    handles = {} if handles is None else handles
    symbols, same_as = dict(symbols or {}), dict(same_as or {})
    x_name = _axis_name(x, br)
    fx, fy = _factor(scale, x, br), _factor(scale, y, br)
    marks = []
    for spt in br.special_points:
        folds = _folds_in(spt, br)
        kind = "fold" if folds is not None else spt.kind
        px, py = _coordinate(x, spt.p, spt.observables, br), _coordinate(y, spt.p, spt.observables, br)
        if kind in kinds and kind in (*_NAMES, "fold") and px is not None and py is not None:
            marks.append((spt, folds, kind, px * fx, py * fy))
    wide, high = _extent(br, x, y, fx, fy)
    folds_at = [(px, py) for spt, _, kind, px, py in marks if kind == "fold" and spt.located]
    for spt, folds, kind, px, py in marks:
        if kind == "event" and any(abs(px - qx) <= _SAME_PLACE * wide and abs(py - qy) <= _SAME_PLACE * high
                                   for qx, qy in folds_at):
            continue
        mk, name = _fold_marker(folds, x_name, symbols, same_as) if folds is not None else (kind, _NAMES[kind])
        label = name
        if kind == "bifurcation" and name not in handles and spt.info.get("key") is not None:
            # the first one's mode in its legend entry: a text beside a marker lands on other markers
            # and curves in a crowded diagram
            label = f"{name} (first: ${spt.info.get('family', 'n')} = {spt.info['key']}$)"
        line, = ax.plot([px], [py], ls="none", label=label if name not in handles else None,
                        **style.marker_style(mk, located=spt.located))
        handles.setdefault(name, line)
    return handles


def _jump_parameter(jump: Any) -> float:
    """The load a snap happens at: a :class:`JumpResult`'s ``p``, or the number itself."""
    return float(getattr(jump, "p", jump))


def draw_jumps(ax: Any, jumps: Iterable[tuple[Any, Mapping[str, float], Mapping[str, float]]], x: str, y: str,
               br: Branch, *, scale: Mapping[str, float] | None = None) -> int:
    """Draw each snap as a dotted arrow from the point it leaves to the point it lands on.

    A snap whose ends coincide on the diagram (it changes the state, not the quantities drawn: a body
    an indenter lets go at zero force) gets no arrow: the fold it leaves is marked there already.

    Parameters
    ----------
    ax : matplotlib Axes
        With the branches drawn (their extent sets what "coincide" means).
    jumps : iterable of ``(jump, obs_from, obs_to)``
        ``jump`` a :class:`JumpResult` (or its parameter), the observables at both ends.
    x, y : str
        The quantities on the axes.
    br : Branch
        A branch of the diagram: it names the parameter.
    scale : mapping of str to float, optional
        As :func:`plot_branches` takes it.

    Returns
    -------
    int
        The number of arrows drawn.
    """
    from . import style

    fx, fy = _factor(scale, x, br), _factor(scale, y, br)
    wide, high = ax.dataLim.width, ax.dataLim.height
    drawn = 0
    for jump, obs_from, obs_to in jumps:
        p = _jump_parameter(jump)
        a = (_coordinate(x, p, dict(obs_from), br), _coordinate(y, p, dict(obs_from), br))
        b = (_coordinate(x, p, dict(obs_to), br), _coordinate(y, p, dict(obs_to), br))
        if None in a or None in b:
            continue
        (ax0, ay0), (bx0, by0) = (a[0] * fx, a[1] * fy), (b[0] * fx, b[1] * fy)
        if abs(bx0 - ax0) <= _SHORTEST_ARROW * wide and abs(by0 - ay0) <= _SHORTEST_ARROW * high:
            continue
        ax.annotate("", xy=(bx0, by0), xytext=(ax0, ay0),
                    arrowprops=dict(arrowstyle="-|>", ls=(0, (1.0, 1.5)), lw=1.0, color=style.GREY,
                                    mutation_scale=9, shrinkA=0, shrinkB=2), zorder=3)
        # an annotation does not widen the axes: a snap that ends the path (no branch starts at its
        # landing) would point off them, and matplotlib then drops the arrow
        ax.update_datalim([(ax0, ay0), (bx0, by0)])
        drawn += 1
    if drawn:
        ax.autoscale_view()
    return drawn


def axis_label(name: str, axis_labels: Mapping[str, str] | None = None) -> str:
    r"""The label of an axis showing the quantity ``name``: its entry in ``axis_labels`` when that is
    mathtext (``"$w/R$"``), the name with the entry in brackets when it is text (``"w (pole displacement)"``),
    else the name, a ratio ``a_over_b`` written ``$a/b$``."""
    what = (axis_labels or {}).get(name)
    if what:
        return what if "$" in what else f"{name} ({what})"
    top, _, bottom = name.partition("_over_")
    if bottom and top.isidentifier() and bottom.isidentifier():
        return f"${top}/{bottom}$"
    return name


def branch_handle(color: str, label: str) -> Any:
    """The legend entry of a branch (or a run): its colour, as a stable line."""
    from matplotlib.lines import Line2D

    from . import style

    return Line2D([], [], color=color, lw=style.STABLE["lw"], label=label)


def legend_entries(branch_handles: Sequence[Any], drawn: set[str], point_handles: Mapping[str, Any],
                   snaps: bool) -> list[Any]:
    """What the legend lists, nothing that is not on the plot: the branches (when more than one), the line
    styles drawn (stable solid, unstable dashed), the kinds of points marked, the snaps' arrow."""
    from matplotlib.lines import Line2D

    from . import style

    entries = list(branch_handles) if len(branch_handles) > 1 else []
    if len(entries) > MAX_BRANCH_ENTRIES:
        # a trace through dozens of small snaps (a contact ring moving node by node) would list a legend
        # taller than the figure; the colours repeat by then anyway
        more = len(entries) - (MAX_BRANCH_ENTRIES - 1)
        entries = entries[:MAX_BRANCH_ENTRIES - 1] + [Line2D([], [], color="none", label=f"and {more} more branches")]
    for kind, look in (("stable", style.STABLE), ("unstable", style.UNSTABLE)):
        if kind in drawn:
            entries.append(Line2D([], [], color="0.15", label=kind, **look))
    entries += list(point_handles.values())
    if snaps:
        entries.append(Line2D([], [], color=style.GREY, ls=(0, (1.0, 1.5)), lw=1.0, label="snap (jump)"))
    return entries


#: The most branches a legend names one by one (:func:`legend_entries`); beyond, the last entry counts the rest.
MAX_BRANCH_ENTRIES = 8
#: Legend texts longer than this many characters are broken into lines (after a comma): a long label
#: would widen the legend beside the axes until the axes are a sliver.
LEGEND_LINE = 32


def comma_parts(text: str, at: str = ",") -> list[str]:
    """``text`` cut after each ``at`` (a comma) that is not inside ``$...$`` (mathtext), the cuts kept."""
    parts, in_math, start = [], False, 0
    for i, ch in enumerate(text):
        in_math ^= ch == "$"
        if ch == at and not in_math:
            parts.append(text[start:i + 1])
            start = i + 1
    return parts + [text[start:]]


def _shown_length(text: str) -> int:
    """About how many characters ``text`` shows: a mathtext command (``\\hat``) shows as one character at
    most, ``$``, braces, ``_`` and ``^`` as none."""
    import re

    return len(re.sub(r"\\[A-Za-z]+|[${}_^]", "", text))


def wrapped(text: str, width: int = LEGEND_LINE) -> str:
    """``text`` broken into lines of at most ``width`` shown characters where it can be: after commas
    (:func:`comma_parts`), and a part longer than a line between words (never inside ``$...$``)."""
    lines = [""]
    for part in comma_parts(text):
        words = comma_parts(part, " ") if _shown_length(part) > width else [part]
        for word in words:
            if lines[-1] and _shown_length(lines[-1]) + _shown_length(word) > width:
                lines[-1] = lines[-1].rstrip()
                lines.append(word.lstrip())
            else:
                lines[-1] += word
    return "\n".join(lines)


def add_legend(ax: Any, entries: Sequence[Any], title: str | None = None) -> Any:
    """The legend beside ``ax``, top aligned (a dense diagram leaves no corner free, and there it hides no
    curve), its long texts broken into lines (:data:`LEGEND_LINE`); None when there is nothing to list."""
    if not entries:
        return None
    for entry in entries:
        entry.set_label(wrapped(entry.get_label()))
    return ax.legend(handles=list(entries), loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0,
                     title=title, alignment="left")


#: The colour of a branch drawn as a background (:func:`plot_branches`' ``faded``).
FADED = "0.82"


def plot_branches(branches: Sequence[Branch] | Branch, x: str = "p", y: str | None = None, ax=None,
                  jumps: Iterable[tuple[JumpResult, dict[str, float], dict[str, float]]] = (),
                  colors: Sequence[str] | None = None, labels: Sequence[str] | None = None,
                  special_kinds: Sequence[str] = SPECIAL_KINDS,
                  stability: str | None = None, axis_labels: Mapping[str, str] | None = None,
                  note: str = "", zero_line: bool = False, title: str = "",
                  scale: Mapping[str, float] | None = None, control: str | None = None, smooth: bool = True,
                  symbols: Mapping[str, str] | None = None, same_as: Mapping[str, str] | None = None,
                  faded: Sequence[int] = ()):
    r"""Plot branches: stable solid, unstable dashed, unknown stability thin; special points marked.

    The pieces, each usable alone: :func:`draw_branch` (each branch as one line per run of equal
    stability, drawn smooth from the stored tangents), :func:`mark_special_points` (a fold marked by
    the quantity that folds: an open circle when it is the quantity on the x axis, a filled triangle
    otherwise; the markers of :data:`contin.plot.style.MARKERS`), :func:`draw_jumps` (the snaps as dotted
    arrows), :func:`axis_label` and :func:`add_legend` (the branches when more than one is labelled,
    the line styles that occur, titled by the control they refer to, and the kinds of points that
    occur, beside the axes: nothing that is not on the plot).

    Parameters
    ----------
    branches : Branch or sequence of Branch
    x, y : str
        Observable names (``"p"`` or the parameter name for the parameter); ``y`` defaults to the
        first observable.
    ax : matplotlib Axes, optional
    jumps : iterable of ``(JumpResult, obs_from, obs_to)``
        Snaps drawn as dotted arrows between the two points (observable dicts give coordinates).
    colors, labels : per-branch colours and legend labels.
    special_kinds : which special point kinds to mark (``"fold"`` includes declared folds).
    stability : str, optional
        The stability label to style by (e.g. ``"displacement"``); default the primary label of
        each branch.  A branch without that label is drawn thin (stability unknown).
    axis_labels : mapping of str to str, optional
        What an axis' quantity is, by name (:func:`axis_label`).  A text with ``$`` is the whole label
        (mathtext, e.g. ``{"F": r"$F R / 2\pi D$"}``); other text is added to the name.
    note : str
        A line under the title (e.g. the classification).
    zero_line : bool
        Draw the line ``y = 0`` (where a force changes sign).
    title : str
        The figure's title (e.g. the scene).
    scale : mapping of str to float, optional
        Factors by quantity name: the axis shows ``factor * quantity`` (a model's reference units,
        ``{"w": 1 / R}`` for ``w/R``); the marks and tangents are scaled alike.
    control : str, optional
        What the stability refers to: the legend's title (``"displacement control"`` above "stable" and
        "unstable"); default the ``stability`` label when one is given.
    smooth : bool
        Draw the pieces between stored points as cubics where tangents are stored (else straight).
    symbols : mapping of str to str, optional
        The quantities' symbols (mathtext) in the legend's names, by name: ``{"dV": r"$\Delta V$"}``
        reads "fold in ΔV" where the default is the name itself in math italics.
    same_as : mapping of str to str, optional
        Quantities that are another one in other units, by name: ``{"w_over_R": "w"}`` (a fold in ``w``
        is a fold in ``w_over_R``, drawn as a fold when ``w_over_R`` is on the x axis).
    faded : sequence of int
        Branches (by position) drawn beneath the others in light grey, stability styled, without their special
        points: a background to compare with (the axisymmetric path beneath the path a structure takes).

    Returns
    -------
    matplotlib Axes
    """
    from . import style

    branches = [branches] if isinstance(branches, Branch) else list(branches)
    if ax is None:  # pyplot only for a figure of its own: the command line draws on an Agg canvas without it
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(style.WIDTH, style.HEIGHT))
    y = y if y is not None else next(iter(branches[0].observables), "p")
    drawn: set[str] = set()
    branch_handles = []
    faded = {int(i) for i in faded}
    shown = [bi for bi in range(len(branches)) if bi not in faded]
    for bi, br in enumerate(branches):
        if len(br):
            background = bi in faded
            color = FADED if background else (colors[bi] if colors else
                                              style.COLORS[shown.index(bi) % len(style.COLORS)])
            drawn |= draw_branch(ax, br, x, y, color=color, stability=stability, scale=scale, smooth=smooth,
                                 zorder=0 if background else None)
            if labels and bi < len(labels) and labels[bi]:
                branch_handles.append(branch_handle(color, labels[bi]))
    points: dict[str, Any] = {}
    for bi, br in enumerate(branches):  # after every branch: the marks lie above all lines
        if bi in faded:
            continue
        mark_special_points(ax, br, x, y, kinds=special_kinds, scale=scale, symbols=symbols, same_as=same_as,
                            handles=points)
    snaps = draw_jumps(ax, jumps, x, y, branches[0], scale=scale)
    if zero_line:
        ax.axhline(0.0, color="0.75", lw=0.6, zorder=0)
    ax.set_xlabel(axis_label(_axis_name(x, branches[0]), axis_labels))
    ax.set_ylabel(axis_label(_axis_name(y, branches[0]), axis_labels))
    if title or note:
        ax.set_title("\n".join(t for t in (title, note) if t))
    control = control if control is not None else stability
    add_legend(ax, legend_entries(branch_handles, drawn, points, snaps > 0),
               title=f"{control} control" if control and drawn & {"stable", "unstable"} else None)
    return ax
