"""Automatic bifurcation diagrams: trace, switch at every branch point to a given depth, merge what repeats.

:func:`auto_diagram` traces the branch through a start, then at every located branch point tries
every direction of its record (:class:`contin.Bifurcation`) and both halves of each, and does the
same on the branches found, to a given depth.  Before a half is traced, a short probe of it (a few
steps of :func:`contin.switch_branch`) is compared with every branch traced so far: a probe that
lies on one (:func:`contin.analyses.diagram.position_on`) is that branch reached again, from the
other end or from another of its branch points, and one that lies on the image ``g u`` of one under
an element ``g`` of the model's declared symmetry (:attr:`contin.Problem.symmetry_generators`) is a
copy of it.  Neither is traced again; both are listed among the attempts, a copy also on its branch
point's node (``copies``).  The two halves of one direction are one curve (they meet at the branch
point), whatever the model's symmetry.  The graph is :func:`contin.diagram` with ``merge=True``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from typing import TYPE_CHECKING, Any

import numpy as np

from ..palc import continuation, switch_branch
from ..problem import Problem
from ..results.branch import Branch, SpecialPoint
from ..settings import Settings
from ..watch.branching import group_elements
from .deflation import DeflatedBranches, deflated_branches
from .diagram import CURVE_TOL, NodeIndex, build_diagram, position_on

if TYPE_CHECKING:
    import networkx as nx

__all__ = ["AutoDiagram", "SwitchAttempt", "auto_diagram"]

#: Accepted steps of the probes that decide whether a half is new, tried in turn until one is off the point.
PROBE_STEPS = (3, 12, 48)
#: How far (in multiples of the curve tolerance) a probe's point must be from the branch point to be compared.
PROBE_REACH = 100.0


@dataclass
class SwitchAttempt:
    """One half of one direction at one branch point, and what became of it.

    Attributes
    ----------
    parent : int
        The branch (index in :attr:`AutoDiagram.branches`) on which the point lies.
    p : float
        The branch point's parameter.
    direction : int
        Which of the record's directions (``Bifurcation.directions``).
    half : int
        +1 or -1 (``switch_branch(direction=...)``).
    depth : int
        1 for a point of the start branch (or of a deflated one), 2 for a point of a branch found at 1, ...
    status : str
        ``"traced"`` (a new branch), ``"same"`` (the probe lies on a traced branch), ``"copy"`` (on
        the image of one under the declared symmetry), ``"failed"`` (the switch raised, or its run
        did not succeed) or ``"unresolved"`` (the record has no direction to switch to).
    message : str
    branch : int or None
        Traced: the new branch's index.  Same or copy: the branch it repeats (``copy_of``).
    element : int or None
        Copy: the index of the group element ``g`` (in :func:`contin.watch.branching.group_elements`
        of the declared generators) with the probe on ``g`` applied to that branch.
    run : Branch or None
        A failed switch's run, if it returned one (not in the diagram).
    """

    parent: int
    p: float
    direction: int
    half: int
    depth: int
    status: str
    message: str = ""
    branch: int | None = None
    element: int | None = None
    run: Branch | None = None


@dataclass
class AutoDiagram:
    """What :func:`auto_diagram` traced, tried and assembled.

    Attributes
    ----------
    graph : networkx.MultiDiGraph
        :func:`contin.diagram` of :attr:`branches` with ``merge=True``; branch edges also carry
        ``curve`` (index in :attr:`curves`), branch-point nodes the ``copies`` recognised there.
    branches : list of Branch
        Every run traced, each once: the start branch first.
    curves : list of list of int
        The runs that make one curve: the two halves of a direction at a branch point, the two runs of
        a deflated solution, the start branch alone.
    attempts : list of SwitchAttempt
        Every half tried, in order.
    deflations : list of DeflatedBranches
        The deflation at each parameter of ``deflate_at``.
    """

    graph: "nx.MultiDiGraph"
    branches: list[Branch]
    curves: list[list[int]]
    attempts: list[SwitchAttempt] = field(default_factory=list)
    deflations: list[DeflatedBranches] = field(default_factory=list)

    @property
    def failures(self) -> list[SwitchAttempt]:
        """The attempts that failed or could not be resolved."""
        return [a for a in self.attempts if a.status in ("failed", "unresolved")]

    @property
    def copies(self) -> list[SwitchAttempt]:
        """The attempts recognised as symmetric copies of a traced branch."""
        return [a for a in self.attempts if a.status == "copy"]

    @property
    def success(self) -> bool:
        """Every run succeeded and every attempt was traced or recognised."""
        return all(br.success for br in self.branches) and not self.failures


class _Builder:
    """The runs and curves so far, and the tests that tell a new half from a traced one."""

    def __init__(self, problem: Problem, size: int, settings: Settings | None, switch_kwargs: dict[str, Any],
                 curve_tol: float, rtol: float) -> None:
        self.problem = problem
        self.settings = settings
        self.kwargs = switch_kwargs
        self.curve_tol = curve_tol
        self.rtol = rtol
        self.branches: list[Branch] = []
        self.curves: list[list[int]] = []
        self.level: list[int] = []
        self.attempts: list[SwitchAttempt] = []
        self.visited = NodeIndex(rtol)
        self.copy_points: list[tuple[SpecialPoint, dict[str, int]]] = []
        generators = tuple(getattr(problem, "symmetry_generators", ()) or ())
        self.elements = group_elements(generators, size) if generators else None

    def add(self, runs: Sequence[Branch], level: int) -> None:
        """Runs that are one curve."""
        first = len(self.branches)
        self.branches.extend(runs)
        self.level.extend([level] * len(runs))
        self.curves.append(list(range(first, len(self.branches))))

    def known_points(self) -> list[SpecialPoint]:
        return [spt for br in self.branches for spt in br.branch_points() if spt.located]

    def owner(self, u: np.ndarray, p: float) -> tuple[int, int | None] | None:
        """``(branch, element)`` of a traced branch the point lies on (element None: the point itself does)."""
        for bi, br in enumerate(self.branches):
            if position_on(br, u, p, self.curve_tol) is not None:
                return bi, None
        for e, g in enumerate(self.elements or ()):
            v = g.T @ u  # g orthogonal: g^T u lies on a branch when u lies on its image under g
            if np.array_equal(v, u):
                continue
            for bi, br in enumerate(self.branches):
                if position_on(br, v, p, self.curve_tol) is not None:
                    return bi, e
        return None

    def seen(self, spt: SpecialPoint) -> bool:
        """Whether the point was already switched at (it lies on two traced branches, or was met twice)."""
        u = np.asarray(spt.u, dtype=float)
        if self.visited.find(float(spt.p), u) is not None:
            return True
        self.visited.nodes.append((f"visited{len(self.visited.nodes)}", float(spt.p), u))
        return False

    def explore(self, roots: list[int], depth: int) -> None:
        """Switch at the branch points of ``roots``, then at those of the branches found, ``depth`` levels deep."""
        frontier = roots
        for level in range(1, depth + 1):
            frontier = [new for parent in frontier for new in self.switch_all(parent, level)]

    def switch_all(self, parent: int, depth: int) -> list[int]:
        """Try every half of every direction at the branch points of ``parent``; the new branches' indices."""
        new: list[int] = []
        for spt in self.branches[parent].branch_points():
            if spt.label == "origin" or not spt.located or self.seen(spt):
                continue
            record = spt.bifurcation
            if record is None or not len(record.directions):
                kind = "no record" if record is None else f"kind {record.kind!r}"
                self.attempts.append(SwitchAttempt(parent, float(spt.p), -1, 0, depth, "unresolved",
                                                   f"the branch point's record resolves no direction ({kind})"))
                continue
            for k in range(len(record.directions)):
                halves = [bi for half in (1, -1) if (bi := self.switch(parent, spt, k, half, depth)) is not None]
                if halves:
                    self.curves.append(halves)
                    new.extend(halves)
        return new

    def switch(self, parent: int, spt: SpecialPoint, k: int, half: int, depth: int) -> int | None:
        """One half: the index of the new branch, or None (the attempt says why)."""
        attempt = SwitchAttempt(parent, float(spt.p), k, half, depth, "failed")
        self.attempts.append(attempt)
        known = self.known_points()
        u_bp = np.asarray(spt.u, dtype=float)
        scale = max(1.0, float(np.max(np.abs(u_bp), initial=0.0)))
        away = None
        for steps in PROBE_STEPS:  # until the probe is clearly off the branch point (first steps may be tiny)
            try:
                probe = switch_branch(self.problem, spt, self.settings, direction=half, branch=k, known=known,
                                      **{**self.kwargs, "max_steps": steps})
            except (ValueError, RuntimeError, ArithmeticError) as exc:
                attempt.message = f"the switch raised {type(exc).__name__}: {exc}"
                return None
            if len(probe) == 0:
                break
            gaps = np.maximum(np.max(np.abs(np.asarray(probe.u) - u_bp), axis=1) / scale,
                              np.abs(np.asarray(probe.p) - spt.p) / max(1.0, abs(spt.p)))
            if gaps.max() >= PROBE_REACH * self.curve_tol:
                away = int(np.argmax(gaps))
                break
            if probe.status != "max_steps":
                break
        owner = None if away is None else self.owner(np.asarray(probe.u[away]), float(probe.p[away]))
        if owner is not None:
            attempt.branch, attempt.element = owner
            attempt.status = "same" if owner[1] is None else "copy"
            if owner[1] is not None:
                self.copy_points.append((spt, {"copy_of": owner[0], "element": owner[1], "direction": k,
                                               "half": half}))
            attempt.message = (f"lies on branch {owner[0]}" if owner[1] is None
                               else f"lies on the image of branch {owner[0]} under symmetry element {owner[1]}")
            return None
        try:
            run = switch_branch(self.problem, spt, self.settings, direction=half, branch=k, known=known, **self.kwargs)
        except (ValueError, RuntimeError, ArithmeticError) as exc:
            attempt.message = f"the switch raised {type(exc).__name__}: {exc}"
            return None
        if not run.success:
            attempt.message, attempt.run = f"{run.status}: {run.message}", run
            return None
        attempt.status, attempt.message, attempt.branch = "traced", f"{run.status}: {run.message}", len(self.branches)
        self.branches.append(run)
        self.level.append(depth)
        return attempt.branch


