"""Energy-first models: a structure declared by its element energies, assembled into a :class:`Problem`.

Writing a conservative model by hand means deriving its gradient, Hessian, sparse assembly, ``df/dp``
and the second derivatives fold location uses.  Here the user writes only element energies:

1. declare each element type in sympy (:class:`contin.modelkit.codegen.Element`: local dofs, per-element
   parameters, optionally the continuation parameter ``p``);
2. turn them into numpy kernels: :func:`contin.modelkit.codegen.generate_kernels` writes a module to commit
   (check it in a test with :func:`contin.modelkit.codegen.check_generated`), or
   :func:`contin.modelkit.codegen.compile_kernels` builds it in process for quick work;
3. assemble: :class:`EnergyProblem` takes the kernels and, per element type, the connectivity (local
   dof -> global dof) and the parameter values, and gives the exact energy, residual (gradient),
   sparse symmetric Hessian, ``df/dp``, ``d/dp J`` and directional derivative ``d/dt J(u + t v)``.

::

    import numpy as np, sympy as sp
    import contin
    from contin.modelkit.codegen import Element

    x1, y1, x2, y2, EA, L0, y, p = sp.symbols("x1 y1 x2 y2 EA L0 y p", real=True)
    L = sp.sqrt((x2 - x1) ** 2 + (y2 - y1) ** 2)
    bar = Element("bar", EA / (2 * L0) * (L - L0) ** 2, (x1, y1, x2, y2), (EA, L0))
    load = Element("load", p * y, (y,), parameter=p)          # dead load p pushing the apex down
    # global dofs: 0, 1 left support, 2, 3 right support (fixed), 4, 5 apex
    P = contin.EnergyProblem([bar, load], {"bar": ([[0, 1, 4, 5], [2, 3, 4, 5]], [1.0, np.hypot(1, 0.1)]),
                                           "load": [[5]]},
                             n_dofs=6, fixed={0: -1.0, 1: 0.0, 2: 1.0, 3: 0.0})
    branch = contin.continuation(P, [0.0, 0.1], 0.0)

Without generation, :class:`GradientProblem` takes an energy and its exact gradient and builds a
sparse finite-difference Hessian from the gradient, with columns grouped by a greedy colouring of
the sparsity pattern (given, or detected once).

``Problem(energy=E)`` without a residual is refused with an error pointing here: differentiating
an energy numerically twice costs ``O(n^2)`` energy evaluations per Jacobian and loses about half
the digits to each difference, too slow and too noisy for Newton's tolerance.
"""

from __future__ import annotations

import types
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..numerics.linalg import BANDED_FRACTION, DENSE_LIMIT, BandedLU, Factorization, FixedPattern, factorize
from ..problem import Problem

__all__ = ["EnergyProblem", "GradientProblem", "column_groups", "detect_pattern"]

Array = np.ndarray
_KINDS = ("energy", "gradient", "hessian", "gradient_dp", "hessian_dp", "hessian_directional")


def _kernel_module(kernels: Any) -> Any:
    """A generated module (or namespace) as is; a sequence of Elements compiled in process."""
    if hasattr(kernels, "ELEMENTS"):
        return kernels
    from .codegen import compile_kernels  # sympy only when the user asks for in-process generation

    return compile_kernels(list(kernels))


