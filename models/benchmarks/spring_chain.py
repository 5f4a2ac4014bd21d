"""A chain of ``k`` identical bistable springs in series under displacement control.

Each spring carries the force

    f(e) = e - s w [tanh((e - 1)/w) + tanh(1/w)],     f'(e) = 1 - s sech^2((e - 1)/w),

at the elongation ``e``: unit stiffness far from ``e = 1``, a softening of depth ``s > 1`` and width
``w`` around it, so the law rises, falls (slope down to ``1 - s``) and rises again, and ``f(0) = 0``.
Its energy is ``W(e) = e^2/2 - s w^2 log cosh((e - 1)/w) - s w tanh(1/w) e + s w^2 log cosh(1/w)``.
A cubic law would not do: every cubic is point-symmetric about its inflection, and then two springs
under a prescribed total elongation never snap (the falling branch is nowhere steeper than the rising
one at the same force), while this law's falling branch is twice as steep as its rising ones
(``s = 3``).  The chain's ends are ``Delta`` apart (the parameter, the total elongation), the
elongations sum to it and the energy is ``E = sum_i W(e_i)``.  Two choices of unknowns
(``coordinates``), both with ``e = G u + Delta g``:

- ``"nodes"``: the positions ``x_1 .. x_{k-1}`` of the inner nodes (``x_0 = 0``, ``x_k = Delta``),
  ``e_i = x_i - x_{i-1}``: what one writes first.  ``df/dDelta`` is ``-f'(e_k)`` on the last node.
- ``"modes"``: ``e = Delta / k + Q z`` with ``Q`` an orthonormal basis of the vectors with zero sum
  (``k - 1`` columns).  The homogeneous branch is ``z = 0`` for every ``Delta``, and the permutations
  of the springs act on ``z`` by the orthogonal matrices ``Q^T P Q``.

In either, ``f(u) = G^T f(e)``, ``J = G^T diag(f'(e)) G`` and ``df/dDelta = G^T diag(f'(e)) g``.  The
spring force (equal in all springs at equilibrium) is the observable ``"force"``.

Closed forms
------------
*One spring.*  The spinodal elongations ``e_a,b = 1 -+ w arccosh(sqrt(s))`` (``f' = 0``) bound the
falling branch; ``F_max = f(e_a)`` and ``F_min = f(e_b)`` are the peak and the valley.  For
``F_min < F < F_max`` the three elongations with ``f(e) = F`` lie one on each monotone branch, phase
1 (``e < e_a``), 2 (falling) and 3 (``e > e_b``): :meth:`BistableChain.phase_elongations` (the root
of a monotone function on each branch).

*The homogeneous branch* ``e_i = Delta / k``, force ``f(Delta / k)``.  Its Hessian is ``f'(Delta/k) G^T G``:
in ``"nodes"`` ``G^T G`` is ``tridiag(-1, 2, -1)`` of size ``k - 1``, so the eigenvalues are
``4 f'(Delta/k) sin^2(j pi / (2 k))``, ``j = 1 .. k-1``; in ``"modes"`` ``G^T G = I`` and all ``k - 1`` are
``f'(Delta / k)``.  All vanish together at ``Delta = k e_a`` and ``Delta = k e_b``: two branch points of
multiplicity ``k - 1`` (the kernel is every change of the elongations with zero sum).  In ``"nodes"``
``df/dDelta`` vanishes there too.

*The branches that leave it.*  Near ``e_a``, with ``Delta / k = e_a + eta`` and ``m`` springs
elongating by ``(k - m) delta`` while ``k - m`` shorten by ``m delta`` (the fixed-point space of
``S_m x S_{k-m}``), equal forces need ``(eta + (k - m) delta)^2 = (eta - m delta)^2`` to leading
order (``f`` is quadratic at its peak), so ``Delta - k e_a = -k (k - 2m) delta / 2``: a transcritical
branch for ``k != 2m`` and a pitchfork for ``k = 2m`` (the two springs of ``k = 2``; a chain with
``k = 6`` has both).  Far from the spinodal these are the branches with ``m`` springs in one phase
and ``k - m`` in another, ``Delta = (k - m) e_p(F) + m e_q(F)``.  Stability under displacement
control: all springs on rising branches is stable; one spring on the falling branch is stable iff
``sum_i 1 / f'(e_i) < 0`` (i.e. ``dDelta/dF < 0``; the Hessian restricted to zero-sum changes);
two or more on it is unstable (Puglisi & Truskinovsky, *Mechanics of a discrete chain with bi-stable
elements*, J. Mech. Phys. Solids 48 (2000) 1-27).

*The quasi-static sawtooth* (loading from ``Delta = 0``, a state kept until it loses stability): the
chain runs through the families ``j = 0 .. k`` of ``k - j`` springs in phase 1 and ``j`` in phase 3,
``Delta_j(F) = (k - j) e_1(F) + j e_3(F)``.  Family ``j`` rises until its ``n = k - j`` phase-1
springs reach ``e_a`` at ``F_max`` (a branch point of multiplicity ``n - 1``).  There, with the
compliance ``C = j / f'(e_3(F_max))`` of the springs in phase 3:

- ``n >= 3``: every branch that leaves towards larger ``Delta`` has two springs on the falling
  branch: the chain snaps at ``Delta_j(F_max)``;
- ``n = 2``: a pitchfork; along it ``1/f'(e_1) + 1/f'(e_2) -> -(2/3) f'''(e_a) / f''(e_a)^2`` (expand
  ``f`` to third order about its peak), so the branch with one spring softening is stable and the
  path goes on iff ``(2/3) f'''(e_a) / f''(e_a)^2 > C``.  Here ``f'''(e_a) = (2 / w^2)(3/s - 2)``, negative
  for ``s > 3/2``: the chain snaps;
- ``n = 1``: no branch point, the force has a smooth maximum and the one softening spring goes on.

A path that goes on follows one spring down the falling branch until ``sum_i 1 / f'(e_i) = 0``
(a fold in ``Delta``), where it snaps.  Every snap, at fixed ``Delta``, lands on family ``j + 1``
(one more spring on its outer branch; the landing force solves ``Delta_{j+1}(F) = Delta`` on the
stable part, where that spring may still be on its falling branch).  :meth:`BistableChain.sawtooth`
lists the teeth.

Symmetry
--------
``symmetry_generators`` (``"modes"`` only): the transposition of springs 1 and 2 and the cycle
``(1 2 .. k)``, as the orthogonal matrices ``Q^T P Q``; they generate ``S_k`` (``k!`` elements).  In
``"nodes"`` the permutations act on ``(x, Delta)`` together (they move ``x_{k-1}`` by ``Delta``), not
linearly on the state: the tuple is empty there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq

from contin import Problem

__all__ = ["BistableChain", "Tooth"]


@dataclass(frozen=True)
class Tooth:
    """One snap of the quasi-static sawtooth of :meth:`BistableChain.sawtooth`.

    Attributes
    ----------
    delta : float
        The total elongation at which the chain snaps.
    force_before, force_after : float
        The spring force just before the snap (the tooth's peak) and on the landing.
    springs_out : int
        Springs in phase 3 before the snap (family ``j``).
    at : str
        ``"spinodal"``: the snap is at the family's branch point (``F_max``); ``"fold"``: at the
        fold of the path with one spring softening.
    multiplicity : int
        The kernel's dimension where family ``j`` meets ``F_max`` (``k - j - 1``; 0 where the force
        has a smooth maximum there).
    """

    delta: float
    force_before: float
    force_after: float
    springs_out: int
    at: str
    multiplicity: int


class BistableChain(Problem):
    """``k`` identical bistable springs in series, total elongation ``Delta`` prescribed (module docstring).

    Parameters
    ----------
    k : int
        Number of springs (at least 2).
    softening : float
        ``s > 1``: the depth of the softening (the falling branch's steepest slope is ``1 - s``).
    width : float
        ``0 < w <= 0.2``: the width of the softening in elongation.
    coordinates : str
        ``"nodes"`` or ``"modes"``.
    """

    def __init__(self, k: int = 3, softening: float = 3.0, width: float = 0.1, coordinates: str = "nodes") -> None:
        if int(k) != k or k < 2:
            raise ValueError(f"BistableChain: k = {k!r} must be an integer >= 2")
        if not softening > 1:
            raise ValueError(f"BistableChain: softening = {softening!r} must be > 1 (else the law is monotone)")
        if not 0 < width <= 0.2:
            raise ValueError(f"BistableChain: width = {width!r} must lie in (0, 0.2]")
        if coordinates not in ("nodes", "modes"):
            raise ValueError(f"BistableChain: coordinates must be 'nodes' or 'modes', got {coordinates!r}")
        self.k, self.s, self.w, self.coordinates = int(k), float(softening), float(width), coordinates
        super().__init__(symmetric=True, name=f"bistable_chain(k={self.k}, {coordinates})", parameter_name="Delta")
        if coordinates == "nodes":
            G = np.zeros((self.k, self.k - 1))
            G[np.arange(self.k - 1), np.arange(self.k - 1)] = 1.0
            G[np.arange(1, self.k), np.arange(self.k - 1)] = -1.0
            g = np.zeros(self.k)
            g[-1] = 1.0
            self.symmetry_generators: tuple[sp.csr_matrix, ...] = ()
        else:
            G = self.zero_sum_basis(self.k)
            g = np.full(self.k, 1.0 / self.k)
            swap = np.eye(self.k)[[1, 0, *range(2, self.k)]]
            cycle = np.roll(np.eye(self.k), 1, axis=0)
            self.symmetry_generators = tuple(sp.csr_matrix(G.T @ P @ G) for P in (swap, cycle))
        self.G, self.g = G, g
        self._obs = {"force": lambda u, D: float(np.mean(self.spring_force(self.elongations(u, D)))),
                     "spread": lambda u, D: float(np.ptp(self.elongations(u, D)))}

    @property
    def observables(self):
        return self._obs

    @staticmethod
    def zero_sum_basis(k: int) -> np.ndarray:
        """An orthonormal basis ``Q`` (``k x (k-1)``) of the vectors whose entries sum to zero.

        The Helmert basis: column ``j`` is ``(1, .., 1, -j, 0, .., 0) / sqrt(j (j + 1))`` with ``j`` ones.
        """
        Q = np.zeros((k, k - 1))
        for j in range(1, k):
            Q[:j, j - 1] = 1.0
            Q[j, j - 1] = -float(j)
            Q[:, j - 1] /= math.sqrt(j * (j + 1))
        return Q

    # ---- the spring --------------------------------------------------------------------------------
    def spring_force(self, e: np.ndarray | float) -> np.ndarray | float:
        """``f(e) = e - s w [tanh((e - 1)/w) + tanh(1/w)]``."""
        e = np.asarray(e, dtype=float)
        return e - self.s * self.w * (np.tanh((e - 1.0) / self.w) + math.tanh(1.0 / self.w))

    def spring_stiffness(self, e: np.ndarray | float) -> np.ndarray | float:
        """``f'(e) = 1 - s sech^2((e - 1)/w)``."""
        return 1.0 - self.s / np.cosh((np.asarray(e, dtype=float) - 1.0) / self.w) ** 2

    def spring_energy(self, e: np.ndarray | float) -> np.ndarray | float:
        """``W(e)``, with ``W(0) = 0`` (module docstring)."""
        e = np.asarray(e, dtype=float)
        x = (e - 1.0) / self.w
        log_cosh = np.logaddexp(x, -x) - math.log(2.0)  # no overflow for large |x|
        log_cosh_0 = math.log(math.cosh(1.0 / self.w))
        return (0.5 * e ** 2 - self.s * self.w ** 2 * log_cosh - self.s * self.w * math.tanh(1.0 / self.w) * e
                + self.s * self.w ** 2 * log_cosh_0)

    def spring_derivatives_at_peak(self) -> tuple[float, float]:
        """``(f''(e_a), f'''(e_a)) = (-(2/w) sqrt(1 - 1/s), (2/w^2)(3/s - 2))``."""
        return -2.0 / self.w * math.sqrt(1.0 - 1.0 / self.s), 2.0 / self.w ** 2 * (3.0 / self.s - 2.0)

    def elongations(self, u: np.ndarray, Delta: float) -> np.ndarray:
        """The springs' elongations ``e = G u + Delta g``."""
        return self.G @ np.asarray(u, dtype=float) + Delta * self.g

    # ---- the model ---------------------------------------------------------------------------------
    def energy(self, u, Delta):
        return float(np.sum(self.spring_energy(self.elongations(u, Delta))))

    def _pull_back(self, x: np.ndarray) -> np.ndarray:
        """``G^T x``: per-spring values to the unknowns.

        In ``"modes"`` ``G^T 1 = 0``, so ``G^T x = G^T (x - mean(x))``; the second form is exactly zero
        when all springs carry the same value (the homogeneous branch), where the first keeps the
        rounding error of ``G``'s entries.
        """
        return self.G.T @ (x - np.mean(x)) if self.coordinates == "modes" else self.G.T @ x

    def residual(self, u, Delta):
        return self._pull_back(self.spring_force(self.elongations(u, Delta)))

    def jacobian(self, u, Delta):
        k = self.spring_stiffness(self.elongations(u, Delta))
        return sp.csr_matrix(self.G.T @ (k[:, None] * self.G))

    def dresidual_dp(self, u, Delta):
        return self._pull_back(self.spring_stiffness(self.elongations(u, Delta)) * self.g)

    def state(self, elongations: np.ndarray) -> np.ndarray:
        """The unknowns ``u`` of given elongations (``Delta`` is their sum): ``G u = e - Delta g``."""
        e = np.asarray(elongations, dtype=float)
        return np.linalg.lstsq(self.G, e - e.sum() * self.g, rcond=None)[0]

    # ---- closed forms ------------------------------------------------------------------------------
    @property
    def spinodals(self) -> tuple[float, float]:
        """``(e_a, e_b) = 1 -+ w arccosh(sqrt(s))``: where ``f' = 0``."""
        r = self.w * math.acosh(math.sqrt(self.s))
        return 1.0 - r, 1.0 + r

    @property
    def force_range(self) -> tuple[float, float]:
        """``(F_min, F_max) = (f(e_b), f(e_a))``: the valley and the peak of ``f``."""
        e_a, e_b = self.spinodals
        return float(self.spring_force(e_b)), float(self.spring_force(e_a))

    def phase_elongations(self, F: float) -> tuple[float, float, float]:
        """``(e_1, e_2, e_3)``: the elongations with ``f(e) = F`` on the three branches, ``F_min <= F <= F_max``."""
        F_min, F_max = self.force_range
        if not F_min - 1e-12 <= F <= F_max + 1e-12:
            raise ValueError(f"BistableChain.phase_elongations: F = {F} outside [{F_min}, {F_max}]")
        e_a, e_b = self.spinodals
        reach = 2.0 * self.s * self.w + 1.0  # |f(e) - e| <= 2 s w: the roots lie within this of F
        residual = lambda e: float(self.spring_force(e)) - F
        roots = []
        for lo, hi in ((min(e_a, F) - reach, e_a), (e_a, e_b), (e_b, max(e_b, F) + reach)):
            a, b = residual(lo), residual(hi)
            roots.append(lo if a == 0 else hi if b == 0 or a * b > 0 else brentq(residual, lo, hi, xtol=1e-15))
        return roots[0], roots[1], roots[2]

    def homogeneous_eigenvalues(self, Delta: float) -> np.ndarray:
        """Hessian eigenvalues on the homogeneous branch, sorted (module docstring)."""
        stiffness = float(self.spring_stiffness(Delta / self.k))
        if self.coordinates == "modes":
            return np.full(self.k - 1, stiffness)
        j = np.arange(1, self.k)
        return np.sort(4.0 * stiffness * np.sin(j * np.pi / (2 * self.k)) ** 2)

    def homogeneous_branch_points(self) -> list[tuple[float, float, int]]:
        """``(Delta, F, multiplicity)`` of the homogeneous branch's two branch points."""
        (e_a, e_b), (F_min, F_max) = self.spinodals, self.force_range
        return [(self.k * e_a, F_max, self.k - 1), (self.k * e_b, F_min, self.k - 1)]

    def family_elongation(self, F: float, outer: int, softening: int = 0) -> float:
        """``Delta`` of the equilibrium with ``outer`` springs in phase 3, ``softening`` in phase 2, the rest in phase 1."""
        e1, e2, e3 = self.phase_elongations(F)
        return (self.k - outer - softening) * e1 + softening * e2 + outer * e3

    def compliance(self, F: float, outer: int, softening: int = 1) -> float:
        """``dDelta/dF = sum_i 1 / f'(e_i)`` of that equilibrium (one softening spring: stable iff negative)."""
        e1, e2, e3 = self.phase_elongations(F)
        counts = (self.k - outer - softening, softening, outer)
        return float(sum(c / self.spring_stiffness(e) for c, e in zip(counts, (e1, e2, e3)) if c))

    def _first_fold(self, outer: int, from_top: bool) -> float | None:
        """The first root of :meth:`compliance` with one softening spring, scanning from ``F_max`` or ``F_min``.

        None when the compliance stays negative (no fold: the softening spring passes the falling
        branch without a snap).
        """
        F_min, F_max = self.force_range
        grid = np.linspace(F_min, F_max, 2001)[1:-1]
        grid = grid[::-1] if from_top else grid
        values = [self.compliance(F, outer) for F in grid]
        for a, b, Fa, Fb in zip(values, values[1:], grid, grid[1:]):
            if a < 0 <= b:
                return float(brentq(lambda F: self.compliance(F, outer), min(Fa, Fb), max(Fa, Fb), xtol=1e-15))
        return None

    def _landing_force(self, Delta: float, outer: int) -> float:
        """Force of the stable equilibrium of family ``outer`` at ``Delta`` (its last spring in phase 3, or in phase 2)."""
        F_min, F_max = self.force_range
        if self.family_elongation(F_min, outer) <= Delta <= self.family_elongation(F_max, outer):
            return float(brentq(lambda F: self.family_elongation(F, outer) - Delta, F_min, F_max, xtol=1e-15))
        # the landing spring is still on its falling branch: the stable part next to F_min
        top = self._first_fold(outer - 1, from_top=False) or F_max
        return float(brentq(lambda F: self.family_elongation(F, outer - 1, 1) - Delta, F_min, top, xtol=1e-15))

    def pitchfork_goes_on(self, outer: int) -> bool:
        """Whether family ``outer`` with two springs left in phase 1 goes on past ``F_max`` (module docstring)."""
        f2, f3 = self.spring_derivatives_at_peak()
        reservoir = outer / float(self.spring_stiffness(self.phase_elongations(self.force_range[1])[2]))
        return 2.0 / 3.0 * f3 / f2 ** 2 > reservoir

    def sawtooth(self) -> list[Tooth]:
        """The snaps of the quasi-static loading path from ``Delta = 0`` (module docstring), in order."""
        F_max = self.force_range[1]
        teeth = []
        for j in range(self.k):
            n = self.k - j
            fold = self._first_fold(j, from_top=True) if n == 1 or (n == 2 and self.pitchfork_goes_on(j)) else F_max
            if fold is None:
                continue  # the softening spring reaches phase 3 without a snap
            at = "spinodal" if fold == F_max else "fold"
            Delta = self.family_elongation(F_max, j) if at == "spinodal" else self.family_elongation(fold, j, 1)
            teeth.append(Tooth(Delta, fold, self._landing_force(Delta, j + 1), j, at, n - 1))
        return teeth
