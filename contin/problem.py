"""The model interface of the engine: :class:`Problem`.

A problem is a parametrised nonlinear system ``f(u, p) = 0`` with ``u`` in R^n and a scalar
parameter ``p``.  For a conservative model ``f`` is the gradient of an energy and its Jacobian is
the (sparse, symmetric) Hessian; the engine then uses the energy for jumps and the Hessian's inertia
for stability.

Stability: the engine asks :meth:`Problem.stability` for the Morse index (and, on request, the
smallest eigenvalues) under every *stability label*.  A model declares its labelled operators in one
place, ``stability_operators={label: operator}`` (the first label is the primary one); an operator
that is the leading block of another one (e.g. the Hessian of a displacement-controlled structure
inside that of the force-controlled one) is declared as ``LeadingBlock(of=label, size=m)`` and then
shares that operator's factorization, so both Morse indices cost one pivot-free ``L D L^T`` (and,
where that cannot be trusted, the block's own count plus the sign of its Schur complement:
:func:`contin.numerics.stability.nested_inertias`).  A negative size counts from the end: ``size=-1`` is the
operator without its last row and column (a border whose size the model does not fix).
An operator that is a Hessian bordered by ``k`` equality constraints (a KKT matrix, e.g. a load
turned into a Lagrange multiplier by prescribing its conjugate displacement) is declared as
``Constrained(operator, k)``: its Morse index is that of the Hessian restricted to the constraints'
tangent space, the bordered matrix's count minus ``k`` (:class:`Constrained`).
Shorthands: ``stability_operator=op`` is ``{"stability": op}``, and ``symmetric=True`` alone uses
the Jacobian.

Two ways to build one:

* wrap plain callables: ``Problem(residual=f, jacobian=J, energy=E, symmetric=True)``;
* subclass and override the methods (models with structure do this, e.g. to supply a banded
  factorization or a stability operator that differs from the Jacobian).
"""

from __future__ import annotations

import math

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from .numerics.linalg import Factorization, factorize
from .numerics.stability import StabilityInfo, leading_inertias, nested_inertias, stability_info

__all__ = ["Problem", "NonFiniteError", "LeadingBlock", "Constrained"]

Array = np.ndarray


class NonFiniteError(FloatingPointError):
    """A model returned NaN or inf.  The engine treats it as a failed evaluation, never a result."""


@dataclass(frozen=True)
class LeadingBlock:
    """A stability operator that is the leading ``size`` x ``size`` block of label ``of``'s operator.

    Declared as a value of ``Problem(stability_operators=...)``.  Sylvester's law of inertia then
    counts both Morse indices from one factorization of the larger operator
    (:func:`contin.numerics.stability.nested_inertias`).  A negative ``size`` counts from the end, as a slice
    does: ``LeadingBlock("force", -1)`` is the force operator without its last row and column.
    """

    of: str
    size: int

    def rows(self, n: int) -> int:
        """The block's size inside an ``n`` x ``n`` operator."""
        return self.size if self.size >= 0 else n + self.size