class _Block:
    """One element type's connectivity and parameters, with the index arrays of its scatter."""

    def __init__(self, name: str, spec: Mapping[str, Any], funcs: dict[str, Callable], conn: Any, params: Any,
                 free_of: Array) -> None:
        self.name, self.funcs = name, funcs
        ndof, npar = len(spec["dofs"]), len(spec["params"])
        conn = np.asarray(conn, dtype=np.int64)
        if conn.ndim != 2 or conn.shape[1] != ndof:
            raise ValueError(f"element {name!r}: connectivity must have shape (m, {ndof}), got {conn.shape}")
        if conn.size and (conn.min() < 0 or conn.max() >= free_of.size):
            raise ValueError(f"element {name!r}: connectivity refers to dofs outside 0..{free_of.size - 1}")
        m = conn.shape[0]
        q = np.asarray(params if params is not None else np.zeros(0), dtype=float)
        if q.ndim <= 1:  # the same parameters for every element
            q = np.broadcast_to(q.reshape(1, -1), (m, q.size))
        if q.shape != (m, npar):
            raise ValueError(f"element {name!r}: parameters must have shape ({m}, {npar}) or ({npar},), "
                             f"got {np.shape(params)}")
        self.m = m
        self.conn_t = np.ascontiguousarray(conn.T)  # (ndof, m): gathers x[conn_t] in kernel layout
        self.q = np.ascontiguousarray(q.T)
        local = free_of[self.conn_t]  # free index of each local dof, -1 where fixed
        # gradient: rows of the (ndof, m) kernel output that land on free dofs
        mask = local >= 0
        self.g_take, self.g_rows = np.flatnonzero(mask), local[mask]
        # Hessian: packed pair k of element e is entry k * m + e; an off-diagonal pair also lands on
        # its mirror (both when two local dofs share one global dof, which is then its second derivative)
        takes, rows, cols = [], [], []
        for k, (a, b) in enumerate(spec["pairs"]):
            I, J = local[a], local[b]
            e = np.flatnonzero((I >= 0) & (J >= 0))
            takes.append(k * m + e), rows.append(I[e]), cols.append(J[e])
            if a != b:
                takes.append(k * m + e), rows.append(J[e]), cols.append(I[e])
        self.h_take = np.concatenate(takes) if takes else np.zeros(0, np.int64)
        self.h_rows = np.concatenate(rows) if rows else np.zeros(0, np.int64)
        self.h_cols = np.concatenate(cols) if cols else np.zeros(0, np.int64)

    def call(self, kind: str, X: Array, p: float, V: Array | None = None) -> Array:
        xl = X[self.conn_t]
        if kind == "hessian_directional":
            return self.funcs[kind](xl, V[self.conn_t], self.q, p)
        return self.funcs[kind](xl, self.q, p)


