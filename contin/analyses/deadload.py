"""Force control of any displacement-controlled conservative problem: a dead load on its parameter.

A displacement-controlled problem prescribes a generalized displacement ``p`` (a pole's travel, an
indenter's position) and has an energy ``E(u, p)``; the force conjugate to ``p`` is ``dE/dp``.
Loading the same structure by a dead force ``F`` instead makes ``p`` an unknown and adds the load's
potential ``-F p``::

    U = [u, p],    E_F(U, F) = E(u, p) - F p,
    residual  [f(u, p); dE/dp(u, p) - F],
    Jacobian  [[J, f_p], [f_p^T, d2E/dp2]]     (f = dE/du, f_p = df/dp = d2E/du dp).

So the force-controlled problem is the displacement-controlled one bordered by one row and column,
whatever the model: :class:`DeadLoad` builds it from the displacement problem's own residual,
Jacobian, ``dresidual_dp`` and two further derivatives it declares (:class:`ConjugateForce`).  The
construction is generic (the engine's :class:`~contin.Problem` interface and nothing of a model),
so it lives beside the other problem constructions of the engine (:mod:`contin.analyses.twopar`).

Stability under the dead load is the inertia of the bordered Jacobian (the load is linear in ``p``,
so the Jacobian is the Hessian); under the displacement control it is the inertia of the leading
block, declared as such (:class:`contin.problem.LeadingBlock`), so the engine counts both from one
factorization (:func:`contin.numerics.stability.nested_inertias`).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from ..numerics.linalg import Factorization, FixedPattern, factorize
from ..problem import LeadingBlock, Problem

__all__ = ["ConjugateForce", "DeadLoad", "bordered_matrix"]


@runtime_checkable
class ConjugateForce(Protocol):
    """What a displacement-controlled problem declares so that :class:`DeadLoad` can load it by a force."""

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        """``dE/dp`` at fixed ``u``: the force the prescribed displacement ``p`` takes."""

    def conjugate_stiffness(self, u: np.ndarray, p: float) -> float:
        """``d2E/dp2`` at fixed ``u``."""


def bordered_matrix(A: Any, col: np.ndarray, d: float) -> sp.csr_matrix:
    """``[[A, col], [col^T, d]]`` as canonical CSR, built in O(nnz) (only the nonzeros of ``col`` are stored).

    Where ``A`` is a matrix of a fixed pattern (:class:`contin.numerics.linalg.FixedPattern`: read-only index
    arrays), the bordered pattern and the places of ``A``'s values in it are kept for the next call
    with the same pattern and the same nonzeros of ``col``: the matrix is then filled, not built.
    """
    A = A if isinstance(A, sp.csr_matrix) else sp.csr_matrix(A)
    if not A.has_canonical_format:
        A = A.copy()
        A.sum_duplicates()
    col = np.asarray(col, dtype=float)
    nz = np.flatnonzero(col)
    layout = _border_layout(A, nz)
    data = np.empty(layout.pattern.nnz)
    data[layout.inner] = A.data
    data[layout.border] = col[nz]
    data[layout.row] = col[nz]
    data[-1] = d
    return layout.pattern.matrix(data)


class _BorderLayout:
    """The pattern of ``[[A, col], [col^T, d]]`` and where ``A``'s values and the border go in its values."""

    def __init__(self, A: sp.csr_matrix, nz: np.ndarray) -> None:
        m = A.shape[0]
        shift = np.zeros(m + 1, dtype=np.int64)
        shift[nz + 1] = 1
        shift = np.cumsum(shift)  # bordered rows above each row: each ends with its column-m entry
        indptr = np.append(A.indptr + shift, A.nnz + 2 * nz.size + 1)
        self.inner = np.arange(A.nnz) + np.repeat(shift[:-1], np.diff(A.indptr))
        self.border = indptr[nz + 1] - 1
        self.row = np.arange(A.nnz + nz.size, A.nnz + 2 * nz.size)
        indices = np.empty(A.nnz + 2 * nz.size + 1, dtype=np.int32)
        indices[self.inner], indices[self.border] = A.indices, m
        indices[self.row], indices[-1] = nz, m
        self.pattern = FixedPattern(indices, indptr, (m + 1, m + 1))


