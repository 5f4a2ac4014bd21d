"""Recording of a traced branch: accepted points, their stability, and the special points.

:class:`Recorder` collects what the continuation accepts and builds the :class:`Branch`.  At the end
it gives every fold, branch point and extremum event its stability on either side (see
:func:`stability_around`).
"""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np

from .path.curve import Curve, Point
from .problem import Problem
from .results.branch import Branch, SpecialPoint
from .settings import Settings
from .watch.modes import family_counts

__all__ = ["Recorder", "stability_around"]


def stability_around(spt: SpecialPoint, n_negative_by: dict[str, np.ndarray], primary: str) -> None:
    """Record the stability on either side of a special point, under every label, in ``spt.info``.

    The sides are the stored points around it: ``index`` and ``index + 1``, or, for a point that ends
    its branch (``info["ends_branch"]``, stored last), only the point before.  The shape is::

        info["stability"] = {label: {"n_negative_before": int, "stable_before": bool,
                                     "n_negative_after": int, "stable_after": bool}}   # per label
        info["stability_label"] = label        # the label of the flat keys below
        info["n_negative_before"], info["stable_before"], info["n_negative_after"], info["stable_after"]

    The flat keys are given under ``info["stability_label"]``: the primary (first) label for folds
    and branch points (the control of the traced problem), the label an extremum event declares
    (:class:`contin.watch.events.Event`; none without one).  ``*_after`` is absent for a point that ends
    the branch.
    """
    ends = bool(spt.info.get("ends_branch"))
    before = spt.index - 1 if ends else spt.index
    after = None if ends else spt.index + 1
    table: dict[str, dict[str, Any]] = {}
    for label, nneg in n_negative_by.items():
        entry: dict[str, Any] = {}
        for side, i in (("before", before), ("after", after)):
            if i is not None and 0 <= i < len(nneg):
                entry[f"n_negative_{side}"] = int(nneg[i])
                entry[f"stable_{side}"] = bool(nneg[i] == 0)
        table[label] = entry
    spt.info["stability"] = table
    label = spt.info.get("stability_label", primary if spt.kind != "event" else None)
    if label in table:
        spt.info["stability_label"] = label
        spt.info.update(table[label])


def observed_rates(problem: Any, pt: Point) -> dict[str, tuple[float, float, Any, float]]:
    """``(value, d obs/ds, d obs/du, d obs/dp)`` of each observable with a declared derivative at ``pt``.

    Evaluated once per point and kept on it (``pt.observed``): the continuation loop's step guard
    and the recorder read the same numbers.  ``d obs/ds = dobs/du . t_u + dobs/dp t_p``; NaN where
    the derivative cannot be evaluated.
    """
    if pt.observed is None:
        observed = {}
        for name, derivative in problem.observable_derivatives.items():
            fun = problem.observables.get(name)
            if fun is None:
                continue
            value = float(fun(pt.u, pt.p))
            d_u, d_p, rate = None, math.nan, math.nan
            if pt.t_u is not None and pt.t_p is not None:
                try:
                    d_u, d_p = derivative(pt.u, pt.p)
                    d_p = float(d_p)
                    rate = float(np.dot(d_u, pt.t_u) + d_p * pt.t_p)
                except (ValueError, TypeError, ArithmeticError):
                    d_u, d_p, rate = None, math.nan, math.nan
            observed[name] = (value, rate, d_u, d_p)
        pt.observed = observed
    return pt.observed


def _watched(spt: SpecialPoint) -> bool:
    """Special points that get stability data: folds, branch points and extremum events."""
    return spt.kind in ("fold", "branch_point") or "extremum_of" in spt.info


