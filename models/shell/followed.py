"""The path a shell of revolution really takes under slowly increasing load: stable pieces and snaps, across views.

A shell loaded slowly stays on a stable equilibrium.  Where the branch it is on loses stability it either goes
on along a stable branch that emanates there in the direction of loading, or it snaps to the next stable state at
the same load.  :func:`follow_path` does this across the views of the shell:

* it starts on the axisymmetric trace (the traced model, with its harmonic blocks watched) and stops at the first
  located loss of stability under the control: a fold in the control's parameter, a branch point, or a
  bifurcation into ``n`` waves;
* at a bifurcation into ``n`` waves it steps onto the ``n``-wave branch in the 3-D view restricted to ``D_n``
  (:func:`contin_models.shell.lift.follow_waves`, stability against every representation of ``D_n``); at a
  bifurcation of a ``D_n`` branch into another representation, onto the branch of its isotropy subgroup
  (:func:`~contin_models.shell.lift.follow_symmetry_breaking`, both sides); at a branch point of the traced class,
  onto its other branch (:func:`contin.switch_branch`, both sides);
* such a branch is taken when its first points are stable under the control and it goes on in the direction of
  loading; otherwise (a fold, or a branch that turns back or is unstable: a subcritical bifurcation) the shell
  snaps: :func:`~contin_models.shell.lift.jump_in_full_space` descends in the energy at the load just past the
  point with no symmetry imposed, and says what symmetry the landing has;
* the path goes on from the landing in the view of its symmetry: the traced model when it is axisymmetric, the
  ``D_m`` view (every representation watched) when it has ``m`` waves and a mirror, the view without symmetry
  otherwise;
* until the end of the load, or until a step cannot be made, which is said.

Under a prescribed volume (the traced model a :class:`contin.ConjugateControl` of the pressure-controlled one) every
view is one too (:class:`~contin_models.shell.lift.VolumeView`, built where the views are built), stable means stable
on the volume constraint, and a snap descends in the energy on the constraint
(:func:`~contin_models.shell.constrained_snap.jump_on_constraint`): it keeps the volume and drops the pressure.

Every piece is checked to be stable under the control at each stored point; a piece whose first point is not
(a landing that is stable in the space of the snap but not against a class of the next view) stops the path
with the reason.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from contin.analyses.conjugate import ConjugateControl
from contin.analyses.jump import JumpError
from contin.analyses.lift import LiftError
from contin.palc import CorrectorFailure, continuation, switch_branch
from contin.problem import NonFiniteError, Problem
from contin.results.branch import Branch, SpecialPoint

from .fourier import AngularBasis, transfer_coefficients
from .lift import (StateSymmetry, follow_symmetry_breaking, follow_waves, is_view, same_load, state_symmetry,
                   unknowns_of)
from .problem3d import Shell3D, gauge_for

__all__ = ["Piece", "Snap", "FollowedPath", "follow_path", "STOPS", "END_TOL", "view_descriptor", "rebuild_view"]

#: The located points that end a piece: each is where a stable branch loses stability under the control.
STOPS = ("fold", "branch_point", "bifurcation")

#: Steps of the probe that decides whether an emanating branch is taken (stable, in the direction of loading).
PROBE_STEPS = 4

#: The first step of a probe (at most; in the arclength norm relative to the start's scales): an emanating branch
#: that bends away from its tangent within a few of the settings' steps makes the corrector fail at larger ones, each
#: failure costing Newton iterations in a 3-D view.
PROBE_DS = 1e-4

#: Relative step of the load past a point that the shell snaps from, where the energy descent runs.
SNAP_OVERSHOOT = 1e-6

#: Relative size of waves below which a snap's landing is tried in the view of the higher symmetry without them.
LANDING_SYMMETRY_TOL = 1e-4

#: Descents of one snap: each that lands unstable against a class its view does not carry breaks that symmetry too.
MAX_DESCENTS = 4

#: Failures of a trace or a lift that stop the path with their message instead of a traceback.
_STEP_FAILURES = (LiftError, CorrectorFailure, NonFiniteError, np.linalg.LinAlgError, ValueError, ArithmeticError,
                  JumpError)


@dataclass
class Piece:
    """One stable branch piece of the followed path.

    Attributes
    ----------
    index : int
        Its place in :attr:`FollowedPath.pieces`.
    problem : Problem
        The view it was traced in (the traced axisymmetric model, or a :class:`Shell3D`).
    branch : Branch
        The traced piece; it ends where it loses stability (its last special point) or at the end of the load.
    symmetry : str
        ``"O(2)"`` (axisymmetric), ``"D<m>"`` or ``"none"``: the symmetry of the view it was traced in.
    waves : int
        ``m`` of ``D<m>``; 0 for the axisymmetric piece and for a piece without symmetry.
    parent : int or None
        The piece it came from.
    start : str
        ``"load"`` (the unloaded shell), ``"bifurcation"``, ``"branch point"`` or ``"snap"``.
    start_p : float
        The parameter where it started.
    end : str
        Why it ended: ``"end of load"``, ``"fold"``, ``"branch_point"``, ``"bifurcation"`` or ``"stopped"``.
    relocated : dict or None
        For a piece that starts at a bifurcation lifted from the view before into its own: how far the branch
        point moved when it was located again there (``moved_p``, ``moved_u``: the largest change of an unknown,
        ``mode_angle``: between the lifted and the located null vector, radians); None otherwise.
    """

    index: int
    problem: Problem
    branch: Branch
    symmetry: str
    waves: int
    parent: int | None
    start: str
    start_p: float
    end: str = ""
    relocated: dict[str, float] | None = None


@dataclass
class Snap:
    """A snap of the followed path: from the end of one piece to the landing where the next starts.

    Attributes
    ----------
    from_piece, to_piece : int
        The pieces (``to_piece`` is None when the path stopped at the landing).
    p : float
        The parameter the energy descent ran at (just past the point snapped from).
    view : Problem
        The view the energy descent ran in: the piece's own for a fold or a branch point of its class, the view
        where a symmetry-breaking bifurcation is simple (the isotropy subgroup's, with a mirror) for one.
    symmetry : str
        The landing's symmetry.
    jump : contin.JumpResult
        The descent (``u_from`` and ``u_to`` in the unknowns of the view it ran in).
    """

    from_piece: int
    to_piece: int | None
    p: float
    view: Problem
    symmetry: str
    jump: Any


@dataclass
class FollowedPath:
    """The outcome of :func:`follow_path`.

    Attributes
    ----------
    pieces : list of Piece
        In path order.
    snaps : list of Snap
        In path order.
    status : str
        ``"completed"`` (the end of the load reached) or ``"stopped"``.
    message : str
        Where and why it ended.
    label : str
        The stability label of the control every piece is judged by.
    """

    pieces: list[Piece] = field(default_factory=list)
    snaps: list[Snap] = field(default_factory=list)
    status: str = "stopped"
    message: str = ""
    label: str = ""

    @property
    def success(self) -> bool:
        """The end of the load was reached along stable pieces and snaps."""
        return self.status == "completed"


@dataclass(frozen=True)
class _Trace:
    """How every piece is traced: with the caller's events."""

    events: tuple
    end: tuple[str, float] | None = None

    def run(self, problem: Problem, u: np.ndarray, p: float, st: Any, origin: Any = None) -> Branch:
        st = _settings_for(problem, st)
        if self.end is not None and float(problem.evaluate_observables(u, p)[self.end[0]]) >= self.end[1]:
            st = dataclasses.replace(st, max_steps=0)  # a landing beyond the end of the load: its point alone
        return continuation(problem, u, p, st, events=self.events, origin=origin)

    def switch(self, problem: Problem, point: SpecialPoint, st: Any, side: int) -> Branch:
        return switch_branch(problem, point, _settings_for(problem, st), direction=side, events=self.events)


def _settings_for(problem: Problem | None, st: Any) -> Any:
    """The settings of a piece in ``problem`` (None: a 3-D view yet to be built): in a 3-D view the Morse indices
    alone, without eigenvalues.

    Chord corrector updates (:attr:`contin.Settings.max_chord_rate`) would save a few percent here, but they take
    the tangent from another linearization, and where a fold and a branch point coincide (a one-wave state turning
    in the volume at the pitchfork where it meets another branch) that decides which of the two is located: the
    path then goes another way."""
    if problem is None or is_view(problem):
        # the path needs each point's Morse index per class (one factorization each), not its eigenvalues (a
        # shift-invert Lanczos run on a 3-D view's wide band)
        st = dataclasses.replace(st, n_eigs=0)
    return st


def _first_step(branch: Branch, st: Any) -> float:
    """The arclength of a probe's first accepted step (within the settings' bounds): where a branch leaves its
    branch point, the step its trace starts with instead of shrinking again from the settings' ``ds``."""
    if len(branch) < 2 or not np.isfinite(branch.s[1] - branch.s[0]):
        return st.ds
    return float(min(max(abs(branch.s[1] - branch.s[0]), st.ds_min), st.ds_max))


def _count(branch: Branch, label: str) -> np.ndarray:
    if label in branch.stability_by:
        return np.asarray(branch.n_negative_under(label), dtype=int)
    return np.asarray(branch.n_negative, dtype=int)


def _taken(branch: Branch, start_p: float, label: str, direction: int) -> bool:
    """Whether a probe of an emanating branch is stable under ``label`` and goes on in the loading direction."""
    if len(branch) < 2:
        return False
    counts = _count(branch, label)
    return bool(np.all(counts[1:] == 0) and direction * (float(branch.p[-1]) - start_p) > 0.0)


def view_descriptor(problem: Problem) -> dict[str, Any] | None:
    """What a piece's view is built from beside the scene: the angular basis (``n``, ``K``, ``mirror``, ``M``) and the
    gauge of a 3-D view; None for the traced axisymmetric model.  :func:`rebuild_view` builds the view again."""
    if not is_view(problem):
        return None
    b = problem.basis
    return {"n": int(b.n), "K": int(b.K), "mirror": bool(b.mirror), "M": None if b.M is None else int(b.M),
            "gauge": None if problem.gauge is None else [int(g) for g in problem.gauge]}


def rebuild_view(descriptor: dict[str, Any] | None, source: Problem, structure: Any) -> Problem:
    """The view a piece was traced in, from its :func:`view_descriptor` and the traced model ``source`` of the same
    scene (its structure, load, control and indenter): ``source`` itself for None.

    The views of the followed path carry the traced model's reference, which is axisymmetric for every scene the
    path is followed for; a caller restarting from a saved state checks that it is an equilibrium of the view."""
    from .lift import same_load, waves_view

    if descriptor is None:
        return source
    try:
        n, K, mirror = int(descriptor["n"]), int(descriptor["K"]), bool(descriptor["mirror"])
        M = None if descriptor.get("M") is None else int(descriptor["M"])
        gauge = None if descriptor.get("gauge") is None else (int(descriptor["gauge"][0]), int(descriptor["gauge"][1]))
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise ValueError(f"a piece's view is described by n, K, mirror, M and gauge, got {descriptor!r} ({exc})") from None
    view = waves_view(source, structure, n, K, every_mode=True)
    basis = AngularBasis(n, K, mirror=mirror, M=M)
    same = (view.basis.n, view.basis.K, view.basis.mirror, view.basis.M) == (basis.n, basis.K, basis.mirror, basis.M)
    if same and gauge is None:
        return view
    return same_load(view, basis, every_mode=True, gauge=gauge)


def _symmetry_of(problem: Problem) -> tuple[str, int]:
    if is_view(problem):
        b = problem.basis
        return (f"D{b.n}", b.n) if b.mirror else ("none", 0)
    return "O(2)", 0


def follow_path(source: Problem, u0: np.ndarray, p0: float, settings: Any, *, structure: Any, label: str,
                p_end: float | None = None, end: tuple[str, float] | None = None, K: int = 2,
                max_pieces: int = 12, events: Sequence[Any] = (),
                say: Callable[[str], None] | None = None, start_problem: Problem | None = None) -> FollowedPath:
    """Follow the stable path of a shell of revolution from ``(u0, p0)`` to ``p_end`` (see the module docstring).

    Parameters
    ----------
    source : Problem
        The traced axisymmetric model with its harmonic blocks (the operator family ``"n"``): a
        :class:`~contin_models.shell.structure.ShellOfRevolution` with ``harmonics``, or the paper's point-load model
        given them (:func:`contin_models.shell_scene.build.watch_harmonics`).
    u0, p0 : the stable start: the unloaded shell, or a state of ``start_problem`` when it is given.
    settings : contin.Settings
        Settings of every piece (steps, tolerances, bounds); the path sets ``stop_at``, ``stability`` and the
        bound at ``p_end``.
    structure : ShellStructure
        The structure whose energy the source's is (the 3-D views are built on it).
    label : str
        The stability label of the control (``"displacement"`` or ``"force"``; ``"volume"`` under a prescribed
        volume): what stable means on the path.
    p_end : float, optional
        The end of the load (``> p0``): the parameter's bound.
    end : (str, float), optional
        An observable's end (``("w", w_end)``: the load goes on until the deflection reaches ``w_end``, as a dead
        load does until the shell everts); at least one of ``p_end`` and ``end`` is given, the first reached ends
        the path.
    K : int
        Harmonics above 0 of the ``D_n`` view of an ``n``-wave branch.
    max_pieces : int
        Stop after this many pieces.
    events : sequence of contin.Event
        Located along every piece (e.g. the extrema of the load); they do not end a piece, but a terminal extremum
        of the parameter itself (``folds`` the parameter's name) ends it as a fold.
    start_problem : Problem, optional
        The view ``u0`` is a state of, when it is not ``source``: a restart from a point of a saved followed path's
        piece in a 3-D view (:func:`contin_models.shell_scene.follow.resume_followed`).
    say : callable, optional
        Told one line per step of the path (progress).

    Returns
    -------
    FollowedPath
    """
    if p_end is None and end is None:
        raise ValueError("follow_path: give the end of the load as p_end (the parameter's), end (an observable's) "
                         "or both")
    if p_end is not None and not p_end > p0:
        raise ValueError(f"follow_path: the end of the load p_end must be above the start {p0!r}, got {p_end!r}")
    st = dataclasses.replace(settings, stop_at=STOPS, stability=True, direction=1)
    if p_end is not None:
        st = dataclasses.replace(st, p_max=float(p_end))
    if end is not None:
        st = dataclasses.replace(st, bounds={**settings.bounds, str(end[0]): (None, float(end[1]))})
    trace = _Trace(tuple(events), None if end is None else (str(end[0]), float(end[1])))
    tell = say or (lambda text: None)
    out = FollowedPath(label=label)
    pname = source.parameter_name

    def add(problem: Problem, branch: Branch, parent: int | None, start: str, start_p: float) -> Piece:
        sym, waves = _symmetry_of(problem)
        piece = Piece(len(out.pieces), problem, branch, sym, waves, parent, start, start_p)
        out.pieces.append(piece)
        tell(f"piece {piece.index} ({sym}) from {pname} = {start_p:.6g}: {len(branch)} points, {branch.message}")
        return piece

    first = source if start_problem is None else start_problem
    piece = add(first, trace.run(first, u0, p0, st), None, "load", p0)
    while True:
        br = piece.branch
        if len(br) == 0:
            piece.end = "stopped"
            out.message = f"the piece from {pname} = {piece.start_p:.10g} could not start: {br.message}"
            return out
        if end is not None and piece.start == "snap" and float(br.observables[end[0]][0]) >= end[1]:
            piece.end = "end of load"
            out.status = "completed"
            out.message = (f"the snap at {pname} = {piece.start_p:.10g} landed beyond the end of the load, {end[0]} = "
                           f"{end[1]:.10g}, after {len(out.pieces) - 1} stable piece(s) and {len(out.snaps)} snap(s)")
            return out
        back = _turns_back(br)
        turn = None
        if back is not None:  # a fold of the load the piece passed without locating it
            turn = _turn_at_a_branch_point(br, back, pname)
            if turn is None:  # not followed past it
                missed = next((spt for spt in br.special_points if spt.kind in STOPS and not spt.located
                               and spt.index >= back - 1), None)
                piece.branch, piece.end = br.head(back + 1), "stopped"
                why = ("" if missed is None else f"; a {missed.kind} was found there but not located"
                       + (f" ({missed.info['error']})" if missed.info.get("error") else ""))
                out.message = (f"the piece in {piece.symmetry} from {pname} = {piece.start_p:.10g} turns back in the "
                               f"load after {pname} = {float(br.p[back]):.10g}, at a fold it did not locate{why}: the "
                               "path is not followed past it")
                return out
            piece.branch = br = br.head(back + 1)
            tell(f"  the piece turns back at {pname} = {turn.p:.10g} where a fold and a branch point meet (neither "
                 "could be located): left from its last point before the turn")
        last = br.special_points[-1] if br.special_points else None
        # a terminal extremum of the parameter (events): a fold the fold test may miss where it is a pitchfork too,
        # and where the bisection may not converge either: the path turns back there, located or not
        turned = last is not None and last.kind == "event" and last.info.get("folds") == pname
        if turned:
            last = dataclasses.replace(last, kind="fold")
        stop = turn if turn is not None else (
            last if (br.status == "event" and last is not None and (last.located or turned) and last.kind in STOPS)
            else None)
        # the located point that ends a piece is singular: its count is either side's
        counts = _count(br, label)[: len(br) - (1 if stop is not None else 0)]
        if np.any(counts != 0):
            bad = int(np.flatnonzero(counts != 0)[0])
            piece.end = "stopped"
            out.message = (f"the piece in {piece.symmetry} from {pname} = {piece.start_p:.10g} is unstable under "
                           f"{label} control at {pname} = {float(br.p[bad]):.10g} ({int(counts[bad])} negative "
                           "eigenvalue(s)) without a located point")
            return out
        if stop is None:
            reached = _reached(br, p_end, end)
            if br.status == "bound" and reached is not None:
                piece.end = "end of load"
                out.status = "completed"
                out.message = (f"reached {reached} along {len(out.pieces)} stable piece(s) and "
                               f"{len(out.snaps)} snap(s)")
            else:
                piece.end = "stopped"
                out.message = f"the piece in {piece.symmetry} stopped at {pname} = {float(br.p[-1]):.10g}: {br.message}"
            return out
        piece.end = stop.kind
        if len(out.pieces) >= max_pieces:
            out.message = f"stopped after max_pieces = {max_pieces} pieces at {pname} = {stop.p:.10g}"
            return out
        try:
            piece = _leave(piece, stop, source, structure, st, label, K, out, add, tell, trace)
        except _STEP_FAILURES as exc:
            out.message = f"could not leave the {stop.kind} at {pname} = {stop.p:.10g} of piece {piece.index}: {exc}"
            return out
        if piece is None:
            return out


#: Relative distance to the end of the load within which it is reached (the run's bound is located to it).
END_TOL = 1e-9

#: Relative fall of the load between stored points of a piece beyond which the piece turned back.
TURN_BACK_TOL = 1e-10


def _turns_back(br: Branch) -> int | None:
    """The last stored point before a piece's load falls (None: it never does).  A piece of the followed path goes
    on in the direction of loading and ends at the located fold where it would turn: a fall means a fold the
    trace passed without locating it."""
    p = np.asarray(br.p, dtype=float)
    if p.size < 2:
        return None
    fall = np.flatnonzero(np.diff(p) < -TURN_BACK_TOL * np.maximum(1.0, np.abs(p[:-1])))
    return int(fall[0]) if fall.size else None


def _turn_at_a_branch_point(br: Branch, back: int, pname: str) -> SpecialPoint | None:
    """Where a piece turns back in the load at a fold that coincides with a branch point: the last stored point before
    the turn, as an unlocated fold of the load (None: the turn is not such a point).

    An ``n``-wave branch that rejoins the axisymmetric path (the end of a bubble of it) has its fold in the load at
    the junction, a pitchfork: there the fold's extended system and the pseudo-arclength corrector are both singular,
    so the fold cannot be located, nor the branch point.  The state before the turn is a converged point of the piece
    within a step of the junction; the snap from it lands on the branch the piece rejoins, or says why it does not."""
    near = [spt for spt in br.special_points if not spt.located and spt.index >= back - 1]
    fold = any(spt.kind == "fold" and spt.info.get("folds") == pname for spt in near)
    if not (fold and any(spt.kind == "branch_point" for spt in near)):
        return None
    return SpecialPoint("fold", float(br.p[back]), np.array(br.u[back], dtype=float),
                        {k: float(v[back]) for k, v in br.observables.items()}, index=back, located=False,
                        info={"folds": pname, "method": "the last point before a turn where a fold and a branch point "
                              "meet", "bracket_p": [float(br.p[back]), float(br.p[min(back + 1, len(br) - 1)])]})


def _reached(br: Branch, p_end: float | None, end: tuple[str, float] | None) -> str | None:
    """What end of the load the branch's last point reached (None: none)."""
    if p_end is not None and abs(float(br.p[-1]) - p_end) <= END_TOL * max(1.0, abs(p_end)):
        return f"{br.meta.get('parameter_name', 'p')} = {p_end:.10g}"
    if end is not None:
        name, value = end
        if abs(float(br.observables[name][-1]) - value) <= END_TOL * max(1.0, abs(value)):
            return f"{name} = {value:.10g}"
    return None


def _leave(piece: Piece, stop: SpecialPoint, source: Problem, structure: Any, st: Any, label: str, K: int,
           out: FollowedPath, add: Callable[..., Piece], tell: Callable[[str], None], trace: "_Trace") -> Piece | None:
    """The next piece after ``stop``: a stable emanating branch, or the landing of a snap (None: the path stopped,
    ``out.message`` says why)."""
    problem = piece.problem
    probe = dataclasses.replace(st, max_steps=PROBE_STEPS, ds=max(min(st.ds, PROBE_DS), st.ds_min))
    # where the emanating branch is traced from, once lifted: (view, its branch point, the sides to try)
    start: tuple[Problem, SpecialPoint, tuple[int, ...]] | None = None
    first: Branch | None = None  # the probe of the first side, traced by the lift itself
    what = ""
    if stop.kind == "bifurcation" and stop.info.get("family") == "n":
        wb = follow_waves(problem, stop, K, structure=structure, settings=_settings_for(None, probe), every_mode=True)
        # the two halves of the n-wave branch are one branch turned by pi / n: one side is enough
        start, first = (wb.problem, wb.branch_point, (1,)), wb.branch
        what = f"the {int(stop.info['key'])}-wave branch"
    elif stop.kind == "bifurcation" and stop.info.get("family") == "representation" and is_view(problem):
        bb = follow_symmetry_breaking(problem, stop, settings=_settings_for(None, probe), direction=1)
        start, first = (bb.problem, bb.branch_point, (1, -1)), bb.branch
        what = f"the branch breaking into {stop.info['key']}"
    elif stop.kind == "branch_point" and stop.bifurcation is not None and len(stop.bifurcation.directions):
        start = (problem, stop, (1, -1))
        what = "the other branch of the branch point"
    if start is not None:
        view, bp, sides = start
        for side in sides:
            br = first if (side == 1 and first is not None) else switch_branch(view, bp, _settings_for(view, probe),
                                                                                  direction=side)
            if _taken(br, float(stop.p), label, 1):
                tell(f"  {what} is stable and rises: followed")
                taken = add(view, trace.switch(view, bp, dataclasses.replace(st, ds=_first_step(br, st)), side),
                            piece.index, "branch point" if stop.kind == "branch_point" else "bifurcation",
                            float(stop.p))
                if bp is not stop:  # lifted into another view and located again there
                    taken.relocated = {key: float(bp.info[key]) for key in ("moved_p", "moved_u", "mode_angle")
                                       if key in bp.info}
                    tell(f"  the branch point moved by {taken.relocated.get('moved_p', math.nan):.3g} in "
                         f"{source.parameter_name} when located again in the {taken.symmetry} view")
                return taken
        tell(f"  {what} is not stable in the direction of loading: the shell snaps")
    # a snap from a bifurcation starts in the view where the point is simple, kicked along its mode
    full_from = (start[0], start[1]) if (start is not None and stop.kind == "bifurcation") else None
    return _snap(piece, stop, source, structure, K, st, label, full_from, out, add, trace)


def _snap(piece: Piece, stop: SpecialPoint, source: Problem, structure: Any, K: int, st: Any, label: str,
          full_from: tuple[Shell3D, SpecialPoint] | None, out: FollowedPath,
          add: Callable[..., Piece], trace: "_Trace") -> Piece | None:
    """Snap from ``stop`` at the load just past it and start the next piece at the landing.

    A fold or a branch point of the traced class is left within the piece's own view (the symmetry it has is
    kept by the descent); a bifurcation that breaks the symmetry from the view where it is simple, kicked along
    its mode, with no symmetry imposed."""
    p_snap = float(stop.p) + SNAP_OVERSHOOT * max(abs(float(stop.p)), 1e-12)
    problem = piece.problem
    if full_from is None and is_view(problem):
        full_from = (problem, stop)
    if full_from is None:  # the axisymmetric trace's own snap lands axisymmetric
        jr = _jump(problem, np.asarray(stop.u), p_snap)
        if not jr.success:
            out.message = f"the snap from the {stop.kind} at {problem.parameter_name} = {stop.p:.10g} did not land: {jr.message}"
            return None
        trial = continuation(problem, jr.u_to, p_snap, _settings_for(problem, dataclasses.replace(st, max_steps=0,
                                                                                          stop_at=())))
        if len(trial) and _count(trial, label)[0] == 0:
            out.snaps.append(Snap(piece.index, len(out.pieces), p_snap, problem, piece.symmetry, jr))
            return add(problem, trace.run(problem, jr.u_to, p_snap, st, origin=jr), piece.index, "snap", p_snap)
        n = _unstable_class(trial, "n")
        if not len(trial) or n is None:
            out.message = (f"the snap from the {stop.kind} at {problem.parameter_name} = {stop.p:.10g} landed on an "
                           f"axisymmetric state that is not stable under {label} control: {trial.message}")
            return None
        # stable among axisymmetric states, not against n waves: on in the D_n view, kicked along the block's mode
        view, u_from, kick = _into_waves(problem, structure, np.asarray(trial.u[0]), p_snap, int(n), K)
    else:
        view, bp = full_from
        null = bp.bifurcation.null_vector if (bp.bifurcation is not None and bp is not stop) else None
        # the view where the point is simple has a mirror: no turning about the axis for the descent to slide along
        u_from, kick = np.asarray(bp.u), None if null is None else np.asarray(null, dtype=float)
    for _ in range(MAX_DESCENTS):
        jr = _jump(view, u_from, p_snap, direction=kick)
        if not jr.success and stop.kind == "fold" and jr.message.startswith(LINE_SEARCH_FAILED):
            jr = _stays(jr)
        if not jr.success:
            out.message = (f"the snap from the {stop.kind} at {problem.parameter_name} = {stop.p:.10g} did not land "
                           f"on a stable state: {jr.message}")
            return None
        try:
            landed = _landing(source, view, jr, p_snap, st, label)
        except ValueError:  # Newton's method does not make the state an equilibrium in the view of its symmetry
            if not jr.info.get("stays"):
                raise
            landed = (None, None, None)
        if jr.info.get("stays") and landed[0] is None:
            out.message = (f"the snap from the {stop.kind} at {problem.parameter_name} = {stop.p:.10g} did not land "
                           f"on a stable state: {jr.info['descent']}; nor is the state where it stalled a stable "
                           "equilibrium past the fold")
            return None
        if landed[0] is not None:
            nxt, u_next, sym = landed
            out.snaps.append(Snap(piece.index, len(out.pieces), p_snap, view, sym.label, jr))
            return add(nxt, trace.run(nxt, u_next, p_snap, st, origin=jr if nxt is view else None), piece.index,
                       "snap", p_snap)
        # stable in the descent's view, not against a class it does not carry: on into that class's subgroup
        _, unstable, key = landed
        view, u_from, kick = _into_class(unstable, key, p_snap)
    out.message = (f"the snap from the {stop.kind} at {problem.parameter_name} = {stop.p:.10g} found no stable state "
                   f"after {MAX_DESCENTS} descents, each breaking the symmetry the last landed with")
    return None


#: How :func:`contin.jump` says that its descent stopped because no step along its direction lowers the energy.
LINE_SEARCH_FAILED = "line search failed"


def _stays(jr: Any) -> Any:
    """A descent from a fold that stopped where no step lowers the energy, its last state taken as the landing, to be
    checked.

    Where an ``n``-wave branch rejoins a stable branch at a pitchfork (the end of a bubble of it), its fold in the load
    is that junction, and the state just past it is next to an equilibrium of the branch rejoined: there is no snap,
    and the descent stalls at once on the flat energy, short of its gradient tolerance.  Its last state is then the
    landing if Newton's method at the load past the fold makes it a stable equilibrium (:func:`_landing` decides; the
    caller reports the descent's failure where it does not)."""
    return dataclasses.replace(jr, success=True,
                               message="no snap: the state past the fold is next to a stable equilibrium (a branch "
                                       "rejoined), reached by Newton's method",
                               info={**jr.info, "stays": True, "descent": jr.message})


def _load(problem: Problem, u: np.ndarray) -> float:
    """The multiplier of a state under a prescribed volume (the pressure); 0 under the other controls."""
    return problem.split(u)[1] if isinstance(problem, ConjugateControl) else 0.0


def _jump(problem: Problem, u: np.ndarray, p: float, direction: np.ndarray | None = None) -> Any:
    """:func:`contin.jump` from ``u`` at the parameter ``p``; under a prescribed volume (:class:`contin.ConjugateControl`,
    whose Lagrangian is a saddle in the pressure) the descent on the constraint,
    :func:`~contin_models.shell.constrained_snap.jump_on_constraint`."""
    from contin.analyses.jump import jump

    from .constrained_snap import jump_on_constraint

    if isinstance(problem, ConjugateControl):
        return jump_on_constraint(problem, u, p, direction=direction)
    return jump(problem, u, p, direction=direction)


def _landing(source: Problem, view: Shell3D, jr: Any, p: float, st: Any,
             label: str) -> tuple[Problem | None, Any, Any]:
    """Where the path goes on from a landing of ``view``: ``(next view, its unknowns, the landing's symmetry)``, or
    ``(None, (the view, its corrected state), the class it is unstable against)`` when the landing is unstable
    against a class of perturbation the descent's view did not carry.

    The descent stops at its gradient tolerance, which can leave waves of a few 1e-6 on a landing of higher
    symmetry: the higher symmetry is tried first, and kept where its view converges to a stable state there."""
    c = view.full_state(jr.u_to, jr.p)
    sym = state_symmetry(view.basis, c)
    coarse = state_symmetry(view.basis, c, LANDING_SYMMETRY_TOL)
    unstable = None
    for candidate in ([coarse] if coarse.label != sym.label else []) + [sym]:
        nxt, u_next = _view_of_landing(source, view, jr.u_to, jr.p, candidate)
        trial = continuation(nxt, u_next, p, _settings_for(nxt, dataclasses.replace(st, max_steps=0, stop_at=())))
        if len(trial) and _count(trial, label)[0] == 0:
            return nxt, u_next, candidate
        if candidate is sym and len(trial):
            unstable = (nxt, trial)
    if unstable is None:
        raise ValueError(f"the landing of the snap at {view.parameter_name} = {p:.10g} does not converge in the view "
                         f"of its symmetry {sym.label}")
    nxt, trial = unstable
    return None, (nxt, np.asarray(trial.u[0])), _unstable_class(trial)


def _unstable_class(branch: Branch, family: str = "representation") -> Any:
    """The first key of an operator family (a representation, a wave number) whose operator is indefinite at a
    branch's first point (None: none is, the traced class is)."""
    modes = branch.meta.get("modes", {}).get(family)
    if modes is None:
        return None
    counts = np.asarray(modes["n_negative"], dtype=int).reshape(len(branch.p), -1)[0]
    hit = np.flatnonzero(counts > 0)
    return list(modes["keys"])[int(hit[0])] if hit.size else None


def _into_class(unstable: tuple[Problem, np.ndarray], key: str | None,
                p: float) -> tuple[Problem, np.ndarray, np.ndarray | None]:
    """A state of a view that is unstable against the class ``key`` (None: against its own class, or in a view
    without a mirror), carried into the view where the descent can leave it: ``(view, unknowns, kick)``.

    For a class of another representation, the isotropy subgroup's view (:func:`~contin_models.shell.lift.breaking`,
    without a mirror under a gauge when the subgroup has none) and the block's lowest eigenvector lifted there as the
    kick; otherwise the same view, kicked along its own lowest eigenvector."""
    from contin.numerics.stability import stability_info

    from .lift import breaking, subgroup_basis, subgroup_lift

    view, u = unstable
    if key is None or not is_view(view):
        return view, u, None
    family = view.operator_families[0]
    block = family.operator(key, u, p)
    vector = stability_info(block, 1, vectors=True).eigenvectors[:, 0]
    b = breaking(view.basis, key)
    target = same_load(view, subgroup_basis(view.basis, key), b.turn, every_mode=True)
    lift = subgroup_lift(view, target, key)
    u_t = lift.state(u, p)
    kick = lift.mode(vector)
    if not target.basis.mirror:  # no mirror left: the turning about the axis is held by a gauge
        gauged, turn = _gauged(target, target.full_state(u_t, p))
        kick_c = transfer_coefficients(target.T @ kick, target.basis, gauged.basis, turn)
        c = transfer_coefficients(target.full_state(u_t, p), target.basis, gauged.basis, turn)
        return gauged, unknowns_of(gauged, c, _load(target, u_t)), unknowns_of(gauged, kick_c)
    return target, u_t, kick


def _into_waves(source: Problem, structure: Any, u: np.ndarray, p: float, n: int,
                K: int) -> tuple[Shell3D, np.ndarray, np.ndarray]:
    """An axisymmetric state of the traced model, unstable against ``n`` waves, in the ``D_n`` view
    (:func:`~contin_models.shell.lift.waves_view`), with the harmonic block's lowest eigenvector lifted there as the
    kick: ``(view, unknowns, kick)``."""
    from contin.numerics.stability import stability_info

    from .lift import shell_lift, waves_view

    family = next(f for f in source.operator_families if f.name == "n")
    vector = stability_info(family.operator(n, u, p), 1, vectors=True).eigenvectors[:, 0]
    view = waves_view(source, structure, n, K, every_mode=True)
    lift = shell_lift(source, view, n)
    return view, lift.state(u, p), lift.mode(vector)


def _gauged(view: Shell3D, c: np.ndarray) -> tuple[Shell3D, float]:
    """The view without a mirror of ``view``'s basis, its turning held by the gauge of the state ``c``, and the
    angle to turn ``c`` by for it (:func:`~contin_models.shell.problem3d.gauge_for`)."""
    basis = view.basis if not view.basis.mirror else AngularBasis(view.basis.n, view.basis.K, mirror=False,
                                                                  M=view.basis.M)
    gauge, turn = gauge_for(basis, transfer_coefficients(c, view.basis, basis))
    return same_load(view, basis, gauge=gauge), turn


def _view_of_landing(source: Problem, view: Shell3D, u: np.ndarray, p: float,
                     sym: StateSymmetry) -> tuple[Problem, np.ndarray]:
    """The view the path goes on in from a landing ``u`` of ``view`` of symmetry ``sym``, and the landing's unknowns
    there: the traced model for an axisymmetric landing, the ``D_m`` view of its waves for ``m`` waves and a
    mirror, else the view without a mirror under a gauge."""
    c = view.full_state(u, p)
    load = _load(view, u)
    if sym.label == "O(2)":
        return source, unknowns_of(source, c[view.view.axisymmetric_dofs()], load)
    m = sym.order
    top = int(view.basis.wave_numbers.max())
    if sym.mirror is None:
        if not view.basis.mirror and view.gauge is not None:
            return view, np.asarray(u, dtype=float)
        gauged, turn = _gauged(view, c)
        return gauged, unknowns_of(gauged, transfer_coefficients(c, view.basis, gauged.basis, turn), load)
    if view.basis.mirror and m == view.basis.n:
        return view, np.asarray(u, dtype=float)
    K = max(1, math.ceil(top / m))
    M = view.basis.M  # the descent's own quadrature where it suits the basis: the landing keeps its energy
    basis = AngularBasis(m, K, M=M if (M % (2 * m) == 0 and M > 2 * K * m) else None)
    target = same_load(view, basis, every_mode=True)
    # turned onto the mirror, the landing's waves that are not multiples of m and its antisymmetric part are below
    # the symmetry's threshold: dropped, and the first corrector step of the next piece takes up what they were
    both = AngularBasis(1, top, mirror=False, M=view.basis.M)
    turned = transfer_coefficients(c, view.basis, both, float(sym.mirror)).reshape(-1, both.m)
    turned[:, [i for i, t in enumerate(both.terms) if (t[0] == "T") == (t[1] == "cos") or t[2] % m]] = 0.0
    return target, unknowns_of(target, transfer_coefficients(turned.ravel(), both, basis), load)