class EnergyProblem(Problem):
    """A conservative model assembled from generated element kernels (see the module docstring).

    Parameters
    ----------
    kernels : module or sequence of :class:`contin.modelkit.codegen.Element`
        A generated kernel module (imported committed file, or :func:`contin.modelkit.codegen.compile_kernels`),
        or the elements themselves, then generated in process at construction (needs sympy).
    elements : mapping of element name to ``conn`` or ``(conn, params)``
        Per element type: ``conn`` an integer array ``(m, n_local)`` of global dof numbers, and
        ``params`` the per-element parameters ``(m, n_params)`` (or ``(n_params,)`` shared by all).
        Give ``conn`` as a list or an array: a tuple value is read as ``(conn, params)``.
    n_dofs : int
        Number of global dofs, fixed ones included.
    fixed : mapping of global dof to value, optional
        Prescribed dofs.  The unknowns ``u`` are the other dofs in increasing global order.
    observables, observable_derivatives, name, parameter_name, residual_scale
        As for :class:`Problem`; observables receive the free unknowns ``u`` (use :meth:`full_state`
        for global dofs).
    stability_operators : mapping, optional
        As for :class:`Problem`; by default the Hessian (``symmetric=True``).

    Notes
    -----
    The CSR pattern of the Hessian (diagonal included) and the index arrays that scatter the packed
    element Hessians into it are built once; an assembly is one kernel call per element type and one
    ``bincount``.  When the numbering gives a narrow band the Jacobian is factorized by
    :class:`contin.numerics.linalg.BandedLU` with the band known from the pattern (the rule of
    :func:`contin.numerics.linalg.factorize`, without rescanning the matrix).
    """

    def __init__(self, kernels: Any, elements: Mapping[str, Any], n_dofs: int,
                 fixed: Mapping[int, float] | None = None, *,
                 observables: Mapping[str, Callable[[Array, float], float]] | None = None,
                 observable_derivatives: Mapping[str, Callable[[Array, float], tuple[Array, float]]] | None = None,
                 stability_operators: Mapping[str, Any] | None = None, name: str = "energy_problem",
                 parameter_name: str = "p", residual_scale: float | None = None) -> None:
        super().__init__(observables=observables, observable_derivatives=observable_derivatives, symmetric=True,
                         stability_operators=stability_operators, name=name, parameter_name=parameter_name,
                         residual_scale=residual_scale)
        self.kernels = _kernel_module(kernels)
        specs = self.kernels.ELEMENTS
        unknown = set(elements) - set(specs)
        if unknown:
            raise ValueError(f"no kernels for elements {sorted(unknown)}; the kernels define {sorted(specs)}")
        fixed = {int(k): float(v) for k, v in (fixed or {}).items()}
        if any(not 0 <= k < n_dofs for k in fixed):
            raise ValueError(f"fixed dofs must lie in 0..{n_dofs - 1}")
        self.n_dofs = int(n_dofs)
        self.free = np.array(sorted(set(range(self.n_dofs)) - set(fixed)), dtype=np.int64)
        self.n = self.free.size
        free_of = np.full(self.n_dofs, -1, dtype=np.int64)
        free_of[self.free] = np.arange(self.n)
        self._x_fixed = np.zeros(self.n_dofs)
        self._x_fixed[list(fixed)] = list(fixed.values())
        self.blocks = []
        for el, value in elements.items():
            conn, params = value if isinstance(value, tuple) else (value, None)
            funcs = {kind: getattr(self.kernels, f"{el}_{kind}") for kind in _KINDS}
            self.blocks.append(_Block(el, specs[el], funcs, conn, params, free_of))
        self._build_pattern()

    def _build_pattern(self) -> None:
        n = self.n
        diag = np.arange(n, dtype=np.int64)
        rows = np.concatenate([b.h_rows for b in self.blocks] + [diag])
        cols = np.concatenate([b.h_cols for b in self.blocks] + [diag])
        keys, slot = np.unique(rows * n + cols, return_inverse=True)  # sorted: row-major, the CSR order
        self._slot = slot[:rows.size - n]  # the diagonal entries only shape the pattern
        self._nnz = keys.size
        self._csr_pattern = FixedPattern(keys % n, np.searchsorted(keys // n, np.arange(n + 1)).astype(np.int64), (n, n))
        self.bandwidth = int(np.max(np.abs(keys // n - keys % n), initial=0))
        self._banded = n > DENSE_LIMIT and 2 * self.bandwidth + 1 <= max(BANDED_FRACTION * n, 8)

    # ---- states ----------------------------------------------------------------------------------
    def full_state(self, u: Array) -> Array:
        """All ``n_dofs`` global dofs: the unknowns ``u`` and the fixed values."""
        X = self._x_fixed.copy()
        X[self.free] = u
        return X

    def _direction(self, v: Array) -> Array:
        V = np.zeros(self.n_dofs)
        V[self.free] = v  # fixed dofs do not move
        return V

    @property
    def pattern(self) -> sp.csr_matrix:
        """The sparsity pattern of the Hessian (ones), diagonal included."""
        return self._csr(np.ones(self._nnz))

    def _csr(self, data: Array) -> sp.csr_matrix:
        return self._csr_pattern.matrix(data)

    # ---- assembly --------------------------------------------------------------------------------
    def _vector(self, kind: str, u: Array, p: float) -> Array:
        X = self.full_state(np.asarray(u, dtype=float))
        out = np.zeros(self.n)
        for b in self.blocks:
            out += np.bincount(b.g_rows, weights=b.call(kind, X, p).ravel()[b.g_take], minlength=self.n)
        return out

    def _matrix(self, kind: str, u: Array, p: float, v: Array | None = None) -> sp.csr_matrix:
        X = self.full_state(np.asarray(u, dtype=float))
        V = None if v is None else self._direction(np.asarray(v, dtype=float))
        parts = [b.call(kind, X, p, V).ravel()[b.h_take] for b in self.blocks]
        data = np.bincount(self._slot, weights=np.concatenate(parts) if parts else None, minlength=self._nnz)
        return self._csr(data)

    def energy(self, u: Array, p: float) -> float:
        """Total energy: the sum of every element's energy."""
        X = self.full_state(np.asarray(u, dtype=float))
        return float(sum(np.sum(b.call("energy", X, p)) for b in self.blocks))

    def residual(self, u: Array, p: float) -> Array:
        """Gradient of the energy with respect to the unknowns."""
        return self._vector("gradient", u, p)

    def jacobian(self, u: Array, p: float) -> sp.csr_matrix:
        """Sparse symmetric Hessian with respect to the unknowns (fixed pattern, see :attr:`pattern`)."""
        return self._matrix("hessian", u, p)

    def dresidual_dp(self, u: Array, p: float) -> Array:
        """Exact ``d/dp`` of the gradient."""
        return self._vector("gradient_dp", u, p)

    def jacobian_dp(self, u: Array, p: float) -> sp.csr_matrix:
        """Exact ``d/dp`` of the Hessian."""
        return self._matrix("hessian_dp", u, p)

    def jacobian_directional_derivative(self, u: Array, p: float, v: Array) -> sp.csr_matrix:
        """Exact ``d/dt J(u + t v, p)`` at ``t = 0`` (third derivatives of the energy along ``v``)."""
        return self._matrix("hessian_directional", u, p, v)

    def factorize(self, J: Any) -> Factorization:
        """Banded LU with the band of the pattern when it is narrow, else :func:`contin.numerics.linalg.factorize`."""
        if self._banded and sp.issparse(J) and J.shape == (self.n, self.n):
            return BandedLU(J, self.bandwidth, self.bandwidth)
        return factorize(J)


# ---- finite-difference Hessians of an exact gradient ---------------------------------------------
def detect_pattern(gradient: Callable[[Array], Array], u: Array) -> sp.csr_matrix:
    """Sparsity pattern of the Jacobian of ``gradient`` by one forward difference per column.

    A gradient entry that does not depend on a dof is computed from identical inputs on both sides
    of the difference, so its difference is exactly zero; every other entry is kept.  The point is
    ``u`` moved by a fixed pseudo-random offset (seed 0, relative size 1e-3), so that an entry that
    happens to vanish at ``u`` (a symmetric state) is not mistaken for a structural zero.  Costs
    ``n + 1`` gradient calls, once.

    Parameters
    ----------
    gradient : callable ``u -> ndarray``
        The exact gradient at the parameter of interest.
    u : ndarray
        Where to probe.

    Returns
    -------
    scipy.sparse.csr_matrix
        Symmetrised boolean pattern, diagonal included.
    """
    u = np.asarray(u, dtype=float)
    n = u.size
    x = u + 1e-3 * (1.0 + np.abs(u)) * np.random.default_rng(0).uniform(-1.0, 1.0, n)
    g0 = np.asarray(gradient(x), dtype=float)
    rows, cols = [np.arange(n)], [np.arange(n)]
    for j in range(n):
        e = x.copy()
        e[j] += 1e-6 * (1.0 + abs(x[j]))
        i = np.flatnonzero(np.asarray(gradient(e), dtype=float) != g0)
        rows.append(i), cols.append(np.full(i.size, j))
    r, c = np.concatenate(rows), np.concatenate(cols)
    P = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(n, n))
    return (P + P.T).astype(bool).tocsr()


def column_groups(pattern: Any) -> list[Array]:
    """Groups of structurally orthogonal columns (no two share a nonzero row), by greedy colouring.

    Columns in one group can be differenced together: one gradient difference along the sum of
    their unit vectors gives each of their columns exactly, since their nonzeros never overlap.
    Columns are coloured in order of decreasing conflict degree (Welsh-Powell), each with the
    smallest colour none of its conflicts has.  A banded matrix of half-bandwidth ``w`` needs
    ``2 w + 1`` groups whatever its size.

    Parameters
    ----------
    pattern : sparse matrix or ndarray
        Nonzero pattern of the Jacobian.

    Returns
    -------
    list of ndarray
        The column indices of each group, in increasing colour.
    """
    P = sp.csr_matrix(pattern, dtype=bool).astype(np.int8)
    C = (P.T @ P).tocsr()  # columns j, k conflict when some row has both
    n = C.shape[0]
    colour = np.full(n, -1, dtype=np.int64)
    for j in np.argsort(-np.diff(C.indptr), kind="stable"):
        used = colour[C.indices[C.indptr[j]:C.indptr[j + 1]]]
        taken = np.zeros(used.size + 1, dtype=bool)
        taken[used[(used >= 0) & (used <= used.size)]] = True
        colour[j] = int(np.argmin(taken))  # smallest free colour (there is one among used.size + 1)
    return [np.flatnonzero(colour == c) for c in range(int(colour.max(initial=-1)) + 1)]


class GradientProblem(Problem):
    """A conservative model from an energy and its exact gradient; sparse FD Hessian by column colouring.

    For quick work without code generation.  The Hessian is the central difference of the gradient
    along one direction per column group (:func:`column_groups`), so it costs ``2 x groups``
    gradient calls (a banded model: a constant, independent of ``n``) and is accurate to about
    ``1e-9`` relative; it is symmetrised.  :class:`EnergyProblem` is exact and faster.

    Parameters
    ----------
    energy : callable ``(u, p) -> float``
        The energy.
    gradient : callable ``(u, p) -> ndarray``
        Its exact gradient (the residual).
    pattern : sparse matrix or ndarray, optional
        Sparsity pattern of the Hessian; detected at the first Jacobian by :func:`detect_pattern`
        (``n + 1`` gradient calls, once) when omitted.
    dgradient_dp : callable ``(u, p) -> ndarray``, optional
        Exact ``d/dp`` of the gradient; central differences otherwise.
    observables, observable_derivatives, name, parameter_name, residual_scale
        As for :class:`Problem`.

    Attributes
    ----------
    gradient_calls : int
        Number of gradient evaluations so far (residuals and Hessian differences).
    """

    def __init__(self, energy: Callable[[Array, float], float], gradient: Callable[[Array, float], Array],
                 pattern: Any = None, *, dgradient_dp: Callable[[Array, float], Array] | None = None,
                 observables: Mapping[str, Callable[[Array, float], float]] | None = None,
                 observable_derivatives: Mapping[str, Callable[[Array, float], tuple[Array, float]]] | None = None,
                 name: str = "gradient_problem", parameter_name: str = "p", residual_scale: float | None = None) -> None:
        super().__init__(energy=energy, dresidual_dp=dgradient_dp, observables=observables,
                         observable_derivatives=observable_derivatives, symmetric=True, name=name,
                         parameter_name=parameter_name, residual_scale=residual_scale)
        self._gradient = gradient
        self.gradient_calls = 0
        self._groups: list[Array] | None = None
        if pattern is not None:
            self._set_pattern(pattern)

    def _set_pattern(self, pattern: Any) -> None:
        P = sp.csr_matrix(pattern, dtype=bool)
        P = (P + P.T + sp.identity(P.shape[0], dtype=bool, format="csr")).astype(bool).tocsr()
        P.sort_indices()
        self._pattern = P
        self._groups = column_groups(P)
        self._rows = np.repeat(np.arange(P.shape[0]), np.diff(P.indptr))
        self._cols = P.indices.astype(np.int64)
        colour = np.empty(P.shape[0], dtype=np.int64)
        for c, g in enumerate(self._groups):
            colour[g] = c
        self._entry_colour = colour[self._cols]

    @property
    def groups(self) -> list[Array] | None:
        """Column groups of the FD Hessian (``None`` until the pattern is known)."""
        return self._groups

    def residual(self, u: Array, p: float) -> Array:
        """The user's gradient."""
        self.gradient_calls += 1
        return np.asarray(self._gradient(u, p), dtype=float)

    def jacobian(self, u: Array, p: float) -> sp.csr_matrix:
        """Sparse symmetric Hessian by central differences of the gradient, one pair per column group."""
        u = np.asarray(u, dtype=float)
        if self._groups is None:
            self._set_pattern(detect_pattern(lambda x: self.residual(x, p), u))
        h = 6e-6 * (1.0 + np.abs(u))  # ~ eps^(1/3): balances truncation and roundoff of a central difference
        data = np.empty(self._cols.size)
        for c, cols in enumerate(self._groups):
            d = np.zeros(u.size)
            d[cols] = h[cols]
            diff = self.residual(u + d, p) - self.residual(u - d, p)
            e = np.flatnonzero(self._entry_colour == c)
            data[e] = diff[self._rows[e]] / (2.0 * h[self._cols[e]])
        J = sp.csr_matrix((data, self._pattern.indices.copy(), self._pattern.indptr.copy()), shape=self._pattern.shape)
        return (0.5 * (J + J.T)).tocsr()