class Recorder:
    """Accumulates accepted points and special points into a :class:`Branch`.

    Parameters
    ----------
    problem : Problem
    st : Settings
    curve : Curve
        Gives the absolute tolerance every stored point must meet.
    """

    def __init__(self, problem: Problem, st: Settings, curve: Curve) -> None:
        self.problem, self.st, self.curve = problem, st, curve
        self.p: list[float] = []
        self.u: list[np.ndarray] = []
        self.s: list[float] = []
        self.t_p: list[float] = []
        self.res: list[float] = []
        self.iters: list[int] = []
        self.obs: dict[str, list[float]] = {name: [] for name in problem.observables}
        # d(observable)/ds of the observables with exact derivatives (for smooth plots, Branch.tangents)
        self.derivatives = {name: d for name, d in problem.observable_derivatives.items() if name in self.obs}
        self.tangents: dict[str, list[float]] = {name: [] for name in self.derivatives}
        self.n_neg_by: dict[str, list[int]] = {}
        self.eigs_by: dict[str, list[np.ndarray]] = {}
        self.specials: list[SpecialPoint] = []
        # changes of the stability count that no located point explains (the result is in doubt)
        self.doubts: list[str] = []
        #: parameters at which the run crossed a bend at a fixed parameter (:func:`contin.palc._bridge_bend`)
        self.bridged: list[float] = []
        self.families = tuple(getattr(problem, "operator_families", ())) if st.stability else ()
        self.modes: dict[str, list[list[int]]] = {fam.name: [] for fam in self.families}
        self.lowest: dict[str, list[list[float]]] = {fam.name: [] for fam in self.families}

    def add(self, pt: Point) -> None:
        """Store an accepted point (its observables and, when asked, its stability)."""
        if not (pt.residual <= self.curve.tol):
            raise AssertionError("internal error: attempted to store an unconverged point")
        self.p.append(pt.p)
        if self.st.store_states or not self.u:
            self.u.append(pt.u.copy())
        else:
            self.u[-1] = pt.u.copy()
        self.s.append(pt.s)
        self.t_p.append(pt.t_p)
        self.res.append(pt.residual)
        self.iters.append(pt.iterations)
        observed = observed_rates(self.problem, pt) if self.derivatives else {}
        for name, fun in self.problem.observables.items():
            self.obs[name].append(observed[name][0] if name in observed else float(fun(pt.u, pt.p)))
        for name in self.derivatives:
            self.tangents[name].append(observed[name][1] if name in observed else math.nan)
        extra = 0
        if self.families:
            for fam in self.families:
                counts = (pt.modes or {}).get(fam.name)
                counts = list(counts if counts is not None else family_counts(fam, pt.u, pt.p))
                self.modes[fam.name].append(counts)
                lows = (pt.modes or {}).get(f"{fam.name}.lowest")
                self.lowest[fam.name].append([float(v) for v in lows] if lows is not None else [math.nan] * len(counts))
                extra += sum(fam.copies(k) * c for k, c in zip(fam.keys, counts))
        if self.st.stability:
            self._add_stability(pt, extra)

    def stability_of(self, pt: Point) -> dict[str, Any]:
        """The problem's stability at ``pt`` by label, computed once and kept on the point."""
        if pt.stability is None:
            pt.stability = self.problem.stability(pt.u, pt.p, self.st.n_eigs)
        return pt.stability

    def _add_stability(self, pt: Point, extra: int = 0) -> None:
        """Store the point's Morse index under every label, plus ``extra``: the negative eigenvalues of the
        problem's operator families (other modes, shared by every control), so that a point is stable
        only when it is stable against every mode."""
        infos = self.stability_of(pt)
        if not infos:
            raise ValueError(f"stability requested but problem {self.problem.name!r} has no stability operator")
        if not self.n_neg_by:  # the first point fixes the labels and their order
            self.n_neg_by = {label: [] for label in infos}
            self.eigs_by = {label: [] for label in infos}
        k = self.st.n_eigs
        for label in self.n_neg_by:
            info = infos[label]
            e = np.full(k, np.nan)
            m = min(info.eigenvalues.size, k)
            e[:m] = info.eigenvalues[:m]
            self.n_neg_by[label].append(info.n_negative + extra)
            self.eigs_by[label].append(e)

    def special(self, spt: SpecialPoint) -> None:
        """Store a special point; without an index it lies after the last stored point."""
        if spt.index < 0:
            spt.index = len(self.p) - 1
        self.specials.append(spt)

    def special_late(self, spt: SpecialPoint) -> None:
        """Store a special point found after later ones (its ``index`` set), in path order."""
        at = next((k for k, other in enumerate(self.specials) if other.index > spt.index), len(self.specials))
        self.specials.insert(at, spt)

    def finish(self, status: str, message: str, t_start: float) -> Branch:
        """The :class:`Branch` of everything recorded, ended for ``status`` / ``message``."""
        n = self.u[0].size if self.u else 0
        stab = self.st.stability and any(self.n_neg_by.values())
        by_label = {label: (np.array(self.n_neg_by[label], dtype=int), np.array(self.eigs_by[label]))
                    for label in self.n_neg_by} if stab else {}
        if stab:
            primary = next(iter(by_label))
            nneg = {label: v[0] for label, v in by_label.items()}
            for spt in self.specials:
                if _watched(spt):
                    stability_around(spt, nneg, primary)
        first = next(iter(by_label.values()), (None, None))
        return Branch(
            p=np.array(self.p), u=np.array(self.u) if self.u else np.zeros((0, n)), s=np.array(self.s),
            tangent_p=np.array(self.t_p), residual=np.array(self.res),
            newton_iterations=np.array(self.iters, dtype=int),
            observables={k: np.array(v) for k, v in self.obs.items()},
            n_negative=first[0], eigenvalues=first[1], stability_by=by_label,
            special_points=self.specials, status=status, message=message, meta=self._meta(t_start),
            tangents={k: np.array(v) for k, v in self.tangents.items()})

    def _meta(self, t_start: float) -> dict[str, Any]:
        meta: dict[str, Any] = {}
        if self.families:
            meta["modes"] = {fam.name: {"keys": list(fam.keys), "multiplicity": [fam.copies(k) for k in fam.keys],
                                        "n_negative": self.modes[fam.name], "lowest": self.lowest[fam.name]}
                             for fam in self.families}
        return {**meta, "problem": self.problem.name, "parameter_name": self.problem.parameter_name,
                "wall_time_s": time.perf_counter() - t_start, "n_steps": max(len(self.p) - 1, 0),
                "tol": self.st.tol, "abs_tol": self.curve.tol, "state_weight": self.curve.state_weight,
                "param_weight": self.curve.param_weight}
