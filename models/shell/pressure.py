"""Uniform pressure on the discrete spherical cap, as a :class:`contin.Problem` (issue 16).

The energy is ``E_el(x) + p (V(x) - V0)`` (``docs/model.md#loads``): the elastic energy of
the shell (stretching, bending and the pole's mirror element, as for
:class:`contin_models.shell.ShellPointLoad`) plus the potential of an external pressure ``p``
(positive pushing the cap in) from :class:`contin_models.shell.volume.PressureTerm`, with the base
plane fixed at the reference base height.  The pressure is the parameter (force control);
``df/dp = dV`` exactly.  :class:`ShellPressure` is the spherical cap's case of the general
:class:`contin_models.shell.structure.ShellOfRevolution` (any meridian, any support, any load), which
holds the mechanism; this module keeps the cap's constructor, its normalisations and the reasoning
behind the clamp.

Supports (``docs/model.md#supports``)
-------------------------------------
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

from .elements import ClampedEdge
from .geometry import spherical_cap
from .structure import ShellOfRevolution, ShellStructure

__all__ = ["ShellPressure", "ClampedEdge", "BOUNDARIES", "classical_pressure", "cap_lambda",
           "phi_hat_for_lambda"]

BOUNDARIES = ("clamped", "pinned", "sliding")
"""The supports of the base edge (module docstring)."""


def classical_pressure(E: float, h: float, R: float, nu: float) -> float:
    """Classical buckling pressure of the complete sphere, ``p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2))``."""
    return 2.0 * E * (h / R) ** 2 / math.sqrt(3.0 * (1.0 - nu * nu))


def cap_lambda(R: float, h: float, phi_hat: float, nu: float) -> float:
    """Shallow-cap parameter ``lambda = 2 (3 (1 - nu^2))^(1/4) sqrt(H / h)``, ``H = R (1 - sin phi_hat)``.

    The rise ``H`` is that of the cap whose base is at ``phi_hat`` from the equator
    (``docs/model.md#classical-values``).  It is not the paper's ``lambda``
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


class ShellPressure(ShellOfRevolution):
    """Spherical cap under a uniform external pressure ``p`` (the parameter), on a chosen support.

    Parameters
    ----------
    R, E, nu, h, phi_hat : float
        Sphere radius, Young's modulus, Poisson's ratio, thickness and base angle from the equator
        (``docs/model.md#geometry``).
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
    ``w_over_h``, ``w_over_L`` (over ``R``), ``p_over_p_c`` (:func:`classical_pressure`) and ``V``
    (the enclosed volume above the reference base plane), all with exact derivatives.
    ``residual_scale`` is :func:`contin_models.shell.problem.shell_residual_scale` on this problem's
    unknowns, as for :class:`ShellPointLoad` (its Notes explain the two terms).
    """

    def __init__(self, R: float = 1.0, E: float = 1e6, nu: float = 0.3, h: float = 0.01, phi_hat: float = 0.8,
                 N: int = 200, boundary: Literal["clamped", "pinned", "sliding"] = "clamped",
                 pole_ratio: float = 1.0, kappa11_length: Literal["reference", "current"] = "current") -> None:
        if boundary not in BOUNDARIES:
            raise ValueError(f"ShellPressure: boundary must be one of {BOUNDARIES}, got {boundary!r}")
        self.cap = spherical_cap(R, phi_hat, N, pole_ratio)
        self.R, self.E, self.nu, self.h, self.phi_hat, self.N = (float(R), float(E), float(nu), float(h),
                                                                 float(phi_hat), int(N))
        structure = ShellStructure(self.cap, E, nu, h, boundary, kappa11_length)
        super().__init__(structure, "pressure", "force", length=self.R,
                         p_c=classical_pressure(self.E, self.h, self.R, self.nu))
        self.name = f"shell_pressure_{boundary}"
        self.boundary = boundary
        self.clamp = structure.clamp
        self.z_pole_ref = float(self.cap.z[-1])
        self.n_full = structure.n_full

    def lam(self) -> float:
        """This cap's shallow-cap parameter :func:`cap_lambda`."""
        return cap_lambda(self.R, self.h, self.phi_hat, self.nu)

    def edge_rotation(self, x: np.ndarray) -> float:
        """Rotation of the first edge (chord) from its reference direction, radians, counter-clockwise."""
        ref = self.cap.x
        a = math.atan2(x[3] - x[1], x[2] - x[0])
        b = math.atan2(ref[3] - ref[1], ref[2] - ref[0])
        return (a - b + math.pi) % (2.0 * math.pi) - math.pi

    def __repr__(self) -> str:
        return (f"ShellPressure(R={self.R}, E={self.E}, nu={self.nu}, h={self.h}, phi_hat={self.phi_hat}, "
                f"N={self.N}, boundary={self.boundary!r}, pole_ratio={self.cap.pole_ratio})")