@dataclass(frozen=True)
class Constrained:
    """A stability operator that is a Hessian bordered by ``constraints`` equality constraints.

    Declared as a value of ``Problem(stability_operators=...)``: ``operator(u, p)`` returns the
    bordered (KKT) matrix ``K = [[H, A], [A^T, D]]``, ``A`` the ``n x k`` constraint gradients.  The
    label's Morse index is that of ``H`` restricted to the tangent space ``A^T v = 0``, which is
    ``n_neg(K) - k``: for ``D = 0`` and ``A`` of full rank, ``K`` has the inertia of ``Z^T H Z``
    (``Z`` a basis of the tangent space) plus ``k`` positive and ``k`` negative eigenvalues (Gould
    1985; Maddocks 1987).  The same holds for a negative definite ``D`` (a multiplier that enters
    the energy concavely: ``K`` is then congruent to ``diag(D, H - A D^{-1} A^T)``, and ``-A D^{-1}
    A^T`` is the penalty whose limit is the constraint), so the count stays right as ``D -> 0^-``.
    A positive ``D`` is not such a saddle and is refused when the count is taken.

    Another label may be a :class:`LeadingBlock` of this one (e.g. the unconstrained Hessian ``H``
    itself): both are then counted from one factorization, as for any operator.  Exactly at a point
    where ``H`` is singular the count is decided by roundoff; it is kept at 0 or above.

    Only the Morse index is given: the eigenvalues of ``K`` are not those of the restricted Hessian,
    so :meth:`Problem.stability` reports none for this label whatever ``n_eigs`` asks.
    """

    operator: Callable[[Array, float], Any]
    constraints: int = 1

    def __post_init__(self) -> None:
        if not callable(self.operator):
            raise TypeError(f"Constrained: the operator must be callable (u, p) -> matrix, got {self.operator!r}")
        if int(self.constraints) != self.constraints or self.constraints < 1:
            raise ValueError(f"Constrained: the number of constraints must be a positive integer, "
                             f"got {self.constraints!r}")

    def __call__(self, u: Array, p: float) -> Any:
        K = self.operator(u, p)
        self.check(K)
        return K

    def check(self, K: Any) -> None:
        """Refuse a bordered matrix whose multiplier block ``D`` has a positive eigenvalue (see above)."""
        n, k = K.shape[0], int(self.constraints)
        if k >= n:
            raise ValueError(f"Constrained: a {n} x {n} operator cannot carry {k} constraints")
        D = (sp.csr_matrix(K)[n - k:, n - k:].toarray() if sp.issparse(K) else np.asarray(K)[n - k:, n - k:])
        if np.any(np.linalg.eigvalsh(0.5 * (D + D.T)) > 0.0):
            raise ValueError("Constrained: the multiplier block of the bordered operator has a positive eigenvalue; "
                             "its count minus the constraints is not the constrained Morse index (the load "
                             "enters the energy convexly, not as a multiplier)")

    def count(self, n_negative: int) -> int:
        """The constrained Morse index from the bordered operator's count (kept at 0 or above)."""
        return max(int(n_negative) - int(self.constraints), 0)


def _leading(H: Any, block: LeadingBlock) -> Any:
    """The leading block of a sparse or dense matrix (sparse stays CSR)."""
    m = block.rows(H.shape[0])
    return sp.csr_matrix(H)[:m, :m] if sp.issparse(H) else np.asarray(H)[:m, :m]


def _fd_step(x: float) -> float:
    return 1e-6 * (1.0 + abs(x))


