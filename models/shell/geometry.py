"""Reference (undeformed) geometry of the discrete spherical cap.

The meridian of a spherical cap of radius ``R`` lies in the ``(r, z)`` half plane ``r >= 0``.  Its
base is at polar angle ``phi_hat`` measured from the horizontal r-axis, i.e. at
``(R cos phi_hat, R sin phi_hat)``, and its pole at ``(0, R)`` (``docs/model.md#geometry``).  The
``N`` nodes run from the base (node 0) to the pole (node ``N-1``); traversed from base to pole the
meridian turns counter-clockwise, so its curvatures are positive.

Node spacing (:func:`theta_nodes`)
----------------------------------
By default the nodes are graded towards the pole: the spacing there is ``pole_ratio = 1/2`` of the
spacing over the rest of the cap, changing smoothly over a fixed fraction ``GRADING_WIDTH = 0.15``
of the meridian.  A point load makes the continuum bending moment log-singular at the pole, so a
uniform mesh converges like ``N^-2 log N``: for the default scene the force at ``w/R = 0.1``
converges at observed orders 1.79, 1.81, 1.82 over N = 50..800, while the graded mesh gives
1.94, 1.92, 1.92 with errors 0.56 to 0.75 times those of the uniform mesh at equal N (the linear
stiffness error about 0.35 times; the force maximum, which is not at the singular point, converges
at order 2.0 on both meshes with an error 1.19 times larger on the graded one).  ``python -m
studies.shell_mesh_convergence`` prints these numbers.  The grading map is odd in the distance from
the pole, so the meridian continued across the axis by its mirror image is a smooth mesh and the
discrete curvatures stay second-order accurate next to the pole.  ``pole_ratio = 1`` gives the
uniform mesh of the paper, node ``i`` at ``theta_i = phi_hat + i (pi/2 - phi_hat) / (N - 1)``, on
which ``kappa22 = 1/R`` holds exactly (on a graded mesh it holds to O(spacing^2); the reference
curvatures are always computed from the discrete geometry, so the reference state is stress free
either way).

Notation (paper section 3(a)): edge ``i`` joins nodes ``i`` and ``i+1``; its length ``l^i`` and
radius ``r^i = (r_i + r_{i+1}) / 2`` are edge quantities, and the Voronoi length
``l_i = (l^{i-1} + l^i) / 2`` is a node quantity.  At the two end nodes, which have a single edge,
the Voronoi length is half that edge.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _generated as gen

__all__ = ["ReferenceCap", "spherical_cap", "reference_quantities", "theta_nodes", "grading_map", "interleave", "split", "POLE_RATIO", "GRADING_WIDTH"]

#: Default ratio of the node spacing at the pole to the spacing away from it (1: uniform mesh).
POLE_RATIO = 0.5
#: Fraction of the meridian (from the pole) over which the graded spacing blends into the uniform one.
GRADING_WIDTH = 0.15


def grading_map(t, pole_ratio: float = POLE_RATIO, width: float = GRADING_WIDTH):
    """The pole grading map ``G(t) = (t - (1 - q) w tanh(t / w)) / (1 - (1 - q) w tanh(1 / w))``.

    ``t`` is the node-index coordinate counted from the pole (0 at the pole, 1 at the base) and
    ``G(t)`` the fraction of the meridian between the node and the pole (:func:`theta_nodes`; also
    used by :func:`contin_models.shell.meridian.meridian`).  ``G(0) = 0``, ``G(1) = 1``; ``G`` is odd
    and increasing with ``G'(t)`` proportional to ``1 - (1 - q) sech^2(t / w)`` (``q`` at the pole).
    Scalars or arrays ``t``; the arguments are not checked (see :func:`theta_nodes`).
    """
    a = (1.0 - pole_ratio) * width
    return (t - a * np.tanh(t / width)) / (1.0 - a * math.tanh(1.0 / width))


def theta_nodes(phi_hat: float, N: int, pole_ratio: float = POLE_RATIO, width: float = GRADING_WIDTH) -> np.ndarray:
    """Polar angles of the ``N`` nodes, base (``phi_hat``) to pole (``pi/2``), graded towards the pole.

    With ``t = 1 - i/(N-1)`` (1 at the base, 0 at the pole) the angular distance from the pole is
    ``alpha G(t)``, ``alpha = pi/2 - phi_hat``, with the N-independent map
    ``G(t) = (t - (1 - q) w tanh(t / w)) / (1 - (1 - q) w tanh(1 / w))``, ``q = pole_ratio``,
    ``w = width``.  The spacing is proportional to ``G'(t) = 1 - (1 - q) sech^2(t / w)``: ``q`` times
    the base spacing at the pole, uniform away from it.  ``G`` is odd, so the mesh mirrored across
    the axis is smooth.

    Parameters
    ----------
    phi_hat : float
        Polar angle of the base, in ``(0, pi/2)``.
    N : int
        Number of nodes, ``>= 3``.
    pole_ratio : float
        Spacing at the pole relative to the base, in ``(0, 1]``; 1 gives the uniform mesh.
    width : float
        Width of the graded zone as a fraction of the meridian, ``> 0``.

    Returns
    -------
    ndarray, shape ``(N,)``
        Increasing angles with ``theta[0] = phi_hat`` and ``theta[-1] = pi/2`` exactly.
    """
    if not (0.0 < pole_ratio <= 1.0):
        raise ValueError(f"theta_nodes: pole_ratio must be in (0, 1], got {pole_ratio!r}")
    if not (width > 0.0 and math.isfinite(width)):
        raise ValueError(f"theta_nodes: width must be a positive number, got {width!r}")
    alpha = 0.5 * math.pi - phi_hat
    if pole_ratio == 1.0:
        theta = phi_hat + alpha * np.arange(N) / (N - 1)
    else:
        t = 1.0 - np.arange(N) / (N - 1)
        theta = 0.5 * math.pi - alpha * grading_map(t, pole_ratio, width)
    theta[0], theta[-1] = phi_hat, 0.5 * math.pi
    return theta


def interleave(r: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Pack node coordinates into the state vector ``[r_0, z_0, r_1, z_1, ...]``.

    Parameters
    ----------
    r, z : ndarray, shape ``(N,)``
        Node coordinates.

    Returns
    -------
    ndarray, shape ``(2 N,)``
    """
    r = np.asarray(r, dtype=float)
    x = np.empty(2 * r.size)
    x[0::2] = r
    x[1::2] = z
    return x