def auto_diagram(problem: Problem, u0: Any, p0: float, depth: int = 2, settings: Settings | None = None, *,
                 deflate_at: Sequence[float] = (), curve_tol: float = CURVE_TOL, rtol: float = 1e-6,
                 **kwargs: Any) -> AutoDiagram:
    """Trace from a start, switch at every located branch point to ``depth``, and assemble the diagram.

    Parameters
    ----------
    problem : Problem
    u0 : array_like
        The start's state.
    p0 : float
        The start's parameter.
    depth : int
        How many times to switch: 0 traces the start branch alone, 1 also every branch leaving its
        branch points, 2 also those leaving theirs, ...
    settings : Settings, optional
        Of every run (fields may also be keywords: give the bounds, ``p_min``, ``p_max``).
    deflate_at : sequence of float
        Parameters at which to look for branches the traced ones do not reach
        (:func:`contin.deflated_branches`); each found is traced, switched from like the start
        branch, and joined to the diagram.
    curve_tol : float
        How close (scaled like ``rtol``) a probe must lie to a traced branch, or its symmetric image,
        to be it (:func:`contin.analyses.diagram.position_on`).
    rtol : float
        Relative tolerance under which two points are one node (:func:`contin.diagram`).
    **kwargs
        Further keywords of :func:`contin.continuation` (``direction`` only for the start branch).

    Returns
    -------
    AutoDiagram
        The branches, the curves they make, every attempt with its status, and the graph.
    """
    if int(depth) != depth or depth < 0:
        raise ValueError(f"auto_diagram: depth must be a whole number >= 0, got {depth!r}")
    switch_kwargs = {key: value for key, value in kwargs.items() if key not in ("direction", "tangent", "origin")}
    builder = _Builder(problem, int(np.size(u0)), settings, switch_kwargs, curve_tol, rtol)
    builder.add([continuation(problem, u0, p0, settings, **kwargs)], 0)
    builder.explore([0], int(depth))
    deflations = []
    names = {f.name for f in fields(Settings)}
    for p in deflate_at:
        found = deflated_branches(problem, p, builder.branches, settings=settings,
                                  **{key: value for key, value in switch_kwargs.items() if key in names})
        deflations.append(found)
        first = len(builder.branches)
        for runs in _by_solution(found):
            builder.add(runs, 0)
        builder.explore(list(range(first, len(builder.branches))), int(depth))
    G, index = build_diagram(builder.branches, rtol=rtol, merge=True, curve_tol=curve_tol)
    curve_of = {bi: ci for ci, members in enumerate(builder.curves) for bi in members}
    for *_, data in G.edges(data=True):
        if data.get("kind") == "branch":
            data["curve"] = curve_of[data["branch"]]
    for spt, record in builder.copy_points:
        node = index.find(spt.p, np.asarray(spt.u, dtype=float))
        if node is not None:
            G.nodes[node].setdefault("copies", []).append(record)
    return AutoDiagram(G, builder.branches, builder.curves, builder.attempts, deflations)


def _by_solution(found: DeflatedBranches) -> list[list[Branch]]:
    """The runs of a deflation grouped by the solution they were traced from (one curve each)."""
    groups: dict[int, list[Branch]] = {}
    for br in found.branches:
        groups.setdefault(int(br.meta["deflation"]["solution"]), []).append(br)
    return list(groups.values())
