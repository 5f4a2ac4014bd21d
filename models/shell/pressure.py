"""Uniform pressure on the discrete spherical cap, as a :class:`contin.Problem` (issue 16, first step).

The energy is ``E_el(x) + p (V(x) - V0)`` (``docs/revolution.md`` section 3): the elastic energy of
:class:`contin_models.shell.ShellPointLoad`'s free shell (stretching, bending and the pole's mirror
element, reused through a displacement-controlled ``ShellPointLoad``, see :attr:`ShellPressure.elastic`)
plus the potential of an external pressure ``p`` (positive pushing the cap in) from
:class:`contin_models.shell.volume.PressureTerm`, with the base plane fixed at the reference base
height.  The pressure is the parameter (force control); ``df/dp = dV`` exactly.

Supports (``docs/revolution.md`` section 2)
-------------------------------------------
``"sliding"``
    ``z_0`` fixed, ``r_0`` free: the paper's base.
``"pinned"``
    ``r_0`` and ``z_0`` fixed; the edge rotates freely (no bending element at the base node, as in
    the free shell).
``"clamped"``
    ``r_0`` and ``z_0`` fixed and the edge rotation held by :class:`ClampedEdge`: a bending element at
    the base node whose second edge is the first edge of the shell and whose first edge ends at a
    fixed ghost node on the reference *tangent* at the base, continued beyond the edge.

Why the ghost sits on the tangent, with the element over the half cell inside the shell
-------------------------------------------------------------------------------------------
A bending element of an interior node measures ``kappa11 = 2 tan(xi/2) / L`` from the turning angle
``xi`` between its two edges.  At a clamped edge the shell's tangent keeps its reference direction,
and the chord of the first edge (length ``l``) makes with that tangent the angle ``kappa l / 2 +
O(l^2)``, ``kappa`` the edge curvature.  So the turning angle between the fixed tangent and the first
chord, over ``L = l / 2``, is the edge curvature to first order, both in the reference state (where
it gives ``kappabar ~ 1/R``) and under any deformation that keeps the tangent: the element measures
the edge curvature change and weighs it with the half cell ``pi r_0 l / 2`` that the base node owns
inside the shell (the same nodal quadrature as the interior nodes, whose cells are their Voronoi
lengths).  The length ``L = l/2`` is the reference one (the generated ``"bend"`` kernel), since the
current-length kernel would average the first edge with the ghost edge; the base node is fixed, so
the two lengths differ only by the first edge's membrane strain.

The other natural choice, a fixed ghost on the sphere continued beyond the edge (the
reflection of node 1 about the edge in the reference angle) with the interior element's full
Voronoi length ``l``, measures half the curvature change: with the ghost held, only the first edge
turns, by ``kappa l / 2``, whereas an interior element sees both its edges turn.  It still clamps the
edge (the element penalizes the first chord's rotation), but with the edge curvature at the base
node off by a factor 2, i.e. an O(1) error on one node of the boundary layer.  The tangent ghost has
no such error.  Only the ghost's direction matters (with the reference-length kernel neither
``kappa11`` nor ``kappa22``, through the normal bisecting the two edges' normals, depends on the
ghost's distance); it is put one first-edge length away.

``tests/test_shell_pressure.py`` checks the clamp against the membrane solution of a deep cap and
against the free rotation of the pinned edge.

Unknowns
--------
The full interleaved state ``x = [r_0, z_0, ..., r_{N-1}, z_{N-1}]`` without the fixed dofs:
``z_0`` and ``r_{N-1}`` always (the pole on the axis), ``r_0`` too when pinned or clamped.  The pole
height ``z_{N-1}`` is the last unknown.  The Hessian keeps the shell's half-bandwidth 5
(:data:`contin_models.shell.energy.HALF_BANDWIDTH`); the volume's and the clamp's couplings lie inside it.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
import scipy.sparse as sp

from contin.linalg import BandedLU, Factorization
from contin.problem import Problem

from . import _generated as gen
from .energy import HALF_BANDWIDTH
from .geometry import ReferenceCap
from .problem import ShellPointLoad, SubMatrix, csr_slots, shell_residual_scale
from .volume import PressureTerm, volume_gradient, volume_hessian

__all__ = ["ShellPressure", "ClampedEdge", "BOUNDARIES", "classical_pressure", "cap_lambda",
           "phi_hat_for_lambda"]

BOUNDARIES = ("clamped", "pinned", "sliding")
"""The supports of the base edge (module docstring)."""

#: Hessians (with the pressure and the clamp) kept by :class:`ShellPressure`: the engine asks for
#: the Jacobian, the stability operator and observable derivatives at the same state.
_HESSIAN_CACHE_SIZE = 2


def classical_pressure(E: float, h: float, R: float, nu: float) -> float:
    """Classical buckling pressure of the complete sphere, ``p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2))``."""
    return 2.0 * E * (h / R) ** 2 / math.sqrt(3.0 * (1.0 - nu * nu))


def cap_lambda(R: float, h: float, phi_hat: float, nu: float) -> float:
    """Shallow-cap parameter ``lambda = 2 (3 (1 - nu^2))^(1/4) sqrt(H / h)``, ``H = R (1 - sin phi_hat)``.

    The rise ``H`` is that of the cap whose base is at ``phi_hat`` from the equator
    (``docs/revolution.md`` sections 1 and 5).  It is not the paper's ``lambda``
    (:func:`contin_models.shell.boundaries.depth_parameter`), which it equals in the shallow limit.
    """
    H = R * (1.0 - math.sin(phi_hat))
    return 2.0 * (3.0 * (1.0 - nu * nu)) ** 0.25 * math.sqrt(H / h)


def phi_hat_for_lambda(lam: float, R: float, h: float, nu: float) -> float:
    """The base angle ``phi_hat`` of the cap with :func:`cap_lambda` equal to ``lam`` (inverse map)."""
    H = h * (lam / 2.0) ** 2 / math.sqrt(3.0 * (1.0 - nu * nu))
    if not 0.0 < H < R:
        raise ValueError(f"phi_hat_for_lambda: lambda = {lam!r} needs a rise H = {H!r} in (0, R = {R!r})")
    return math.asin(1.0 - H / R)


class ClampedEdge:
    """Bending element of the base node against a fixed ghost node on the reference edge tangent.

    The element is the interior nodes' bending element (generated ``"bend"`` kernel: ``kappa11``
    over the reference length given) on the nodes ``(ghost, 0, 1)``, with length and weight the
    half of the first reference edge inside the shell; the module docstring explains the choice.

    Parameters
    ----------
    cap : ReferenceCap
        The reference cap (node 0 is the edge).
    kb, nu : float
        Bending stiffness ``E h^3 / (12 (1 - nu^2))`` and Poisson's ratio.
    """

    #: Full-state dofs of the element's real nodes (0 and 1): ``r_0, z_0, r_1, z_1``.
    dofs = np.arange(4)

    def __init__(self, cap: ReferenceCap, kb: float, nu: float) -> None:
        theta = float(cap.theta[0])
        l0 = float(cap.edge_length[0])
        # the meridian runs base -> pole with increasing theta, tangent (-sin, cos); the ghost lies
        # one edge length behind the base along it
        self.ghost = (float(cap.r[0]) + l0 * math.sin(theta), float(cap.z[0]) - l0 * math.cos(theta))
        self.lbar = 0.5 * l0  # the base node's cell inside the shell
        self.rbar = float(cap.r[0])
        self.kb, self.nu = float(kb), float(nu)
        k11, k22 = gen.bend_curvatures(*self.ghost, cap.r[0], cap.z[0], cap.r[1], cap.z[1],
                                       self.lbar, self.rbar, 0.0, 0.0, self.kb, self.nu)
        self.kappa_bar = (float(k11), float(k22))

    def _args(self, x: np.ndarray) -> tuple:
        return (*self.ghost, x[0], x[1], x[2], x[3], self.lbar, self.rbar, *self.kappa_bar, self.kb, self.nu)

    def curvatures(self, x: np.ndarray) -> tuple[float, float]:
        """``(kappa11, kappa22)`` at the base node of a full state."""
        k11, k22 = gen.bend_curvatures(*self._args(x))
        return float(k11), float(k22)

    def energy(self, x: np.ndarray) -> float:
        """Element energy ``pi rbar lbar kb (B11^2 + 2 nu B11 B22 + B22^2)`` of a full state."""
        return float(gen.bend_energy(*self._args(x)))

    def gradient(self, x: np.ndarray) -> np.ndarray:
        """Gradient (4,) in :attr:`dofs` (the ghost's entries are dropped: it is fixed)."""
        return gen.bend_gradient(*self._args(x))[2:]

    def hessian(self, x: np.ndarray) -> np.ndarray:
        """Hessian (4, 4) in :attr:`dofs`."""
        return gen.bend_hessian(*self._args(x))[2:, 2:]


class ShellPressure(Problem):
    """Spherical cap under a uniform external pressure ``p`` (the parameter), on a chosen support.

    Parameters
    ----------
    R, E, nu, h, phi_hat : float
        Sphere radius, Young's modulus, Poisson's ratio, thickness and base angle from the equator
        (``docs/physics.md`` section 1).
    N : int
        Number of nodes (base = 0, pole = ``N-1``).
    boundary : {"clamped", "pinned", "sliding"}
        Support of the base edge (module docstring).
    pole_ratio : float
        Node spacing at the pole over the spacing elsewhere.  Default 1 (uniform): a pressure has no
        point-load singularity at the pole for a grading to resolve.
    kappa11_length : {"reference", "current"}
        Length in the interior nodes' ``kappa11`` (as in :class:`ShellPointLoad`).

    Notes
    -----
    Observables: ``p``, ``w`` (pole deflection ``zbar_pole - z_pole``, positive inwards),
    ``w_over_h``, ``p_over_p_c`` (:func:`classical_pressure`) and ``V`` (the enclosed volume above
    the reference base plane), all with exact derivatives.  ``residual_scale`` is
    :func:`contin_models.shell.problem.shell_residual_scale` on this problem's unknowns, as for
    :class:`ShellPointLoad` (its Notes explain the two terms).
    """

    def __init__(self, R: float = 1.0, E: float = 1e6, nu: float = 0.3, h: float = 0.01, phi_hat: float = 0.8,
                 N: int = 200, boundary: Literal["clamped", "pinned", "sliding"] = "clamped",
                 pole_ratio: float = 1.0, kappa11_length: Literal["reference", "current"] = "current") -> None:
        if boundary not in BOUNDARIES:
            raise ValueError(f"ShellPressure: boundary must be one of {BOUNDARIES}, got {boundary!r}")
        # the free shell with the pole's mirror element: its energy is the elastic part of ours
        self.elastic = ShellPointLoad(R, E, nu, h, phi_hat, N, "displacement", kappa11_length, "mirror", pole_ratio)
        el = self.elastic
        self.cap = el.cap
        self.R, self.E, self.nu, self.h, self.phi_hat, self.N = el.R, el.E, el.nu, el.h, el.phi_hat, el.N
        self.boundary = boundary
        self.p_c = classical_pressure(self.E, self.h, self.R, self.nu)
        self.pressure = PressureTerm.from_reference(self.cap.x)
        self.z_pole_ref = el.z_pole_ref
        n = el.n_full
        self.n_full = n
        fixed = {1, n - 2} | ({0} if boundary in ("pinned", "clamped") else set())  # z_0, r_{N-1}, r_0
        self.idx = np.array([i for i in range(n) if i not in fixed])

        H0 = el.elastic_hessian(self.cap.x)
        self._sub = SubMatrix(H0, self.idx)
        # the volume Hessian's fixed pattern, scattered into the shell's (it lies inside the band)
        HV = volume_hessian(self.cap.x, self.pressure.z_ref)
        self._v_nnz = HV.nnz
        self._v_slots = csr_slots(H0, np.repeat(np.arange(n), np.diff(HV.indptr)), HV.indices)
        if boundary == "clamped":
            self.clamp: ClampedEdge | None = ClampedEdge(self.cap, el.shell.kb, el.shell.nu)
            rr, cc = np.meshgrid(ClampedEdge.dofs, ClampedEdge.dofs, indexing="ij")
            self._clamp_slots = csr_slots(H0, rr.ravel(), cc.ravel())
        else:
            self.clamp = None
        self._cache: list[tuple[np.ndarray, float, sp.csr_matrix]] = []

        scale = shell_residual_scale(self.E, self.h, self.R, self._sub(self._structure_hessian(self.cap.x)))
        observables = {"p": lambda u, p: float(p), "w": self._obs_w,
                       "w_over_h": lambda u, p: self._obs_w(u, p) / self.h,
                       "p_over_p_c": lambda u, p: float(p) / self.p_c, "V": self._obs_V}
        derivatives = {"p": lambda u, p: (np.zeros(self.n), 1.0), "w": self._dobs_w,
                       "w_over_h": lambda u, p: (self._dobs_w(u, p)[0] / self.h, 0.0),
                       "p_over_p_c": lambda u, p: (np.zeros(self.n), 1.0 / self.p_c),
                       "V": lambda u, p: (volume_gradient(self.full_state(u), self.pressure.z_ref)[self.idx], 0.0)}
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         name=f"shell_pressure_{boundary}", parameter_name="p", residual_scale=scale)

    # ---- maps between the full state and the unknowns --------------------------------------------
    @property
    def n(self) -> int:
        """Number of unknowns."""
        return self.idx.size

    def full_state(self, u: np.ndarray, p: float = 0.0) -> np.ndarray:
        """Full interleaved state from the unknowns (the fixed dofs at their reference values)."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n,):
            raise ValueError(f"unknown vector must have shape ({self.n},), got {u.shape}")
        x = self.cap.x
        x[self.idx] = u
        return x

    def unknowns(self, x: np.ndarray) -> np.ndarray:
        """The unknowns of a full state (the fixed dofs are dropped, not checked)."""
        return np.asarray(x, dtype=float)[self.idx].copy()

    def reference_unknowns(self) -> np.ndarray:
        """Unknowns of the reference (stress-free) state, the equilibrium at ``p = 0``."""
        return self.unknowns(self.cap.x)

    def lam(self) -> float:
        """This cap's shallow-cap parameter :func:`cap_lambda`."""
        return cap_lambda(self.R, self.h, self.phi_hat, self.nu)

    # ---- energy of the structure (elastic + clamp) and of the pressure ----------------------------
    def structure_energy(self, x: np.ndarray) -> float:
        """Elastic energy of a full state, with the clamp's element when clamped."""
        e = self.elastic.elastic_energy(x)
        return e + self.clamp.energy(x) if self.clamp is not None else e

    def _structure_gradient(self, x: np.ndarray) -> np.ndarray:
        g = self.elastic.elastic_gradient(x)
        if self.clamp is not None:
            g[ClampedEdge.dofs] += self.clamp.gradient(x)
        return g

    def _structure_hessian(self, x: np.ndarray) -> sp.csr_matrix:
        H = self.elastic.elastic_hessian(x)  # a copy: the shell's cached matrix is shared
        if self.clamp is not None:
            H.data[self._clamp_slots] += self.clamp.hessian(x).ravel()
        return H

    def _hessian(self, x: np.ndarray, p: float) -> sp.csr_matrix:
        """Full Hessian ``d2E_el + p d2V`` (shell pattern); shared with the cache, do not modify."""
        for xc, pc, Hc in self._cache:
            if pc == p and np.array_equal(xc, x):
                return Hc
        H = self._structure_hessian(x)
        HV = volume_hessian(x, self.pressure.z_ref)
        assert HV.nnz == self._v_nnz  # the pattern is fixed (stored zeros kept)
        H.data[self._v_slots] += float(p) * HV.data
        self._cache.insert(0, (x.copy(), float(p), H))
        del self._cache[_HESSIAN_CACHE_SIZE:]
        return H

    # ---- the Problem interface -------------------------------------------------------------------
    def energy(self, u: np.ndarray, p: float) -> float:
        x = self.full_state(u)
        return self.structure_energy(x) + self.pressure.energy(x, p)

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        x = self.full_state(u)
        return (self._structure_gradient(x) + self.pressure.gradient(x, p))[self.idx]

    def jacobian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        return self._sub(self._hessian(self.full_state(u), p))

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        return self.pressure.gradient_dp(self.full_state(u))[self.idx]

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        """``dE/dp = V - V0``, the volume change (the pressure's conjugate)."""
        return self.pressure.energy_dp(self.full_state(u))

    def factorize(self, J) -> Factorization:
        """Banded LU with the shell's half-bandwidth (O(N))."""
        return BandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH)

    # ---- observables -----------------------------------------------------------------------------
    def _obs_w(self, u: np.ndarray, p: float) -> float:
        return self.z_pole_ref - float(u[-1])  # the pole height is the last unknown

    def _dobs_w(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        d = np.zeros(self.n)
        d[-1] = -1.0
        return d, 0.0

    def _obs_V(self, u: np.ndarray, p: float) -> float:
        return self.pressure.volume(self.full_state(u))

    def edge_rotation(self, x: np.ndarray) -> float:
        """Rotation of the first edge (chord) from its reference direction, radians, counter-clockwise."""
        ref = self.cap.x
        a = math.atan2(x[3] - x[1], x[2] - x[0])
        b = math.atan2(ref[3] - ref[1], ref[2] - ref[0])
        return (a - b + math.pi) % (2.0 * math.pi) - math.pi

    # ---- linear response -------------------------------------------------------------------------
    def linear_response(self) -> np.ndarray:
        """``dx/dp`` at the reference state (full state, zero on the fixed dofs): ``J du = -dV``."""
        u0 = self.reference_unknowns()
        du = self.factorize(self.jacobian(u0, 0.0)).solve(-self.dresidual_dp(u0, 0.0))
        dx = np.zeros(self.n_full)
        dx[self.idx] = du
        return dx

    def __repr__(self) -> str:
        return (f"ShellPressure(R={self.R}, E={self.E}, nu={self.nu}, h={self.h}, phi_hat={self.phi_hat}, "
                f"N={self.N}, boundary={self.boundary!r}, pole_ratio={self.cap.pole_ratio})")
