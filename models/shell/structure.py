"""A shell of revolution on any reference meridian, with its supports and one load (issue 16).

:class:`ShellStructure` is the elastic part: the discrete stretching and bending energy of
:class:`contin_models.shell.ShellEnergy` on a reference polyline (a spherical cap, a plate, a cone,
a complete sphere, ...), a mirror bending element at every end on the axis (a closed pole, as in
:class:`contin_models.shell.ShellPointLoad`), and the supports of the edge at node 0
(``docs/model.md#supports``):

``"sliding"``
    ``z_0`` fixed, ``r_0`` free, the edge rotates freely (the paper's base).
``"pinned"``
    ``r_0``, ``z_0`` fixed, free rotation.  On a closed end (node 0 a pole on the axis, as the south pole
    of a complete sphere) it is a point support: the pole's point held in space (its height here, and in
    the harmonic blocks its sideways motion too), so that a point force at the other pole is reacted.
``"clamped"``
    ``r_0``, ``z_0`` fixed and the edge tangent held (:class:`ClampedEdge`).
``"free"``
    nothing fixed at the edge.

An end on the axis keeps ``r = 0``.  When nothing holds the shell in ``z`` (a free edge, or a closed
shell with a free pole at each end) its rigid translation along the axis is removed by fixing the height
of the node nearest the middle of the meridian (:attr:`ShellStructure.rigid_fix`): only loads in
self-equilibrium (pressure) may act on such a shell, so that support carries no reaction, and the
problems check it (:class:`ShellOfRevolution` refuses a point or ring force on it).

:class:`ShellOfRevolution` composes the structure with one load as a :class:`contin.Problem`
(``docs/model.md#loads``):

* a point force ``F`` at the pole or a ring force ``Q`` on a node ring, potential ``-F w`` with
  ``w = zbar_k - z_k`` the node's deflection (positive down).  Force control: ``F`` is the
  parameter and every free dof an unknown (the natural ordering keeps the band).  Displacement
  control: ``w`` is the parameter and ``z_k`` is eliminated; the load is the reaction
  ``F = dE/dw``.
* a uniform pressure ``p`` through the enclosed-volume potential ``p (V - V0)``
  (:class:`contin_models.shell.volume.PressureTerm`), with the pressure as the parameter.  (The
  volume as the parameter is the engine's generic Lagrange construction on this problem.)

Stability labels: under force control, ``"force"`` (the Hessian on all unknowns) first and
``"displacement"`` (the same without the loaded node's height); under displacement control the
other way round.
"""

from __future__ import annotations

import copy
import math
from typing import Any, Literal

import numpy as np
import scipy.sparse as sp

from contin.numerics.linalg import BandedLU, Factorization, same_values, symmetric_column
from contin.problem import LeadingBlock, Problem

from .elements import ClampedEdge, MomentFreeEdge, PoleMirror, edge_tangent
from .energy import HALF_BANDWIDTH, ShellEnergy
from .problem import SubMatrix, csr_slots, shell_residual_scale
from .reference import ShellReference
from .supports import SUPPORTS  # defined apart: the scene schema reads it without loading numpy
from .volume import PressureTerm, volume_gradient, volume_hessian

__all__ = ["ShellStructure", "ShellOfRevolution", "ClampedEdge", "MomentFreeEdge", "SUPPORTS", "LOADS", "edge_tangent",
           "default_harmonics"]

LOADS = ("point", "ring", "pressure")
"""The loads :class:`ShellOfRevolution` composes."""

#: Hessians kept per structure: the engine asks for the Jacobian, the stability operators and the
#: observables' derivatives at the same state.
_HESSIAN_CACHE_SIZE = 3


