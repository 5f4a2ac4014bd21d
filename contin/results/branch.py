"""Results: a traced branch (arrays of converged points) and its located special points.

Everything here is plain data.  A branch saves to a single ``.npz`` file (arrays plus a JSON header)
and loads back identical.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from .io import ResultFileError, json_ready, read_bundle, write_bundle

__all__ = ["Bifurcation", "SpecialPoint", "Branch", "SPECIAL_KINDS", "SUCCESSES", "BranchFileError"]

SPECIAL_KINDS = ("fold", "branch_point", "event", "jump", "bifurcation")

#: The statuses of a run that ended for a planned reason (:attr:`Branch.success`).
SUCCESSES = ("bound", "event", "closed_loop", "reached_branch_point")


class BranchFileError(ResultFileError):
    """A saved branch file is unreadable, truncated or inconsistent."""


@dataclass
class Bifurcation:
    """What a located branch point knows about the branches through it: the record every switch reads.

    Attributes
    ----------
    multiplicity : int
        Dimension of the Jacobian's kernel (1 at a simple branch point).
    kernel : ndarray, shape (multiplicity, n)
        An orthonormal basis of that kernel (rows); for a mode of an operator family, the mode in
        that operator's own variables.
    directions : ndarray, shape (k, n + 1)
        Directions ``(du, dp)`` of the branches that emanate (not the traced one), in the order a
        switch tries them; empty where they are not resolved.  At a simple point of a symmetric
        problem they come from the algebraic bifurcation equation and carry no arclength weight.
    traced : ndarray, shape (n + 1,), or None
        The traced branch's tangent at the point.
    equation : dict of str to float
        Coefficients of the reduced bifurcation equation: ``a``, ``b``, ``c`` of the algebraic
        bifurcation equation ``a alpha^2 + 2 b alpha beta + c beta^2 = 0`` at a simple point.
    kind : str
        ``"pitchfork"``, ``"transcritical"``, ``"symmetric"`` (a multiple point whose directions come
        from the model's symmetry), ``"reduced"`` (from its reduced equation), ``"multiple"`` (a
        multiple point not resolved) or ``"unresolved"``.
    key : str
        What identifies it among the branch's points of the same place (a mode's key, or "").
    koiter : dict of str to float
        Koiter's ``a`` and ``b`` (``p / p_c = 1 + a xi + b xi^2``) where computed
        (:func:`contin.koiter_coefficients`).
    eigenvalues : ndarray
        The Jacobian's eigenvalues on the kernel at the located point (roundoff-small).
    labels : list of str
        What each entry of ``directions`` is (at a multiple point: its isotropy, and how many
        copies of the branch the symmetry makes).
    """

    multiplicity: int
    kernel: np.ndarray
    directions: np.ndarray
    traced: np.ndarray | None = None
    equation: dict[str, float] = field(default_factory=dict)
    kind: str = "unresolved"
    key: str = ""
    koiter: dict[str, float] = field(default_factory=dict)
    eigenvalues: np.ndarray = field(default_factory=lambda: np.zeros(0))
    labels: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.kernel = np.atleast_2d(np.asarray(self.kernel, dtype=float))
        self.directions = np.asarray(self.directions, dtype=float).reshape(-1, self.kernel.shape[1] + 1) \
            if np.size(self.directions) else np.zeros((0, self.kernel.shape[1] + 1))
        self.traced = None if self.traced is None else np.asarray(self.traced, dtype=float)
        self.eigenvalues = np.asarray(self.eigenvalues, dtype=float)

    @property
    def null_vector(self) -> np.ndarray:
        """The first kernel vector (the null vector at a simple point)."""
        return self.kernel[0]

    def header(self) -> dict[str, Any]:
        """JSON-serialisable form (arrays as lists)."""
        return {"multiplicity": int(self.multiplicity), "kernel": self.kernel.tolist(),
                "directions": self.directions.tolist(), "traced": None if self.traced is None else self.traced.tolist(),
                "equation": {k: float(v) for k, v in self.equation.items()}, "kind": self.kind, "key": self.key,
                "koiter": {k: float(v) for k, v in self.koiter.items()}, "eigenvalues": self.eigenvalues.tolist(),
                "labels": list(self.labels)}

    @classmethod
    def from_header(cls, h: dict[str, Any]) -> "Bifurcation":
        """The record described by :meth:`header`."""
        return cls(multiplicity=int(h["multiplicity"]), kernel=np.array(h["kernel"], dtype=float),
                   directions=np.array(h["directions"], dtype=float),
                   traced=None if h.get("traced") is None else np.array(h["traced"], dtype=float),
                   equation=dict(h.get("equation", {})), kind=h.get("kind", "unresolved"), key=h.get("key", ""),
                   koiter=dict(h.get("koiter", {})), eigenvalues=np.array(h.get("eigenvalues", []), dtype=float),
                   labels=list(h.get("labels", [])))


def _legacy_record(info: dict[str, Any], n: int) -> Bifurcation | None:
    """The record of a branch point saved before records existed (its directions were keys of ``info``)."""
    direction = info.get("bifurcation_direction")
    if direction is None or np.size(direction) != n + 1:
        return None
    d = np.asarray(direction, dtype=float)
    kernel = np.asarray(info.get("null_vector", d[:n]), dtype=float)
    abe = info.get("abe") or {}
    return Bifurcation(multiplicity=1, kernel=kernel[None, :] / max(float(np.linalg.norm(kernel)), 1e-300),
                       directions=d[None, :], traced=info.get("branch_tangent"), equation=dict(abe),
                       kind=info.get("bifurcation_type", "unresolved"))


@dataclass
class SpecialPoint:
    """A special point on a branch.

    Attributes
    ----------
    kind : str
        ``"fold"``, ``"branch_point"``, ``"event"`` or ``"jump"``.
    p : float
        Parameter value.
    u : ndarray
        State.
    observables : dict
        Observables at the point.
    residual : float
        Max-norm residual of the point's defining system (the extended system for a fold or
        branch point, the equilibrium equations plus the event condition for an event).
    located : bool
        True when the point was converged on its defining system; False when only bracketed.
    s : float
        Arclength along the branch.
    index : int
        The point lies between stored points ``index`` and ``index + 1``.
    label : str
        Event name, ``"start"``/``"end"`` of a jump, etc.
    bifurcation : Bifurcation or None
        At a located branch point: its kernel, the directions of the branches through it and the
        coefficients of its reduced equation (:class:`Bifurcation`).
    info : dict
        Extra data: the bracket (``bracket_p``), the jump's source, ...  Folds, branch points and
        extremum events of a branch traced with stability carry ``info["stability"]``:
        ``{label: {"n_negative_before", "stable_before", "n_negative_after", "stable_after"}}`` for
        every stability label (the stored points on either side; only ``*_before`` when the point
        ends its branch), and the same four keys flat under ``info["stability_label"]`` (the
        primary label for folds and branch points, the declared one for an extremum event, see
        :func:`contin.extremum`).  ``info["folds"]`` names the quantity that has a limit point
        there (the continuation parameter for a fold; what an extremum event declares).
    """

    kind: str
    p: float
    u: np.ndarray
    observables: dict[str, float] = field(default_factory=dict)
    residual: float = float("nan")
    located: bool = False
    s: float = float("nan")
    index: int = -1
    label: str = ""
    info: dict[str, Any] = field(default_factory=dict)
    bifurcation: Bifurcation | None = None

    def __post_init__(self) -> None:
        if self.kind not in SPECIAL_KINDS:
            raise ValueError(f"special point kind must be one of {SPECIAL_KINDS}, got {self.kind!r}")

    def stability_under(self, label: str | None = None) -> dict[str, Any]:
        """``{"n_negative_before", "stable_before", "n_negative_after", "stable_after"}`` under ``label``.

        Default: the point's own ``info["stability_label"]``.  Empty when not known (no stability
        data, or a kind that does not carry it); see :attr:`info`.
        """
        label = self.info.get("stability_label") if label is None else label
        return dict(self.info.get("stability", {}).get(label, {}))

    def header(self) -> dict[str, Any]:
        """JSON-serialisable description (everything but the state vector)."""
        return {
            "kind": self.kind, "p": float(self.p), "observables": {k: float(v) for k, v in self.observables.items()},
            "residual": float(self.residual), "located": bool(self.located), "s": float(self.s),
            "index": int(self.index), "label": self.label, "info": json_ready(self.info, keep_nonfinite=True),
            "bifurcation": None if self.bifurcation is None else json_ready(self.bifurcation.header(),
                                                                           keep_nonfinite=True),
        }

    @classmethod
    def from_header(cls, header: dict[str, Any], u: np.ndarray) -> "SpecialPoint":
        """The special point described by :meth:`header`, with its state ``u``."""
        h = header
        bif = h.get("bifurcation")
        record = Bifurcation.from_header(bif) if bif is not None else _legacy_record(h["info"], np.asarray(u).size)
        return cls(kind=h["kind"], p=h["p"], u=u, observables=h["observables"], residual=h["residual"],
                   located=h["located"], s=h["s"], index=h["index"], label=h["label"], info=h["info"],
                   bifurcation=record)

    def __repr__(self) -> str:
        loc = "located" if self.located else "bracketed"
        lab = f" {self.label}" if self.label else ""
        return f"SpecialPoint({self.kind}{lab}, p={self.p:.10g}, {loc}, residual={self.residual:.2e})"


@dataclass
class Branch:
    """A traced branch: converged points in path order, plus special points.

    Attributes
    ----------
    p : ndarray (m,)
        Parameter at each point.
    u : ndarray (m, n)
        States.
    s : ndarray (m,)
        Arclength (in the continuation's weighted norm) from the first point.
    tangent_p : ndarray (m,)
        Parameter component of the unit tangent (its sign change marks a fold).
    residual : ndarray (m,)
        Max-norm residual of each stored point (all within the tolerance).
    newton_iterations : ndarray (m,)
        Corrector iterations for each point.
    observables : dict of ndarray
        Observables per point.
    n_negative : ndarray (m,) of int or None
        Negative eigenvalues of the stability operator (None when not computed; -1 where unknown).
    eigenvalues : ndarray (m, k) or None
        Smallest eigenvalues of the stability operator.
    stability_by : dict
        ``{label: (n_negative, eigenvalues)}`` for every stability operator of the problem (the
        first label is the primary one, also given as ``n_negative`` and ``eigenvalues``).
        :meth:`columns` gives them as ``stable_<label>`` and ``n_negative_<label>``.
    special_points : list of SpecialPoint
        Located folds, branch points, events and jumps, in path order.
    status : str
        Why the run ended: ``"bound"``, ``"event"``, ``"closed_loop"`` (a switched branch returned to
        the branch point it left), ``"reached_branch_point"`` (a switched branch met a branch point it
        was told of) (successes), ``"max_steps"`` (the step budget ran out first), ``"stalled"`` (no
        progress over :attr:`contin.Settings.stall_steps` steps: the path is not heading for an end), ``"min_step"``
        (the step collapsed below ``ds_min``; the message gives the last corrector failure),
        ``"unexplained"`` (the run reached its end, but the stability count changed somewhere that
        no located point explains: the result is in doubt, the message says where),
        ``"failed"`` (could not start, or the model check failed).  ``"completed"`` is what
        ``"max_steps"`` was called before (not a success either).
    message : str
        Human-readable reason.
    meta : dict
        Problem name, parameter name, settings.
    tangents : dict of ndarray
        ``d(observable)/ds`` at each stored point, by observable name: the rate of change along the
        path per unit arclength (the unit tangent times the problem's exact observable derivatives,
        :attr:`contin.Problem.observable_derivatives`); NaN, or no entry, where not known.  With
        :attr:`tangent_p` (``dp/ds``) they let a plot draw the branch as smooth cubic pieces between
        stored points (:func:`contin.plot_branches`).
    """

    p: np.ndarray
    u: np.ndarray
    s: np.ndarray
    tangent_p: np.ndarray
    residual: np.ndarray
    newton_iterations: np.ndarray
    observables: dict[str, np.ndarray] = field(default_factory=dict)
    n_negative: np.ndarray | None = None
    eigenvalues: np.ndarray | None = None
    stability_by: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    special_points: list[SpecialPoint] = field(default_factory=list)
    status: str = "completed"
    message: str = ""
    meta: dict[str, Any] = field(default_factory=dict)
    tangents: dict[str, np.ndarray] = field(default_factory=dict)

    # ---- conveniences ----------------------------------------------------------------------------
    def __len__(self) -> int:
        return int(self.p.size)

    @property
    def stable(self) -> np.ndarray | None:
        """Boolean array: no negative eigenvalue at the point (None without stability data)."""
        if self.n_negative is None:
            return None
        return self.n_negative == 0

    @property
    def stability_labels(self) -> list[str]:
        """Stability labels in order (the first is the primary one); empty without stability data."""
        return list(self.stability_by)

    def n_negative_under(self, label: str | None = None) -> np.ndarray:
        """Morse index of every point under the stability operator ``label`` (default: the primary one)."""
        if label is None:
            if self.n_negative is None:
                raise KeyError("branch has no stability data")
            return self.n_negative
        try:
            return self.stability_by[label][0]
        except KeyError:
            raise KeyError(f"branch has no stability label {label!r}; it has {sorted(self.stability_by)}") from None

    def stable_under(self, label: str | None = None) -> np.ndarray:
        """Boolean stability of every point under the stability operator ``label`` (default: the primary one)."""
        return self.n_negative_under(label) == 0

    def columns(self) -> dict[str, np.ndarray]:
        """One column per quantity, one row per stored point, in a fixed order (for tables and CSV).

        Columns: ``p``, ``s``, every observable (in the problem's order), ``residual``,
        ``newton_iterations``, then for every stability label (primary first) ``stable_<label>``
        (1 stable, 0 not) and ``n_negative_<label>`` (the Morse index).  A model adds its own
        columns to this dictionary rather than rebuilding it.
        """
        cols: dict[str, np.ndarray] = {"p": self.p, "s": self.s}
        cols.update((name, values) for name, values in self.observables.items() if name not in cols)
        cols["residual"] = self.residual
        cols["newton_iterations"] = self.newton_iterations
        for label, (nneg, _) in self.stability_by.items():
            cols[f"stable_{label}"] = (np.asarray(nneg) == 0).astype(int)
            cols[f"n_negative_{label}"] = np.asarray(nneg, dtype=int)
        return cols

    @property
    def success(self) -> bool:
        """True when the run ended for a planned reason: a bound, a stopping event, a closed loop, a
        known branch point.

        Running out of steps (``"max_steps"``) is not a success: the target was not reached.
        """
        return self.status in SUCCESSES

    def head(self, keep: int, special_points: list[SpecialPoint] | None = None) -> "Branch":
        """The first ``keep`` stored points as a branch of their own (a copy of the arrays' heads), with the special
        points ``special_points`` (default: those before the last kept point, and a jump's landing at it).

        The part of a branch before a point: before a restart's point, joined to the run traced from it
        (:func:`contin.app.restart.join_branches`), or before where a path stops being followed.
        """
        if special_points is None:
            special_points = [spt for spt in self.special_points
                              if spt.index < keep - 1 or (spt.kind == "jump" and spt.index <= keep - 1)]

        def rows(a: Any) -> Any:
            return None if a is None else np.asarray(a)[:keep]

        return replace(self, p=self.p[:keep], u=np.asarray(self.u)[:keep], s=self.s[:keep],
                       tangent_p=self.tangent_p[:keep], residual=self.residual[:keep],
                       newton_iterations=self.newton_iterations[:keep],
                       observables={k: v[:keep] for k, v in self.observables.items()}, n_negative=rows(self.n_negative),
                       eigenvalues=rows(self.eigenvalues),
                       stability_by={k: (np.asarray(a)[:keep], np.asarray(e)[:keep])
                                     for k, (a, e) in self.stability_by.items()},
                       special_points=list(special_points), tangents={k: v[:keep] for k, v in self.tangents.items()},
                       meta=dict(self.meta, n_steps=max(keep - 1, 0), **_head_modes(self.meta, keep)))

    def folds(self) -> list[SpecialPoint]:
        """Special points of kind ``"fold"``."""
        return [sp for sp in self.special_points if sp.kind == "fold"]

    def branch_points(self) -> list[SpecialPoint]:
        """Special points of kind ``"branch_point"``."""
        return [sp for sp in self.special_points if sp.kind == "branch_point"]

    def events(self, label: str | None = None) -> list[SpecialPoint]:
        """Special points of kind ``"event"`` (optionally with a given label)."""
        return [sp for sp in self.special_points if sp.kind == "event" and (label is None or sp.label == label)]

    def tangent(self, name: str) -> np.ndarray | None:
        """``d(name)/ds`` along the branch (``"p"`` or the parameter name: :attr:`tangent_p`); None when not stored."""
        if name == "p" or name == self.meta.get("parameter_name"):
            return self.tangent_p if self.tangent_p.shape == self.p.shape else None
        values = self.tangents.get(name)
        return values if values is not None and values.shape == self.p.shape else None

    def observable(self, name: str) -> np.ndarray:
        """Observable values along the branch; ``"p"`` gives the parameter."""
        if name == "p" or name == self.meta.get("parameter_name"):
            return self.p
        try:
            return self.observables[name]
        except KeyError:
            raise KeyError(f"branch has no observable {name!r}; it has {sorted(self.observables)}") from None

    def __repr__(self) -> str:
        kinds = ", ".join(f"{sp.kind}@{sp.p:.6g}" for sp in self.special_points)
        return f"Branch({len(self)} points, status={self.status!r}, special=[{kinds}])"

    # ---- persistence -----------------------------------------------------------------------------
    def save(self, path: str | os.PathLike) -> Path:
        """Write the branch to ``path`` (``.npz``), atomically: a temporary file is moved in place."""
        header, arrays = self.to_bundle()
        return write_bundle(path, "contin-branch", header, arrays)

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Branch":
        """Load a branch written by :meth:`save`; raises :class:`BranchFileError` if it is corrupt."""
        header, arrays = read_bundle(path, "contin-branch", BranchFileError)
        return cls.from_bundle(header, arrays, where=str(path))

    def to_bundle(self, prefix: str = "") -> tuple[dict[str, Any], dict[str, np.ndarray]]:
        """The branch as a JSON header and named arrays (names start with ``prefix``), for a bundle file."""
        arrays: dict[str, np.ndarray] = {
            "p": self.p, "u": self.u, "s": self.s, "tangent_p": self.tangent_p,
            "residual": self.residual, "newton_iterations": self.newton_iterations,
        }
        if self.n_negative is not None:
            arrays["n_negative"] = self.n_negative
        if self.eigenvalues is not None:
            arrays["eigenvalues"] = self.eigenvalues
        obs_names = list(self.observables)
        for i, name in enumerate(obs_names):
            arrays[f"obs_{i}"] = self.observables[name]
        for i, spt in enumerate(self.special_points):
            arrays[f"special_u_{i}"] = spt.u
        tangent_names = list(self.tangents)
        for i, name in enumerate(tangent_names):
            arrays[f"dobs_{i}"] = self.tangents[name]
        stab_labels = list(self.stability_by)
        for i, label in enumerate(stab_labels):
            arrays[f"stab_nneg_{i}"], arrays[f"stab_eigs_{i}"] = self.stability_by[label]
        header = {
            "version": 1, "observables": obs_names, "stability_labels": stab_labels, "tangents": tangent_names,
            "special_points": [spt.header() for spt in self.special_points],
            "status": self.status, "message": self.message, "meta": json_ready(self.meta, keep_nonfinite=True),
        }
        return header, {prefix + k: v for k, v in arrays.items()}

    @classmethod
    def from_bundle(cls, header: dict[str, Any], arrays: dict[str, np.ndarray], prefix: str = "",
                    where: str = "bundle") -> "Branch":
        """The branch stored by :meth:`to_bundle`; raises :class:`BranchFileError` (naming ``where``) if inconsistent."""
        try:
            arrays = {k[len(prefix):]: v for k, v in arrays.items() if k.startswith(prefix)}
            observables = {name: arrays[f"obs_{i}"] for i, name in enumerate(header["observables"])}
            specials = [SpecialPoint.from_header(h, arrays[f"special_u_{i}"])
                        for i, h in enumerate(header["special_points"])]
            branch = cls(
                p=arrays["p"], u=arrays["u"], s=arrays["s"], tangent_p=arrays["tangent_p"],
                residual=arrays["residual"], newton_iterations=arrays["newton_iterations"],
                observables=observables, n_negative=arrays.get("n_negative"),
                eigenvalues=arrays.get("eigenvalues"), special_points=specials,
                stability_by={label: (arrays[f"stab_nneg_{i}"], arrays[f"stab_eigs_{i}"])
                              for i, label in enumerate(header.get("stability_labels", []))},
                status=header["status"], message=header["message"], meta=header["meta"],
                tangents={name: arrays[f"dobs_{i}"] for i, name in enumerate(header.get("tangents", []))})
        except Exception as exc:  # key, type and shape errors all mean "corrupt"
            raise BranchFileError(f"{where}: inconsistent branch data ({type(exc).__name__}: {exc})") from None
        m = branch.p.size
        for name, arr in [("u", branch.u), ("s", branch.s), ("residual", branch.residual)]:
            if arr.shape[0] != m:
                raise BranchFileError(f"{where}: array {name!r} has {arr.shape[0]} rows, expected {m}")
        return branch


def _head_modes(meta: dict[str, Any], keep: int) -> dict[str, Any]:
    """``meta["modes"]`` (the watched families' per-point counts, :mod:`contin.watch.modes`) for the first
    ``keep`` points."""
    if "modes" not in meta:
        return {}
    out = {}
    for name, fam in meta["modes"].items():
        width = len(fam.get("keys", [])) or 1
        out[name] = {**fam, **{key: np.asarray(fam[key], dtype=float).reshape(-1, width)[:keep].tolist()
                               for key in ("n_negative", "lowest") if key in fam}}
    return {"modes": out}
