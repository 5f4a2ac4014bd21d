"""Quasi-static sweeps: follow the stable equilibrium while the load goes monotonically to a target.

A structure loaded slowly stays on a stable equilibrium branch until that branch ends in a fold
(limit point) of the control parameter; there it snaps dynamically to another stable state at the
same load and loading continues from there.  :func:`quasistatic` reproduces this: it alternates
:func:`contin.continuation` (stopping at the first fold) and :func:`contin.jump` (from the fold to a
distinct stable state), until the parameter reaches ``p_end`` (or, for a sweep without an end
load, until a bound or the caller's stop condition ends it).  A loading sweep followed by an
unloading sweep gives the hysteresis loop; :func:`contin.diagram` of the two sweeps' branches and
jumps shows it as a cycle.

This is the toolkit's only load-snap loop.  Models adapt it, never copy it: :class:`SnapRules`
says how a fold is left (overshoot and kick schedule, what counts as a distinct landing, whether
the jump is restated at the fold), ``locate_snap`` says where a snap is when a branch ends on an
event (a precursor of a fold too sharp for the engine, or a fold the model locates better), and
``stop_after_jump`` ends a sweep on a landing.  :func:`leave_fold` is one snap of the loop on its own.

The module is generic: it knows nothing about any model beyond the :class:`contin.Problem`
interface (a conservative problem with an energy and a stability operator).  It uses one engine
internal, the fixed-parameter Newton of :class:`contin.palc.Curve` (to converge the start and to
restate a landing at its fold).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from ..numerics.linalg import SingularMatrixError
from ..numerics.stability import stability_info
from ..palc import CorrectorFailure, Curve, Settings, continuation, switch_branch
from ..problem import NonFiniteError, Problem
from ..results.branch import Branch, BranchFileError, SpecialPoint
from ..results.io import json_ready, read_bundle, write_bundle
from ..watch.events import Event
from .jump import JumpError, JumpResult, jump, state_scale

__all__ = ["quasistatic", "QuasiStaticResult", "SnapRules", "DEFAULT_JUMP_ATTEMPTS", "leave_fold", "restate_jump",
           "bound_passed"]

#: Default ``jump_attempts`` of :func:`quasistatic`: ``(relative overshoot, perturbation)`` pairs
#: tried in turn.  Exactly at a fold the energy is flat to third order along the null vector, so the
#: minimisation may stall next to the fold; a parameter a hair past the fold has no equilibrium
#: nearby and the minimisation has to leave for the distant stable state.
#: The engine's default kick (1e-3 to 1e-1 of the state's size) can be too large: where the energy
#: along the null vector stiffens quickly (a thin structure's membrane stretching does this) it rises on
#: both sides of the fold state at that distance, so a smaller kick is tried next.
DEFAULT_JUMP_ATTEMPTS: tuple[tuple[float, float | None], ...] = ((1e-6, None), (1e-6, 1e-4), (1e-4, None),
                                                                 (1e-4, 1e-4))

_SETTING_NAMES = frozenset(f.name for f in fields(Settings))


@dataclass
class QuasiStaticResult:
    """Outcome of :func:`quasistatic`.

    Attributes
    ----------
    p0 : float
        Start of the control parameter.
    p_end : float or None
        Its target (None: the sweep had no end load).
    direction : int
        ``+1`` when loading (``p_end > p0``), ``-1`` otherwise.
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
        ``"completed"`` (reached ``p_end``; without ``p_end``: a bound of the settings, reached by a
        branch or by a snap's landing, or ``stop_after_jump`` said so), ``"jump_failed"`` (no snap attempt landed on a distinct
        stable state), ``"max_snaps"`` (a fold was reached after ``max_snaps`` snaps),
        ``"branch_point"`` (the stable branch ends in a branch point where a stable bifurcating
        branch goes on in the sweep direction, a supercritical pitchfork: there is no snap, and the
        sweep does not choose the branch; at any other branch point the structure snaps as at a
        fold), ``"lost_stability"`` (a stored point is unstable although no fold or
        branch point was located), ``"unstable_start"`` (the starting state is not stable) or
        ``"stopped"`` (a continuation run ended for another reason: ``max_steps``, a step-size
        failure, or a user bound before ``p_end``, reached by a branch or by a snap's landing; the
        branch's own message is quoted).
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
    p_end: float | None
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
    def failed(self) -> bool:
        """True when the loop itself failed (a snap, the snap budget, stability, a branch point or the start).

        False for ``"completed"`` and for ``"stopped"``, where a continuation run ended for its own
        reason (a bound, ``max_steps``) and its branch says why.
        """
        return self.status in ("jump_failed", "max_snaps", "lost_stability", "branch_point", "unstable_start")

    # ---- persistence -----------------------------------------------------------------------------
    def save(self, path: Any) -> Any:
        """Write the whole sweep (branches, jumps, folds, outcome) to one ``.npz`` file, atomically.

        :meth:`load` reads it back identical; e.g. to plot or to build its :func:`contin.diagram`
        later without tracing again.
        """
        branches, jumps = [b.to_bundle(f"branch{k}.") for k, b in enumerate(self.branches)], \
            [j.to_bundle(f"jump{k}.") for k, j in enumerate(self.jumps)]
        arrays: dict[str, np.ndarray] = {"u_final": np.asarray(self.u_final)}
        for _, a in branches + jumps:
            arrays.update(a)
        for k, fold in enumerate(self.folds):
            arrays[f"fold{k}.u"] = np.asarray(fold.u if fold.u is not None else np.zeros(0))
        header = {"p0": float(self.p0), "p_end": None if self.p_end is None else float(self.p_end),
                  "direction": int(self.direction), "status": self.status, "message": self.message,
                  "p_final": float(self.p_final), "info": json_ready(self.info, keep_nonfinite=True),
                  "branches": [h for h, _ in branches], "jumps": [h for h, _ in jumps],
                  "folds": [f.header() for f in self.folds]}
        return write_bundle(path, "contin-quasistatic", header, arrays)

    @classmethod
    def load(cls, path: Any) -> "QuasiStaticResult":
        """Load a sweep written by :meth:`save`; raises :class:`contin.BranchFileError` if it is corrupt."""
        header, arrays = read_bundle(path, "contin-quasistatic", BranchFileError)
        where = str(path)
        try:
            folds = [SpecialPoint.from_header(h, arrays[f"fold{k}.u"]) for k, h in enumerate(header["folds"])]
            return cls(p0=header["p0"], p_end=header["p_end"], direction=header["direction"],
                       branches=[Branch.from_bundle(h, arrays, f"branch{k}.", where)
                                 for k, h in enumerate(header["branches"])],
                       jumps=[JumpResult.from_bundle(h, arrays, f"jump{k}.", where)
                              for k, h in enumerate(header["jumps"])],
                       folds=folds, status=header["status"], message=header["message"],
                       u_final=arrays["u_final"], p_final=header["p_final"], info=header["info"])
        except BranchFileError:
            raise
        except Exception as exc:
            raise BranchFileError(f"{where}: inconsistent quasi-static data ({type(exc).__name__}: {exc})") from None

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
        end = "open" if self.p_end is None else f"{self.p_end:.6g}"
        return (f"QuasiStaticResult({self.p0:.6g} -> {end}: {len(self.branches)} branches, "
                f"{len(self.jumps)} jumps, status={self.status!r})")


def _distance(u_a: np.ndarray, u_b: np.ndarray) -> float:
    return float(np.max(np.abs(np.asarray(u_a) - np.asarray(u_b)), initial=0.0))


#: Exceptions after which a jump attempt counts as failed and the next one is tried.
_ATTEMPT_ERRORS = (JumpError, NonFiniteError, CorrectorFailure, SingularMatrixError, np.linalg.LinAlgError, ValueError)


@dataclass(frozen=True)
class SnapRules:
    """How :func:`quasistatic` leaves a fold: the jump attempts and what counts as a landing.

    Attributes
    ----------
    attempts : sequence of (float, float or None)
        ``(overshoot, perturbation)`` pairs tried in turn until one lands on a distinct stable state
        (default :data:`DEFAULT_JUMP_ATTEMPTS`).  The energy is minimised at ``p_fold + direction *
        overshoot * unit`` (never beyond ``p_end``); ``perturbation`` is the initial kick of
        :func:`contin.jump` along the unstable eigenvector in units of ``perturbation_unit`` (None:
        the engine's default kick).
    overshoot_unit : {"sweep", "fold"}
        The ``unit`` of the overshoot: ``"sweep"`` is ``max(|p_fold|, |p_end - p0|)`` (``|p_fold|``
        when the sweep has no end load), ``"fold"`` is ``|p_fold|`` alone, so that the snap load is
        a fixed relative distance past the fold whatever the sweep's end.
    perturbation_unit : float, optional
        Unit of the kicks, the given ones and the engine's default ones (max-norm); default the
        fold state's scale ``max|u_fold|`` (:func:`contin.analyses.jump.state_scale`).  A model whose state
        has a natural length (e.g. a radius) passes it here.
    separation : callable ``(u_fold, p_fold, u_to, p_to) -> float``, optional
        Distance of a landing from the fold state, in the units of ``min_separation``; default
        ``max|u_to - u_fold| / max|u_fold|``.  A model can measure it in the observable that
        tells two states apart (a pole displacement in units of the radius).
    min_separation : float
        A landing with ``separation > min_separation`` is a snap.  A closer one may be the
        minimisation stalling next to the fold or a short snap to a distinct stable state (a thin
        structure's snap may move it by a fraction of its thickness); it counts as a snap only if, carried
        back to the fold's parameter by Newton's method, it stays on a stable branch of its own
        instead of falling back onto the fold.  Otherwise the next attempt is tried.
    restate : bool
        Carry each landing back to the fold's own parameter by Newton's method (see
        :func:`restate_jump`); False keeps the jump at the parameter it was minimised at.
    give_up_on : tuple of exception types
        Errors of an attempt after which the later attempts are not tried either (e.g. a larger
        overshoot that could only push further out of the model's domain).
    tol : float, optional
        Relative gradient tolerance of the minimisation (default: the continuation ``tol``).
    max_iter : int
        Iteration limit of each minimisation.
    """

    attempts: tuple[tuple[float, float | None], ...] = DEFAULT_JUMP_ATTEMPTS
    overshoot_unit: str = "sweep"
    perturbation_unit: float | None = None
    separation: Callable[[np.ndarray, float, np.ndarray, float], float] | None = None
    min_separation: float = 1e-3
    restate: bool = True
    give_up_on: tuple[type[BaseException], ...] = ()
    tol: float | None = None
    max_iter: int = 500

    def validate(self) -> None:
        """Raise ``ValueError`` for rules that cannot snap."""
        if not self.attempts:
            raise ValueError("quasistatic: jump_attempts must contain at least one (overshoot, perturbation) pair")
        if self.overshoot_unit not in ("sweep", "fold"):
            raise ValueError(f"quasistatic: overshoot_unit must be 'sweep' or 'fold', got {self.overshoot_unit!r}")

    def landing_distance(self, u_fold: np.ndarray, p_fold: float, u_to: np.ndarray, p_to: float,
                         reference: tuple[float, float] | None = None) -> float:
        """How far a landing is from the fold state (see ``separation``), in the state's scale
        (:func:`contin.analyses.jump.state_scale`, with the problem's ``reference`` scales)."""
        if self.separation is not None:
            return float(self.separation(u_fold, p_fold, u_to, p_to))
        return _distance(u_to, u_fold) / state_scale(u_fold, reference)


@dataclass
class _Sweep:
    """What one :func:`quasistatic` call keeps fixed: the problem, its settings and the snap rules."""

    problem: Problem
    curve: Curve
    rules: SnapRules
    direction: int
    p0: float
    p_end: float | None

    def overshoot_unit(self, p_fold: float) -> float:
        if self.rules.overshoot_unit == "fold" or self.p_end is None:
            return abs(p_fold)
        return max(abs(p_fold), abs(self.p_end - self.p0))

    def jump_parameter(self, p_fold: float, overshoot: float) -> float:
        p_jump = p_fold + self.direction * overshoot * self.overshoot_unit(p_fold)
        if self.p_end is not None and self.direction * (p_jump - self.p_end) > 0:
            p_jump = self.p_end  # never snap beyond the end of the sweep
        return p_jump

    def snap(self, fold: SpecialPoint, u_fold: np.ndarray) -> tuple[JumpResult | None, list[str]]:
        """Try each attempt of the rules; return the first jump landing on a distinct stable state."""
        rules, problem = self.rules, self.problem
        p_fold = float(fold.p)
        reasons: list[str] = []
        kick_unit = rules.perturbation_unit or state_scale(u_fold, problem.reference_scales)
        tol = self.curve.settings.tol if rules.tol is None else float(rules.tol)
        trials = [(overshoot, kick, d) for overshoot, kick in rules.attempts for d in _kick_directions(fold)]
        for k, (overshoot, kick, d) in enumerate(trials):
            p_jump = self.jump_parameter(p_fold, overshoot)
            tag = (f"attempt {k + 1} (overshoot {overshoot:g}, perturbation "
                   f"{'default' if kick is None else f'{kick:g}'}"
                   f"{'' if d is None else ', along a resolved branch direction'})")
            try:
                jr = jump(problem, u_fold, p_jump, tol=tol, max_iter=rules.max_iter,
                          perturbation=None if kick is None else kick * kick_unit, scale=kick_unit, direction=d)
            except _ATTEMPT_ERRORS as exc:
                reasons.append(f"{tag}: {exc}")
                if isinstance(exc, rules.give_up_on):
                    break
                continue
            if not jr.success:
                reasons.append(f"{tag}: {jr.message or 'did not land on a stable state'}")
                continue
            sep = rules.landing_distance(u_fold, p_fold, jr.u_to, jr.p, problem.reference_scales)
            if sep <= rules.min_separation:
                nearby = _nearby_landing_branch(problem, self.curve, jr, u_fold, p_fold)
                if isinstance(nearby, str):
                    reasons.append(f"{tag}: landed back next to the fold (separation {sep:.2e} <= "
                                   f"{rules.min_separation:g}, and {nearby})")
                    continue
            jr.info.update({"fold_p": p_fold, "p_minimised": p_jump, "overshoot": overshoot, "attempt": k + 1,
                            "separation": _distance(jr.u_to, u_fold)})
            if not rules.restate:
                jr.info["restated"] = False
                return jr, reasons
            return _restate_at_fold(problem, self.curve, jr, u_fold, p_fold, jr.info["separation"]), reasons
        return None, reasons

def _kick_directions(point: SpecialPoint) -> list[np.ndarray | None]:
    """The kicks a snap tries: the unstable eigenvector (None), and at a multiple branch point each
    resolved branch direction both ways (any vector of the kernel is an eigenvector there, and the
    energy may fall along some of them only)."""
    record = point.bifurcation
    if record is None or record.multiplicity < 2:
        return [None]
    rows = record.directions[:, :-1] if len(record.directions) else record.kernel
    return [None] + [sign * np.asarray(row, dtype=float) for row in rows for sign in (1.0, -1.0)]


def leave_fold(problem: Problem, fold: SpecialPoint, direction: int, settings: Settings | None = None,
               rules: SnapRules | None = None, *, u_fold: np.ndarray | None = None,
               p_end: float | None = None, p0: float | None = None) -> tuple[JumpResult | None, list[str]]:
    """Snap from one fold as :func:`quasistatic` does: try the rules' attempts until one lands.

    Parameters
    ----------
    problem : Problem
        The conservative problem the fold belongs to.
    fold : SpecialPoint
        The fold (or the point a model located as its snap); its state is ``fold.u`` unless
        ``u_fold`` is given.
    direction : int
        ``+1`` when the load was increasing into the fold, ``-1`` when decreasing.
    settings : Settings, optional
        Continuation settings (their ``tol`` is the default jump tolerance; the restating Newton
        uses them).
    rules : SnapRules, optional
        The attempts and landing rules (default ``SnapRules()``).
    u_fold : ndarray, optional
        The fold state, if ``fold`` does not carry it.
    p_end, p0 : float, optional
        The sweep's end and start: the overshoot never passes ``p_end``, and ``overshoot_unit =
        "sweep"`` measures it in ``max(|p_fold|, |p_end - p0|)``.

    Returns
    -------
    (JumpResult or None, list of str)
        The first jump that landed on a distinct stable state (None if none did) and the reasons
        why the attempts before it failed.
    """
    st = settings or Settings()
    u = np.asarray(fold.u if u_fold is None else u_fold, dtype=float)
    start = float(fold.p) if p0 is None else float(p0)
    sweep = _Sweep(problem, Curve(problem, st), rules or SnapRules(), int(direction), start, p_end)
    return sweep.snap(fold, u)


def restate_jump(problem: Problem, jr: JumpResult, u_fold: np.ndarray, p_fold: float,
                 settings: Settings | None = None) -> JumpResult:
    """Carry a jump minimised a hair past a fold back to the fold's own parameter ``p_fold``.

    Newton from the landing at ``p_fold``; the result is the jump stated at the fold, or ``jr``
    unchanged (``info["restated"]`` False, with the reason) if the landing branch is not regular,
    stable and near there.  :func:`quasistatic` does this for every snap unless its rules say not to.
    """
    curve = Curve(problem, settings or Settings())
    return _restate_at_fold(problem, curve, jr, np.asarray(u_fold, dtype=float), float(p_fold),
                            _distance(jr.u_to, u_fold))


#: A landing carried back to the fold's parameter stays on its own branch when it moves by at most
#: this fraction of its distance from the fold state.
_SAME_BRANCH_MOVE = 0.1


def _carry_to_fold_parameter(problem: Problem, curve: Curve, u_to: np.ndarray, p_fold: float,
                             sep: float) -> tuple[np.ndarray, float, Any] | str:
    """The landing's branch at the fold's parameter: Newton from ``u_to`` at ``p_fold``.

    Returns ``(state, residual, stability)`` when Newton converges to a stable state that moved by at
    most :data:`_SAME_BRANCH_MOVE` times ``sep`` (the landing's distance from the fold state), i.e.
    the landing's branch is regular and stable across the overshoot; otherwise the reason, a phrase.
    """
    try:
        u, res, _ = curve.newton_fixed_p(u_to, p_fold)
        stab = stability_info(problem.stability_operator(u, p_fold), 1)
    except (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        return str(exc)
    moved = _distance(u, u_to)
    if stab.n_negative > 0:
        return f"the landing branch at the fold parameter is unstable (moved {moved:.2e})"
    if moved > _SAME_BRANCH_MOVE * sep:
        return (f"carried back to the fold parameter the landing moves by {moved:.2e}, more than "
                f"{_SAME_BRANCH_MOVE:g} of its distance {sep:.2e} from the fold state: it falls back towards the fold")
    return u, res, stab


def _nearby_landing_branch(problem: Problem, curve: Curve, jr: JumpResult, u_fold: np.ndarray,
                           p_fold: float) -> None | str:
    """Whether a landing close to the fold state is a stable state of its own: None if it is, else why not.

    Past the fold the fold's branch has no equilibrium nearby, so a landing close to the fold state is
    either a stall of the descent on the fold's flat energy or a distinct stable state a short way off
    (a thin structure's small snap moves by a fraction of its thickness).  Carried back to the fold's
    parameter, a stall falls back onto the fold (it moves by its whole distance from it), while a
    distinct state stays put on its own stable branch (:func:`_carry_to_fold_parameter`).  Minimised at
    the fold's parameter itself, the two cannot be told apart this way: such a landing counts as a stall.
    """
    if jr.p == p_fold:
        return "it was minimised at the fold's own parameter"
    carried = _carry_to_fold_parameter(problem, curve, jr.u_to, p_fold, _distance(jr.u_to, u_fold))
    return carried if isinstance(carried, str) else None


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
    carried = _carry_to_fold_parameter(problem, curve, jr.u_to, p_fold, sep)
    if isinstance(carried, str):
        jr.info.update({"restated": False, "restate_error": carried})
        return jr
    u_to, res, stab = carried
    info = dict(jr.info, restated=True, separation=_distance(u_to, u_fold))
    return replace(jr, p=p_fold, u_to=u_to, energy_from=float(problem.energy(u_fold, p_fold)),
                   energy_to=float(problem.energy(u_to, p_fold)), residual=res, n_negative=stab.n_negative,
                   smallest_eigenvalue=float(stab.eigenvalues[0]), info=info)


def _terminal_point(br: Branch) -> SpecialPoint | None:
    """The fold or branch point that ends ``br`` (the engine stops exactly on it), if any."""
    return next((s for s in br.special_points if s.info.get("ends_branch") and s.kind in ("fold", "branch_point")),
                None)


#: A stored point closer to a terminal fold than this fraction of the step that reached it counts as the
#: fold itself: the fold's eigenvalue there is zero to within what the state's tolerance fixes, and on a
#: stiff model (a contact barrier next to its indenter) its computed sign can be either.
AT_THE_FOLD = 0.01


def _first_unstable(br: Branch, terminal: SpecialPoint | None) -> int | None:
    """Index of the first stored point with a negative eigenvalue (a terminal fold's zero one excluded).

    With a terminal fold (the last stored point) that one eigenvalue is also allowed at the point before it,
    when that point lies within :data:`AT_THE_FOLD` of its step from the fold.
    """
    n_neg = np.asarray(br.n_negative)
    if terminal is None:
        return int(bad[0]) if (bad := np.flatnonzero(n_neg > 0)).size else None
    n_neg = n_neg[:-1].copy()
    s = np.asarray(br.s, dtype=float)
    if len(s) >= 3 and n_neg[-1] == 1 and abs(s[-1] - s[-2]) <= AT_THE_FOLD * abs(s[-1] - s[-3]):
        n_neg[-1] = 0
    bad = np.flatnonzero(n_neg > 0)
    return int(bad[0]) if bad.size else None


def _sweep_settings(settings: Settings | None, overrides: dict[str, Any], direction: int, p_end: float | None,
                    stop_at_branch_points: bool) -> Settings:
    unknown = set(overrides) - _SETTING_NAMES
    if unknown:
        raise TypeError(f"unknown quasistatic option(s): {', '.join(sorted(unknown))}")
    st = replace(settings or Settings(), **overrides)
    bound = {} if p_end is None else ({"p_max": p_end} if direction > 0 else {"p_min": p_end})
    stop_at = ("fold", "branch_point") if stop_at_branch_points else ("fold",)
    st = replace(st, direction=direction, stability=True, stop_at=stop_at, **bound)
    st.validate()
    return st


def _sweep_direction(p0: float, p_end: float | None, direction: int | None) -> int:
    if p_end is None:
        if direction not in (1, -1):
            raise ValueError(f"quasistatic without p_end needs direction = +1 or -1, got {direction!r}")
        return int(direction)
    if not (math.isfinite(p0) and math.isfinite(p_end)) or p_end == p0:
        raise ValueError(f"quasistatic needs finite p0 != p_end (got p0 = {p0!r}, p_end = {p_end!r})")
    implied = 1 if p_end > p0 else -1
    if direction is not None and direction != implied:
        raise ValueError(f"quasistatic: direction {direction!r} points away from p_end = {p_end!r}")
    return implied


def _snap_rules(snap: SnapRules | None, jump_attempts: Sequence[tuple[float, float | None]] | None,
                jump_tol: float | None, jump_max_iter: int | None, min_separation: float | None) -> SnapRules:
    """The snap rules of a sweep: ``snap`` (default ``SnapRules()``) with the shorthands that are given.

    Parameters
    ----------
    snap : SnapRules or None
        The caller's rules.
    jump_attempts, jump_tol, jump_max_iter, min_separation
        Shorthands of :func:`quasistatic` for ``attempts``, ``tol``, ``max_iter`` and
        ``min_separation``; None keeps the field of ``snap``.

    Returns
    -------
    SnapRules
        The validated rules.
    """
    shorthand = {"attempts": None if jump_attempts is None else tuple(jump_attempts), "tol": jump_tol,
                 "max_iter": jump_max_iter, "min_separation": min_separation}
    rules = replace(snap or SnapRules(), **{k: v for k, v in shorthand.items() if v is not None})
    rules.validate()
    return rules


def bound_passed(problem: Problem, bounds: dict[str, tuple[float | None, float | None]], u: np.ndarray,
                 p: float) -> str:
    """Which bound on an observable the state ``(u, p)`` lies on or beyond, in words (``""``: none).

    Parameters
    ----------
    problem : Problem
        The problem whose observables the bounds name.
    bounds : dict
        ``name -> (lower, upper)``, either None for no bound (as in :class:`contin.Settings`).
    u, p : ndarray, float
        The state.

    Returns
    -------
    str
        E.g. ``"on or beyond the bound gap >= 0.1 (gap = 0.05)"``, or ``""`` inside every bound.
    """
    for name, (lo, hi) in bounds.items():
        value = float(problem.observables[name](u, p))
        for limit, side, past in ((lo, ">=", lambda v, b: v <= b), (hi, "<=", lambda v, b: v >= b)):
            if limit is not None and past(value, float(limit)):
                return f"on or beyond the bound {name} {side} {float(limit):.10g} ({name} = {value:.10g})"
    return ""


class _SweepEnd(Exception):
    """Ends the loop of :func:`quasistatic`, carrying the finished result; never leaves that function.

    Every step of the loop can end the sweep; raising lets the loop read as its sequence of steps
    instead of a test after each one.
    """

    def __init__(self, result: QuasiStaticResult) -> None:
        super().__init__(result.message)
        self.result = result


@dataclass
class _SweepLoop:
    """One :func:`quasistatic` call under way: its steps, each of which may end the sweep.

    A step that ends the sweep raises :class:`_SweepEnd` with the result (see :meth:`end`).

    Attributes
    ----------
    sweep : _Sweep
        The problem, the continuation settings (``sweep.curve.settings``) and the snap rules.
    pname : str
        The parameter's name, for the messages.
    events : sequence of Event
        User events passed to every continuation run.
    max_snaps : int
        Snap budget: reaching one more fold ends the sweep.
    check_stability : bool
        Whether an unstable stored point without a located fold ends the sweep.
    locate_snap, stop_after_jump : callable or None
        The hooks of :func:`quasistatic`.
    out : QuasiStaticResult
        The result being assembled: branches, folds, jumps and attempt reasons are appended as the
        sweep goes; status, message and final state are set by :meth:`end`.
    """

    sweep: _Sweep
    pname: str
    events: Sequence[Event]
    max_snaps: int
    check_stability: bool
    locate_snap: Callable[[Branch], SpecialPoint | None] | None
    stop_after_jump: Callable[[JumpResult], str | None] | None
    out: QuasiStaticResult

    @classmethod
    def begin(cls, sweep: _Sweep, events: Sequence[Event], max_snaps: int, check_stability: bool,
              locate_snap: Callable[[Branch], SpecialPoint | None] | None,
              stop_after_jump: Callable[[JumpResult], str | None] | None) -> _SweepLoop:
        """A loop with an empty result (no branches, jumps or folds yet)."""
        pname = sweep.problem.parameter_name
        out = QuasiStaticResult(p0=sweep.p0, p_end=sweep.p_end, direction=sweep.direction, branches=[], jumps=[],
                                folds=[], status="", message="", u_final=np.zeros(0), p_final=sweep.p0,
                                info={"parameter_name": pname, "jump_attempts": []})
        return cls(sweep, pname, events, max_snaps, check_stability, locate_snap, stop_after_jump, out)

    def end(self, status: str, message: str, u_fin: np.ndarray, p_fin: float) -> _SweepEnd:
        """Complete the result with why and where the sweep stopped; the caller raises what is returned."""
        out = self.out
        out.status, out.message, out.u_final, out.p_final = status, message, np.asarray(u_fin), float(p_fin)
        return _SweepEnd(out)

    def start(self, u0: Any) -> np.ndarray:
        """The state the first run starts from, after checking that it converges to a stable equilibrium.

        Raises
        ------
        ValueError
            If the problem has no stability operator.
        """
        problem, p0, pname = self.sweep.problem, self.sweep.p0, self.pname
        u_raw = np.array(u0, dtype=float).ravel()
        try:
            u_start, _, _ = self.sweep.curve.newton_fixed_p(u_raw, p0)
        except (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError) as exc:
            raise self.end("stopped", f"could not converge the starting state at {pname} = {p0:.10g}: {exc}",
                           u_raw, p0)
        op = problem.stability_operator(u_start, p0)
        if op is None:
            raise ValueError(f"quasistatic needs a stability operator; problem {problem.name!r} has none")
        n_neg = stability_info(op, 1).n_negative
        if n_neg > 0:
            raise self.end("unstable_start", f"the starting state at {pname} = {p0:.10g} is unstable ({n_neg} "
                           "negative eigenvalue(s)); a quasi-static sweep starts on a stable equilibrium",
                           u_start, p0)
        # the first run starts from u0 itself: continuation corrects it at p0 as it corrects any start
        return u_raw

    def load(self, u: np.ndarray, p: float, origin: JumpResult | None) -> Branch:
        """One continuation run from ``(u, p)`` in the sweep direction: to a fold, a bound or ``p_end``."""
        br = continuation(self.sweep.problem, u, p, self.sweep.curve.settings, events=self.events, origin=origin)
        self.out.branches.append(br)
        if len(br) == 0:
            raise self.end("stopped", f"continuation from {self.pname} = {p:.10g} failed: {br.message}", u, p)
        return br

    def check_branch(self, br: Branch) -> SpecialPoint | None:
        """The fold or branch point ending ``br``; the sweep ends if ``br`` lost stability or reached ``p_end``."""
        pname, p0, p_end = self.pname, self.sweep.p0, self.sweep.p_end
        u_last, p_last = br.u[-1], float(br.p[-1])
        terminal = _terminal_point(br)
        i = _first_unstable(br, terminal) if self.check_stability else None
        if i is not None:
            j = max(i - 1, 0)
            raise self.end("lost_stability", f"the branch became unstable at {pname} = {br.p[i]:.10g} (stored "
                           f"point {i}, {int(br.n_negative[i])} negative eigenvalue(s)) without a located fold "
                           "or branch point", br.u[j], float(br.p[j]))
        if br.status == "bound" and (p_end is None or abs(p_last - p_end) <= 1e-9 * max(1.0, abs(p_end),
                                                                                       abs(p_end - p0))):
            reached = p_last if p_end is None else p_end
            raise self.end("completed", f"reached {pname} = {reached:.10g} after {len(self.out.jumps)} snap(s)",
                           u_last, p_last)
        return terminal

    def fold_to_leave(self, br: Branch, terminal: SpecialPoint | None) -> tuple[SpecialPoint, np.ndarray]:
        """The fold to snap from and its state; the sweep ends if ``br`` ends otherwise or the budget is spent.

        ``terminal`` is what :meth:`check_branch` found; when the branch ended on an event (a located
        fold or a terminal user event) ``locate_snap`` is asked for the fold instead.
        """
        pname, p_end = self.pname, self.sweep.p_end
        u_last, p_last = br.u[-1], float(br.p[-1])
        if br.status == "event" and self.locate_snap is not None:
            terminal = self.locate_snap(br)
        if terminal is None or br.status != "event":
            end = "" if p_end is None else f" before reaching {pname} = {p_end:.10g}"
            raise self.end("stopped", f"continuation stopped at {pname} = {p_last:.10g}{end} (status "
                           f"{br.status!r}: {br.message})", u_last, p_last)
        if terminal.kind == "branch_point" and self.continues_past(terminal):
            raise self.end("branch_point", f"the stable branch ends in a branch point at {pname} = "
                           f"{terminal.p:.10g}, where a stable bifurcating branch goes on in the sweep "
                           "direction (no snap): follow it with contin.switch_branch", u_last, p_last)
        self.out.folds.append(terminal)
        if len(self.out.jumps) >= self.max_snaps:
            end = "" if p_end is None else f", before {pname} = {p_end:.10g}"
            raise self.end("max_snaps", f"reached a fold at {pname} = {terminal.p:.10g} after max_snaps = "
                           f"{self.max_snaps} snap(s){end}", u_last, p_last)
        return terminal, (u_last if terminal.u is None else np.asarray(terminal.u, dtype=float))

    def continues_past(self, bp: SpecialPoint) -> bool:
        """Whether the stable path goes on continuously through the branch point ``bp`` (no snap there).

        That is the supercritical case: a bifurcating branch leaves ``bp`` in the sweep direction and
        is stable.  Otherwise (the bifurcating branches turn back, or are unstable, as on a shallow
        arch whose symmetric path bifurcates before its limit load) the structure snaps at ``bp``.
        A branch point that is only bracketed, or whose bifurcating branch cannot be stepped onto,
        is treated as a snap point too; the snap's own checks then decide.
        """
        if not bp.located or bp.bifurcation is None or not len(bp.bifurcation.directions):
            return False
        st = self.sweep.curve.settings
        for side in (1, -1):
            try:
                br = switch_branch(self.sweep.problem, bp, st, direction=side, max_steps=3)
            except (CorrectorFailure, NonFiniteError, SingularMatrixError, np.linalg.LinAlgError, ValueError):
                continue
            if len(br) >= 2 and br.n_negative is not None and int(br.n_negative[-1]) == 0 \
                    and self.sweep.direction * (float(br.p[-1]) - float(bp.p)) > 0:
                return True
        return False

    def jump_from(self, fold: SpecialPoint, u_fold: np.ndarray) -> JumpResult:
        """The jump from the fold by the snap rules; the sweep ends if no attempt lands."""
        jr, reasons = self.sweep.snap(fold, u_fold)
        self.out.info["jump_attempts"].append(reasons)
        if jr is None:
            where = "branch point" if fold.kind == "branch_point" else "fold"
            raise self.end("jump_failed", f"the snap at the {where} {self.pname} = {fold.p:.10g} did not land on a "
                           f"distinct stable state: {'; '.join(reasons)}", u_fold, float(fold.p))
        self.out.jumps.append(jr)
        return jr

    def check_landing(self, jr: JumpResult, fold: SpecialPoint) -> None:
        """End the sweep if the snap from ``fold`` reached ``p_end``, landed on or beyond a bound of the settings
        (on an observable), or ``stop_after_jump`` says so.

        A landing beyond a bound ends the sweep as a branch reaching that bound does (``"completed"`` without
        ``p_end``, else ``"stopped"``): a continuation run from there would never cross the bound, and the
        sweep would go on outside the range the caller allowed.
        """
        pname, p_end, n_snaps = self.pname, self.sweep.p_end, len(self.out.jumps)
        if p_end is not None and jr.p == p_end:  # minimised at p_end and not restated at the fold
            raise self.end("completed", f"reached {pname} = {p_end:.10g} by the snap at the fold {pname} = "
                           f"{fold.p:.10g} ({n_snaps} snap(s))", jr.u_to, jr.p)
        beyond = bound_passed(self.sweep.problem, self.sweep.curve.settings.bounds, jr.u_to, jr.p)
        if beyond:
            raise self.end("completed" if p_end is None else "stopped",
                           f"the snap at the fold {pname} = {fold.p:.10g} landed {beyond} ({n_snaps} snap(s))",
                           jr.u_to, jr.p)
        enough = self.stop_after_jump(jr) if self.stop_after_jump is not None else None
        if enough:
            raise self.end("completed", f"{enough} ({n_snaps} snap(s))", jr.u_to, jr.p)


def quasistatic(problem: Problem, u0: Any, p0: float, p_end: float | None = None, settings: Settings | None = None,
                *, direction: int | None = None, max_snaps: int = 10, snap: SnapRules | None = None,
                locate_snap: Callable[[Branch], SpecialPoint | None] | None = None,
                stop_after_jump: Callable[[JumpResult], str | None] | None = None,
                stop_at_branch_points: bool = True, check_stability: bool = True, events: Sequence[Event] = (),
                jump_attempts: Sequence[tuple[float, float | None]] | None = None, jump_tol: float | None = None,
                jump_max_iter: int | None = None, min_separation: float | None = None,
                **overrides: Any) -> QuasiStaticResult:
    """Follow the stable equilibrium while the parameter goes monotonically from ``p0`` towards ``p_end``.

    The sweep traces the stable branch through ``(u0, p0)`` with :func:`contin.continuation` in the
    direction of ``p_end``, stopping at ``p_end`` or at the first fold, whichever comes first.  At a
    fold the branch cannot continue in the sweep direction, so the structure snaps:
    :func:`contin.jump` minimises the energy at a parameter slightly past the fold (in the sweep
    direction) and the landing must be a stable state distinct from the fold state.  By default the
    landing is then carried back to the fold's own parameter by Newton's method (the landing branch
    is regular there), so the jump is stated at the fold load, as in the quasi-static idealisation,
    and joins the fold in :func:`contin.diagram`.  Continuation resumes from the landing
    (``origin=`` the jump) in the same direction.  Every stored point of every branch is checked to
    be stable under the problem's primary stability operator (the one :func:`contin.jump` minimises
    with).

    This is the toolkit's one load-snap loop; models adapt it through the hooks below rather than
    writing their own.

    Parameters
    ----------
    problem : Problem
        A conservative problem (energy and symmetric Hessian, or a stability operator).
    u0 : array_like
        Starting state (corrected by Newton at ``p0``); it must be stable.
    p0 : float
        Start of the parameter sweep.
    p_end : float, optional
        End of the sweep (``p_end < p0`` unloads).  None: no end load; the sweep goes in
        ``direction`` until a bound of ``settings`` (on an observable) ends it, which then counts as
        completed, or until ``stop_after_jump`` says so.
    settings : Settings, optional
        Continuation options; fields may also be passed as keywords.  The sweep sets ``direction``,
        the bound at ``p_end`` (``p_max`` when loading, ``p_min`` when unloading), ``stop_at`` (folds,
        and branch points unless ``stop_at_branch_points`` is False) and ``stability=True``; every
        other option is used as given (e.g. a bound on an observable).
    direction : int, optional
        ``+1`` (loading) or ``-1``; required without ``p_end``, implied by it otherwise.
    max_snaps : int
        Maximum number of snaps; reaching one more fold ends the sweep with status ``"max_snaps"``.
    snap : SnapRules, optional
        How a fold is left and what counts as a landing (default ``SnapRules()``).
    locate_snap : callable ``(Branch) -> SpecialPoint or None``, optional
        Where the snap is, asked whenever a branch ends on an event: a terminal user event (a model
        whose fold is too sharp for the engine to resolve stops on a precursor event and locates the
        fold itself) or the engine's located fold (the branch's last special point, which the model
        may return as it is or locate more precisely).  The returned point (with its state ``u``) is
        snapped from; None means the branch's end is not a snap and the sweep stops there.
    stop_after_jump : callable ``(JumpResult) -> str or None``, optional
        Asked after every snap; a message ends the sweep as completed.  A landing on or beyond a bound of
        the settings (on an observable) ends the sweep without it, as that bound ends a branch.
    stop_at_branch_points : bool
        End a branch at a branch point: the structure snaps there (an arch bifurcating before its
        limit load), unless a stable bifurcating branch goes on in the sweep direction (status
        ``"branch_point"``); False continues through branch points along the traced branch.
    check_stability : bool
        End the sweep with status ``"lost_stability"`` at a stored point that is unstable although
        no fold or branch point was located.  False trusts the located folds alone (for a model
        whose stability labels are known to flicker between folds, the caller reports them).
    events : sequence of Event
        User events passed to every continuation run.
    jump_attempts, jump_tol, jump_max_iter, min_separation
        Shorthands that override the same fields of ``snap`` (``attempts``, ``tol``, ``max_iter``,
        ``min_separation``).
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
        If ``p_end == p0``, ``max_snaps < 0``, no jump attempt is given, the direction is missing or
        contradicts ``p_end``, or the problem has no stability operator.
    TypeError
        For an unknown keyword.

    Examples
    --------
    Loading and unloading of a snapping structure (the hysteresis loop)::

        load = contin.quasistatic(problem, u0, 0.0, p_hi)
        unload = contin.quasistatic(problem, load.u_final, p_hi, 0.0)
        G = contin.diagram(load.branches + unload.branches, load.jumps + unload.jumps)
    """
    p0 = float(p0)
    p_end = None if p_end is None else float(p_end)
    direction = _sweep_direction(p0, p_end, direction)
    if max_snaps < 0:
        raise ValueError(f"quasistatic: max_snaps must be >= 0, got {max_snaps!r}")
    rules = _snap_rules(snap, jump_attempts, jump_tol, jump_max_iter, min_separation)
    st = _sweep_settings(settings, overrides, direction, p_end, stop_at_branch_points)
    run = _SweepLoop.begin(_Sweep(problem, Curve(problem, st), rules, direction, p0, p_end), events, max_snaps,
                           check_stability, locate_snap, stop_after_jump)
    # every step below either hands the next its input or ends the sweep by raising _SweepEnd
    try:
        u, p, origin = run.start(u0), p0, None
        while True:
            br = run.load(u, p, origin)
            fold, u_fold = run.fold_to_leave(br, run.check_branch(br))
            jr = run.jump_from(fold, u_fold)
            run.check_landing(jr, fold)
            u, p, origin = jr.u_to, jr.p, jr
    except _SweepEnd as end:
        return end.result