def split(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Views ``(r, z)`` of an interleaved state vector ``[r_0, z_0, r_1, z_1, ...]``.

    Parameters
    ----------
    x : ndarray, shape ``(2 N,)``

    Returns
    -------
    r, z : ndarray, shape ``(N,)``
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size % 2:
        raise ValueError(f"state vector must be 1-d with an even length, got shape {x.shape}")
    return x[0::2], x[1::2]


@dataclass(frozen=True, eq=False)
class ReferenceCap:
    """The discretised reference spherical cap.  Build it with :func:`spherical_cap`.

    Attributes
    ----------
    R : float
        Sphere radius.
    phi_hat : float
        Polar angle of the base, from the horizontal axis, in ``(0, pi/2)``.
    N : int
        Number of nodes (base = node 0, pole = node ``N-1``).
    theta : ndarray, shape ``(N,)``
        Polar angle of each node.
    r, z : ndarray, shape ``(N,)``
        Node coordinates (``r[-1] = 0`` and ``z[-1] = R`` exactly).
    edge_length : ndarray, shape ``(N-1,)``
        Reference edge lengths ``lbar^i`` (chords).
    edge_radius : ndarray, shape ``(N-1,)``
        Reference edge radii ``rbar^i = (r_i + r_{i+1}) / 2``.
    voronoi_length : ndarray, shape ``(N,)``
        Reference Voronoi lengths ``lbar_i`` (half an edge at the two end nodes).
    node_radius : ndarray, shape ``(N,)``
        Reference node radii ``rbar_i = r_i``.
    kappa11, kappa22 : ndarray, shape ``(N,)``
        Reference discrete curvatures at the interior nodes ``1 .. N-2`` from the same formulas as
        the bending element (on the uniform mesh ``kappa11 = 1 / (R cos(dtheta / 2))``, ``kappa22 = 1 / R`` up to
        round-off); NaN at the base and the pole, where the interior-node formulas do not apply.
    """

    R: float
    phi_hat: float
    N: int
    theta: np.ndarray
    r: np.ndarray
    z: np.ndarray
    edge_length: np.ndarray
    edge_radius: np.ndarray
    voronoi_length: np.ndarray
    node_radius: np.ndarray
    kappa11: np.ndarray
    kappa22: np.ndarray
    pole_ratio: float = 1.0

    @property
    def x(self) -> np.ndarray:
        """Reference state vector ``[r_0, z_0, r_1, z_1, ...]`` (a new array)."""
        return interleave(self.r, self.z)

    @property
    def dtheta(self) -> float:
        """Angle subtended by one edge on the uniform mesh, ``(pi/2 - phi_hat) / (N - 1)``; the largest one on a graded mesh."""
        if self.pole_ratio == 1.0:
            return (0.5 * math.pi - self.phi_hat) / (self.N - 1)
        return float(np.max(np.diff(self.theta)))

    @property
    def alpha(self) -> float:
        """Half-opening angle of the cap, ``pi/2 - phi_hat``."""
        return 0.5 * math.pi - self.phi_hat


def reference_quantities(r: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, ...]:
    """Edge lengths and radii, Voronoi lengths and discrete curvatures of a reference polyline.

    Parameters
    ----------
    r, z : ndarray, shape ``(N,)``
        Node coordinates, edge (node 0) to pole (node ``N-1``).

    Returns
    -------
    edge_length, edge_radius : ndarray, shape ``(N-1,)``
        Chords ``lbar^i`` and radii ``rbar^i = (r_i + r_{i+1}) / 2``.
    voronoi_length : ndarray, shape ``(N,)``
        Half the sum of a node's edges (half an edge at the two end nodes).
    kappa11, kappa22 : ndarray, shape ``(N,)``
        Discrete curvatures at the interior nodes from the bending element's own formulas; NaN at the
        two end nodes.
    """
    N = r.size
    dr, dz = np.diff(r), np.diff(z)
    edge_length = np.sqrt(dr**2 + dz**2)
    edge_radius = 0.5 * (r[:-1] + r[1:])
    voronoi_length = np.zeros(N)
    voronoi_length[:-1] += 0.5 * edge_length
    voronoi_length[1:] += 0.5 * edge_length
    kappa11 = np.full(N, np.nan)
    kappa22 = np.full(N, np.nan)
    k11, k22 = gen.bend_curvatures(r[:-2], z[:-2], r[1:-1], z[1:-1], r[2:], z[2:],
                                   voronoi_length[1:-1], r[1:-1], 0.0, 0.0, 1.0, 0.0)
    kappa11[1:-1] = k11
    kappa22[1:-1] = k22
    return edge_length, edge_radius, voronoi_length, kappa11, kappa22


def spherical_cap(R: float, phi_hat: float, N: int, pole_ratio: float = POLE_RATIO) -> ReferenceCap:
    """Discretise the reference spherical cap with ``N`` nodes (graded towards the pole, see :func:`theta_nodes`).

    Parameters
    ----------
    R : float
        Sphere radius, ``> 0``.
    phi_hat : float
        Polar angle of the base measured from the horizontal axis, in ``(0, pi/2)``.
    N : int
        Number of nodes, ``>= 3``.
    pole_ratio : float
        Node spacing at the pole relative to the rest of the cap, in ``(0, 1]`` (1: uniform in arc
        length, as in the paper).

    Returns
    -------
    ReferenceCap
    """
    R = float(R)
    phi_hat = float(phi_hat)
    if not (R > 0 and math.isfinite(R)):
        raise ValueError(f"spherical_cap: R must be a positive number, got {R!r}")
    if not (0.0 < phi_hat < 0.5 * math.pi):
        raise ValueError(f"spherical_cap: phi_hat must be in (0, pi/2), got {phi_hat!r}")
    if int(N) != N or N < 3:
        raise ValueError(f"spherical_cap: N must be an integer >= 3, got {N!r}")
    N = int(N)
    theta = theta_nodes(phi_hat, N, float(pole_ratio))
    r = R * np.cos(theta)
    z = R * np.sin(theta)
    r[-1], z[-1] = 0.0, R  # the pole exactly on the axis
    edge_length, edge_radius, voronoi_length, kappa11, kappa22 = reference_quantities(r, z)
    for a in (theta, r, z, edge_length, edge_radius, voronoi_length, kappa11, kappa22):
        a.setflags(write=False)
    return ReferenceCap(R=R, phi_hat=phi_hat, N=N, theta=theta, r=r, z=z, edge_length=edge_length,
                        edge_radius=edge_radius, voronoi_length=voronoi_length, node_radius=r,
                        kappa11=kappa11, kappa22=kappa22, pole_ratio=float(pole_ratio))
