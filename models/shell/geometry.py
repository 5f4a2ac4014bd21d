"""Reference (undeformed) geometry of the discrete spherical cap.

The meridian of a spherical cap of radius ``R`` lies in the ``(r, z)`` half plane ``r >= 0``.  Its
base is at polar angle ``phi_hat`` measured from the horizontal r-axis, i.e. at
``(R cos phi_hat, R sin phi_hat)``, and its pole at ``(0, R)`` (``docs/physics.md`` section 1).  The
``N`` nodes are uniformly spaced in arc length from the base (node 0) to the pole (node ``N-1``):
node ``i`` is at polar angle ``theta_i = phi_hat + i (pi/2 - phi_hat) / (N - 1)``.  Traversed from
base to pole the meridian turns counter-clockwise, so its curvatures are positive.

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

__all__ = ["ReferenceCap", "spherical_cap", "interleave", "split"]


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
        the bending element (``kappa11 = 1 / (R cos(dtheta / 2))``, ``kappa22 = 1 / R`` up to
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

    @property
    def x(self) -> np.ndarray:
        """Reference state vector ``[r_0, z_0, r_1, z_1, ...]`` (a new array)."""
        return interleave(self.r, self.z)

    @property
    def dtheta(self) -> float:
        """Angle subtended by one edge, ``(pi/2 - phi_hat) / (N - 1)``."""
        return (0.5 * math.pi - self.phi_hat) / (self.N - 1)

    @property
    def alpha(self) -> float:
        """Half-opening angle of the cap, ``pi/2 - phi_hat``."""
        return 0.5 * math.pi - self.phi_hat


def spherical_cap(R: float, phi_hat: float, N: int) -> ReferenceCap:
    """Discretise the reference spherical cap with ``N`` nodes uniform in arc length.

    Parameters
    ----------
    R : float
        Sphere radius, ``> 0``.
    phi_hat : float
        Polar angle of the base measured from the horizontal axis, in ``(0, pi/2)``.
    N : int
        Number of nodes, ``>= 3``.

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
    theta = phi_hat + (0.5 * math.pi - phi_hat) * np.arange(N) / (N - 1)
    r = R * np.cos(theta)
    z = R * np.sin(theta)
    r[-1], z[-1] = 0.0, R  # the pole exactly on the axis
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
    for a in (theta, r, z, edge_length, edge_radius, voronoi_length, kappa11, kappa22):
        a.setflags(write=False)
    return ReferenceCap(R=R, phi_hat=phi_hat, N=N, theta=theta, r=r, z=z, edge_length=edge_length,
                        edge_radius=edge_radius, voronoi_length=voronoi_length, node_radius=r,
                        kappa11=kappa11, kappa22=kappa22)