class Problem:
    """A parametrised nonlinear system ``f(u, p) = 0`` as the continuation engine sees it.

    Parameters
    ----------
    residual : callable ``(u, p) -> ndarray``, optional
        The residual ``f`` (for a conservative model: the energy gradient).
    jacobian : callable ``(u, p) -> sparse or ndarray``, optional
        ``df/du``.  Without it a dense finite-difference Jacobian is used (small problems only).
    dresidual_dp : callable ``(u, p) -> ndarray``, optional
        ``df/dp``; central finite differences if omitted.
    energy : callable ``(u, p) -> float``, optional
        Energy whose gradient is ``residual``; required by :func:`contin.jump`.
    observables : mapping of name to callable ``(u, p) -> float``, optional
        Named scalar outputs recorded at every point and usable in events and bounds.
    observable_derivatives : mapping of name to callable ``(u, p) -> (ndarray, float)``, optional
        Exact derivatives ``(d obs/du, d obs/dp)`` of some observables.  An extremum event of such
        an observable then uses the exact derivative along the tangent instead of a finite
        difference, whose roundoff noise limits how precisely the extremum can be located.
    symmetric : bool
        The Jacobian is a symmetric Hessian; enables stability (inertia) analysis.
    stability_operator : callable ``(u, p) -> matrix``, optional
        Symmetric matrix whose negative eigenvalues count the unstable directions; defaults to the
        Jacobian when ``symmetric``.
    stability_operators : mapping of label to callable ``(u, p) -> matrix`` or :class:`LeadingBlock`
        Several stability notions at once (e.g. ``{"displacement": ..., "force": ...}`` for a
        structure that can be loaded either way); the first one is the primary label.  Overrides
        ``stability_operator``.  A :class:`LeadingBlock` value declares a label whose operator is the
        leading block of another label's, counted from the same factorization; a :class:`Constrained`
        value one whose operator is bordered by constraints (its count is the bordered matrix's minus
        their number).
    operator_families : sequence of :class:`contin.watch.modes.OperatorFamily`, optional
        Further symmetric operators, one per key (e.g. a wave number), whose definiteness the branch
        watches besides the problem's own: a change of a key's Morse index is a bifurcation into that
        mode, located and recorded (:mod:`contin.watch.modes`).  Also settable as the attribute
        ``operator_families``.
    symmetry_generators : sequence of matrices, optional
        Generators of the model's symmetry group: orthogonal ``n x n`` matrices ``g`` (sparse or dense)
        acting linearly on the state with ``E(g u, p) = E(u, p)``, so that ``g`` maps equilibria to
        equilibria.  At a multiple branch point the engine resolves the branches by it (the
        equivariant branching lemma, :mod:`contin.watch.branching`).  Also settable as the attribute
        ``symmetry_generators``.
    name, parameter_name : str
        Labels used in output.
    residual_scale : float, optional
        Typical size of the terms that cancel in the residual.  Convergence means
        ``max|f| <= tol * residual_scale``, so the tolerance is relative to the model's own units
        and stays above the roundoff floor when a discretization makes the terms large.  When not
        given, the first continuation run calibrates it from its start point
        (``||df/dp|| P``, see :meth:`contin.path.curve.Curve.calibrate`) and keeps it; until then it
        reads 1.  Every run (not only the first) sets the arclength weights its settings leave
        open from its own start.  Giving it declares the model's units its own: the weights the
        settings leave open are then 1.
    difference_scale : float, optional
        How far the state must move for the model's nonlinearity to show, in the units of the unknowns (the
        thickness of a thin structure whose unknowns are its coordinates).  Difference steps along a state direction
        (Koiter's coefficients) are taken as a fraction of it.  Default: ``1 + max|u|`` at the point, which is
        right where the unknowns are displacements and far too large where they are positions.  Also settable as
        the attribute.
    """

    def __init__(
        self,
        residual: Callable[[Array, float], Array] | None = None,
        jacobian: Callable[[Array, float], Any] | None = None,
        dresidual_dp: Callable[[Array, float], Array] | None = None,
        energy: Callable[[Array, float], float] | None = None,
        observables: Mapping[str, Callable[[Array, float], float]] | None = None,
        observable_derivatives: Mapping[str, Callable[[Array, float], tuple[Array, float]]] | None = None,
        symmetric: bool = False,
        stability_operator: Callable[[Array, float], Any] | None = None,
        stability_operators: Mapping[str, Callable[[Array, float], Any]] | None = None,
        name: str = "problem",
        parameter_name: str = "p",
        residual_scale: float | None = None,
        operator_families: Sequence[Any] = (),
        symmetry_generators: Sequence[Any] = (),
        difference_scale: float | None = None,
    ) -> None:
        if residual is None and energy is not None and type(self).residual is Problem.residual:
            raise TypeError("Problem(energy=...) needs the residual (the energy's gradient): the engine does not "
                            "differentiate energies numerically (O(n^2) energy calls per Jacobian, half the digits "
                            "lost per difference).  Declare element energies and use contin.EnergyProblem (exact "
                            "generated derivatives), or pass the exact gradient to contin.GradientProblem (sparse "
                            "finite-difference Hessian); see contin.modelkit.energy.")
        self.operator_families = tuple(operator_families)
        self.symmetry_generators = tuple(symmetry_generators)
        self._residual = residual
        self._jacobian = jacobian
        self._dresidual_dp = dresidual_dp
        self._energy = energy
        self._stability_operator = stability_operator
        self._stability_operators = dict(stability_operators or {})
        for label, op in self._stability_operators.items():
            if isinstance(op, LeadingBlock) and (op.of not in self._stability_operators
                                                 or isinstance(self._stability_operators[op.of], LeadingBlock)):
                raise ValueError(f"stability operator {label!r} is a LeadingBlock of {op.of!r}, which must be "
                                 f"a declared operator (one of {sorted(self._stability_operators)}), not a block")
        self._observables = dict(observables or {})
        self._observable_derivatives = dict(observable_derivatives or {})
        self.symmetric = bool(symmetric)
        self.name = name
        self.parameter_name = parameter_name
        self._residual_scale_value = None if residual_scale is None else float(residual_scale)
        self._residual_scale_calibrated = False
        if difference_scale is not None and not (math.isfinite(difference_scale) and difference_scale > 0.0):
            raise ValueError(f"Problem: difference_scale must be a finite length > 0, got {difference_scale!r}")
        self.difference_scale = None if difference_scale is None else float(difference_scale)

    # ---- residual scale ----------------------------------------------------------------------------
    @property
    def residual_scale(self) -> float:
        """The residual scale given (or calibrated, see :meth:`calibrate_residual_scale`); 1 before either."""
        scale = getattr(self, "_residual_scale_value", None)
        return 1.0 if scale is None else scale

    @residual_scale.setter
    def residual_scale(self, value: float | None) -> None:
        self._residual_scale_value = None if value is None else float(value)
        self._residual_scale_calibrated = False

    @property
    def gives_residual_scale(self) -> bool:
        """Whether the model chose its own units: a residual scale given (or a model's own property), not calibrated."""
        if type(self).residual_scale is not Problem.residual_scale or not hasattr(self, "_residual_scale_value"):
            return True  # a model's own property, or a subclass that never declared the scale open
        return self._residual_scale_value is not None and not getattr(self, "_residual_scale_calibrated", False)

    def calibrate_residual_scale(self, scale: float) -> None:
        """Adopt ``scale`` as the residual scale unless the model gave one (the first calibration stays).

        Kept on the problem, not per run, so that every part of the engine that reads
        ``residual_scale`` (fold location, jumps, later runs from other points) uses one tolerance.
        """
        if getattr(self, "_residual_scale_value", None) is None and type(self).residual_scale is Problem.residual_scale:
            self._residual_scale_value = float(scale)
            self._residual_scale_calibrated = True

    @property
    def reference_scales(self) -> tuple[float, float] | None:
        """State and parameter scales ``(U, P)`` the first calibrated run measured at its start (None before).

        Later runs from points where a scale cannot be measured (a branch point, ``u = 0`` or
        ``p = 0``) fall back on them (:func:`contin.path.scales.start_scales`).
        """
        return getattr(self, "_reference_scales", None)

    def adopt_reference_scales(self, U: float, P: float) -> None:
        """Keep ``(U, P)`` as :attr:`reference_scales` unless a run already set them (the first stays)."""
        if getattr(self, "_reference_scales", None) is None and math.isfinite(U) and math.isfinite(P):
            self._reference_scales = (float(U), float(P))

    # ---- the interface ---------------------------------------------------------------------------
    def residual(self, u: Array, p: float) -> Array:
        """Residual ``f(u, p)``."""
        if self._residual is None:
            raise NotImplementedError(f"{type(self).__name__} defines no residual")
        return np.asarray(self._residual(u, p), dtype=float)

    def jacobian(self, u: Array, p: float):
        """Jacobian ``df/du`` as a scipy.sparse matrix (or ndarray for small problems)."""
        if self._jacobian is not None:
            return self._jacobian(u, p)
        return self._fd_jacobian(u, p)

    def dresidual_dp(self, u: Array, p: float) -> Array:
        """Derivative of the residual with respect to the parameter."""
        if self._dresidual_dp is not None:
            return np.asarray(self._dresidual_dp(u, p), dtype=float)
        eps = _fd_step(p)
        return (self.residual(u, p + eps) - self.residual(u, p - eps)) / (2 * eps)

    @property
    def has_energy(self) -> bool:
        """Whether :meth:`energy` is available."""
        return self._energy is not None or type(self).energy is not Problem.energy

    def energy(self, u: Array, p: float) -> float:
        """Energy whose gradient is the residual."""
        if self._energy is None:
            raise NotImplementedError(f"{type(self).__name__} defines no energy")
        return float(self._energy(u, p))

    @property
    def observables(self) -> dict[str, Callable[[Array, float], float]]:
        """Named scalar functions of ``(u, p)``."""
        return self._observables

    @property
    def observable_derivatives(self) -> dict[str, Callable[[Array, float], tuple[Array, float]]]:
        """Exact derivatives ``(d obs/du, d obs/dp)`` of the observables that provide them."""
        return getattr(self, "_observable_derivatives", {})

    def stability_operator(self, u: Array, p: float):
        """Symmetric operator whose inertia decides stability (``None``: no stability analysis).

        With several labelled operators this is the primary (first) one.
        """
        if self._stability_operators:
            return self._labelled_operator(next(iter(self._stability_operators)), u, p)
        if self._stability_operator is not None:
            return self._stability_operator(u, p)
        if self.symmetric:
            return self.jacobian(u, p)
        return None

    def index_from_jacobian(self, n_negative: int) -> int | None:
        """The primary Morse index from the Jacobian's negative count ``n_negative``, or None.

        Known where the primary stability operator is the Jacobian itself (the default for a symmetric
        problem, or declared so) or the Jacobian bordered by constraints (:class:`Constrained`, whose count
        is ``n_negative`` minus the constraints); None for any other operator, whose count needs a
        factorization of its own (:meth:`stability`).  The engine uses it to take the index from the
        corrector's factorization.
        """
        cls = type(self)
        if cls.stability_operator is not Problem.stability_operator \
                or cls.stability_operators is not Problem.stability_operators:
            return None
        declared = getattr(self, "_stability_operators", {})
        if declared:
            op = next(iter(declared.values()))
            if isinstance(op, Constrained):
                return op.count(n_negative) if op.operator == self.jacobian else None
            return int(n_negative) if op == self.jacobian else None
        if self._stability_operator is None and self.symmetric:
            return int(n_negative)
        return None

    def stability_operators(self, u: Array, p: float) -> dict[str, Any]:
        """Stability operators by label; the first label is the primary one.

        The default is ``{"stability": stability_operator(u, p)}`` (empty when there is none).
        Override (or pass ``stability_operators=``) to label each point under several controls.
        """
        declared = getattr(self, "_stability_operators", {})
        if declared:
            full = {label: op(u, p) for label, op in declared.items() if not isinstance(op, LeadingBlock)}
            return {label: _leading(full[op.of], op) if isinstance(op, LeadingBlock) else full[label]
                    for label, op in declared.items()}
        op = self.stability_operator(u, p)
        return {} if op is None else {"stability": op}

    def _labelled_operator(self, label: str, u: Array, p: float) -> Any:
        op = self._stability_operators[label]
        if isinstance(op, LeadingBlock):
            return _leading(self._stability_operators[op.of](u, p), op)
        return op(u, p)

    def stability(self, u: Array, p: float, n_eigs: int = 0) -> dict[str, StabilityInfo]:
        """Morse index (and the ``n_eigs`` smallest eigenvalues) under every stability label.

        The one way the engine asks for stability.  With ``n_eigs = 0`` an operator declared as the
        :class:`LeadingBlock` of another is counted with it (:meth:`_nested_counts`); otherwise every
        operator is counted on its own.  A :class:`Constrained` operator's count is the bordered
        matrix's minus its constraints, without eigenvalues.  Empty when the problem has no operator.
        """
        declared = getattr(self, "_stability_operators", {})
        constrained = {label: op for label, op in declared.items() if isinstance(op, Constrained)}
        if n_eigs == 0:
            counts = self._nested_counts(u, p)
            if counts is not None:
                return {label: StabilityInfo(constrained[label].count(n) if label in constrained else int(n),
                                             np.zeros(0)) for label, n in counts.items()}
        # a bordered matrix's eigenvalues are not those of its restricted Hessian: its count only
        infos = {label: stability_info(op, 0 if label in constrained else n_eigs)
                 for label, op in self.stability_operators(u, p).items()}
        for label, op in constrained.items():
            if label in infos:  # a subclass may return other operators than the declared ones
                infos[label] = StabilityInfo(op.count(infos[label].n_negative), np.zeros(0))
        return infos

    def _nested_counts(self, u: Array, p: float) -> dict[str, int] | None:
        """Morse indices of operators declared as leading blocks of one other operator, with that operator's.

        One pivot-free ``L D L^T`` of the enclosing operator counts every block.  When it cannot be
        trusted and there is one block, :func:`contin.numerics.stability.nested_inertias` counts the block on
        its own and adds the sign of its Schur complement; with several blocks None (each operator is
        then counted on its own).  None as well when the operators are not one operator and its blocks.
        """
        declared = getattr(self, "_stability_operators", {})
        blocks = {label: op for label, op in declared.items() if isinstance(op, LeadingBlock)}
        roots = {op.of for op in blocks.values()}
        if len(roots) != 1 or len(blocks) + 1 != len(declared):
            return None
        root = roots.pop()
        H = declared[root](u, p)
        n = H.shape[0]
        if len(blocks) == 1 and 0 < next(iter(blocks.values())).rows(n) < n:
            (label, block), = blocks.items()
            n_block, n_root = nested_inertias(H, block.rows(n))
            counts = {label: n_block, root: n_root}
            return {name: counts[name] for name in declared}
        sizes = [blocks[label].rows(n) if label in blocks else n for label in declared]
        nested = leading_inertias(H, sizes)
        return None if nested is None else dict(zip(declared, nested))

    def max_step_fraction(self, u: Array, p: float, du: Array, dp: float) -> float:
        """Largest fraction ``t`` in (0, 1] of the step ``(du, dp)`` from ``(u, p)`` the model can take.

        Models whose residual is only defined on part of the space (a log barrier that is infinite
        at contact) return the fraction that keeps the whole segment ``(u, p) + s (du, dp)``,
        ``0 <= s <= t``, inside it, as incremental-potential contact filters its steps.  The engine
        shortens every Newton, predictor, fold-location and jump step to this fraction, so the
        model is never evaluated outside its domain.  The default is 1 (no restriction).
        """
        return 1.0

    def factorize(self, J) -> Factorization:
        """Factorize a Jacobian; override to exploit a model's structure."""
        return factorize(J)

    def jacobian_directional_derivative(self, u: Array, p: float, v: Array) -> Any:
        """``d/de J(u + e v, p)`` at ``e = 0`` (second derivative along ``v``), by forward differences.

        Used by the fold extended system, where it only sets Newton's convergence rate, not the
        located point; a forward difference (error ~1e-7) costs one Jacobian instead of two, since
        the fold Newton already holds ``J(u, p)``.  Models with exact second derivatives may
        override it.
        """
        scale = max(1.0, float(np.max(np.abs(u), initial=0.0)))
        vnorm = float(np.max(np.abs(v), initial=0.0))
        if vnorm == 0.0:
            return sp.csr_matrix((u.size, u.size))
        eps = 1e-7 * scale / vnorm
        J0 = self.checked_jacobian(u, p)  # first: a model that caches its last Jacobian has this one
        Jp = self.checked_jacobian(u + eps * v, p)
        return (Jp - J0) / eps

    def jacobian_dp(self, u: Array, p: float) -> Any:
        """``d/dp J(u, p)`` by forward differences (see :meth:`jacobian_directional_derivative`)."""
        eps = 1e-7 * (1.0 + abs(p))
        J0 = self.checked_jacobian(u, p)
        return (self.checked_jacobian(u, p + eps) - J0) / eps

    # ---- helpers used by the engine --------------------------------------------------------------
    def _fd_jacobian(self, u: Array, p: float):
        n = u.size
        f0 = self.residual(u, p)
        J = np.empty((f0.size, n))
        for j in range(n):
            h = _fd_step(u[j])
            e = np.zeros(n)
            e[j] = h
            J[:, j] = (self.residual(u + e, p) - self.residual(u - e, p)) / (2 * h)
        return J

    def evaluate_observables(self, u: Array, p: float) -> dict[str, float]:
        """All observables at ``(u, p)`` as floats."""
        return {name: float(fun(u, p)) for name, fun in self.observables.items()}

    def checked_residual(self, u: Array, p: float) -> Array:
        """Residual, raising :class:`NonFiniteError` instead of returning NaN or inf.

        Python's float arithmetic in a model's code raises ``OverflowError`` (``x ** 5`` past the
        largest float), ``ZeroDivisionError`` or ``ValueError`` (``math.sqrt`` of a negative number)
        where numpy would return inf or NaN; those are the same event, a state outside the range where
        the model is finite, and raise the same error.
        """
        try:
            with np.errstate(all="ignore"):
                r = self.residual(u, p)
        except (OverflowError, ZeroDivisionError, ValueError) as exc:
            raise NonFiniteError(f"residual of {self.name!r} is not finite at p = {p!r} ({exc})") from exc
        if not np.isfinite(r).all():
            raise NonFiniteError(f"residual of {self.name!r} is not finite at p = {p!r}")
        return r

    def checked_jacobian(self, u: Array, p: float):
        """Jacobian, raising :class:`NonFiniteError` on NaN or inf entries (or the errors of
        :meth:`checked_residual`)."""
        try:
            with np.errstate(all="ignore"):
                J = self.jacobian(u, p)
        except (OverflowError, ZeroDivisionError, ValueError) as exc:
            raise NonFiniteError(f"Jacobian of {self.name!r} is not finite at p = {p!r} ({exc})") from exc
        data = J.data if sp.issparse(J) else np.asarray(J)
        if not np.isfinite(data).all():
            raise NonFiniteError(f"Jacobian of {self.name!r} is not finite at p = {p!r}")
        return J

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r}, symmetric={self.symmetric})"
