"""A square membrane with the symmetry of the square: ``E(u) = int 1/2 |grad u|^2 - 1/2 p u^2 + 1/4 u^4``.

On the unit square with ``u = 0`` on the boundary, discretised on the ``n x n`` interior nodes
``(x_i, y_l) = ((i + 1) h, (l + 1) h)``, ``h = 1 / (n + 1)``, with the gradient by differences
along the grid's edges (the boundary edges included) and every sum weighted by ``h^2``::

    E(u, p) = 1/2 sum_edges (u_a - u_b)^2 - h^2 p/2 sum u^2 + h^2/4 sum u^4
    f(u, p) = h^2 (A u - p u + u^3),      J = h^2 (A - p I + 3 diag(u^2)),

``A`` the five-point Dirichlet Laplacian (``-Delta_h``).  The state is ``u[l n + i] = u(x_i, y_l)``.

Closed forms
------------
*Trivial branch and its branch points.*  ``u = 0`` solves ``f = 0`` for every ``p``; there
``J = h^2 (A - p I)``.  The eigenvectors of ``A`` are ``phi_jk(x_i, y_l) = 2 sin(j pi x_i) sin(k pi y_l)``
(``1 <= j, k <= n``) with eigenvalues ``lambda_jk = (4/h^2) (sin^2(j pi h/2) + sin^2(k pi h/2))``
(the product of two one-dimensional Dirichlet problems, e.g. LeVeque, *Finite Difference Methods for
Ordinary and Partial Differential Equations*, SIAM 2007, ch. 3), so ``J`` has the eigenvalues
``h^2 (lambda_jk - p)`` and the trivial branch has a branch point at every ``p = lambda_jk``: simple
for ``j = k``, double for ``j != k`` (``lambda_jk = lambda_kj``).  The factor 2 normalises
``||phi||_h^2 = h^2 sum phi^2 = 1``: ``sum_{i=1}^{n} sin^2(j pi i h) = (n + 1)/2``.

*The double point (1,2)/(2,1) and its cubic bifurcation equation.*  With ``u = a phi_12 + b phi_21 + w``
(``w`` orthogonal to the kernel, ``O(|a|^3)``) the reduced energy is, to fourth order,
``1/2 (lambda_12 - p)(a^2 + b^2) + 1/4 (alpha (a^4 + b^4) + 6 beta a^2 b^2)`` with
``alpha = h^2 sum phi_12^4`` and ``beta = h^2 sum phi_12^2 phi_21^2``; the odd terms
``h^2 sum phi_12^3 phi_21`` vanish because ``x -> 1 - x`` keeps ``phi_12`` and flips ``phi_21``.
On the grid the sums are exact trigonometric sums: ``sum_i sin^4(j pi i h) = 3 (n + 1)/8`` and
``sum_i sin^2(pi i h) sin^2(2 pi i h) = (n + 1)/4`` for ``n + 1 > 4``, so ``alpha = 9/4`` and
``beta = 1``, the values of the continuum integrals (:meth:`D4Square.quartic_coefficients` computes
the grid sums).  The cubic bifurcation equation
``(lambda - p) a + alpha a^3 + 3 beta a b^2 = 0`` (and ``a <-> b``) has two kinds of solutions:

- pure modes ``b = 0``: ``||u||_h^2 = a^2 = (p - lambda) / alpha``, i.e. ``4 (p - lambda) / 9``;
- mixed modes ``a = +-b``: ``||u||_h^2 = a^2 + b^2 = 2 (p - lambda) / (alpha + 3 beta)``, i.e.
  ``8 (p - lambda) / 21``,

to leading order in ``p - lambda`` (both supercritical), with ``||u||_h = (h^2 sum u^2)^{1/2}``,
the amplitude the observable ``"norm"`` reports.  In the kernel the pure modes are minima of the
reduced energy on its circle (``3 beta > alpha``) and the mixed ones saddles, so near ``lambda_12``
the pure branches have Morse index 1 (the mode (1,1)) and the mixed ones 2; the trivial branch has 3.
Of the pure and mixed branches the square's symmetry maps every pure one to every other and every
mixed one to every other (Golubitsky, Stewart & Schaeffer, *Singularities and Groups in Bifurcation
Theory* II, Springer 1988, the equivariant branching lemma: ``D4`` acts on the kernel by its
two-dimensional irreducible representation; the reflections across the axes fix the pure directions and those across the
diagonals the mixed ones).  The simple points ``j = k`` are supercritical pitchforks with
``||u||_h^2 = (p - lambda_jj) / alpha_jj`` (``alpha_jj = 9/4`` as well).

Symmetry
--------
``symmetry_generators``: the quarter turn ``(x, y) -> (y, 1 - x)`` of the grid and the reflection
``x -> 1 - x``, as permutation matrices; they generate ``D4`` (8 elements).  The energy is also even
in ``u``; ``u -> -u`` is not among the generators.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from contin import Problem

from .symmetry import signed_permutation

__all__ = ["D4Square"]


class D4Square(Problem):
    """The square membrane of the module docstring on ``n x n`` interior nodes; parameter ``p``.

    Parameters
    ----------
    n : int
        Interior nodes per side (at least 5, so that the grid sums of the module docstring hold).
    """

    def __init__(self, n: int = 30) -> None:
        if int(n) != n or n < 5:
            raise ValueError(f"D4Square: n = {n!r} must be an integer >= 5")
        self.n = int(n)
        self.h = 1.0 / (self.n + 1)
        super().__init__(symmetric=True, name=f"d4_square(n={self.n})", parameter_name="p")
        one = sp.diags([-np.ones(self.n - 1), 2 * np.ones(self.n), -np.ones(self.n - 1)], [-1, 0, 1])
        eye = sp.identity(self.n)
        # A = -Delta_h; the state runs along x fastest (u[l n + i] = u(x_i, y_l))
        self.laplacian = ((sp.kron(eye, one) + sp.kron(one, eye)) / self.h ** 2).tocsr()
        self._h2 = self.h ** 2
        phi12, phi21 = self.mode(1, 2), self.mode(2, 1)
        self._obs = {
            "norm": lambda u, p: float(np.sqrt(self._h2 * np.dot(u, u))),
            "a12": lambda u, p: float(self._h2 * np.dot(phi12, u)),
            "a21": lambda u, p: float(self._h2 * np.dot(phi21, u)),
            "u_max": lambda u, p: float(np.max(np.abs(u))),
        }
        self.symmetry_generators = (self._quarter_turn(), self._reflection())

    @property
    def observables(self):
        return self._obs

    # ---- the model -------------------------------------------------------------------------------
    def energy(self, u, p):
        return float(0.5 * self._h2 * u @ (self.laplacian @ u) - 0.5 * self._h2 * p * np.dot(u, u)
                     + 0.25 * self._h2 * np.sum(u ** 4))

    def residual(self, u, p):
        return self._h2 * (self.laplacian @ u - p * u + u ** 3)

    def jacobian(self, u, p):
        return (self._h2 * (self.laplacian + sp.diags(3.0 * u ** 2 - p))).tocsr()

    def dresidual_dp(self, u, p):
        return -self._h2 * np.asarray(u, dtype=float)

    # ---- grid and symmetry -----------------------------------------------------------------------
    def _grid_index(self) -> np.ndarray:
        return np.arange(self.n * self.n).reshape(self.n, self.n)  # [l, i] -> l n + i

    def _quarter_turn(self) -> sp.csr_matrix:
        """``(g u)(x_i, y_l) = u(y_l, 1 - x_i)``: the grid turned by 90 degrees."""
        idx = self._grid_index()
        i, l = np.meshgrid(np.arange(self.n), np.arange(self.n))
        source = idx[self.n - 1 - i, l]  # node (x = y_l, y = 1 - x_i) is [l' = n-1-i, i' = l]
        return signed_permutation(source.ravel())

    def _reflection(self) -> sp.csr_matrix:
        """``(g u)(x_i, y_l) = u(1 - x_i, y_l)``."""
        idx = self._grid_index()
        return signed_permutation(idx[:, ::-1].ravel())

    # ---- closed forms ----------------------------------------------------------------------------
    def eigenvalue(self, j: int, k: int) -> float:
        """``lambda_jk`` of the discrete Dirichlet Laplacian (a branch point of the trivial branch)."""
        s = np.sin(np.pi * self.h / 2 * np.array([j, k], dtype=float)) ** 2
        return float(4.0 / self._h2 * s.sum())

    def mode(self, j: int, k: int) -> np.ndarray:
        """``phi_jk = 2 sin(j pi x) sin(k pi y)`` on the grid, with ``h^2 sum phi^2 = 1``."""
        x = self.h * np.arange(1, self.n + 1)
        return (2.0 * np.outer(np.sin(k * np.pi * x), np.sin(j * np.pi * x))).ravel()  # [l, i]

    def trivial_hessian_eigenvalues(self, p: float) -> np.ndarray:
        """All eigenvalues ``h^2 (lambda_jk - p)`` of the Hessian at ``u = 0``, sorted."""
        s = np.sin(np.pi * self.h / 2 * np.arange(1, self.n + 1)) ** 2
        lam = 4.0 / self._h2 * (s[:, None] + s[None, :])
        return np.sort(self._h2 * (lam.ravel() - p))

    def branch_points(self, p_max: float) -> list[tuple[float, int, tuple[int, int]]]:
        """Branch points of the trivial branch below ``p_max``: ``(p, multiplicity, (j, k) with j <= k)``."""
        points = []
        for j in range(1, self.n + 1):
            for k in range(j, self.n + 1):
                lam = self.eigenvalue(j, k)
                if lam < p_max:
                    points.append((lam, 1 if j == k else 2, (j, k)))
        return sorted(points)

    def quartic_coefficients(self, j: int = 1, k: int = 2) -> tuple[float, float]:
        """``(alpha, beta) = (h^2 sum phi_jk^4, h^2 sum phi_jk^2 phi_kj^2)``, the grid sums."""
        a, b = self.mode(j, k), self.mode(k, j)
        return float(self._h2 * np.sum(a ** 4)), float(self._h2 * np.sum(a ** 2 * b ** 2))

    def branch_amplitude(self, p: float, kind: str, j: int = 1, k: int = 2) -> float:
        """Leading-order ``||u||_h`` on the branch from ``lambda_jk``: ``kind`` ``"pure"`` or ``"mixed"``.

        For ``j == k`` only ``"pure"`` exists (the simple pitchfork).
        """
        alpha, beta = self.quartic_coefficients(j, k)
        lam = self.eigenvalue(j, k)
        if kind == "pure":
            return float(np.sqrt((p - lam) / alpha))
        if kind == "mixed" and j != k:
            return float(np.sqrt(2.0 * (p - lam) / (alpha + 3.0 * beta)))
        raise ValueError(f"D4Square.branch_amplitude: kind must be 'pure' or (for j != k) 'mixed', got {kind!r}")