class ShellStructure:
    """Elastic energy of a shell of revolution with its supports, on the full interleaved state.

    Parameters
    ----------
    meridian
        The reference polyline: any object with ``N``, ``r``, ``z``, ``x``, ``edge_length``,
        ``edge_radius``, ``voronoi_length`` and ``node_radius`` (a
        :class:`contin_models.shell.geometry.ReferenceCap` or a meridian of
        :mod:`contin_models.shell.meridian`).  An end with ``r = 0`` is a pole on the axis.
    E, nu : float
        Young's modulus and Poisson's ratio.
    h : float or ndarray, optional
        Thickness, or node thicknesses ``(N,)``; default the meridian's ``thickness``.
    boundary : {"sliding", "pinned", "clamped", "free"}
        Support of the edge at node 0.  When node 0 is a pole: ``"free"`` (or the default, read as
        it) or ``"pinned"`` (a point support of the pole); ``"clamped"`` raises ValueError.
    kappa11_length : {"reference", "current"}
        Length in the interior nodes' ``kappa11`` (:class:`contin_models.shell.ShellEnergy`).
    edge_bending : {"moment_free", "none"}
        Bending element of an edge node that may rotate (sliding, pinned, free):
        :class:`MomentFreeEdge` (the default), or none, as the paper's base (its point-load model,
        :class:`contin_models.shell.ShellPointLoad`, is this structure with ``"sliding"`` and
        ``"none"``).  A clamped edge has :class:`ClampedEdge` either way.

    Attributes
    ----------
    reference : ShellReference
        The reference data of every element, the supports and the poles
        (:class:`contin_models.shell.reference.ShellReference`), built once: :attr:`shell` and the harmonic
        blocks read it.
    fixed : ndarray
        Sorted full-state dofs the supports and the axis fix (read-only).
    rigid_fix : int or None
        The dof fixed only to remove the rigid translation along the axis (module docstring).
    poles : list of int
        The nodes on the axis (0, ``N-1`` or both).
    """

    def __init__(self, meridian: Any, E: float, nu: float, h: float | np.ndarray | None = None,
                 boundary: Literal["sliding", "pinned", "clamped", "free"] = "sliding",
                 kappa11_length: Literal["reference", "current"] = "current",
                 edge_bending: Literal["moment_free", "none"] = "moment_free") -> None:
        if h is None:
            h = getattr(meridian, "thickness", None)
            if h is None:
                raise ValueError("ShellStructure: give the thickness h (the meridian carries none)")
        self.meridian = meridian
        self.reference = ref = ShellReference.build(meridian, E, nu, h, kappa11_length, boundary, edge_bending)
        self.shell = ShellEnergy(reference=ref)
        self.E, self.nu = ref.E, ref.nu
        N = int(meridian.N)
        self.N, self.n_full = N, 2 * N
        self.poles = list(ref.axis_nodes)
        self.boundary = ref.boundary
        self.kb_nodes = ref.kb_nodes
        self.h_nodes = ref.h_nodes
        self.rigid_fix: int | None = ref.rigid_fix
        self.fixed = ref.fixed
        self.free = ref.free

        # mirror bending elements of the poles: (element, full-state dofs of (a, -, b) local variables)
        self._poles: list[tuple[PoleMirror, np.ndarray]] = [(p.element, p.dofs) for p in ref.poles]

        H0 = self.shell.hessian(meridian.x)
        self._pattern = H0
        self._pole_slots = []
        for _, dofs in self._poles:
            rr, cc = np.meshgrid(dofs, dofs, indexing="ij")
            self._pole_slots.append(csr_slots(H0, rr.ravel(), cc.ravel()))
        self.edge_element: ClampedEdge | MomentFreeEdge | None = None if ref.edge is None else ref.edge.element
        #: The clamp's element (None unless clamped).
        self.clamp = self.edge_element if self.boundary == "clamped" else None
        self.edge_bending = edge_bending
        if self.edge_element is not None:
            rr, cc = np.meshgrid(ClampedEdge.dofs, ClampedEdge.dofs, indexing="ij")
            self._clamp_slots = csr_slots(H0, rr.ravel(), cc.ravel())
        self._grad_cache: tuple[np.ndarray, np.ndarray] | None = None
        self._hess_cache: list[tuple[np.ndarray, sp.csr_matrix]] = []

    @property
    def pattern(self) -> sp.csr_matrix:
        """The fixed CSR pattern of every full Hessian (do not modify)."""
        return self._pattern

    @property
    def pole_elements(self) -> tuple[tuple[PoleMirror, np.ndarray], ...]:
        """The mirror bending element of each pole of :attr:`poles` (same order), with the full-state dofs
        of its local variables: ``(r_nb, z_nb, z_pole)`` at the north pole, ``(r_1, z_0, z_1)`` at the south
        one (``nb`` the pole's neighbour).  The dof arrays are read-only."""
        return tuple(self._poles)

    def reference_state(self) -> np.ndarray:
        """The reference full state (a new array)."""
        return self.meridian.x

    @staticmethod
    def _ab(element_dofs: np.ndarray, x: np.ndarray) -> tuple[float, float]:
        a, zlo, zhi = x[element_dofs]
        return float(a), float(zhi - zlo)

    def energy(self, x: np.ndarray) -> float:
        """Elastic energy of a full state: stretching, bending, poles and the edge node's element."""
        e = self.shell.energy(x)
        for element, dofs in self._poles:
            e += element.energy(*self._ab(dofs, x))
        if self.edge_element is not None:
            e += self.edge_element.energy(x)
        return float(e)

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """Gradient of :meth:`energy` in all ``2N`` dofs (a new array)."""
        if self._grad_cache is not None and same_values(self._grad_cache[0], x):
            return self._grad_cache[1].copy()
        g = self.shell.gradient(x)
        for element, dofs in self._poles:
            g[dofs] += element.gradient_hessian(*self._ab(dofs, x))[0]
        if self.edge_element is not None:
            g[ClampedEdge.dofs] += self.edge_element.gradient(x)
        self._grad_cache = (np.array(x, dtype=float), g.copy())
        return g

    def hessian(self, x: np.ndarray) -> sp.csr_matrix:
        """Hessian of :meth:`energy` in all ``2N`` dofs, in :attr:`pattern` (shared: do not modify)."""
        for i, (xc, Hc) in enumerate(self._hess_cache):
            if same_values(xc, x):
                if i:
                    self._hess_cache.insert(0, self._hess_cache.pop(i))
                return Hc
        H = self.shell.hessian(x)
        for (element, dofs), slots in zip(self._poles, self._pole_slots):
            H.data[slots] += element.gradient_hessian(*self._ab(dofs, x))[1].ravel()
        if self.edge_element is not None:
            H.data[self._clamp_slots] += self.edge_element.hessian(x).ravel()
        self._hess_cache.insert(0, (np.array(x, dtype=float), H))
        del self._hess_cache[_HESSIAN_CACHE_SIZE:]
        return H

    def residual_scale(self, H_free: sp.csr_matrix, length: float) -> float:
        """:func:`contin_models.shell.problem.shell_residual_scale` with the largest thickness."""
        return shell_residual_scale(self.E, float(np.max(self.h_nodes)), length, H_free)

    def __repr__(self) -> str:
        return f"ShellStructure(N={self.N}, E={self.E}, nu={self.nu}, boundary={self.boundary!r}, poles={self.poles})"


