"""A closed shell probed at its pole while its enclosed volume is held: :class:`ProbeAtFixedVolume`.

A complete sphere (any closed shell of revolution) filled with an incompressible liquid and probed by a
point at its north pole keeps its enclosed volume ``V*``; the pressure of the fill is then not a load
but the Lagrange multiplier of the constraint ``V = V*``.  The probe's travel ``w`` (the pole's
deflection, :class:`contin_models.shell.structure.ShellOfRevolution` under displacement control) stays
the continuation parameter::

    U = [u, p / unit],    L(U, w) = E(u, w) + p (V(u, w) - V*)     (E the elastic energy),
    residual  [dE/du + p dV/du;  unit (V - V*)],
    Jacobian  [[H + p d2V, unit dV/du], [unit dV/du^T, 0]],

which is the pressure-loaded probe of :class:`ShellOfRevolution` (``pressure=``, its fixed pressure set
to the multiplier by :meth:`~ShellOfRevolution.with_pressure`) bordered by the volume's gradient, as
:class:`contin.analyses.conjugate.ConjugateControl` borders a load's problem by its conjugate; only the
parameter differs (here the probe's travel, the volume fixed; there the volume).  ``unit`` stores the
multiplier in the state's units for the arclength metric (as ``ConjugateControl``'s ``multiplier_unit``).

Stability labels: ``"volume"`` (primary: the probe's travel and the volume held, the Hessian on the
volume constraint's tangent space, the bordered count minus one, :class:`contin.problem.Constrained`)
and ``"pressure"`` (the probe's travel held at the fixed pressure of the gas, the leading block).  The
harmonic blocks ``n >= 1`` (``harmonics``) change neither the volume nor the pole's deflection to first
order and are the pressure-loaded shell's at the multiplier's pressure
(:func:`contin_models.shell.harmonic.harmonic_family`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import scipy.sparse as sp

from contin.analyses.deadload import bordered_matrix
from contin.numerics.linalg import Factorization
from contin.problem import Constrained, LeadingBlock, Problem

from .energy import HALF_BANDWIDTH
from .structure import ShellOfRevolution, default_harmonics
from .volume import volume_gradient

__all__ = ["ProbeAtFixedVolume", "VOLUME_PROBE_LABELS"]

#: Stability labels: the volume held (primary), then the pressure held.
VOLUME_PROBE_LABELS = ("volume", "pressure")


class ProbeAtFixedVolume(Problem):
    """A probe's travel at the pole of a closed shell whose enclosed volume is held at ``volume`` (module docstring).

    Parameters
    ----------
    probe : ShellOfRevolution
        A point load under displacement control on a closed shell, built with a pressure (``pressure=``
        nonzero, so that it carries the volume term; its value is replaced by the multiplier).
    volume : float
        The enclosed volume held, ``V*`` (the meridian's length unit cubed), e.g. the pressurised shell's.
    unit : float
        The multiplier is stored as ``p / unit`` (a pressure per length: e.g. ``p_c / h``), ``> 0``.
    harmonics : int
        Watch the blocks ``n = 1 .. harmonics`` (``-1``: :func:`contin_models.shell.structure.default_harmonics`;
        0: none).
    pole_held : bool
        The probe holds its pole laterally (the ``n = 1`` translation of the pole removed).
    p_c : float, optional
        Pressure that normalises the observable ``p_over_p_c``.

    Notes
    -----
    Observables: the probe's (``F``, ``w``, ``w_over_h``, ``w_over_L``, ``F_norm``, ``V``) at the
    multiplier's pressure, the multiplier ``p`` and ``p_over_p_c``; ``F``, ``F_norm``, ``w``, ``V`` and ``p``
    with exact derivatives.  :meth:`join` and :meth:`split` map between ``U`` and ``(u, p)``.
    """

    def __init__(self, probe: ShellOfRevolution, volume: float, unit: float, harmonics: int = 0,
                 pole_held: bool = False, p_c: float | None = None) -> None:
        if not isinstance(probe, ShellOfRevolution) or probe.load != "point" or probe.control != "displacement":
            raise ValueError("ProbeAtFixedVolume: the probe must be a ShellOfRevolution with load='point' under "
                             f"control='displacement', got {probe!r}")
        if probe.pressure is None:
            raise ValueError("ProbeAtFixedVolume: build the probe with a nonzero pressure (its volume term)")
        if 0 not in probe.structure.poles:
            raise ValueError("ProbeAtFixedVolume: the shell must be closed (a pole at node 0) to enclose a volume")
        if not (math.isfinite(volume) and volume > 0.0):
            raise ValueError(f"ProbeAtFixedVolume: volume must be positive and finite, got {volume!r}")
        if not (math.isfinite(unit) and unit > 0.0):
            raise ValueError(f"ProbeAtFixedVolume: unit must be positive and finite, got {unit!r}")
        self.probe, self.volume, self.unit = probe, float(volume), float(unit)
        self._member: ShellOfRevolution | None = None
        self.structure = probe.structure
        self.p_c = p_c
        z = probe.z_node
        s = self.unit

        def force(U: np.ndarray, w: float) -> float:
            u, p = self.split(U)
            return float(self.member(p).observables["F"](u, w))

        def dforce(U: np.ndarray, w: float) -> tuple[np.ndarray, float]:
            u, p = self.split(U)
            du, dw = self.member(p).observable_derivatives["F"](u, w)
            # F = -dE/dz_pole: the multiplier's share is -dV/dz_pole
            return np.append(du, -s * self._volume_gradient(u, w)[z]), float(dw)

        def dvolume(U: np.ndarray, w: float) -> tuple[np.ndarray, float]:
            g = self._volume_gradient(self.split(U)[0], w)
            return np.append(g[probe.idx], 0.0), -float(g[z])

        f_norm = probe.length / (2.0 * math.pi * probe.D)
        observables: dict[str, Any] = {name: self._member_observable(name) for name in probe.observables}
        observables.update(F=force, F_norm=lambda U, w: force(U, w) * f_norm, p=lambda U, w: self.split(U)[1])
        derivatives: dict[str, Any] = {
            "F": dforce, "F_norm": lambda U, w: tuple(d * f_norm for d in dforce(U, w)),
            "w": lambda U, w: (np.zeros(np.size(U)), 1.0), "V": dvolume,
            "p": lambda U, w: (np.append(np.zeros(np.size(U) - 1), s), 0.0)}
        if p_c is not None:
            observables["p_over_p_c"] = lambda U, w: self.split(U)[1] / p_c
            derivatives["p_over_p_c"] = lambda U, w: (np.append(np.zeros(np.size(U) - 1), s / p_c), 0.0)
        ops = {VOLUME_PROBE_LABELS[0]: Constrained(self.jacobian, 1),
               VOLUME_PROBE_LABELS[1]: LeadingBlock(VOLUME_PROBE_LABELS[0], -1)}
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         stability_operators=ops, name="shell_point_fixed_volume", parameter_name="w",
                         residual_scale=probe.residual_scale, difference_scale=probe.difference_scale)
        self.harmonics = default_harmonics(self.structure) if harmonics == -1 else int(harmonics)
        if self.harmonics < 0:
            raise ValueError(f"ProbeAtFixedVolume: harmonics must be -1, 0 or a wave number >= 1, got {harmonics!r}")
        if self.harmonics:
            from .harmonic import harmonic_family

            self.operator_families = (harmonic_family(
                self.structure, lambda U, w: self.full_state(U, w), self.harmonics,
                pressure=lambda U, w: self.split(U)[1], z_ref=probe.pressure.z_ref, pole_held=pole_held),)

    # ---- state maps ------------------------------------------------------------------------------
    def split(self, U: np.ndarray) -> tuple[np.ndarray, float]:
        """``(u, p)``: the probe's unknowns and the multiplier (a pressure)."""
        U = np.asarray(U, dtype=float)
        return U[:-1], self.unit * float(U[-1])

    def join(self, u: np.ndarray, p: float) -> np.ndarray:
        """``U = [u, p / unit]``."""
        return np.append(np.asarray(u, dtype=float), float(p) / self.unit)

    def full_state(self, U: np.ndarray, w: float) -> np.ndarray:
        """The shell's full state (:meth:`ShellOfRevolution.full_state`) at ``(U, w)``."""
        return self.probe.full_state(self.split(U)[0], w)

    def member(self, p: float) -> ShellOfRevolution:
        """The probe under the fixed pressure ``p`` (shares the structure; the last one is kept, since the engine
        asks for the residual, the Jacobian and the observables at the same state)."""
        if self._member is None or self._member.fixed_pressure != float(p):
            self._member = self.probe.with_pressure(p)
        return self._member

    def _volume_gradient(self, u: np.ndarray, w: float) -> np.ndarray:
        return volume_gradient(self.probe.full_state(u, w), self.probe.pressure.z_ref)

    def _member_observable(self, name: str) -> Any:
        def observable(U: np.ndarray, w: float) -> float:
            u, p = self.split(U)
            return float(self.member(p).observables[name](u, w))
        return observable

    # ---- the Problem interface -------------------------------------------------------------------
    def energy(self, U: np.ndarray, w: float) -> float:
        """The Lagrangian ``E + p (V - V*)`` (the probe's energy carries ``p (V - V0)``)."""
        u, p = self.split(U)
        return self.member(p).energy(u, w) + p * (self.probe.pressure.V0 - self.volume)

    def residual(self, U: np.ndarray, w: float) -> np.ndarray:
        u, p = self.split(U)
        V = self.probe.pressure.volume(self.probe.full_state(u, w))
        return np.append(self.member(p).residual(u, w), self.unit * (V - self.volume))

    def jacobian(self, U: np.ndarray, w: float) -> sp.csr_matrix:
        u, p = self.split(U)
        border = self.unit * self._volume_gradient(u, w)[self.probe.idx]
        return bordered_matrix(self.member(p).jacobian(u, w), border, 0.0)

    def dresidual_dp(self, U: np.ndarray, w: float) -> np.ndarray:
        u, p = self.split(U)
        dV_dw = -float(self._volume_gradient(u, w)[self.probe.z_node])  # z_pole = zbar - w
        return np.append(self.member(p).dresidual_dp(u, w), self.unit * dV_dw)

    def factorize(self, J: Any) -> Factorization:
        """Block elimination of the multiplier on the shell's banded LU (O(N) solves)."""
        from contin_models.contact.indentation import BorderedBandedLU

        return BorderedBandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH)

    def __repr__(self) -> str:
        return f"ProbeAtFixedVolume({self.probe!r}, volume={self.volume!r})"
