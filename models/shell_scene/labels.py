"""What the shell scene's figures say: the scene as a short title, the axes as symbols in reference units.

The engine draws (:func:`contin.plot_branches`); the names of the loads and the shell's reference units
are the model's, handed over in ``TraceResult.plot_options`` (``title``, ``axis_labels`` in mathtext,
``scale``: the factor that turns a quantity into the one the axis shows, ``same_as``: the observables
that are another quantity in those units already, ``w_over_R`` for ``w``).  The length the units refer
to is named by its symbol (:func:`length_symbol`): ``R`` for the spherical cap, never an undefined ``L``.
"""

from __future__ import annotations

import math
from typing import Any

from .shape import length_scale

__all__ = ["scene_title", "force_axes", "pressure_axes", "length_symbol"]


def _number(v: float) -> str:
    return f"{v:.3g}"


def scene_title(scene: dict[str, dict[str, Any]]) -> str:
    """The scene in a few symbols: ``point load, φ̂ = 0.8, h/R = 0.02, N = 200`` (mathtext).

    The load (and the indenter's or ring's radius), the shape (the spherical cap by its opening angle,
    any other geometry by name), ``h`` over the shape's length, the edge when it is not sliding, an
    imperfection when there is one, and the mesh.
    """
    shell, load, imp = scene["shell"], scene["load"], scene.get("imperfection", {})
    kind = load["kind"]
    R = shell["R"]
    L, unit = length_symbol(shell), length_scale(shell) if kind == "ring" else 1.0
    parts = {"point": ["point load"], "ring": [f"ring load, $r_l/{L} = {_number(load['ring_radius'] / unit)}$"],
             "sphere": [f"rigid sphere, $r_s/R = {_number(load['radius'] / R)}$"], "plate": ["rigid plate"],
             "pressure": ["uniform pressure"]}.get(kind, [f"{kind} load"])
    if kind == "pressure" and load.get("control") == "displacement":
        parts = ["volume control"]
    if kind in ("point", "sphere") and load.get("pole_held") and kind == "point":
        parts.append("pole held")
    geometry = shell.get("geometry", "sphere")
    if geometry == "sphere":
        parts.append(rf"$\hat\phi = {_number(shell['phi_hat'])}$")
        parts.append(f"$h/R = {_number(shell['h'] / R)}$")
    else:
        parts.append(f"{geometry} shell")
        parts.append(f"$h = {_number(shell['h'])}$")
    if shell.get("boundary", "sliding") != "sliding":
        parts.append(f"{shell['boundary']} edge")
    if imp.get("kind", "none") != "none":
        waves = f" of {imp['waves']} waves" if imp["kind"] == "mode" and imp.get("waves", 0) else ""
        parts.append(rf"{imp['kind']} imperfection{waves} $\delta/h = {_number(imp.get('delta_over_h', 0.0))}$")
    parts.append(f"$N = {shell['N']}$")
    return ", ".join(parts)


def length_symbol(shell: dict[str, Any]) -> str:
    """The symbol (mathtext, without ``$``) of the shape's length scale
    (:func:`contin_models.shell_scene.shape.length_scale`): ``R`` (sphere, torispherical head), ``a`` (cone,
    plate), ``(a^2/b)`` (the spheroid's radius of curvature at its pole), ``r_{max}`` (a table's largest
    radius)."""
    return {"sphere": "R", "torus": "R", "cone": "a", "plate": "a", "ellipse": "(a^2/b)"}.get(
        shell.get("geometry", "sphere"), "r_{max}")


def force_axes(w: str, length: float, D: float, length_symbol: str = "R", w_symbol: str = "w",
               scaled: dict[str, str] | None = None) -> dict[str, Any]:
    """The plot options of a force-displacement diagram in reference units: ``w / L`` and ``F L / (2 pi D)``
    (``L``: the shape's length, named ``length_symbol``; ``D`` the bending stiffness); ``w`` names the
    travel.

    Parameters
    ----------
    w, length, D, length_symbol, w_symbol
        As above.
    scaled : dict of str to str, optional
        Observables that are ``w`` or ``F`` in these units already, by name (``{"w_over_R": "w",
        "F_norm": "F"}``): labelled alike, and a fold in ``w`` is a fold in them (``same_as``).

    Returns
    -------
    dict
        ``axis_labels``, ``scale`` and ``same_as``.
    """
    L = length_symbol
    labels = {w: f"${w_symbol}/{L}$", "F": rf"$F {L} / 2\pi D$"}
    scaled = dict(scaled or {})
    labels.update({name: labels[of] for name, of in scaled.items()})
    return {"axis_labels": labels, "scale": {w: 1.0 / length, "F": length / (2.0 * math.pi * D)}, "same_as": scaled}


def pressure_axes(p_c: float) -> dict[str, Any]:
    """The plot options of a pressure scene: the pole deflection over the thickness, ``w/h``, and the
    pressure over the classical one, ``p/p_c`` (the observables ``w_over_h`` and ``p_over_p_c``, and ``p``
    scaled to it: what the shapes' labels and ``contin plot -x p`` show)."""
    return {"axis_labels": {"w_over_h": "$w/h$", "p_over_p_c": "$p/p_c$", "p": "$p/p_c$"}, "scale": {"p": 1.0 / p_c},
            "same_as": {"p_over_p_c": "p", "w_over_h": "w"}}