def default_harmonics(structure: ShellStructure) -> int:
    """The largest wave number watched by default: a quarter above the classical critical one, plus 2.

    A shell of revolution buckles into waves of about the classical length
    ``2 pi sqrt(rho h) / (12 (1 - nu^2))^(1/4)`` (``rho`` its smallest radius of curvature); around
    its widest circle (radius ``r_max``) that is ``n* = (12 (1 - nu^2))^(1/4) r_max / sqrt(rho h)``
    waves, and no critical mode is shorter: the complete sphere's critical modes (degree ``l* = n*``
    for ``rho = r_max = R``) have ``n <= l*``, a clamped cap's under pressure ``n`` about ``n* / 2``
    (Huang 1964, ``docs/asymmetric.md``), a point-loaded cap's fewer still.  ``ceil(1.25 n*) + 2``
    leaves a margin above ``n*``; the scenes warn when a located bifurcation comes within 1 of the
    range's end (:func:`contin_models.shell_scene.schema.harmonic_summary`).  ``rho`` is taken from
    the meridian's largest reference curvature (its ``kappa11``, ``kappa22`` at the interior nodes), or
    its length scale for a flat one.
    """
    m = structure.meridian
    h = float(np.max(structure.h_nodes))
    k = np.concatenate([np.abs(np.asarray(m.kappa11, dtype=float)), np.abs(np.asarray(m.kappa22, dtype=float))])
    k = k[np.isfinite(k)]
    kmax = float(np.max(k)) if k.size else 0.0
    rho = 1.0 / kmax if kmax > 0 else float(getattr(m, "length_scale", None) or np.max(m.r))
    n_star = (12.0 * (1.0 - structure.nu ** 2)) ** 0.25 * float(np.max(m.r)) / math.sqrt(rho * h)
    return int(math.ceil(1.25 * n_star)) + 2