#: The bordered layouts of the last few fixed patterns and border nonzeros (by the identity of the
#: patterns' read-only index arrays, which cannot change).
_LAYOUTS: list[tuple[np.ndarray, np.ndarray, np.ndarray, _BorderLayout]] = []


def _border_layout(A: sp.csr_matrix, nz: np.ndarray) -> _BorderLayout:
    fixed = not (A.indices.flags.writeable or A.indptr.flags.writeable)
    if fixed:
        for k, (indices, indptr, columns, layout) in enumerate(_LAYOUTS):
            if indices is A.indices and indptr is A.indptr and np.array_equal(columns, nz):
                _LAYOUTS.insert(0, _LAYOUTS.pop(k))
                return layout
    layout = _BorderLayout(A, nz)
    if fixed:
        _LAYOUTS.insert(0, (A.indices, A.indptr, nz, layout))
        del _LAYOUTS[16:]
    return layout


class DeadLoad(Problem):
    """The problem ``base`` loaded by a dead force on its parameter instead of a prescribed displacement.

    Parameters
    ----------
    base : Problem
        A conservative, displacement-controlled problem (symmetric Jacobian = Hessian, an energy)
        implementing :class:`ConjugateForce`.  Its stability under the prescribed displacement is
        counted on its Jacobian (the Hessian on its unknowns), the leading block of this problem's.
    force : str
        Name of the load, the new parameter (``parameter_name``); default ``"F"``.
    scaled : mapping of name to (str, float), optional
        Observables that are fixed multiples of the load or of the displacement:
        ``{"F_norm": ("F", c)}`` is ``c F``; ``{"w_over_R": ("w", 1 / R)}`` is ``p / R`` with ``"w"``
        the base's ``parameter_name``.  They get exact derivatives.
    labels : (str, str)
        Stability labels of the dead load (primary) and of the base's displacement control.
    factorize : callable, optional
        Factorization of the bordered Jacobian that exploits the model's structure (default: the
        engine's generic one).
    residual_scale : float, optional
        Default: the base's.

    Notes
    -----
    Unknowns ``U = [u, p]``; :meth:`split` and :meth:`join` map between them.  Observables: the
    base's, in its order, evaluated at ``(u, p)``, except that the base's parameter is ``U[-1]``, the
    load is the parameter and ``scaled`` are computed from either; their derivatives are exact.  An
    equilibrium ``(U, F)`` of this problem is one of the base at ``p = U[-1]`` whose conjugate force
    equals ``F``: :meth:`from_displacement_state` maps a base state to it.
    """

    def __init__(self, base: Problem, force: str = "F", scaled: Mapping[str, tuple[str, float]] | None = None,
                 labels: tuple[str, str] = ("force", "displacement"),
                 factorize: Callable[[Any], Factorization] | None = None,
                 residual_scale: float | None = None) -> None:
        if not isinstance(base, ConjugateForce):
            raise TypeError(f"DeadLoad: {type(base).__name__} declares no conjugate_force / conjugate_stiffness")
        self.base = base
        self.force_name = force
        self.displacement_name = base.parameter_name
        self.labels = tuple(labels)
        self._factorize_bordered = factorize
        scaled = dict(scaled or {})
        own: dict[str, Callable[[np.ndarray, float], float]] = {force: lambda U, p: float(p),
                                                                self.displacement_name: lambda U, p: float(U[-1])}
        derivatives: dict[str, Callable[[np.ndarray, float], tuple[np.ndarray, float]]] = {
            force: lambda U, p: (np.zeros(np.size(U)), 1.0), self.displacement_name: lambda U, p: (_last(U, 1.0), 0.0)}
        for name, (of, factor) in scaled.items():
            if of not in own:
                raise ValueError(f"DeadLoad: scaled observable {name!r} must scale {force!r} or "
                                 f"{self.displacement_name!r}, not {of!r}")
            own[name] = _scaled_observable(own[of], factor)
            derivatives[name] = _scaled_derivative(derivatives[of], factor)
        observables = {name: own.get(name) or self._base_observable(name) for name in base.observables}
        observables.update({name: fun for name, fun in own.items() if name not in observables})
        # the base's Hessian is the bordered Jacobian without its border (the last row and column)
        ops = {labels[0]: self.jacobian, labels[1]: LeadingBlock(labels[0], -1)}
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         stability_operators=ops, name=f"{base.name}_dead_load", parameter_name=force,
                         residual_scale=base.residual_scale if residual_scale is None else residual_scale)

    # ---- state maps ------------------------------------------------------------------------------
    def split(self, U: np.ndarray) -> tuple[np.ndarray, float]:
        """``(u, p)``: the base's unknowns and its displacement."""
        U = np.asarray(U, dtype=float)
        return U[:-1], float(U[-1])

    @staticmethod
    def join(u: np.ndarray, p: float) -> np.ndarray:
        """``U = [u, p]``."""
        return np.append(np.asarray(u, dtype=float), float(p))

    def from_displacement_state(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        """``(U, F)`` of a base state: ``U = [u, p]`` and ``F`` its conjugate force (an equilibrium of both)."""
        return self.join(u, p), float(self.base.conjugate_force(np.asarray(u, dtype=float), float(p)))

    def _base_observable(self, name: str) -> Callable[[np.ndarray, float], float]:
        fun = self.base.observables[name]
        return lambda U, F: float(fun(U[:-1], float(U[-1])))

    # ---- the Problem interface -------------------------------------------------------------------
    def energy(self, U: np.ndarray, F: float) -> float:
        u, p = self.split(U)
        return self.base.energy(u, p) - float(F) * p

    def residual(self, U: np.ndarray, F: float) -> np.ndarray:
        u, p = self.split(U)
        return np.append(self.base.residual(u, p), self.base.conjugate_force(u, p) - float(F))

    def jacobian(self, U: np.ndarray, F: float) -> sp.csr_matrix:
        u, p = self.split(U)
        return bordered_matrix(self.base.jacobian(u, p), self.base.dresidual_dp(u, p),
                               float(self.base.conjugate_stiffness(u, p)))

    def dresidual_dp(self, U: np.ndarray, F: float) -> np.ndarray:
        return _last(U, -1.0)

    def jacobian_dp(self, U: np.ndarray, F: float) -> sp.csr_matrix:
        """Exactly zero: the dead load enters the residual linearly."""
        n = np.size(U)
        return sp.csr_matrix((n, n))

    def factorize(self, J: Any) -> Factorization:
        return factorize(J) if self._factorize_bordered is None else self._factorize_bordered(J)

    def max_step_fraction(self, U: np.ndarray, F: float, dU: np.ndarray, dF: float) -> float:
        """The base's domain filter along the step of its unknowns and its displacement."""
        u, p = self.split(U)
        dU = np.asarray(dU, dtype=float)
        return self.base.max_step_fraction(u, p, dU[:-1], float(dU[-1]))


def _last(U: np.ndarray, value: float) -> np.ndarray:
    e = np.zeros(np.size(U))
    e[-1] = value
    return e


def _scaled_observable(fun: Callable[[np.ndarray, float], float], factor: float) -> Callable[[np.ndarray, float], float]:
    return lambda U, p: factor * fun(U, p)


def _scaled_derivative(fun: Callable[[np.ndarray, float], tuple[np.ndarray, float]],
                       factor: float) -> Callable[[np.ndarray, float], tuple[np.ndarray, float]]:
    def derivative(U: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        du, dp = fun(U, p)
        return factor * du, factor * dp
    return derivative

