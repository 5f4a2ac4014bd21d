"""What a shell run saves beside its diagram: the shapes at its special points and its located modes.

:func:`shell_shapes` collects the arrays (``shapes.npz``, written by the command line from
:attr:`contin.app.scene.TraceResult.shapes`) and :func:`draw_shapes` draws them (``shapes.png``): the
deformed meridians at the path's first instability and its folds, mirrored about the axis, with the
load on each (:class:`LoadSketch`: the point force or the ring load as arrows, the rigid sphere or plate
where it stands), and the first located bifurcation's mode as the ring it bends into, seen from above.
Lengths are in units of the shape's length scale, named by its symbol (``r/R`` for the spherical cap).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["shell_shapes", "draw_shapes", "shapes_drawer", "LoadSketch", "observed"]

#: Most meridians drawn (the first instability, then the folds along the path).
MAX_DRAWN = 4


@dataclass(frozen=True)
class LoadSketch:
    """The load as the shapes figure draws it on each deformed meridian.

    Attributes
    ----------
    kind : str
        ``"point"`` (an arrow onto the pole), ``"ring"`` (arrows onto the loaded node on both sides of the
        axis), pushing down or, where ``shapes.npz``'s ``special_F`` is negative, pulling up; ``"sphere"``
        or ``"plate"`` (the rigid indenter where it stands at each shape: ``special_indenter``); any other
        kind (a pressure) is not drawn.
    node : int
        The loaded node of a ring load (an index of the meridian's nodes, edge first).
    radius : float
        The sphere's radius.
    """

    kind: str
    node: int = -1
    radius: float = 0.0


def observed(name: str) -> Callable[[Any], float]:
    """A field of :func:`shell_shapes`: the observable ``name`` at a special point (NaN where it has none)."""
    return lambda spt: float(spt.observables.get(name, np.nan))


def shell_shapes(branches: Sequence[Any], state: Callable[[np.ndarray, float], np.ndarray], families: Sequence[Any] = (),
                 reference: np.ndarray | None = None, path: bool = False,
                 fields: dict[str, Callable[[Any], float]] | None = None) -> dict[str, np.ndarray]:
    """``shapes.npz`` of a shell run: the deformed meridian at every special point, and the located modes.

    Parameters
    ----------
    branches : the run's branches (their special points, in the order of ``summary.json``'s records).
    state : callable ``(u, p) -> x``
        The full interleaved state ``[r_0, z_0, ...]`` of a special point's unknowns and parameter.
    families : the problem's operator families (:class:`contin.OperatorFamily`); a bifurcation's mode is
        saved when its family has a ``mode_shape``.
    reference : the reference state (saved as ``reference_r``, ``reference_z``).
    path : also the meridian at every stored point of every branch, in the order of ``branch.csv``'s rows:
        ``path_branch``, ``path_p`` and ``path_r``, ``path_z`` (one row per point).
    fields : dict of str to callable ``(special point) -> float``, optional
        Further values at each special point, saved as ``special_<name>``: the load ``F`` (what the
        shapes figure's arrows point by), where a rigid indenter stands (``indenter``: the sphere's
        centre height, the plate's height).

    Returns
    -------
    dict
        ``special_record`` (the index of each special point among ``summary.json``'s ``special_points``),
        ``special_branch``, ``special_kind``, ``special_label``, ``special_p``, ``special_r``,
        ``special_z`` (one row per special point), ``special_<name>`` for each of ``fields``; for every located mode ``mode_record`` (its special
        point), ``mode_n``, and its per-node amplitudes ``mode_a``, ``mode_b``, ``mode_c``
        (``dR = a cos n theta``, ``dZ = b cos n theta``, ``dT = c sin n theta``); with ``path`` the
        ``path_*`` arrays; empty when the run has no special point (and ``path`` is false).
    """
    out: dict[str, np.ndarray] = {}
    if path:
        stored = [(bi, u, p) for bi, br in enumerate(branches) for u, p in zip(br.u, br.p)]
        if stored:
            P = np.array([np.asarray(state(u, p), dtype=float) for _, u, p in stored])
            out.update(path_branch=np.array([bi for bi, _, _ in stored]), path_p=np.array([float(p) for *_, p in stored]),
                       path_r=P[:, 0::2], path_z=P[:, 1::2])
    rows = [(bi, spt) for bi, br in enumerate(branches) for spt in br.special_points]
    if not rows:
        return out
    X = np.array([np.asarray(state(spt.u, spt.p), dtype=float) for _, spt in rows])
    out |= {
        "special_record": np.arange(len(rows)), "special_branch": np.array([bi for bi, _ in rows]),
        # an extremum declared a limit point (the force's maximum along a displacement path) is a fold, as in
        # summary.json's records
        "special_kind": np.array(["fold" if spt.kind == "event" and spt.info.get("folds") is not None else spt.kind
                                  for _, spt in rows]),
        "special_label": np.array([spt.label for _, spt in rows]),
        "special_p": np.array([float(spt.p) for _, spt in rows]), "special_r": X[:, 0::2], "special_z": X[:, 1::2]}
    for name, value in (fields or {}).items():
        out[f"special_{name}"] = np.array([float(value(spt)) for _, spt in rows])
    if reference is not None:
        out["reference_r"], out["reference_z"] = np.asarray(reference)[0::2], np.asarray(reference)[1::2]
    by_name = {f.name: f for f in families}
    modes = []
    for k, (_, spt) in enumerate(rows):
        fam = by_name.get(spt.info.get("family")) if spt.kind == "bifurcation" else None
        if fam is not None and fam.mode_shape is not None and spt.info.get("mode") is not None:
            modes.append((k, spt.info["key"], np.asarray(fam.mode_shape(spt.info["key"], spt.info["mode"]))))
    if modes:
        A = np.array([m[2] for m in modes])
        out.update(mode_record=np.array([m[0] for m in modes]), mode_n=np.array([m[1] for m in modes]),
                   mode_a=A[:, :, 0], mode_b=A[:, :, 1], mode_c=A[:, :, 2])
    return out


def _symbol(name: str) -> str:
    """A quantity's name as mathtext (``w`` -> ``$w$``, ``w_b`` -> ``$w_b$``; ``dV`` -> ``$\\Delta V$``)."""
    return {"dV": r"$\Delta V$"}.get(name, f"${name}$")


def draw_shapes(fig: Any, shapes: dict[str, np.ndarray], length: float, parameter: str,
                parameter_label: str | None = None, parameter_scale: float = 1.0, *, length_symbol: str = "R",
                load: LoadSketch | None = None) -> None:
    """Draw ``shapes`` (:func:`shell_shapes`) on the empty matplotlib Figure ``fig`` (project style,
    :mod:`contin.plot.style`; the figure is resized to fit).

    Left: the reference meridian and the deformed ones at the first bifurcation (if any) and the folds
    along the path (at most :data:`MAX_DRAWN`), as cross-sections through the axis, in units of
    ``length`` (its symbol ``length_symbol``: ``r/R``, ``z/R``), to scale, each with its ``load``
    (:class:`LoadSketch`) in its colour.  Right, when a mode was located: the ring of largest radial
    amplitude of the first bifurcation's mode, seen from above, its amplitude exaggerated to a fifth of
    the radius.  ``parameter``: the name of the path's parameter; the labels give its values as
    ``parameter_scale`` times it under ``parameter_label`` (mathtext) when given, as the diagram's
    axis does (``$w/R$``, ``$\\Delta V / V_0$``), else the parameter itself by its symbol.
    """
    from contin.plot import style

    kinds = [str(k) for k in shapes["special_kind"]]
    symbol = parameter_label or _symbol(parameter)
    scale = float(parameter_scale) if parameter_label else 1.0
    chosen: list[int] = []
    bif = [k for k, kind in enumerate(kinds) if kind == "bifurcation"]
    if bif:
        chosen.append(bif[0])
    chosen += [k for k, kind in enumerate(kinds) if kind == "fold" and k not in chosen]
    chosen = sorted(chosen[:MAX_DRAWN])
    modes = "mode_record" in shapes
    # the cross-sections are drawn to scale: the figure is as tall as they need (and room for the text)
    drawn_z = [shapes["special_z"][k] / length for k in chosen]
    drawn_r = [shapes["special_r"][k] / length for k in chosen]
    if "reference_r" in shapes:
        drawn_z.append(shapes["reference_z"] / length)
        drawn_r.append(shapes["reference_r"] / length)
    z_span = float(np.ptp(np.concatenate(drawn_z))) if drawn_z else 1.0
    r_max = float(np.max(np.abs(np.concatenate(drawn_r)))) if drawn_r else 1.0
    z_top = float(np.max(np.concatenate(drawn_z))) if drawn_z else 1.0
    aspect = min(max(1.1 * z_span / max(2.0 * r_max, 1e-12), 0.15), 1.0)
    width = (style.WIDTH - 2.4) if not modes else (style.WIDTH - 1.2) / 2
    if not modes:
        fig.set_size_inches(style.WIDTH, max(width * aspect + 0.95, 1.8))
        ax = fig.add_subplot(1, 1, 1)
    else:
        # the panels above, each legend in a row of its own below its panel: anchored to a panel, a
        # legend under a flat cross-section would sit on its axis label
        top = max(width + 0.75, 3.0)  # the square ring panel, its two-line title and its axis label
        fig.set_size_inches(style.WIDTH, top + LEGEND_ROW)
        grid = fig.add_gridspec(2, 2, height_ratios=[top, LEGEND_ROW])
        ax = fig.add_subplot(grid[0, 0])
    if "reference_r" in shapes:
        r0, z0 = shapes["reference_r"] / length, shapes["reference_z"] / length
        ax.plot(*_section(r0, z0), color=style.GREY, lw=0.9, ls=(0, (1.0, 1.5)), label="reference")
    sketch = _LoadDrawer(ax, load, shapes, length, r_max, z_top)
    for c, k in zip(style.COLORS, chosen):
        r, z = shapes["special_r"][k] / length, shapes["special_z"][k] / length
        name = str(shapes["special_label"][k])
        extremum = re.fullmatch(r"(max|min)\((\w+)\)", name)  # a limit point, e.g. max(F): F's extremum
        what = f"limit point, {extremum[1]} {_symbol(extremum[2])}" if extremum else kinds[k]
        label = f"{what} at {symbol} = {scale * shapes['special_p'][k]:.3g}"
        if kinds[k] == "bifurcation" and modes and k in list(shapes["mode_record"]):
            label += f" ($n = {int(shapes['mode_n'][list(shapes['mode_record']).index(k)])}$)"
        ax.plot(*_section(r, z), color=c, lw=1.3, label=label)
        sketch.draw(k, r, z, c)
    sketch.legend_entry()
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(f"$r / {length_symbol}$")
    ax.set_ylabel(f"$z / {length_symbol}$")
    ax.set_title("cross-sections through the axis (to scale)")
    if not modes:
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
        return
    _legend_below(fig.add_subplot(grid[1, 0]), ax)
    k = int(shapes["mode_record"][0])
    n = int(shapes["mode_n"][0])
    a = shapes["mode_a"][0]
    node = int(np.argmax(np.abs(a)))
    r_ring = float(shapes["special_r"][k][node]) / length
    theta = np.linspace(0.0, 2.0 * np.pi, 361)
    amp = 0.2 * r_ring / max(float(np.max(np.abs(a))), 1e-300)
    ax2 = fig.add_subplot(grid[0, 1])
    ax2.plot(r_ring * np.cos(theta), r_ring * np.sin(theta), color=style.GREY, lw=0.9, ls=(0, (1.0, 1.5)),
             label="axisymmetric")
    rr = r_ring + amp * a[node] * np.cos(n * theta)
    ax2.plot(rr * np.cos(theta), rr * np.sin(theta), color=style.RED, lw=1.3,
             label=f"mode $n = {n}$ (amplitude exaggerated)")
    ax2.set_aspect("equal")
    from matplotlib.ticker import MaxNLocator

    ax2.xaxis.set_major_locator(MaxNLocator(4))
    ax2.yaxis.set_major_locator(MaxNLocator(4))
    ax2.set_xlabel(f"$x / {length_symbol}$")
    ax2.set_ylabel(f"$y / {length_symbol}$")
    # a title no wider than the panel: the constrained layout keeps it inside the figure only then
    ax2.set_title(f"first bifurcation, at {symbol} = {scale * shapes['special_p'][k]:.3g}:\n"
                  f"the ring at $r/{length_symbol} = {r_ring:.3g}$ seen from above")
    _legend_below(fig.add_subplot(grid[1, 1]), ax2)


class _LoadDrawer:
    """Draws a :class:`LoadSketch` on each cross-section of the shapes panel ``ax`` (units of ``length``)."""

    #: Length of a force arrow, a fraction of the panel's half width.
    ARROW = 0.14

    def __init__(self, ax: Any, load: LoadSketch | None, shapes: dict[str, np.ndarray], length: float,
                 r_max: float, z_top: float) -> None:
        self.ax, self.load, self.shapes, self.length = ax, load, shapes, length
        self.r_max, self.z_top = r_max, z_top
        self.drawn, self.pulled = False, False
        has_position = "special_indenter" in shapes
        self.kind = load.kind if load is not None and (load.kind in ("point", "ring") or has_position) else None

    def draw(self, k: int, r: np.ndarray, z: np.ndarray, color: str) -> None:
        """The load on cross-section ``k`` (its meridian ``r``, ``z``, edge to pole), in ``color``."""
        if self.kind in ("point", "ring"):
            node = -1 if self.kind == "point" else self.load.node
            tips = {(0.0, float(z[-1]))} if self.kind == "point" else {(-float(r[node]), float(z[node])),
                                                                      (float(r[node]), float(z[node]))}
            # a pull (F < 0 on a bilateral load) points up, from the node
            pull = "special_F" in self.shapes and float(self.shapes["special_F"][k]) < 0.0
            self.pulled |= pull
            length = self.ARROW * self.r_max
            # each arrow a shaft from the node up and a head at its end (down onto the node, or up for a pull)
            xs = [v for x, _ in sorted(tips) for v in (x, x, np.nan)]
            ys = [v for _, z0 in sorted(tips) for v in (z0, z0 + length, np.nan)]
            self.ax.plot(xs, ys, color=color, lw=1.0, zorder=4)
            self.ax.plot([x for x, _ in tips], [z0 + (length if pull else 0.0) for _, z0 in tips], ls="none",
                         marker="^" if pull else "v", ms=4.5, color=color, zorder=4)
        elif self.kind in ("sphere", "plate"):
            c = float(self.shapes["special_indenter"][k]) / self.length
            if self.kind == "plate":
                xs, ys = np.array([-1.05 * self.r_max, 1.05 * self.r_max]), np.array([c, c])
            else:
                rho = self.load.radius / self.length
                t = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 181)
                xs, ys = rho * np.sin(t), c - rho * np.cos(t)
                # only the part of the sphere below the shell's top: the rest would only stretch the panel
                keep = (ys <= self.z_top + 0.05 * self.r_max) & (np.abs(xs) <= 1.05 * self.r_max)
                xs, ys = np.where(keep, xs, np.nan), np.where(keep, ys, np.nan)
            self.ax.plot(xs, ys, color=color, lw=0.8, ls=(0, (5.0, 1.5, 1.0, 1.5)), zorder=1.8)
        else:
            return
        self.drawn = True

    def legend_entry(self) -> None:
        """One legend entry for the load, in grey (each cross-section's load is drawn in its colour)."""
        if not self.drawn:
            return
        from contin.plot import style

        names = {"point": "point force at the pole", "ring": "ring load",
                 "sphere": "rigid sphere, in each shape's colour", "plate": "rigid plate, in each shape's colour"}
        if self.kind in ("point", "ring"):
            name = names[self.kind] + (" (up: a pull, $F < 0$)" if self.pulled else "")
            self.ax.plot([], [], ls="none", marker="v", ms=5, color=style.GREY, label=name)
        else:
            self.ax.plot([], [], color=style.GREY, lw=0.8, ls=(0, (5.0, 1.5, 1.0, 1.5)), label=names[self.kind])


#: Height in inches of the row that holds the legends under the panels of a figure with a mode.
LEGEND_ROW = 0.9


def _legend_below(cell: Any, ax: Any) -> None:
    """``ax``'s legend at the top of the empty grid cell ``cell`` (its frame and axes hidden)."""
    cell.set_axis_off()
    cell.legend(*ax.get_legend_handles_labels(), loc="upper center", borderaxespad=0.0)


def shapes_drawer(shapes: dict[str, np.ndarray], length: float, parameter: str,
                  plot_options: dict[str, Any] | None = None, *, length_symbol: str = "R",
                  load: LoadSketch | None = None) -> Callable[[Any], None] | None:
    """:attr:`contin.app.scene.TraceResult.draw_shapes` of a shell run: :func:`draw_shapes` bound to its arrays
    (None when there is nothing to draw).  ``plot_options``: the run's diagram options; the parameter's
    axis label and scale there (``axis_labels``, ``scale``) label the shapes as the diagram's axis reads.
    ``length_symbol`` names ``length`` on the axes, ``load`` is drawn on each shape."""
    if not shapes:
        return None
    options = plot_options or {}
    label = options.get("axis_labels", {}).get(parameter)
    label = label if label and "$" in label else None
    factor = options.get("scale", {}).get(parameter, 1.0)
    return lambda fig: draw_shapes(fig, shapes, length, parameter, label, factor, length_symbol=length_symbol,
                                   load=load)


def _section(r: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The meridian (edge to pole) and its mirror image as one cross-section through the axis, edge to edge."""
    return np.concatenate([-r, r[::-1]]), np.concatenate([z, z[::-1]])
