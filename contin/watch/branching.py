"""The branches through a multiple branch point: by the model's symmetry, or by its reduced equation.

At a branch point of multiplicity ``m > 1`` on a branch of symmetric states, the kernel ``K`` of the
Hessian (orthonormal basis ``V``, ``m`` columns) carries a representation of the states' symmetry:
each element ``g`` of the isotropy group of the point acts on kernel coordinates as the orthogonal
``m x m`` matrix ``V^T g V``.  The equivariant branching lemma (Vanderbauwhede; Cicogna; see
Golubitsky, Stewart & Schaeffer, *Singularities and Groups in Bifurcation Theory* II, ch. XIII) says
that for every isotropy subgroup ``H`` whose fixed-point space in ``K`` is a line, a branch of states
with symmetry ``H`` leaves the point tangent to that line.  Lines related by an element of the group
carry copies of one branch (the same branch turned or reflected), so one per orbit is traced.

:func:`symmetric_directions` finds those lines from the generators a model declares
(``Problem.symmetry_generators``: orthogonal matrices ``g`` with ``E(g u, p) = E(u, p)``): the group
is closed from its generators, the elements that fix the point's state are kept, each line is the
fixed space of the subgroup of elements that fix it, and the lines are sorted into orbits.

Without a declared symmetry, :func:`reduced_directions` solves the reduced bifurcation equation on
a two-dimensional kernel: at a point whose quadratic terms vanish (the branch is a symmetric
pitchfork in every direction), the branches leave along the critical directions of the quartic
form ``Q(c) = (V c)^T [d^2/de^2 J(u + e V c)] (V c)`` on the unit circle (the reduced energy's
gradient is parallel to ``c`` there).  ``Q`` is a trigonometric polynomial of degree four in the
angle, fitted from nine samples, and its critical angles are the roots of its derivative.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..problem import Problem

__all__ = ["BranchDirections", "symmetric_directions", "reduced_directions", "group_elements", "isotropy_basis",
           "FixedSpaceProblem", "FullSpaceStability", "full_space_stability", "NEUTRAL_ROUNDOFF"]

#: Largest group closed from the generators (elements); a larger one is not used.
MAX_GROUP_ORDER = 5000
#: Two kernel directions are the same line when ``1 - |c1 . c2|`` is below this.
SAME_LINE = 1e-8


@dataclass
class BranchDirections:
    """The directions of the branches through a multiple point, one per orbit of copies.

    Attributes
    ----------
    directions : list of ndarray
        Unit kernel coordinates ``c`` (the state direction is ``V c``), one per branch traced.
    labels : list of str
        What each is (its isotropy: ``"fixed by k of the N elements"``, or ``"critical direction"``).
    copies : list of int
        How many lines of the kernel carry a copy of each branch (the orbit's size).
    method : str
        ``"symmetry"`` or ``"reduced equation"``.
    note : str
        What could not be resolved, if anything.
    """

    directions: list[np.ndarray] = field(default_factory=list)
    labels: list[str] = field(default_factory=list)
    copies: list[int] = field(default_factory=list)
    method: str = ""
    note: str = ""


def _dense(g: Any) -> np.ndarray:
    return g.toarray() if sp.issparse(g) else np.asarray(g, dtype=float)


def group_elements(generators: Sequence[Any], n: int, limit: int = MAX_GROUP_ORDER) -> list[Any] | None:
    """Every element of the group the generators generate (sparse matrices), or None above ``limit``.

    Elements are told apart by their action on one random vector (two distinct orthogonal maps
    agree on a random vector with probability zero).
    """
    rng = np.random.default_rng(20261129)
    probe = rng.standard_normal(n)
    gens = [sp.csr_matrix(g) for g in generators]
    identity = sp.identity(n, format="csr")
    key = lambda g: tuple(np.round(g @ probe, 9))  # noqa: E731
    seen = {key(identity): identity}
    frontier = [identity]
    while frontier:
        nxt = []
        for h in frontier:
            for g in gens:
                e = (g @ h).tocsr()
                k = key(e)
                if k not in seen:
                    seen[k] = e
                    nxt.append(e)
                    if len(seen) > limit:
                        return None
        frontier = nxt
    return list(seen.values())


def _fixed_space(mats: Sequence[np.ndarray], m: int) -> np.ndarray:
    """Orthonormal basis (columns) of the common fixed space of the ``m x m`` matrices."""
    if not mats:
        return np.eye(m)
    A = np.vstack([M - np.eye(m) for M in mats])
    _, s, Vt = np.linalg.svd(A)
    rank = int(np.count_nonzero(s > 1e-8 * max(1.0, float(s[0]) if s.size else 1.0)))
    return Vt[rank:].T


def symmetric_directions(problem: Problem, u: np.ndarray, V: np.ndarray) -> BranchDirections | None:
    """The axial branch directions of the kernel ``V`` (columns) at the state ``u``, by the declared symmetry.

    None when the problem declares no symmetry, or its group is larger than :data:`MAX_GROUP_ORDER`.
    """
    generators = tuple(getattr(problem, "symmetry_generators", ()) or ())
    if not generators:
        return None
    n, m = V.shape
    elements = group_elements(generators, n)
    if elements is None:
        return BranchDirections(method="symmetry", note=f"the declared group has more than {MAX_GROUP_ORDER} "
                                                       "elements: not used")
    scale = 1.0 + float(np.max(np.abs(u), initial=0.0))
    isotropy = [g for g in elements if float(np.max(np.abs(g @ u - u), initial=0.0)) <= 1e-8 * scale]
    distinct: dict[bytes, np.ndarray] = {}
    for g in isotropy:
        M = V.T @ (g @ V)
        if not np.allclose(M @ M.T, np.eye(m), atol=1e-6):
            return BranchDirections(method="symmetry", note="the kernel is not invariant under the point's "
                                                           "symmetry (the declared generators do not fit the model)")
        distinct.setdefault(np.round(M, 7).tobytes(), M)
    reps = np.array(list(distinct.values()))  # (group order on the kernel, m, m)
    lines = _axial_lines(reps, m)
    out = BranchDirections(method="symmetry")
    done: list[np.ndarray] = []
    for c in lines:
        if any(_same_line(c, d) for d in done):
            continue
        unique = _distinct_lines(reps @ c)
        done += unique
        stabiliser = int(np.count_nonzero(np.max(np.abs(reps @ c - c), axis=1) <= 1e-8))
        out.directions.append(c)
        out.labels.append(f"fixed by {stabiliser} of the {len(reps)} symmetries acting on the kernel")
        out.copies.append(len(unique))
    if not out.directions:
        out.note = "no isotropy subgroup has a one-dimensional fixed space in the kernel"
    return out


def _same_line(a: np.ndarray, b: np.ndarray) -> bool:
    return 1.0 - abs(float(a @ b)) <= SAME_LINE


def _distinct_lines(vectors: np.ndarray) -> list[np.ndarray]:
    """The distinct lines among unit ``vectors`` (rows), one vector each."""
    kept: list[np.ndarray] = []
    for v in vectors:
        if not kept or float(np.max(np.abs(np.array(kept) @ v))) < 1.0 - SAME_LINE:
            kept.append(v)
    return kept


def _axial_lines(reps: np.ndarray, m: int) -> list[np.ndarray]:
    """Lines of the kernel that are the whole fixed space of their own isotropy subgroup.

    Candidates are the one-dimensional fixed spaces of single elements and the intersections of
    fixed spaces with mirrors, built up one mirror at a time (enough for the dihedral and symmetric
    groups' representations met in structures); each is kept when the elements fixing it fix
    nothing more.
    """
    def key(F: np.ndarray) -> bytes:
        return np.round(F @ F.T, 8).tobytes()  # the subspace, whatever its basis

    fixed: dict[bytes, np.ndarray] = {}
    for M in reps:
        F = _fixed_space([M], m)
        if 0 < F.shape[1] < m:
            fixed.setdefault(key(F), F)
    # intersections with the mirrors (fixed spaces of one dimension less than the kernel) reach the
    # fixed spaces of the subgroups that reflections generate (S_m x S_(k-m) of identical cells, the
    # dihedral groups' lines); an element's own line (a rotation's axis) is a candidate as it is
    walls = [F for F in fixed.values() if F.shape[1] == m - 1]
    candidates: list[np.ndarray] = []
    frontier = dict(fixed)
    for _ in range(max(1, m - 1)):
        nxt: dict[bytes, np.ndarray] = {}
        for F in frontier.values():
            if F.shape[1] == 1:
                candidates.append(F[:, 0])
                continue
            for G in walls:
                # the intersection of two subspaces: the common null space of their complements' projectors
                both = _fixed_space([F @ F.T, G @ G.T], m)
                if 0 < both.shape[1] < F.shape[1]:
                    nxt.setdefault(key(both), both)
        frontier = nxt
    lines: list[np.ndarray] = []
    unit = [c / np.linalg.norm(c) for c in candidates]
    for c in (_distinct_lines(np.array(unit)) if unit else []):
        stab = reps[np.max(np.abs(reps @ c - c), axis=1) <= 1e-8]
        if _fixed_space(list(stab), m).shape[1] == 1:
            lines.append(c)
    return lines


def quartic_form(problem: Problem, u: np.ndarray, p: float, w: np.ndarray, step: float = 1e-2) -> float:
    """``w^T [d^2/de^2 J(u + e w, p)] w`` (the fourth derivative of the energy along ``w``), by differences."""
    h = step * (1.0 + float(np.max(np.abs(u), initial=0.0))) / max(float(np.max(np.abs(w))), 1e-300)

    def central(hh: float) -> float:
        Jw = problem.checked_jacobian(u, p) @ w
        return float(w @ (problem.checked_jacobian(u + hh * w, p) @ w - 2.0 * Jw
                          + problem.checked_jacobian(u - hh * w, p) @ w)) / hh ** 2
    return (4.0 * central(0.5 * h) - central(h)) / 3.0


def reduced_directions(problem: Problem, u: np.ndarray, p: float, V: np.ndarray) -> BranchDirections:
    """Branch directions of a two-dimensional kernel from the reduced equation's quartic form (no symmetry needed).

    Only where the quadratic terms vanish on the kernel (checked): a point with quadratic terms, or a
    kernel of three or more dimensions, is reported unresolved in ``note``.
    """
    n, m = V.shape
    out = BranchDirections(method="reduced equation")
    if m != 2:
        out.note = f"a {m}-dimensional kernel without a declared symmetry is not resolved"
        return out
    # quadratic terms: phi_i^T f_uu[V c, V c] for a few c; they must vanish for the quartic to rule
    h = 1e-4 * (1.0 + float(np.max(np.abs(u), initial=0.0)))
    J0 = problem.checked_jacobian(u, p)
    size = float(np.max(np.abs(J0.data if hasattr(J0, "data") else J0), initial=0.0)) or 1.0
    for c in (np.array([1.0, 0.0]), np.array([0.0, 1.0]), np.array([1.0, 1.0]) / math.sqrt(2.0)):
        w = V @ c
        q = V.T @ ((problem.checked_jacobian(u + h * w, p) - problem.checked_jacobian(u - h * w, p)) @ w) / (2 * h)
        if float(np.max(np.abs(q))) > 1e-6 * size:
            out.note = "the reduced equation has quadratic terms on this kernel: not resolved"
            return out
    angles = np.pi * np.arange(9) / 9.0
    values = np.array([quartic_form(problem, u, p, V @ np.array([math.cos(t), math.sin(t)])) for t in angles])
    # Q(t) = a0 + a2 cos 2t + b2 sin 2t + a4 cos 4t + b4 sin 4t
    basis = np.column_stack([np.ones_like(angles), np.cos(2 * angles), np.sin(2 * angles), np.cos(4 * angles),
                             np.sin(4 * angles)])
    a0, a2, b2, a4, b4 = np.linalg.lstsq(basis, values, rcond=None)[0]
    fine = np.linspace(0.0, np.pi, 721)
    dQ = -2 * a2 * np.sin(2 * fine) + 2 * b2 * np.cos(2 * fine) - 4 * a4 * np.sin(4 * fine) + 4 * b4 * np.cos(4 * fine)
    scale = abs(a2) + abs(b2) + abs(a4) + abs(b4)
    if scale <= 1e-9 * max(abs(a0), 1e-300):
        out.note = "the quartic form is the same in every direction (an O(2)-like kernel): no direction is singled out"
        return out
    for k in range(fine.size - 1):
        if dQ[k] == 0.0 or dQ[k] * dQ[k + 1] < 0:
            lo, hi = fine[k], fine[k + 1]
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                d_mid = (-2 * a2 * math.sin(2 * mid) + 2 * b2 * math.cos(2 * mid) - 4 * a4 * math.sin(4 * mid)
                         + 4 * b4 * math.cos(4 * mid))
                d_lo = (-2 * a2 * math.sin(2 * lo) + 2 * b2 * math.cos(2 * lo) - 4 * a4 * math.sin(4 * lo)
                        + 4 * b4 * math.cos(4 * lo))
                if d_lo * d_mid <= 0:
                    hi = mid
                else:
                    lo = mid
            t = 0.5 * (lo + hi)
            out.directions.append(np.array([math.cos(t), math.sin(t)]))
            out.labels.append(f"critical direction of the quartic form at {math.degrees(t):.6g} degrees")
            out.copies.append(1)
    return out


def isotropy_basis(problem: Problem, u: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, int] | None:
    """Orthonormal basis (columns) of the fixed-point space of the symmetries that fix ``u`` and ``direction``.

    That space holds every state with the symmetry of the branch leaving ``u`` along ``direction``;
    within it the branch point is simple.  Returns ``(B, order of the isotropy group)``, or None without
    a declared symmetry (or with a group above :data:`MAX_GROUP_ORDER`), or when the isotropy group is
    trivial (the space is the whole space).
    """
    generators = tuple(getattr(problem, "symmetry_generators", ()) or ())
    if not generators:
        return None
    n = u.size
    elements = group_elements(generators, n)
    if elements is None:
        return None
    scale = 1.0 + float(np.max(np.abs(u), initial=0.0))
    size = float(np.max(np.abs(direction), initial=0.0)) or 1.0
    fixing = [g for g in elements if float(np.max(np.abs(g @ u - u), initial=0.0)) <= 1e-8 * scale
              and float(np.max(np.abs(g @ direction - direction), initial=0.0)) <= 1e-8 * size]
    if len(fixing) <= 1:
        return None
    projector = sum((_dense(g) for g in fixing), np.zeros((n, n))) / len(fixing)
    w, vectors = np.linalg.eigh(0.5 * (projector + projector.T))
    return vectors[:, w > 0.5], len(fixing)


class FixedSpaceProblem(Problem):
    """A symmetric problem restricted to a fixed-point space: unknowns ``z`` with ``u = B z``.

    ``B`` (``n x k``, orthonormal columns) spans the states of one symmetry; the residual is
    ``B^T f(B z, p)`` and the Jacobian ``B^T J B``, the gradient and Hessian of ``E(B z, p)``.  By the
    symmetry, an equilibrium of the restricted problem is one of the full problem, and a multiple
    branch point of the full problem whose symmetric branches are axial is a simple one here.
    Observables are the full problem's at ``B z``.  Stability here is within the space only.
    """

    def __init__(self, problem: Problem, basis: np.ndarray) -> None:
        self.full, self.B = problem, np.asarray(basis, dtype=float)
        observables = {name: (lambda fun: (lambda z, p: fun(self.B @ z, p)))(fun)
                       for name, fun in problem.observables.items()}
        super().__init__(observables=observables, symmetric=problem.symmetric,
                         name=f"{problem.name} (fixed space, {self.B.shape[1]} of {self.B.shape[0]} unknowns)",
                         parameter_name=problem.parameter_name,
                         residual_scale=problem.residual_scale)
        if problem.reference_scales is not None:
            self.adopt_reference_scales(*problem.reference_scales)

    def residual(self, z, p):
        return self.B.T @ self.full.residual(self.B @ z, p)

    def jacobian(self, z, p):
        return self.B.T @ (self.full.jacobian(self.B @ z, p) @ self.B)

    def dresidual_dp(self, z, p):
        return self.B.T @ self.full.dresidual_dp(self.B @ z, p)

    def energy(self, z, p):
        return self.full.energy(self.B @ z, p)

    def max_step_fraction(self, z, p, dz, dp):
        return self.full.max_step_fraction(self.B @ z, p, self.B @ dz, dp)


#: An eigenvalue within this many units of roundoff of its operator's size (``eps ||H||_inf``) is zero:
#: the sign of a neutral mode (the rotation of a ring's oval, or of an O(2)-symmetric strut's tilt,
#: which the branch's symmetry does not fix) is rounding, not stability.
NEUTRAL_ROUNDOFF = 1e3


@dataclass
class FullSpaceStability:
    """The stability of states traced in a fixed-point space, against every mode of the full problem.

    Attributes
    ----------
    by_label : dict
        ``{label: (n_negative, eigenvalues)}`` per stored point, the counts leaving out the neutral
        eigenvalues (``|lambda| <= NEUTRAL_ROUNDOFF eps ||H||_inf``), the eigenvalues padded with NaN
        to ``n_eigs``.
    neutral : ndarray of int
        The number of neutral eigenvalues of the primary operator at each point.
    """

    by_label: dict[str, tuple[np.ndarray, np.ndarray]]
    neutral: np.ndarray


def _max_row_sum(H: Any) -> float:
    if sp.issparse(H):
        return float(np.max(np.asarray(abs(H).sum(axis=1)), initial=0.0))
    return float(np.max(np.sum(np.abs(np.asarray(H, dtype=float)), axis=1), initial=0.0))


def full_space_stability(problem: Problem, states: Sequence[np.ndarray], params: Sequence[float],
                         n_eigs: int) -> FullSpaceStability:
    """Morse indices and smallest eigenvalues of ``problem`` at the given states, neutral modes apart.

    A branch traced in a fixed-point space knows its stability only against the modes of its own
    symmetry; against the others it is counted here, point by point.  A branch that breaks a
    continuous (or, on a fine mesh, nearly continuous) symmetry has a zero eigenvalue along the
    group's orbit, whose computed sign flips from point to point: such neutral eigenvalues are not
    counted as negative, and their number is returned.

    Parameters
    ----------
    problem : the full problem.
    states, params : the stored points, in the full problem's unknowns.
    n_eigs : the eigenvalues kept per point (at least three are computed to find the neutral ones).
    """
    eps = float(np.finfo(float).eps)
    labels: list[str] = []
    counts: dict[str, list[int]] = {}
    eigs: dict[str, list[np.ndarray]] = {}
    neutral: list[int] = []
    for u, p in zip(states, params):
        sizes = {label: _max_row_sum(op) for label, op in problem.stability_operators(u, float(p)).items()}
        k = max(n_eigs, 3)
        infos = problem.stability(u, float(p), k)
        if any(info.n_negative >= info.eigenvalues.size > 0 for info in infos.values()):
            # every eigenvalue computed is negative: the ones next to zero may lie beyond them
            k = max(info.n_negative for info in infos.values()) + 3
            infos = problem.stability(u, float(p), k)
        if not labels:
            labels = list(infos)
            counts, eigs = {label: [] for label in labels}, {label: [] for label in labels}
        for j, label in enumerate(labels):
            info = infos[label]
            w = np.asarray(info.eigenvalues, dtype=float)
            zero = NEUTRAL_ROUNDOFF * eps * sizes.get(label, 0.0)
            counts[label].append(int(info.n_negative) - int(np.sum((w < 0.0) & (w >= -zero))))
            if j == 0:
                neutral.append(int(np.sum(np.abs(w) <= zero)))
            kept = w[:n_eigs]
            eigs[label].append(np.pad(kept, (0, max(0, n_eigs - kept.size)), constant_values=np.nan))
    by_label = {label: (np.array(counts[label], dtype=int), np.array(eigs[label]).reshape(len(counts[label]), n_eigs))
                for label in labels}
    return FullSpaceStability(by_label, np.array(neutral, dtype=int))
