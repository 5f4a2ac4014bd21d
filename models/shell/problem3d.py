"""A shell of revolution in its 3-D view (:class:`contin_models.shell.fourier.FourierShell`) as a :class:`contin.Problem`.

The unknowns are the free Fourier coefficients of the rings (:meth:`FourierShell.reduction`: poles one
point, supports held, and under displacement control the loaded node's height held at the parameter);
the residual is the reduced gradient of the total energy and the Jacobian its Hessian, banded along
the meridian (a banded LU: O(N) per Newton step at a fixed angular resolution).  Loads: a point force
at the pole or a uniform force on a ring (``F``, positive pushing down; force or displacement
control), a uniform external pressure (``p``; a prescribed volume through :class:`contin.ConjugateControl`),
or dead point forces on any material points and ``cos(n theta)`` line loads on rings (``P`` times
each).  The basis fixes the symmetry class of every state traced: a ``D_n`` basis traces
``D_n``-symmetric states only, and its branch points are the ones that keep that symmetry
(``every_mode`` watches the others).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import scipy.sparse as sp

from contin.numerics.linalg import Factorization, bandwidths, symmetric_band_factorization, symmetric_column
from contin.problem import Problem

from .fourier import AngularBasis, FourierShell
from .problem import _scaled

__all__ = ["Shell3D", "LOADS"]

#: The loads of :class:`Shell3D`.
LOADS = ("point", "ring", "pressure", "forces", "sphere", "plate")

#: Largest coefficient of the turning direction, relative to the state's size, below which a state counts as
#: axisymmetric (its ``A2`` block has no turning to take out); the waves of a state on an ``n``-wave branch one
#: step from its bifurcation are several orders above it.
TURNING_NEGLIGIBLE = 1e-9


class Shell3D(Problem):
    """A :class:`~contin_models.shell.structure.ShellStructure` under one load, in the 3-D view.

    Parameters
    ----------
    structure : ShellStructure
        The shell and its supports.
    basis : AngularBasis
        The angular series (and with it the symmetry class of the states).
    load : {"point", "ring", "pressure", "forces"}
        A point force at the pole (node ``N-1``, on the axis), a uniform force on ring ``node``, a uniform
        external pressure, or ``forces`` and ``line_loads``.
    control : {"force", "displacement"}
        The load as the parameter, or (point and ring loads) the loaded node's deflection ``w``.
    length : float, optional
        Length that normalises ``w`` and ``F`` (``w_over_L``, ``F_norm = F L / (2 pi D)``); default the
        meridian's ``length_scale`` (or ``R``).
    p_c : float, optional
        Under pressure, the pressure the observable ``p_over_p_c`` is measured in (e.g. the classical
        buckling pressure).
    every_mode : bool
        Watch the stability against every perturbation, not only those of the basis's class: the Bloch
        blocks of the other irreducible representations of ``D_n`` as an operator family (``"representation"``,
        keyed ``A2``, ``B1``, ``E1``, ...);
        with ``stability`` the engine counts them and locates the bifurcations that break the symmetry.
    forces : sequence of (node, theta, (Fx, Fy, Fz))
        With ``load="forces"``: dead forces (Cartesian, per unit parameter ``P``) on the material point of
        ring ``node`` at the reference angle ``theta``.  A basis with symmetry needs the whole symmetric
        set (every image of a force under the basis's group), as the energy is the whole shell's.
    node : int, optional
        The loaded ring of a ring force (``0 < node < N-1``, off the axis).
    line_loads : sequence of (node, n, (q_r, q_t, q_z))
        With ``load="forces"``: per radian of ring ``node`` the dead load ``(q_r cos n theta, q_t sin n theta,
        q_z cos n theta)`` (components in the reference frame at the material point), ``P`` times it; ``n``
        must be a wave of the basis.
    reference : ndarray, optional
        The stress-free shape as a state of the view (:class:`~contin_models.shell.fourier.FourierShell`),
        e.g. an imperfection of :mod:`contin_models.shell.imperfection3d`: the unloaded equilibrium, where
        the supports hold their rings and from which ``w`` and the loads' work are measured.  Default: the
        structure's axisymmetric reference.
    gauge : (node, k), optional
        In a basis without a mirror, on a shell whose reference has no waves: hold ``R sin k theta`` of ring
        ``node`` at zero.  A state with waves is one of a circle of states turned about the axis, all of the same
        energy, so its Jacobian is singular along the turning; holding one coefficient the turning moves (a state
        turned so that its wave ``k`` at ``node`` is a cosine, :func:`gauge_for`) picks one state of each circle
        and leaves the Jacobian regular and its Morse index that of the circle.

    Notes
    -----
    Stability labels, as the traced model's: under a point or ring force ``"force"`` (the loaded node's
    height free) and ``"displacement"`` (held), the control's own first; under an indenter
    ``"displacement"`` (the travel held) and ``"force"`` (a dead load on the indenter); one label otherwise.
    With ``every_mode`` each label counts the other classes' negative eigenvalues too.

    Observables: the load (``F``, ``p`` or ``P``), ``w`` (the loaded node's deflection: the ring's under a
    ring force, else the pole's where there is one),
    ``w_over_L`` and ``w_over_h`` (over the loaded node's thickness), under a point or ring force ``F_norm``,
    under pressure with ``p_c`` given ``p_over_p_c``, and per force ``u0``, ``u1``, ... (the displacement of its
    point along it); all with exact derivatives.  :meth:`full_state` gives the Fourier
    coefficients of every ring, :attr:`view` the energy.
    """

    def __init__(self, structure: Any, basis: AngularBasis,
                 load: Literal["point", "ring", "pressure", "forces"] = "point",
                 control: Literal["force", "displacement"] = "force", length: float | None = None,
                 forces: Sequence[tuple[int, float, Sequence[float]]] = (), node: int | None = None,
                 line_loads: Sequence[tuple[int, int, Sequence[float]]] = (), every_mode: bool = False,
                 barrier: Any = None, p_c: float | None = None, reference: np.ndarray | None = None,
                 gauge: tuple[int, int] | None = None) -> None:
        if load not in LOADS:
            raise ValueError(f"Shell3D: load must be one of {LOADS}, got {load!r}")
        if control not in ("force", "displacement"):
            raise ValueError(f"Shell3D: control must be 'force' or 'displacement', got {control!r}")
        st = self.structure = structure
        N = st.N
        pole = N - 1 in st.poles
        if load == "point" and not pole:
            raise ValueError("Shell3D: a point load acts at the pole: node N-1 must be on the axis (r = 0)")
        if load == "ring":
            if node is None or not (0 < int(node) < N - 1) or int(node) in st.poles:
                raise ValueError(f"Shell3D: a ring load needs node in (0, {N - 1}), off the axis, got {node!r}")
        indenter = load in ("sphere", "plate")
        if indenter:
            if barrier is None or barrier.indenter.name != load:
                raise ValueError(f"Shell3D: load {load!r} needs barrier = a ContactBarrier with a {load} indenter")
            if control != "displacement" or not pole:
                raise ValueError(f"Shell3D: an indenter ({load}) is driven by its travel (control='displacement') "
                                 "onto a cap with a pole at node N-1")
        if load in ("pressure", "forces") and control != "force":
            raise ValueError(f"Shell3D: load {load!r} takes control='force' (a prescribed volume: "
                             "contin.ConjugateControl on the pressure-controlled problem)")
        if load == "pressure" and st.boundary == "free" and 0 not in st.poles:
            raise ValueError("Shell3D: a free edge cannot carry pressure (the volume is not closed)")
        if st.rigid_fix is not None and load in ("point", "ring"):
            raise ValueError(f"Shell3D: a point or ring force needs a support in z (boundary {st.boundary!r} leaves "
                             "the shell free to translate)")
        if load == "forces" and not forces and not line_loads:
            raise ValueError("Shell3D: load 'forces' needs forces = [(node, theta, (Fx, Fy, Fz)), ...] or "
                             "line_loads = [(node, n, (q_r, q_t, q_z)), ...]")
        self.load, self.control = load, control
        self.view = view = FourierShell(st, basis, reference=reference)
        self.basis = basis
        if length is None:
            length = getattr(st.meridian, "length_scale", None) or getattr(st.meridian, "R", None)
        self.length = float(length) if length is not None else 1.0
        self.c_ref = view.reference_state()
        # the loaded node: the pole under a point load, the ring's node; its height is what a
        # displacement control holds and what ``w`` measures (the pole's otherwise, where there is one)
        self.node = int(node) if load == "ring" else (N - 1 if pole else None)
        self.z_dof = self.node * view.m + basis.index("Z", "cos", 0) if self.node is not None else None
        self.z_ref_node = float(self.c_ref[self.z_dof]) if self.node is not None else math.nan
        held = [2 * self.node + 1] if control == "displacement" and not indenter else []
        self.gauge = None if gauge is None else (int(gauge[0]), int(gauge[1]))
        fixed = [] if gauge is None else [self._gauge_dof(self.gauge)]
        self.reduction = red = view.reduction(control_fixed=held, held=fixed)
        self.T = red.T.tocsc()
        self.Tt = red.T.T.tocsr()
        self.D = float(st.kb_nodes[self.node if self.node is not None else N - 1])
        # the load per unit parameter as a force on the unknowns (dead loads): the point or ring force pushes
        # the loaded node's height down (a ring force is uniform around the ring: it works on the mean
        # height); each of ``forces`` acts on one material point in a fixed direction; each line load on
        # its ring with the density ``(q_r cos n theta, q_t sin n theta, q_z cos n theta)`` per radian
        self.load_vector = np.zeros(view.size)
        self.forces = []
        if load in ("point", "ring"):
            self.load_vector[self.z_dof] = -1.0
        for k, (at, theta, F) in enumerate(forces):
            F = np.asarray(F, dtype=float)
            if F.shape != (3,) or not np.all(np.isfinite(F)) or not np.any(F):
                raise ValueError(f"Shell3D: forces[{k}] needs a finite, nonzero (Fx, Fy, Fz), got {F!r}")
            X = view.point_map(int(at), float(theta))
            self.load_vector += F @ X
            self.forces.append((int(at), float(theta), F, (F / np.linalg.norm(F)) @ X))
        for k, (at, wave, q) in enumerate(line_loads):
            self.load_vector += self._line_load(k, int(at), int(wave), q)
        self._v_ref = view.volume(self.c_ref) if load == "pressure" else 0.0
        # an indenter: the barrier over the surface, its position c = c0 - w_b (w_b the travel, the
        # parameter), c0 where its barrier first reaches the cap's curve on the axis (as in the traced model)
        self.contact = None
        if indenter:
            from .contact3d import Contact3D

            self.contact = Contact3D(view, barrier)
            x_ref = st.reference_state()
            self.c0 = float(barrier.indenter.contact_position(barrier.pole_height(x_ref))) + barrier.dhat
        self._restrict = red.restriction(view.pattern(load == "pressure"))
        H0 = self._restrict(view.hessian(self.c_ref, volume_pattern=load == "pressure").data)
        self.kl, self.ku = bandwidths(H0)  # every entry the pattern may hold is stored
        name = {"point": "F", "ring": "F", "pressure": "p", "forces": "P", "sphere": "F", "plate": "F"}[load]
        self.load_name = name
        observables: dict[str, Any] = {name: self._obs_load}
        derivatives: dict[str, Any] = {name: self._dobs_load}
        if self.node is not None:
            h_node = float(st.h_nodes[self.node])
            observables.update(w=self._obs_w, w_over_L=lambda u, p: self._obs_w(u, p) / self.length,
                               w_over_h=lambda u, p: self._obs_w(u, p) / h_node)
            derivatives.update(w=self._dobs_w, w_over_L=lambda u, p: _scaled(self._dobs_w(u, p), 1.0 / self.length),
                               w_over_h=lambda u, p: _scaled(self._dobs_w(u, p), 1.0 / h_node))
        if load == "pressure" and p_c is not None:
            if not (math.isfinite(p_c) and p_c > 0.0):
                raise ValueError(f"Shell3D: p_c must be a finite pressure > 0, got {p_c!r}")
            observables["p_over_p_c"] = lambda u, p: float(p) / p_c
            derivatives["p_over_p_c"] = lambda u, p: (np.zeros(self.n), 1.0 / p_c)
        self.p_c = p_c
        for k, (_, _, _, along) in enumerate(self.forces):
            observables[f"u{k}"] = lambda u, p, a=along: float(a @ (self.full_state(u, p) - self.c_ref))
            derivatives[f"u{k}"] = lambda u, p, a=along: (self.Tt @ a, 0.0)
        if load in ("point", "ring"):
            f_norm = self.length / (2.0 * math.pi * self.D)
            observables["F_norm"] = lambda u, p: self._obs_load(u, p) * f_norm
            derivatives["F_norm"] = lambda u, p: _scaled(self._dobs_load(u, p), f_norm)
        scale = st.residual_scale(H0, self.length)
        families = (self._bloch_family(),) if every_mode else ()
        if indenter:  # the parameter is the travel; w stays the pole's deflection
            observables[name], derivatives[name] = self._contact_force, self._dcontact_force
            # as the traced model names them: the travel as an observable too, the force normalised
            f_norm = self.length / (2.0 * math.pi * self.D)
            observables["w_b"] = lambda u, p: float(p)
            derivatives["w_b"] = lambda u, p: (np.zeros(self.n), 1.0)
            observables["F_norm"] = lambda u, p: self._contact_force(u, p) * f_norm
            derivatives["F_norm"] = lambda u, p: _scaled(self._dcontact_force(u, p), f_norm)
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         stability_operators=self._stability_operators(2 * self.node + 1 if pole or load == "ring"
                                                                       else None),
                         name=f"shell3d_{load}_{control}",
                         parameter_name="w_b" if indenter else (name if control == "force" else "w"),
                         residual_scale=scale, operator_families=families,
                         difference_scale=float(np.max(st.h_nodes)))

    def _stability_operators(self, height: int | None) -> dict[str, Any] | None:
        """The stability labels of the traced model: ``"force"`` (the Hessian with the loaded node's height
        free) and ``"displacement"`` (with it held), the control's own first; an indenter's ``"displacement"``
        (its travel held) and ``"force"`` (a dead load on it: the Hessian bordered by the travel).  ``height``:
        the traced-model dof of the loaded node's height (``2 i + 1``).  None (one label) under other loads."""
        from contin.analyses.deadload import bordered_matrix

        view = self.view
        if self.contact is not None:
            def dead_load(u: np.ndarray, p: float) -> sp.csr_matrix:
                _, mixed, cc = self.contact.position_derivatives(self.full_state(u, p), self.position(p))
                return bordered_matrix(self.jacobian(u, p), self.Tt @ mixed, cc)

            return {"displacement": self.jacobian, "force": dead_load}
        if self.load not in ("point", "ring") or height is None:
            return None
        other = view.reduction(control_fixed=[height] if self.control == "force" else [])
        restrict = other.restriction(view.pattern(False))

        def other_control(u: np.ndarray, p: float) -> sp.csr_matrix:
            return restrict(view.hessian(self.full_state(u, p)).data)

        return {self.control: self.jacobian, ("displacement" if self.control == "force" else "force"): other_control}

    def _bloch_family(self) -> Any:
        """The Bloch blocks of every class but the traced one as a :class:`contin.OperatorFamily` named
        ``"representation"`` (keys the names of the representations of ``D_n``, ``A2``, ``B1``, ``E1``, ...,
        :func:`contin_models.shell.fourier.representation_name`; the two-dimensional ones with multiplicity 2):
        with ``stability`` the engine counts the Morse index against every perturbation and locates where a
        class's block becomes singular, a bifurcation that breaks the traced symmetry."""
        from contin.watch.modes import OperatorFamily

        if not (self.basis.mirror and self.basis.j == 0):
            raise ValueError("Shell3D: every_mode needs a D_n basis (mirror=True)")
        view = self.view
        classes = {name: cls for name, cls in view.representations().items() if name != "A1"}

        def block(key: str, u: np.ndarray, p: float) -> sp.csr_matrix:
            j, parity, _ = classes[key]
            c = self.full_state(u, p)
            H = view.bloch_block(c, j, parity, pressure=self._pressure(p))
            if (j, parity) == (0, "odd"):
                H = self._without_turning(H, c)
            return H


        return OperatorFamily("representation", tuple(classes), block, multiplicity=lambda key: classes[key][2])

    def _gauge_dof(self, gauge: tuple[int, int]) -> int:
        """The coefficient a gauge holds: ``R sin k theta`` of ring ``node`` (at its reference value, zero)."""
        node, k = gauge
        basis, view = self.basis, self.view
        if basis.mirror or not view.turns_freely:
            raise ValueError("Shell3D: a gauge fixes the turning of states about the axis, which a basis without a "
                             "mirror (mirror=False) and a reference without waves have; this view has none to fix")
        # on the axis only the wave 1 (the pole's sideways position) is a coefficient of its own
        if not 0 <= node < self.structure.N or (node in self.structure.poles and k != 1):
            raise ValueError(f"Shell3D: the gauge's ring must be a node in [0, {self.structure.N - 1}], off the axis "
                             f"unless k = 1, got node {node} with k = {k}")
        try:
            return node * view.m + basis.index("R", "sin", k)
        except KeyError:
            raise ValueError(f"Shell3D: the gauge's wave k = {k} is not a wave of {basis!r}") from None

    def _without_turning(self, H: sp.csr_matrix, c: np.ndarray) -> sp.csr_matrix:
        """The ``A2`` block ``H`` at the state ``c`` with the state's turning about the axis taken out.

        A state with waves is one of a circle of states, the same state turned by any angle, all of the same
        energy: its turning direction (:meth:`FourierShell.turning_direction`) is a null vector of ``H`` up to
        the quadrature's aliasing, whose sign is noise.  Stability is that of the circle, the Morse index of
        ``H`` on the quotient by that direction, which is ``H``'s on any hyperplane the direction crosses: the
        block with the unknown along which the direction is largest held (its row and column replaced by a
        positive diagonal entry, so the block keeps its size and band).  An axisymmetric state is its own
        circle: its block is kept whole.
        """
        if not self.view.turns_freely:  # a reference with waves: turning changes the energy
            return H
        g = self.view.turning_direction(c)[self.view.bloch_unknowns(0, "odd")]
        size = float(np.max(np.abs(c[self.view.axisymmetric_dofs()]))) or 1.0
        if g.size == 0 or float(np.max(np.abs(g))) <= TURNING_NEGLIGIBLE * size:
            return H
        i = int(np.argmax(np.abs(g)))
        H = H.tocsr()
        rows = np.repeat(np.arange(H.shape[0]), np.diff(H.indptr))
        data = H.data.copy()
        data[(rows == i) | (H.indices == i)] = 0.0
        diagonal = np.flatnonzero((rows == i) & (H.indices == i))
        data[diagonal] = float(np.max(np.abs(H.diagonal()))) or 1.0
        return sp.csr_matrix((data, H.indices, H.indptr), shape=H.shape)

    def _line_load(self, k: int, node: int, wave: int, q: Sequence[float]) -> np.ndarray:
        """The unknowns' load vector of a line load on ring ``node``: ``int q(theta) . X(theta) dtheta``."""
        view, basis = self.view, self.basis
        q = np.asarray(q, dtype=float)
        if q.shape != (3,) or not np.all(np.isfinite(q)) or not np.any(q):
            raise ValueError(f"Shell3D: line_loads[{k}] needs a finite, nonzero (q_r, q_t, q_z), got {q!r}")
        if not 0 <= node < self.structure.N or node in self.structure.poles:
            raise ValueError(f"Shell3D: line_loads[{k}] acts on a ring: node in [0, {self.structure.N - 1}] off the "
                             f"axis, got {node}")
        if wave < 0 or wave not in set(basis.wave_numbers.tolist()):
            raise ValueError(f"Shell3D: line_loads[{k}] has wave number {wave}, which the basis does not carry "
                             f"(its waves: {basis.wave_numbers.tolist()})")
        # the integral of products of trigonometric polynomials, exactly by the trapezoidal rule
        M = 2 * (int(basis.wave_numbers.max()) + wave) + 2
        theta = 2.0 * math.pi * np.arange(M) / M
        density = q[:, None] * np.array([np.cos(wave * theta), np.sin(wave * theta), np.cos(wave * theta)])
        P = basis.ring_maps(theta)["P"]                               # (M, 3, m): frame components
        out = np.zeros(view.size)
        out[node * view.m:(node + 1) * view.m] = np.einsum("cq,qcj->j", density, P) * (2.0 * math.pi / M)
        return out

    # ---- maps between the coefficients and the unknowns -------------------------------------------
    @property
    def n(self) -> int:
        """Number of unknowns."""
        return self.reduction.free.size

    def full_state(self, u: np.ndarray, p: float = 0.0) -> np.ndarray:
        """Every ring's Fourier coefficients from the unknowns (and, under displacement control, ``w = p``)."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n,):
            raise ValueError(f"Shell3D: the unknown vector must have shape ({self.n},), got {u.shape}")
        held = self.c_ref
        if self.control == "displacement" and self.contact is None:
            held = held.copy()
            held[self.z_dof] = self.z_ref_node - float(p)
        return self.reduction.full(u, held)

    def unknowns(self, c: np.ndarray) -> np.ndarray:
        """The unknowns of a full coefficient vector (the pole's ``T`` is tied to its ``R``)."""
        return np.asarray(c, dtype=float)[self.reduction.free].copy()

    def reference_unknowns(self) -> np.ndarray:
        """The unknowns of the reference state, the equilibrium at zero load."""
        return self.unknowns(self.c_ref)

    # ---- the Problem interface -------------------------------------------------------------------
    def _pressure(self, p: float) -> float:
        return float(p) if self.load == "pressure" else 0.0

    def position(self, p: float) -> float:
        """The indenter's position at the travel ``p``: ``c0 - p``."""
        return self.c0 - float(p)

    def _gradient(self, c: np.ndarray, p: float) -> np.ndarray:
        g = self.view.gradient(c, self._pressure(p))
        if self.contact is not None:
            return g + self.contact.gradient(c, self.position(p))
        if self.load != "pressure" and self.control == "force":  # the dead loads' potential -p f.(c - c_ref)
            g = g - float(p) * self.load_vector
        return g

    def energy(self, u: np.ndarray, p: float) -> float:
        """The total energy: elastic, the pressure's ``p (V - V_ref)`` or the dead loads' potential."""
        c = self.full_state(u, p)
        if self.load == "pressure":  # p (V - V_ref): the potential vanishes in the reference state
            return self.view.energy(c, float(p)) - float(p) * self._v_ref
        e = self.view.energy(c)
        if self.contact is not None:
            return e + self.contact.energy(c, self.position(p))
        if self.control == "force":
            e -= float(p) * float(self.load_vector @ (c - self.c_ref))
        return e

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        """``dE/dp`` at fixed unknowns: under force control the volume change ``V - V_ref`` under a pressure,
        minus the displacement the dead loads work on (``-load_vector . (c - c_ref)``) otherwise, with which
        :class:`contin.ConjugateControl` prescribes the volume or the loaded points' displacement; under an
        indenter's travel the contact force, with which :class:`contin.DeadLoad` puts a force on it."""
        c = self.full_state(u, p)
        if self.contact is not None:  # dE/dw_b at fixed unknowns: the contact force (contin.DeadLoad on it)
            return -self.contact.position_derivatives(c, self.position(p))[0]
        if self.control != "force":
            raise ValueError("Shell3D.conjugate_force: the load is the parameter under force control (or the travel "
                             "of an indenter) only")
        if self.load == "pressure":
            return self.view.volume(c) - self._v_ref
        return -float(self.load_vector @ (c - self.c_ref))

    def conjugate_stiffness(self, u: np.ndarray, p: float) -> float:
        """``d2E/dp2`` at fixed unknowns: zero for the loads, which enter the energy linearly; the barrier's
        curvature in the indenter's position under an indenter's travel."""
        if self.contact is not None:
            return self.contact.position_derivatives(self.full_state(u, p), self.position(p))[2]
        return 0.0

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        return self.Tt @ self._gradient(self.full_state(u, p), p)

    def jacobian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        c = self.full_state(u, p)
        data = self.view.hessian(c, self._pressure(p), volume_pattern=self.load == "pressure").data
        if self.contact is not None:  # both on the view's pattern without the volume
            data = data + self.contact.hessian(c, self.position(p)).data
        return self._restrict(data)

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        c = self.full_state(u, p)
        if self.contact is not None:  # d/dp at fixed unknowns: the position moves by -dp
            return -(self.Tt @ self.contact.position_derivatives(c, self.position(p))[1])
        if self.load == "pressure":
            return self.Tt @ (self.view.gradient(c, 1.0) - self.view.gradient(c, 0.0))
        if self.control == "force":
            return -(self.Tt @ self.load_vector)
        return -(self.Tt @ symmetric_column(self.view.hessian(c), self.z_dof))  # z = z_ref - w

    def max_step_fraction(self, u: np.ndarray, p: float, du: np.ndarray, dp: float) -> float:
        """Under an indenter, the barrier's filter: no sample point may reach the indenter along the step."""
        if self.contact is None:
            return 1.0
        return self.contact.max_safe_fraction(self.full_state(u, p), self.position(p), self.T @ du, -float(dp))

    def _contact_force(self, u: np.ndarray, p: float) -> float:
        """The indenter's force on the shell, ``-dE/dc`` (positive pushing down)."""
        return -self.contact.position_derivatives(self.full_state(u, p), self.position(p))[0]

    def _dcontact_force(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        _, mixed, cc = self.contact.position_derivatives(self.full_state(u, p), self.position(p))
        return -(self.Tt @ mixed), cc

    def factorize(self, J) -> Factorization:
        """Banded Cholesky where the Jacobian (the energy's Hessian) is positive definite, else banded LU: O(N)
        at a fixed angular resolution."""
        return symmetric_band_factorization(J, max(self.kl, self.ku))

    # ---- observables -----------------------------------------------------------------------------
    def _obs_load(self, u: np.ndarray, p: float) -> float:
        if self.control == "force":
            return float(p)
        return -float(self._gradient(self.full_state(u, p), p)[self.z_dof])

    def _dobs_load(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        if self.control == "force":
            return np.zeros(self.n), 1.0
        col = symmetric_column(self.view.hessian(self.full_state(u, p)), self.z_dof)
        return -(self.Tt @ col), float(col[self.z_dof])

    def _obs_w(self, u: np.ndarray, p: float) -> float:
        if self.control == "displacement" and self.contact is None:
            return float(p)
        return self.z_ref_node - float(self.full_state(u, p)[self.z_dof])

    def _dobs_w(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        if self.control == "displacement" and self.contact is None:
            return np.zeros(self.n), 1.0
        d = np.zeros(self.view.size)
        d[self.z_dof] = -1.0
        return self.Tt @ d, 0.0

    def __repr__(self) -> str:
        return f"Shell3D({self.structure!r}, {self.basis!r}, load={self.load!r}, control={self.control!r})"


def gauge_for(basis: AngularBasis, c: np.ndarray) -> tuple[tuple[int, int], float]:
    """The gauge of :class:`Shell3D` for the state ``c`` of a basis without a mirror, and the angle to turn it by.

    The ring and wave whose ``R`` field moves most when the state turns (the largest ``k sqrt(a^2 + b^2)`` of
    ``R = a cos k theta + b sin k theta``, off the axis); turned by ``atan2(b, a) / k``
    (:func:`~contin_models.shell.fourier.transfer_coefficients`), the state has ``b = 0`` there.

    Raises
    ------
    ValueError
        The state has no waves (nothing turns).
    """
    rows = np.asarray(c, dtype=float).reshape(-1, basis.m)
    best, where = 0.0, None
    for k in sorted({t[2] for t in basis.terms if t[2] > 0}):
        a = rows[:, basis.index("R", "cos", k)]
        b = rows[:, basis.index("R", "sin", k)]
        size = k * np.hypot(a, b)
        i = int(np.argmax(size))
        if size[i] > best:
            best, where = float(size[i]), (i, k, math.atan2(b[i], a[i]) / k)
    if where is None:
        raise ValueError("gauge_for: the state has no waves: it does not turn")
    i, k, angle = where
    return (i, k), angle
