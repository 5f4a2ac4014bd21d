"""Quasi-static sweeps: follow the stable equilibrium while the load goes monotonically to a target.

A structure loaded slowly stays on a stable equilibrium branch until that branch ends in a fold
(limit point) of the control parameter; there it snaps dynamically to another stable state at the
same load and loading continues from there.  :func:`quasistatic` reproduces this: it alternates
:func:`contin.continuation` (stopping at the first fold) and :func:`contin.jump` (from the fold to a
distinct stable state), until the parameter reaches ``p_end``.  A loading sweep followed by an
unloading sweep gives the hysteresis loop; :func:`contin.diagram` of the two sweeps' branches and
jumps shows it as a cycle.

The module is generic: it knows nothing about any model beyond the :class:`contin.Problem`
interface (a conservative problem with an energy and a stability operator).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from .branch import Branch, SpecialPoint
from .events import Event
from .jump import JumpError, JumpResult, jump
from .linalg import SingularMatrixError
from .palc import CorrectorFailure, Curve, Settings, continuation
from .problem import NonFiniteError, Problem
from .stability import stability_info

__all__ = ["quasistatic", "QuasiStaticResult", "DEFAULT_JUMP_ATTEMPTS", "restate_jump"]

#: Default ``jump_attempts`` of :func:`quasistatic`: ``(relative overshoot, perturbation)`` pairs
#: tried in turn.  Exactly at a fold the energy is flat to third order along the null vector, so the
#: minimisation may stall next to the fold; a parameter a hair past the fold has no equilibrium
#: nearby and the minimisation has to leave for the distant stable state.
#: The engine's default kick (1e-3 to 1e-1 of the state's size) can be too large: where the energy
#: along the null vector stiffens quickly (a thin shell's membrane stretching does this) it rises on
#: both sides of the fold state at that distance, so a smaller kick is tried next.
DEFAULT_JUMP_ATTEMPTS: tuple[tuple[float, float | None], ...] = ((1e-6, None), (1e-6, 1e-4), (1e-4, None),
                                                                 (1e-4, 1e-4))

_SETTING_NAMES = frozenset(f.name for f in fields(Settings))


@dataclass
class QuasiStaticResult:
    """Outcome of :func:`quasistatic`.

    Attributes
    ----------
    p0, p_end : float
        Start and target of the control parameter.
    direction : int
        ``+1`` when ``p_end > p0`` (loading), ``-1`` otherwise.
    branches : list of Branch
        The stable branches in sweep order.  Branch ``k + 1`` starts at the landing state of
        ``jumps[k]`` (its first special point is that landing, ``kind="jump"``).
    jumps : list of JumpResult
        The snaps in sweep order, each stated at its fold's parameter: ``u_from`` is the fold state,
        ``u_to`` the stable landing state at the same parameter.  ``info`` holds ``fold_p``,
        ``p_minimised`` (where the energy minimisation ran: past the fold by the overshoot),
        ``overshoot``, ``attempt``, ``separation`` (max-norm distance landing - fold) and
        ``restated`` (False if the landing could not be carried back to ``fold_p``; the jump then
        stays at ``p_minimised``).
    folds : list of SpecialPoint
        The fold that ended each branch that was followed by a snap (or by a failed snap attempt),
        in sweep order.
    status : str
        ``"completed"`` (reached ``p_end``), ``"jump_failed"`` (no snap attempt landed on a distinct
        stable state), ``"max_snaps"`` (a fold was reached after ``max_snaps`` snaps),
        ``"branch_point"`` (the stable branch ends in a branch point: the sweep does not choose a
        bifurcating branch), ``"lost_stability"`` (a stored point is unstable although no fold or
        branch point was located), ``"unstable_start"`` (the starting state is not stable) or
        ``"stopped"`` (a continuation run ended for another reason: ``max_steps``, a step-size
        failure, or a user bound before ``p_end``; the branch's own message is quoted).
    message : str
        Why the sweep stopped, in words.
    u_final : ndarray
        The last stable state reached (at ``p_final``).
    p_final : float
        The parameter reached (``p_end`` when ``status == "completed"``).
    info : dict
        Details: ``jump_attempts`` (per snap, the reasons of the failed attempts), ``parameter_name``.
    """

    p0: float
    p_end: float
    direction: int
    branches: list[Branch]
    jumps: list[JumpResult]
    folds: list[SpecialPoint]
    status: str
    message: str
    u_final: np.ndarray
    p_final: float
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def success(self) -> bool:
        """True when the sweep reached ``p_end``."""
        return self.status == "completed"

    @property
    def jump_parameters(self) -> np.ndarray:
        """Parameters of the folds the sweep snapped at (one per jump, in sweep order)."""
        return np.array([jr.info["fold_p"] for jr in self.jumps], dtype=float)

    def observable(self, name: str) -> np.ndarray:
        """An observable (or ``"p"``/the parameter name) along the whole sweep, branches concatenated.

        A snap appears as two consecutive values at the same parameter: the fold (end of one branch)
        and the landing (start of the next).
        """
        parts = [br.observable(name) for br in self.branches if len(br)]
        return np.concatenate(parts) if parts else np.zeros(0)

    @property
    def p(self) -> np.ndarray:
        """The parameter along the whole sweep (see :meth:`observable`)."""
        parts = [br.p for br in self.branches if len(br)]
        return np.concatenate(parts) if parts else np.zeros(0)

    def __repr__(self) -> str:
        return (f"QuasiStaticResult({self.p0:.6g} -> {self.p_end:.6g}: {len(self.branches)} branches, "
                f"{len(self.jumps)} jumps, status={self.status!r})")


def _distance(u_a: np.ndarray, u_b: np.ndarray) -> float:
    return float(np.max(np.abs(np.asarray(u_a) - np.asarray(u_b)), initial=0.0))


def _snap(problem: Problem, curve: Curve, fold: SpecialPoint, u_fold: np.ndarray, direction: int, p_end: float,
          scale: float, attempts: Sequence[tuple[float, float | None]], tol: float, max_iter: int,
          min_separation: float) -> tuple[JumpResult | None, list[str]]:
    """Try each ``(overshoot, perturbation)``; return the first jump landing on a distinct stable state."""
    p_fold = float(fold.p)
    reasons: list[str] = []
    ref = max(1.0, float(np.max(np.abs(u_fold), initial=0.0)))
    for k, (overshoot, kick) in enumerate(attempts):
        p_jump = p_fold + direction * overshoot * scale
        if direction * (p_jump - p_end) > 0:
            p_jump = p_end  # never snap beyond the end of the sweep
        tag = f"attempt {k + 1} (overshoot {overshoot:g}, perturbation {'default' if kick is None else f'{kick:g}'})"
        try:
            jr = jump(problem, u_fold, p_jump, tol=tol, max_iter=max_iter,
                      perturbation=None if kick is None else kick * ref)
        except (JumpError, NonFiniteError, CorrectorFailure, SingularMatrixError, np.linalg.LinAlgError,
                ValueError) as exc:
            reasons.append(f"{tag}: {exc}")
            continue
        if not jr.success:
            reasons.append(f"{tag}: {jr.message or 'did not land on a stable state'}")
            continue
        sep = _distance(jr.u_to, u_fold)
        if sep <= min_separation * ref:
            reasons.append(f"{tag}: landed back next to the fold (max|u_to - u_fold| = {sep:.2e} "
                           f"<= {min_separation:g} * {ref:.3g})")
            continue
        jr.info.update({"fold_p": p_fold, "p_minimised": p_jump, "overshoot": overshoot, "attempt": k + 1,
                        "separation": sep})
        return _restate_at_fold(problem, curve, jr, u_fold, p_fold, sep), reasons
    return None, reasons


def restate_jump(problem: Problem, jr: JumpResult, u_fold: np.ndarray, p_fold: float,
                 settings: Settings | None = None) -> JumpResult:
    """Carry a jump minimised a hair past a fold back to the fold's own parameter ``p_fold``.

    Newton from the landing at ``p_fold``; the result is the jump stated at the fold, or ``jr``
    unchanged (``info["restated"]`` False, with the reason) if the landing branch is not regular,
    stable and near there.  :func:`quasistatic` does this for every snap.
    """
    curve = Curve(problem, settings or Settings())
    return _restate_at_fold(problem, curve, jr, np.asarray(u_fold, dtype=float), float(p_fold),
                            _distance(jr.u_to, u_fold))


def _restate_at_fold(problem: Problem, curve: Curve, jr: JumpResult, u_fold: np.ndarray, p_fold: float,
                     sep: float) -> JumpResult:
    """The snap at the fold's own parameter: Newton from the landing back to ``p_fold``.

    The overshoot only serves to leave the fold; the landing branch is regular there, so its state at
    ``p_fold`` is a Newton correction away.  Stating the jump at ``p_fold`` makes it start exactly at
    the fold that ended the branch (the same node of :func:`contin.diagram`) and leaves no gap in the
    parameter.  If the correction fails, leaves the landing branch or is not stable, the jump stays at
    the parameter it was minimised at (``info["restated"]`` is False, with the reason).
    """
    if jr.p == p_fold:
        jr.info["restated"] = True
        return jr
    try:
        u_to, res, _ = curve.newton_fixed_p(jr.u_to, p_fold)
        stab = stability_info(problem.stability_operator(u_to, p_fold), 1)
    except (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        jr.info.update({"restated": False, "restate_error": str(exc)})
        return jr
    moved = _distance(u_to, jr.u_to)
    if stab.n_negative > 0 or moved > 0.1 * sep:
        jr.info.update({"restated": False, "restate_error": f"the landing branch at the fold parameter is "
                        f"{'unstable' if stab.n_negative else 'too far from the landing'} (moved {moved:.2e})"})
        return jr
    info = dict(jr.info, restated=True, separation=_distance(u_to, u_fold))
    return replace(jr, p=p_fold, u_to=u_to, energy_from=float(problem.energy(u_fold, p_fold)),
                   energy_to=float(problem.energy(u_to, p_fold)), residual=res, n_negative=stab.n_negative,
                   smallest_eigenvalue=float(stab.eigenvalues[0]), info=info)


def quasistatic(problem: Problem, u0: Any, p0: float, p_end: float, settings: Settings | None = None, *,
                max_snaps: int = 10, jump_attempts: Sequence[tuple[float, float | None]] = DEFAULT_JUMP_ATTEMPTS,
                jump_tol: float | None = None, jump_max_iter: int = 500, min_separation: float = 1e-3,
                events: Sequence[Event] = (), **overrides: Any) -> QuasiStaticResult:
    """Follow the stable equilibrium while the parameter goes monotonically from ``p0`` to ``p_end``.

    The sweep traces the stable branch through ``(u0, p0)`` with :func:`contin.continuation` in the
    direction of ``p_end``, stopping at ``p_end`` or at the first fold, whichever comes first.  At a
    fold the branch cannot continue in the sweep direction, so the structure snaps:
    :func:`contin.jump` minimises the energy at a parameter slightly past the fold (in the sweep
    direction) and the landing must be a stable state distinct from the fold state.  The landing is
    then carried back to the fold's own parameter by Newton's method (the landing branch is regular
    there), so the jump is stated at the fold load, as in the quasi-static idealisation, and joins
    the fold in :func:`contin.diagram`.  Continuation resumes from the landing (``origin=`` the jump)
    in the same direction.  Every stored point of every branch is checked to be stable under the
    problem's primary stability operator (the one :func:`contin.jump` minimises with).

    Parameters
    ----------
    problem : Problem
        A conservative problem (energy and symmetric Hessian, or a stability operator).
    u0 : array_like
        Starting state (corrected by Newton at ``p0``); it must be stable.
    p0, p_end : float
        Start and end of the parameter sweep (``p_end < p0`` unloads).
    settings : Settings, optional
        Continuation options; fields may also be passed as keywords.  The sweep sets ``direction``,
        the bound at ``p_end`` (``p_max`` when loading, ``p_min`` when unloading), ``stop_at`` (folds
        and branch points) and ``stability=True``; every other option is used as given (e.g. a
        bound on an observable, which then stops the sweep with status ``"stopped"``).
    max_snaps : int
        Maximum number of snaps; reaching one more fold ends the sweep with status ``"max_snaps"``.
    jump_attempts : sequence of (float, float or None)
        ``(overshoot, perturbation)`` pairs tried in turn at each fold until one lands on a distinct
        stable state.  The snap is computed at ``p_fold + direction * overshoot * scale`` with
        ``scale = max(|p_fold|, |p_end - p0|)`` (never beyond ``p_end``); ``perturbation`` is the
        initial kick of :func:`contin.jump` along the unstable eigenvector, in max-norm and in units
        of ``max(1, max|u_fold|)`` (None: the engine's default, the smallest of 1e-3, 1e-2, 1e-1 of
        that size that lowers the energy).  A small overshoot keeps the snap load close to the fold
        load; a small kick matters where the energy along the null vector rises within a short
        distance.
    jump_tol : float, optional
        Relative gradient tolerance of the energy minimisation (default: the continuation ``tol``).
    jump_max_iter : int
        Iteration limit of each minimisation.
    min_separation : float
        A landing counts as a distinct state only when ``max|u_to - u_fold| > min_separation *
        max(1, max|u_fold|)``; closer landings are the minimisation stalling next to the fold.
    events : sequence of Event
        User events passed to every continuation run.
    **overrides
        Settings fields.

    Returns
    -------
    QuasiStaticResult
        Branches and jumps in sweep order, the folds snapped at, the final state, a status and a
        message saying why the sweep stopped.

    Raises
    ------
    ValueError
        If ``p_end == p0``, ``max_snaps < 0``, no jump attempt is given, or the problem has no
        stability operator.
    TypeError
        For an unknown keyword.

    Examples
    --------
    Loading and unloading of a snapping structure (the hysteresis loop)::

        load = contin.quasistatic(problem, u0, 0.0, p_hi)
        unload = contin.quasistatic(problem, load.u_final, p_hi, 0.0)
        G = contin.diagram(load.branches + unload.branches, load.jumps + unload.jumps)
    """
    unknown = set(overrides) - _SETTING_NAMES
    if unknown:
        raise TypeError(f"unknown quasistatic option(s): {', '.join(sorted(unknown))}")
    p0, p_end = float(p0), float(p_end)
    if not (math.isfinite(p0) and math.isfinite(p_end)) or p_end == p0:
        raise ValueError(f"quasistatic needs finite p0 != p_end (got p0 = {p0!r}, p_end = {p_end!r})")
    if max_snaps < 0:
        raise ValueError(f"quasistatic: max_snaps must be >= 0, got {max_snaps!r}")
    if not jump_attempts:
        raise ValueError("quasistatic: jump_attempts must contain at least one (overshoot, perturbation) pair")
    direction = 1 if p_end > p0 else -1
    bound = {"p_max": p_end} if direction > 0 else {"p_min": p_end}
    st = replace(settings or Settings(), **overrides)
    st = replace(st, direction=direction, stability=True, stop_at=("fold", "branch_point"), **bound)
    st.validate()
    tol = st.tol if jump_tol is None else float(jump_tol)
    pname = problem.parameter_name
    scale = abs(p_end - p0)

    branches: list[Branch] = []
    jumps: list[JumpResult] = []
    folds: list[SpecialPoint] = []
    attempts_log: list[list[str]] = []
    info: dict[str, Any] = {"parameter_name": pname, "jump_attempts": attempts_log}

    def result(status: str, message: str, u_fin: np.ndarray, p_fin: float) -> QuasiStaticResult:
        return QuasiStaticResult(p0=p0, p_end=p_end, direction=direction, branches=branches, jumps=jumps,
                                 folds=folds, status=status, message=message, u_final=np.asarray(u_fin),
                                 p_final=float(p_fin), info=info)

    curve = Curve(problem, st)
    # ---- the start must be a stable equilibrium
    u_start = np.array(u0, dtype=float).ravel()
    try:
        u_start, _, _ = curve.newton_fixed_p(u_start, p0)
    except (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        return result("stopped", f"could not converge the starting state at {pname} = {p0:.10g}: {exc}",
                      u_start, p0)
    op = problem.stability_operator(u_start, p0)
    if op is None:
        raise ValueError(f"quasistatic needs a stability operator; problem {problem.name!r} has none")
    start_info = stability_info(op, 1)
    if start_info.n_negative > 0:
        return result("unstable_start", f"the starting state at {pname} = {p0:.10g} is unstable "
                      f"({start_info.n_negative} negative eigenvalue(s)); a quasi-static sweep starts on a "
                      "stable equilibrium", u_start, p0)

    u, p, origin = u_start, p0, None
    while True:
        br = continuation(problem, u, p, st, events=events, origin=origin)
        branches.append(br)
        if len(br) == 0:
            return result("stopped", f"continuation from {pname} = {p:.10g} failed: {br.message}", u, p)
        u_last, p_last = br.u[-1], float(br.p[-1])
        # stability of every stored point except a terminal fold or branch point (zero eigenvalue there)
        terminal = next((s for s in br.special_points
                         if s.info.get("ends_branch") and s.kind in ("fold", "branch_point")), None)
        n_neg = np.asarray(br.n_negative)
        check = n_neg[:-1] if terminal is not None else n_neg
        bad = np.flatnonzero(check > 0)
        if bad.size:
            i = int(bad[0])
            return result("lost_stability",
                          f"the branch became unstable at {pname} = {br.p[i]:.10g} (stored point {i}, "
                          f"{int(n_neg[i])} negative eigenvalue(s)) without a located fold or branch point",
                          br.u[max(i - 1, 0)], float(br.p[max(i - 1, 0)]))
        if br.status == "bound" and abs(p_last - p_end) <= 1e-9 * max(1.0, abs(p_end), scale):
            return result("completed", f"reached {pname} = {p_end:.10g} after {len(jumps)} snap(s)", u_last, p_last)
        if terminal is None or br.status != "event":
            return result("stopped", f"continuation stopped at {pname} = {p_last:.10g} before reaching "
                          f"{pname} = {p_end:.10g} (status {br.status!r}: {br.message})", u_last, p_last)
        if terminal.kind == "branch_point":
            return result("branch_point", f"the stable branch ends in a branch point at {pname} = "
                          f"{terminal.p:.10g}; the sweep does not choose a bifurcating branch "
                          "(see contin.switch_branch)", u_last, p_last)
        folds.append(terminal)
        if len(jumps) >= max_snaps:
            return result("max_snaps", f"reached a fold at {pname} = {terminal.p:.10g} after max_snaps = "
                          f"{max_snaps} snap(s), before {pname} = {p_end:.10g}", u_last, p_last)
        jr, reasons = _snap(problem, curve, terminal, u_last, direction, p_end, max(abs(terminal.p), scale),
                            jump_attempts, tol, jump_max_iter, min_separation)
        attempts_log.append(reasons)
        if jr is None:
            return result("jump_failed", f"the snap at the fold {pname} = {terminal.p:.10g} did not land on a "
                          f"distinct stable state: {'; '.join(reasons)}", u_last, p_last)
        jumps.append(jr)
        if jr.p == p_end:  # the snap was minimised at p_end and could not be restated at the fold
            return result("completed", f"reached {pname} = {p_end:.10g} by the snap at the fold {pname} = "
                          f"{terminal.p:.10g} ({len(jumps)} snap(s))", jr.u_to, jr.p)
        u, p, origin = jr.u_to, jr.p, jr