class ShellOfRevolution(Problem):
    """A :class:`ShellStructure` under one load, as a :class:`contin.Problem`.

    Parameters
    ----------
    structure : ShellStructure
        The shell and its supports.
    load : {"point", "ring", "pressure"}
        A point force at the pole (node ``N-1``, which must be on the axis), a ring force on node
        ``node``, or a uniform external pressure (module docstring).  A force needs a support in ``z``:
        an edge, or on a complete sphere the point support of its other pole (``boundary="pinned"``).
    control : {"force", "displacement"}
        The load as the parameter, or (point and ring) the loaded node's deflection ``w``.
        Pressure takes ``"force"`` only here.
    node : int, optional
        The loaded node of a ring force (``0 < node < N-1``, off the axis).
    length : float, optional
        Length that normalises ``w`` and ``F`` (``w_over_L``, ``F_norm = F L / (2 pi D)``); default
        the meridian's ``length_scale`` (or ``R``).
    p_c : float, optional
        Pressure that normalises ``p`` (``p_over_p_c``).
    pressure : float
        A fixed uniform pressure acting besides a point or ring force (0: none).  With it the problem
        is one member of the two-parameter family ``(F, p)``: :meth:`with_pressure` gives the others,
        e.g. for :class:`contin.FoldCurveProblem` to trace a limit load against the pressure.
    harmonics : int, optional
        Watch the stability against non-axisymmetric modes of wave numbers ``1 .. harmonics``
        (:mod:`contin_models.shell.harmonic` blocks as a :class:`contin.OperatorFamily` named ``"n"``,
        each twice in the whole Hessian: its ``cos`` and ``sin`` modes).  ``0`` (default): none;
        ``-1``: :func:`default_harmonics`.
    pole_held : bool
        With ``harmonics``: the load holds the pole laterally (no ``n = 1`` translation of the pole);
        default free, as under a frictionless point (:func:`contin_models.shell.harmonic.harmonic_family`).

    Notes
    -----
    Observables: the load (``F`` or ``p``), ``w`` (the loaded node's deflection, for pressure the
    height drop of node ``N-1``), ``w_over_h`` (over the thickness at that node), ``w_over_L``, and
    ``F_norm``, ``p_over_p_c``, ``V`` and ``w_pole`` (a ring-loaded shell's pole deflection) where
    they apply; all with exact derivatives.
    """

    def __init__(self, structure: ShellStructure, load: Literal["point", "ring", "pressure"] = "point",
                 control: Literal["force", "displacement"] = "force", node: int | None = None,
                 length: float | None = None, p_c: float | None = None, pressure: float = 0.0,
                 harmonics: int = 0, pole_held: bool = False) -> None:
        if load not in LOADS:
            raise ValueError(f"ShellOfRevolution: load must be one of {LOADS}, got {load!r}")
        if control not in ("force", "displacement"):
            raise ValueError(f"ShellOfRevolution: control must be 'force' or 'displacement', got {control!r}")
        st = self.structure = structure
        N = st.N
        self.load, self.control = load, control
        if length is None:
            length = getattr(st.meridian, "length_scale", None) or getattr(st.meridian, "R", None)
        self.length = float(length) if length is not None else 1.0
        x_ref = st.meridian.x
        self.x_ref = x_ref
        if load == "point":
            if N - 1 not in st.poles:
                raise ValueError("ShellOfRevolution: a point load needs a pole at node N-1 (r = 0)")
            node = N - 1
        elif load == "ring":
            if node is None or not (0 < int(node) < N - 1):
                raise ValueError(f"ShellOfRevolution: a ring load needs node in (0, {N - 1}), got {node!r}")
            node = int(node)
        else:
            if control != "force":
                raise ValueError("ShellOfRevolution: pressure takes control='force' here (the volume as the "
                                 "parameter is the engine's Lagrange construction on this problem)")
            if st.boundary == "free" and 0 not in st.poles:
                raise ValueError("ShellOfRevolution: a free edge cannot carry pressure (the volume is not closed)")
            node = N - 1
        if load in ("point", "ring") and st.rigid_fix is not None:
            raise ValueError("ShellOfRevolution: a point or ring force needs a support in z "
                             f"(boundary {st.boundary!r} leaves the shell free to translate)")
        self.node = node
        self.z_node = 2 * node + 1
        self.z_ref_node = float(x_ref[self.z_node])
        self.D = float(st.kb_nodes[node])
        self.h_node = float(st.h_nodes[node])
        self.fixed_pressure = float(pressure)
        if not math.isfinite(self.fixed_pressure):
            raise ValueError(f"ShellOfRevolution: pressure must be finite, got {pressure!r}")
        if self.fixed_pressure != 0.0 and load == "pressure":
            raise ValueError("ShellOfRevolution: a fixed pressure goes with a point or ring load, not with load='pressure'")
        if self.fixed_pressure != 0.0 and st.boundary == "free" and 0 not in st.poles:
            raise ValueError("ShellOfRevolution: a free edge cannot carry pressure (the volume is not closed)")
        self.pressure = PressureTerm.from_reference(x_ref) if load == "pressure" or pressure else None
        if self.pressure is not None:
            HV = volume_hessian(x_ref, self.pressure.z_ref)
            self._v_slots = csr_slots(st.pattern, np.repeat(np.arange(st.n_full), np.diff(HV.indptr)), HV.indices)
        self.p_c = p_c

        # unknowns: force control (and pressure) every free dof; displacement control without z_node
        if control == "displacement":
            self.idx = st.free[st.free != self.z_node]
        else:
            self.idx = st.free.copy()
        self._sub = SubMatrix(st.pattern, self.idx)
        name = "F" if load in ("point", "ring") else "p"
        param = name if control == "force" else "w"
        self.load_name = name
        ops, observables, derivatives = self._bound_callables()
        scale = st.residual_scale(self._sub(st.hessian(x_ref)), self.length)
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         stability_operators=ops, name=f"shell_{load}_{control}", parameter_name=param,
                         residual_scale=scale, difference_scale=float(np.max(st.h_nodes)))
        self.harmonics = default_harmonics(st) if harmonics == -1 else int(harmonics)
        if self.harmonics < 0:
            raise ValueError(f"ShellOfRevolution: harmonics must be -1 (default rule), 0 or a wave number >= 1, "
                             f"got {harmonics!r}")
        self.pole_held = bool(pole_held)
        self.operator_families = self._harmonic_families()

    def _bound_callables(self) -> tuple[dict[str, Any] | None, dict[str, Any], dict[str, Any]]:
        """The stability operators, observables and their derivatives, bound to this problem (its fixed pressure
        among what they read): built again for each copy of :meth:`with_pressure`."""
        st, load, control, x_ref, p_c = self.structure, self.load, self.control, self.x_ref, self.p_c
        N = st.N
        ops: dict[str, Any]
        if load == "pressure":
            ops = None
        elif control == "force":
            without = st.free[st.free != self.z_node]
            if self.idx[-1] == self.z_node:
                ops = {"force": self.jacobian, "displacement": LeadingBlock("force", -1)}
            else:
                sub = SubMatrix(st.pattern, without)
                ops = {"force": self.jacobian,
                       "displacement": lambda u, p: sub(self._elastic_hessian(self.full_state(u, p), p))}
        else:
            with_node = np.concatenate([self.idx, [self.z_node]])
            sub = SubMatrix(st.pattern, with_node)
            ops = {"displacement": self.jacobian,
                   "force": lambda u, p: sub(self._elastic_hessian(self.full_state(u, p), p))}
        name = self.load_name
        observables: dict[str, Any] = {name: self._obs_load, "w": self._obs_w,
                                       "w_over_h": lambda u, p: self._obs_w(u, p) / self.h_node,
                                       "w_over_L": lambda u, p: self._obs_w(u, p) / self.length}
        derivatives: dict[str, Any] = {name: self._dobs_load, "w": self._dobs_w,
                                       "w_over_h": lambda u, p: _times(self._dobs_w(u, p), 1.0 / self.h_node),
                                       "w_over_L": lambda u, p: _times(self._dobs_w(u, p), 1.0 / self.length)}
        if load == "ring" and N - 1 in st.poles:  # the pole's deflection, beside the ring's
            z_pole = 2 * N - 1
            e_pole = np.zeros(st.n_full)
            e_pole[z_pole] = -1.0
            observables["w_pole"] = lambda u, p: float(x_ref[z_pole] - self.full_state(u, p)[z_pole])
            derivatives["w_pole"] = lambda u, p: (e_pole[self.idx], 0.0)
        if load in ("point", "ring"):
            f_norm = self.length / (2.0 * math.pi * self.D)
            observables["F_norm"] = lambda u, p: self._obs_load(u, p) * f_norm
            derivatives["F_norm"] = lambda u, p: _times(self._dobs_load(u, p), f_norm)
        if self.pressure is not None:
            observables["V"] = lambda u, p: self.pressure.volume(self.full_state(u, p))
            derivatives["V"] = lambda u, p: (volume_gradient(self.full_state(u, p), self.pressure.z_ref)[self.idx], 0.0)
        if load == "pressure":
            if p_c is not None:
                observables["p_over_p_c"] = lambda u, p: float(p) / p_c
                derivatives["p_over_p_c"] = lambda u, p: (np.zeros(self.n), 1.0 / p_c)
        return ops, observables, derivatives

    def _harmonic_families(self) -> tuple:
        """The harmonic blocks watched (:func:`contin_models.shell.harmonic.harmonic_family`) at this problem's
        pressure, bound to it (none with ``harmonics = 0``)."""
        if not self.harmonics:
            return ()
        from .harmonic import harmonic_family

        return (harmonic_family(
            self.structure, self.full_state, self.harmonics,
            pressure=(lambda u, p: self._pressure_value(p)) if self.pressure is not None else None,
            z_ref=self.pressure.z_ref if self.pressure is not None else None, pole_held=self.pole_held),)

    def harmonic_block(self, n: int, u: np.ndarray, p: float) -> sp.csr_matrix:
        """The Hessian block of wave number ``n >= 1`` at the state ``(u, p)`` (:func:`contin_models.shell.harmonic.harmonic_block`).

        Shared by both controls: an ``n >= 1`` field changes neither the loaded node's height nor the
        volume to first order; the pressure's load stiffness is included.
        """
        from .harmonic import harmonic_block

        q = self._pressure_value(p) if self.pressure is not None else 0.0
        z_ref = self.pressure.z_ref if self.pressure is not None else None
        return harmonic_block(self.structure, self.full_state(u, p), int(n), pressure=q, z_ref=z_ref)

    # ---- maps between the full state and the unknowns --------------------------------------------
    @property
    def n(self) -> int:
        """Number of unknowns."""
        return self.idx.size

    @property
    def shell(self) -> ShellEnergy:
        """The stretching and bending energy (strains, curvatures)."""
        return self.structure.shell

    def full_state(self, u: np.ndarray, p: float = 0.0) -> np.ndarray:
        """Full interleaved state from the unknowns (and, under displacement control, ``w = p``)."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n,):
            raise ValueError(f"unknown vector must have shape ({self.n},), got {u.shape}")
        x = self.x_ref.copy()
        x[self.idx] = u
        if self.control == "displacement":
            x[self.z_node] = self.z_ref_node - float(p)
        return x

    def unknowns(self, x: np.ndarray) -> np.ndarray:
        """The unknowns of a full state (fixed dofs dropped, not checked)."""
        return np.asarray(x, dtype=float)[self.idx].copy()

    def reference_unknowns(self) -> np.ndarray:
        """Unknowns of the reference state, the equilibrium at zero load."""
        return self.unknowns(self.x_ref)

    # ---- the Problem interface -------------------------------------------------------------------
    def _pressure_value(self, p: float) -> float:
        """The pressure acting at parameter ``p``: ``p`` itself, or the fixed one besides a force."""
        return float(p) if self.load == "pressure" else self.fixed_pressure

    def _elastic_hessian(self, x: np.ndarray, p: float) -> sp.csr_matrix:
        """The structure's Hessian plus the pressure's load stiffness ``p d2V`` (shared when there is none)."""
        H = self.structure.hessian(x)
        q = self._pressure_value(p) if self.pressure is not None else 0.0
        if q != 0.0:
            H = H.copy()
            H.data[self._v_slots] += q * volume_hessian(x, self.pressure.z_ref).data
        return H

    _full_hessian = _elastic_hessian

    def _gradient(self, x: np.ndarray, p: float) -> np.ndarray:
        """Full gradient of the total energy (elastic, pressure and force potentials)."""
        g = self.structure.gradient(x)
        if self.pressure is not None:
            g += self.pressure.gradient(x, self._pressure_value(p))
        if self.load != "pressure" and self.control == "force":  # potential -F w
            g[self.z_node] += float(p)
        return g

    def energy(self, u: np.ndarray, p: float) -> float:
        x = self.full_state(u, p)
        e = self.structure.energy(x)
        if self.pressure is not None:
            e += self.pressure.energy(x, self._pressure_value(p))
        if self.load != "pressure" and self.control == "force":  # potential -F w
            e -= float(p) * (self.z_ref_node - float(x[self.z_node]))
        return e

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        return self._gradient(self.full_state(u, p), p)[self.idx]

    def with_pressure(self, pressure: float) -> "ShellOfRevolution":
        """This point- or ring-loaded problem under another fixed pressure (shares the structure)."""
        if self.load == "pressure":
            raise ValueError("with_pressure: the pressure is this problem's parameter")
        if self.pressure is None:
            raise ValueError("with_pressure: build the problem with a nonzero pressure (its volume term) first")
        other = copy.copy(self)
        ShellOfRevolution._bind_pressure(other, pressure)
        return other

    def _bind_pressure(self, pressure: float) -> None:
        """Set the fixed pressure and bind the stability operators, the observables and the harmonic blocks to this
        problem (a copy's would otherwise read the pressure of the problem it was copied from)."""
        self.fixed_pressure = float(pressure)
        ops, self._observables, self._observable_derivatives = self._bound_callables()
        self._stability_operators = dict(ops or {})
        self.operator_families = self._harmonic_families()

    def jacobian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        return self._sub(self._full_hessian(self.full_state(u, p), p))

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        x = self.full_state(u, p)
        if self.load == "pressure":
            return self.pressure.gradient_dp(x)[self.idx]
        if self.control == "force":
            d = np.zeros(self.structure.n_full)
            d[self.z_node] = 1.0
            return d[self.idx]
        return -symmetric_column(self._elastic_hessian(x, p), self.z_node)[self.idx]  # z_node = zbar - w

    def jacobian_dp(self, u: np.ndarray, p: float):
        if self.control == "force":
            if self.load == "pressure":
                x = self.full_state(u, p)
                HV = self.structure.pattern.copy()
                HV.data[:] = 0.0
                HV.data[self._v_slots] = volume_hessian(x, self.pressure.z_ref).data
                return self._sub(HV)
            return sp.csr_matrix((self.n, self.n))  # a dead load is linear in F
        return super().jacobian_dp(u, p)

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        """``dE/dp``: the volume change under pressure, the load's reaction under displacement control,
        minus the deflection ``-w`` under a force."""
        x = self.full_state(u, p)
        if self.load == "pressure":
            return self.pressure.energy_dp(x)
        if self.control == "force":
            return -(self.z_ref_node - float(x[self.z_node]))
        return -float(self._gradient(x, p)[self.z_node])

    def conjugate_stiffness(self, u: np.ndarray, p: float) -> float:
        """``d2E/dp2`` at fixed unknowns."""
        if self.control == "force":
            return 0.0
        x = self.full_state(u, p)
        return float(symmetric_column(self._elastic_hessian(x, p), self.z_node)[self.z_node])

    def factorize(self, J) -> Factorization:
        """Banded LU with the shell's half-bandwidth (O(N))."""
        return BandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH)

    # ---- observables -----------------------------------------------------------------------------
    def _obs_load(self, u: np.ndarray, p: float) -> float:
        if self.control == "force":
            return float(p)
        return -float(self._gradient(self.full_state(u, p), p)[self.z_node])

    def _dobs_load(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        if self.control == "force":
            return np.zeros(self.n), 1.0
        col = symmetric_column(self._elastic_hessian(self.full_state(u, p), p), self.z_node)
        return -col[self.idx], float(col[self.z_node])

    def _obs_w(self, u: np.ndarray, p: float) -> float:
        if self.control == "displacement":
            return float(p)
        return self.z_ref_node - float(self.full_state(u, p)[self.z_node])

    def _dobs_w(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        if self.control == "displacement":
            return np.zeros(self.n), 1.0
        d = np.zeros(self.structure.n_full)
        d[self.z_node] = -1.0
        return d[self.idx], 0.0

    # ---- linear response -------------------------------------------------------------------------
    def linear_response(self) -> np.ndarray:
        """``dx/dp`` at the reference state (full state; zero on the fixed dofs)."""
        u0 = self.reference_unknowns()
        du = self.factorize(self.jacobian(u0, 0.0)).solve(-self.dresidual_dp(u0, 0.0))
        dx = np.zeros(self.structure.n_full)
        dx[self.idx] = du
        if self.control == "displacement":
            dx[self.z_node] = -1.0
        return dx

    def linear_stiffness(self) -> float:
        """Initial ``dF/dw`` of a point or ring load (``1 / (dw/dF)`` under force control)."""
        if self.load == "pressure":
            raise ValueError("linear_stiffness: a pressure has no single deflection conjugate")
        dx = self.linear_response()
        if self.control == "force":
            return 1.0 / -dx[self.z_node]
        u0 = self.reference_unknowns()
        return float(self._dobs_load(u0, 0.0)[0] @ dx[self.idx] + self._dobs_load(u0, 0.0)[1])

    def __repr__(self) -> str:
        return f"ShellOfRevolution({self.structure!r}, load={self.load!r}, control={self.control!r}, node={self.node})"


def _times(derivative: tuple[np.ndarray, float], factor: float) -> tuple[np.ndarray, float]:
    return derivative[0] * factor, derivative[1] * factor
