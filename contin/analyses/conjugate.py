"""Displacement control of any force-controlled conservative problem: its load as a Lagrange multiplier.

The inverse of :class:`contin.analyses.deadload.DeadLoad`.  A force-controlled problem has an energy
``E(u, p)`` whose parameter ``p`` is a load (a dead force, a pressure); ``c = dE/dp`` is what the
load works on, with the sign of its potential: a load whose potential is ``-p q(u)`` has
``c = -q``, one whose potential is ``+p (V(u) - V0)`` has ``c = V - V0``.  Prescribing the work-
conjugate displacement ``q = -c`` instead of the load (an indenter's travel instead of its force,
the volume of fluid pumped out instead of the pressure) makes ``p`` an unknown, the Lagrange
multiplier of the constraint ``-c(u, p) = q``::

    U = [u, p],    L(U, q) = E(u, p) + p q          (stationary; a saddle in p),
    residual  [f(u, p); c(u, p) + q],
    Jacobian  [[J, f_p], [f_p^T, dc/dp]]              (f = dE/du, f_p = df/dp = dc/du).

For a load that enters the energy linearly (``E = E_0(u) + p c(u)``) ``dc/dp = 0`` and the
Jacobian is a KKT matrix.  The construction uses only the base's residual, Jacobian,
``dresidual_dp`` and ``conjugate_force`` (and ``conjugate_stiffness`` for a load that does not enter
linearly: :class:`LoadConjugate`), so it lives in the engine beside :mod:`contin.analyses.deadload`.

Why the sign ``q = -c``: the parameter then grows as the load does positive work, as the
displacement of a dead load does; :class:`ConjugateControl` of a ``DeadLoad`` is the original
displacement-controlled problem again (the test suite checks the round trip).

Stability.  Under the prescribed displacement the state is stable when the Hessian of ``E`` in
``u`` is positive on the tangent space of the constraint ``c(u) = -q``: the bordered Jacobian's
negative count minus one (:class:`contin.problem.Constrained`).  Under the load itself (force
control) it is the count of ``J``, the leading block (:class:`contin.problem.LeadingBlock`); one
factorization gives both (:func:`contin.numerics.stability.nested_inertias`).  Past a limit point of the
load the load-controlled state is unstable (``J`` has a negative eigenvalue) while the
displacement-controlled one can stay stable: that is why experiments that prescribe the
displacement pass through the snap of the load-controlled problem.

Scaling.  The arclength metric weighs every unknown alike (:class:`contin.Settings`
``state_weight``), but the multiplier is a load, not a displacement.  ``multiplier_unit`` stores it
as ``p / multiplier_unit`` so that it enters the metric in the state's units; the energy, the
residual and the observables are the same functions of the physical load whatever the unit.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp

from ..numerics.linalg import Factorization, factorize
from ..problem import Constrained, LeadingBlock, Problem
from .deadload import _last, _scaled_derivative, _scaled_observable, bordered_matrix

__all__ = ["ConjugateControl", "LoadConjugate"]


@runtime_checkable
class LoadConjugate(Protocol):
    """What a force-controlled problem declares so that :class:`ConjugateControl` can prescribe its conjugate.

    A load that does not enter the energy linearly also declares ``conjugate_stiffness(u, p)``,
    ``d2E/dp2`` at fixed ``u`` (as :class:`contin.analyses.deadload.ConjugateForce` does); it must be
    ``<= 0`` (the multiplier a maximum of the energy, :class:`contin.problem.Constrained`).
    """

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        """``dE/dp`` at fixed ``u``: minus the displacement the load ``p`` works on."""


class ConjugateControl(Problem):
    """The problem ``base`` with its load's work-conjugate displacement prescribed instead of the load.

    Parameters
    ----------
    base : Problem
        A conservative, force-controlled problem (symmetric Jacobian = Hessian, an energy) whose
        parameter is the load, implementing :class:`LoadConjugate`.
    displacement : str
        Name of the prescribed displacement ``q = -dE/dp``, the new parameter (``parameter_name``).
    scaled : mapping of name to (str, float), optional
        Observables that are fixed multiples of the load or of the displacement:
        ``{"q_norm": ("q", 1 / q0)}`` is ``q / q0``, ``{"p_norm": ("p", 1 / p0)}`` is ``p / p0`` with
        ``"p"`` the base's ``parameter_name``.  They get exact derivatives.
    labels : (str, str)
        Stability labels of the prescribed displacement (primary: the constrained count) and of the
        base's load control (the count of its Jacobian).
    linear : bool
        The load enters the energy linearly, ``d2E/dp2 = 0``; then the base need not declare
        ``conjugate_stiffness``.  Without it the base must (else TypeError).
    multiplier_unit : float
        The multiplier is stored as ``p / multiplier_unit`` (module docstring, "Scaling"); choose the
        load that moves the state by about its own scale.  Default 1.
    factorize : callable, optional
        Factorization of the bordered Jacobian that exploits the model's structure (default: the
        engine's generic one, which sees a dense border).
    residual_scale : float, optional
        Default: the base's.

    Notes
    -----
    Unknowns ``U = [u, p / multiplier_unit]``; :meth:`split` and :meth:`join` map between them and
    ``(u, p)``.  Observables: the base's, in its order, evaluated at ``(u, p)`` with the base's exact
    derivatives (where it gives them) carried over; then the load (the base's ``parameter_name``:
    the multiplier), the displacement (the parameter) and ``scaled``.  An equilibrium ``(U, q)`` of
    this problem is one of the base at ``p`` with ``-dE/dp = q``: :meth:`from_load_state` maps a base
    state to it.  Energy: the Lagrangian ``E(u, p) + p q``, which on the constraint is ``E(u, p) - p
    c``, the energy at the prescribed displacement (a saddle in ``p``: a descent such as
    :func:`contin.jump` does not apply to it).
    """

    def __init__(self, base: Problem, displacement: str = "q", scaled: Mapping[str, tuple[str, float]] | None = None,
                 labels: tuple[str, str] = ("displacement", "force"), linear: bool = False,
                 multiplier_unit: float = 1.0, factorize: Callable[[Any], Factorization] | None = None,
                 residual_scale: float | None = None) -> None:
        if not isinstance(base, LoadConjugate):
            raise TypeError(f"ConjugateControl: {type(base).__name__} declares no conjugate_force")
        stiffness = getattr(base, "conjugate_stiffness", None)
        if not linear and not callable(stiffness):
            raise TypeError(f"ConjugateControl: {type(base).__name__} declares no conjugate_stiffness; pass "
                            "linear=True if its load enters the energy linearly (d2E/dp2 = 0)")
        if not (np.isfinite(multiplier_unit) and multiplier_unit > 0):
            raise ValueError(f"ConjugateControl: multiplier_unit must be positive and finite, got {multiplier_unit!r}")
        if len(labels) != 2 or labels[0] == labels[1]:
            raise ValueError(f"ConjugateControl: two distinct stability labels needed, got {labels!r}")
        self.base = base
        self.displacement_name = displacement
        self.load_name = base.parameter_name
        if displacement == self.load_name:
            raise ValueError(f"ConjugateControl: the displacement needs a name other than the load's {displacement!r}")
        self.labels = tuple(labels)
        self.linear = bool(linear)
        self.unit = float(multiplier_unit)
        self._factorize_bordered = factorize

        own: dict[str, Callable[[np.ndarray, float], float]] = {
            self.load_name: lambda U, q: self.unit * float(U[-1]), displacement: lambda U, q: float(q)}
        derivatives: dict[str, Callable[[np.ndarray, float], tuple[np.ndarray, float]]] = {
            self.load_name: lambda U, q: (_last(U, self.unit), 0.0),
            displacement: lambda U, q: (np.zeros(np.size(U)), 1.0)}
        for name, (of, factor) in dict(scaled or {}).items():
            if of not in own:
                raise ValueError(f"ConjugateControl: scaled observable {name!r} must scale {self.load_name!r} or "
                                 f"{displacement!r}, not {of!r}")
            own[name] = _scaled_observable(own[of], factor)
            derivatives[name] = _scaled_derivative(derivatives[of], factor)
        observables = {name: own.get(name) or self._base_observable(name) for name in base.observables}
        observables.update({name: fun for name, fun in own.items() if name not in observables})
        # the base's exact observable derivatives, in (u, p), become ones in U (times the unit for p)
        for name, fun in base.observable_derivatives.items():
            if name not in own and name in observables:
                derivatives[name] = self._base_derivative(fun)
        # primary: the Hessian restricted to the constraint's tangent (the KKT count minus one);
        # the base's load control: the bordered Jacobian without its border
        ops = {labels[0]: Constrained(self.jacobian, 1), labels[1]: LeadingBlock(labels[0], -1)}
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         stability_operators=ops, name=f"{base.name}_conjugate_control", parameter_name=displacement,
                         residual_scale=base.residual_scale if residual_scale is None else residual_scale)

    # ---- state maps ------------------------------------------------------------------------------
    def split(self, U: np.ndarray) -> tuple[np.ndarray, float]:
        """``(u, p)``: the base's unknowns and its load (the multiplier, in the load's own units)."""
        U = np.asarray(U, dtype=float)
        return U[:-1], self.unit * float(U[-1])

    def join(self, u: np.ndarray, p: float) -> np.ndarray:
        """``U = [u, p / multiplier_unit]``."""
        return np.append(np.asarray(u, dtype=float), float(p) / self.unit)

    def from_load_state(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        """``(U, q)`` of a base state: ``U = join(u, p)`` and ``q = -dE/dp`` (an equilibrium of both)."""
        return self.join(u, p), -float(self.base.conjugate_force(np.asarray(u, dtype=float), float(p)))

    def _base_observable(self, name: str) -> Callable[[np.ndarray, float], float]:
        fun = self.base.observables[name]

        def observable(U: np.ndarray, q: float) -> float:
            u, p = self.split(U)
            return float(fun(u, p))
        return observable

    def _base_derivative(self, fun: Callable[[np.ndarray, float], tuple[np.ndarray, float]]
                         ) -> Callable[[np.ndarray, float], tuple[np.ndarray, float]]:
        def derivative(U: np.ndarray, q: float) -> tuple[np.ndarray, float]:
            u, p = self.split(U)
            du, dp = fun(u, p)
            return np.append(np.asarray(du, dtype=float), self.unit * float(dp)), 0.0
        return derivative

    def _load_stiffness(self, u: np.ndarray, p: float) -> float:
        """``d2E/dp2``: zero for a linear load, else the base's ``conjugate_stiffness``."""
        return 0.0 if self.linear else float(self.base.conjugate_stiffness(u, p))

    # ---- the Problem interface -------------------------------------------------------------------
    def energy(self, U: np.ndarray, q: float) -> float:
        """The Lagrangian ``E(u, p) + p q`` (see the class Notes)."""
        u, p = self.split(U)
        return self.base.energy(u, p) + p * float(q)

    def residual(self, U: np.ndarray, q: float) -> np.ndarray:
        # the gradient of the Lagrangian in U: d/d(p / unit) = unit * d/dp keeps the Jacobian symmetric
        u, p = self.split(U)
        return np.append(self.base.residual(u, p), self.unit * (self.base.conjugate_force(u, p) + float(q)))

    def jacobian(self, U: np.ndarray, q: float) -> sp.csr_matrix:
        u, p = self.split(U)
        s = self.unit
        return bordered_matrix(self.base.jacobian(u, p), s * self.base.dresidual_dp(u, p),
                               s * s * self._load_stiffness(u, p))

    def dresidual_dp(self, U: np.ndarray, q: float) -> np.ndarray:
        return _last(U, self.unit)

    def jacobian_dp(self, U: np.ndarray, q: float) -> sp.csr_matrix:
        """Exactly zero: the prescribed displacement enters the residual linearly."""
        n = np.size(U)
        return sp.csr_matrix((n, n))

    def factorize(self, J: Any) -> Factorization:
        return factorize(J) if self._factorize_bordered is None else self._factorize_bordered(J)

    def max_step_fraction(self, U: np.ndarray, q: float, dU: np.ndarray, dq: float) -> float:
        """The base's domain filter along the step of its unknowns and its load."""
        u, p = self.split(U)
        dU = np.asarray(dU, dtype=float)
        return self.base.max_step_fraction(u, p, dU[:-1], self.unit * float(dU[-1]))
