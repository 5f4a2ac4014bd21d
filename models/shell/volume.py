"""Enclosed volume of the discrete shell of revolution, for pressure loading (issue 16).

The state is the interleaved vector ``x = [r_0, z_0, r_1, z_1, ..., r_{N-1}, z_{N-1}]`` of
:mod:`contin_models.shell.energy`: node 0 is the base edge, node ``N-1`` the pole on the axis.
A uniform pressure ``p`` (external, normal to the surface, following it) has the potential
``p (V(x) - V0)``, with ``V`` the volume defined below.

The formula
-----------
By Pappus and Green's theorem, the volume swept by a region ``A`` of the ``(r, z)`` half plane
turned about the axis is ``2 pi int_A r dA = pi oint r^2 dz``, the contour traversed
counter-clockwise.  Along a straight edge from ``(r_i, z_i)`` to ``(r_j, z_j)`` the integrand is a
quadratic in the edge parameter, so the edge contributes exactly

    ``V_e = pi/3 (r_i^2 + r_i r_j + r_j^2) (z_j - z_i)``.

The contour of the region between the shell and a horizontal base plane ``z = z_ref`` is: the
meridian from the base node to the pole (counter-clockwise, as in
:mod:`contin_models.shell.geometry`), down the axis to the plane (``r = 0``: no contribution),
out along the plane to ``r = r_0`` (``dz = 0``: none), then the vertical segment ``r = r_0`` from
``z_ref`` up to the base node ``z_0`` (a cylindrical skirt under the base ring), which gives
``pi r_0^2 (z_0 - z_ref)``.  Hence

    ``V(x) = pi/3 sum_{i=0}^{N-2} (r_i^2 + r_i r_{i+1} + r_{i+1}^2) (z_{i+1} - z_i)
    + pi r_0^2 (z_0 - z_ref)``.

A pole off the axis (``r_{N-1} != 0``) would be closed by a horizontal lid (``dz = 0``), so the
formula stays the volume of a closed body; the shell problems keep ``r_{N-1} = 0``.

The base plane: fixed at ``z = z_ref``
--------------------------------------
The pressure acts on the shell only, not on the base plane (a rigid foundation).  Its virtual work
is ``-p`` times the flux of the virtual displacement through the shell's surface,
``2 pi int r (dr dz' - dz dr')`` along the meridian.  The variation of the edge sum alone
(``S = pi oint_meridian r^2 dz``) is that flux plus an end term ``-pi r_0^2 dz_0`` from the base
node (the pole's end term vanishes since ``r_{N-1} = 0``), so

* the plane through the base node's current height (``V = S``) misses ``pi r_0^2 dz_0``: lifting
  the shell rigidly by ``t`` would do no pressure work, whereas the pressure's resultant on a cap is
  ``p`` times its projected area ``pi r_0^2``; that definition counts the pressure on a base disc
  that moves with the base, which is not part of the shell;
* the fixed plane (``V = S + pi r_0^2 (z_0 - z_ref)``) gives exactly the shell's flux for every
  ``dz_0``, and for ``dr_0`` adds the skirt's flux ``2 pi r_0 (z_0 - z_ref) dr_0``, which vanishes
  when the base node sits on the plane.  It is a true potential (the shell's flux alone is not
  integrable when both ``r_0`` and ``z_0`` move: ``d(pi r_0^2 dz_0) != 0``), and it is exact for
  the paper's sliding base, where ``z_0 = z_ref`` is held fixed, and for a base lifting off
  vertically.

So this module uses the fixed plane; ``z_ref`` defaults (:meth:`PressureTerm.from_reference`) to the
reference base height.  With ``z_0 = z_ref`` both definitions coincide, value and derivatives on
the sliding-base unknowns.  Invariances of this definition: translating every node *and* the plane
in ``z`` leaves ``V`` unchanged; ``V`` is homogeneous of degree 3 in ``(x, z_ref)`` jointly.

Derivatives
-----------
With ``a = r_i, c = z_i, b = r_j, d = z_j`` (the edge's dofs in increasing order ``a, c, b, d``),
``s = a^2 + a b + b^2`` and ``h = d - c``:

* gradient ``pi/3 [(2a + b) h, -s, (a + 2b) h, s]``;
* Hessian (``k = pi/3``): ``aa = bb = 2 k h``, ``ab = k h``, ``ac = -k (2a + b)``,
  ``ad = k (2a + b)``, ``bc = -k (a + 2b)``, ``bd = k (a + 2b)``, ``cc = cd = dd = 0``;
* skirt: gradient ``[2 pi r_0 (z_0 - z_ref), pi r_0^2]``, Hessian
  ``[[2 pi (z_0 - z_ref), 2 pi r_0], [2 pi r_0, 0]]``.

Every coupling lies within one edge's four dofs, so the Hessian is banded with half-bandwidth 3,
inside the shell's 5 (:data:`contin_models.shell.energy.HALF_BANDWIDTH`).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from .geometry import split

__all__ = ["enclosed_volume", "volume_gradient", "volume_hessian", "PressureTerm", "VOLUME_HALF_BANDWIDTH"]

VOLUME_HALF_BANDWIDTH = 3
"""Half-bandwidth of :func:`volume_hessian` in the interleaved ordering (one edge: ``r_i .. z_{i+1}``)."""

_K = math.pi / 3.0

# Local pairs (a, b) of an edge's dofs [r_i, z_i, r_j, z_j] with a structurally nonzero second
# derivative (the z-z block is identically zero, so it is left out of the pattern).
_PAIRS = np.array([(0, 0), (0, 1), (0, 2), (0, 3), (1, 2), (2, 2), (2, 3)])


def _state(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r, z = split(x)
    if r.size < 2:
        raise ValueError(f"the meridian needs at least 2 nodes, got {r.size}")
    return r, z


def enclosed_volume(x: np.ndarray, z_ref: float) -> float:
    """Volume between the surface swept by the meridian polyline and the plane ``z = z_ref``.

    ``V = pi/3 sum_i (r_i^2 + r_i r_{i+1} + r_{i+1}^2) (z_{i+1} - z_i) + pi r_0^2 (z_0 - z_ref)``
    (module docstring: the last term is the cylinder between the base ring and the plane).

    Parameters
    ----------
    x : ndarray, shape ``(2 N,)``
        State ``[r_0, z_0, ..., r_{N-1}, z_{N-1}]``, base (node 0) to pole (node ``N-1``).
    z_ref : float
        Height of the fixed base plane.

    Returns
    -------
    float
        Positive for a meridian that rises from the base to the pole above the plane.
    """
    r, z = _state(x)
    a, b = r[:-1], r[1:]
    edges = (a * a + a * b + b * b) @ np.diff(z)
    return float(_K * edges + math.pi * r[0] ** 2 * (z[0] - z_ref))


def volume_gradient(x: np.ndarray, z_ref: float) -> np.ndarray:
    """Exact gradient of :func:`enclosed_volume` with respect to the interleaved state.

    Edge ``(i, i+1)`` adds ``pi/3 [(2 r_i + r_{i+1}) h, -s, (r_i + 2 r_{i+1}) h, s]`` to
    ``[r_i, z_i, r_{i+1}, z_{i+1}]``, with ``s = r_i^2 + r_i r_{i+1} + r_{i+1}^2`` and
    ``h = z_{i+1} - z_i``; the skirt adds ``[2 pi r_0 (z_0 - z_ref), pi r_0^2]`` to ``[r_0, z_0]``.

    Parameters
    ----------
    x : ndarray, shape ``(2 N,)``
        State vector.
    z_ref : float
        Height of the fixed base plane.

    Returns
    -------
    ndarray, shape ``(2 N,)``
    """
    r, z = _state(x)
    a, b = r[:-1], r[1:]
    h = np.diff(z)
    s = a * a + a * b + b * b
    g = np.zeros(2 * r.size)
    g[0:-2:2] += _K * (2 * a + b) * h       # d/dr_i from the edge starting at node i
    g[2::2] += _K * (a + 2 * b) * h         # d/dr_{i+1} from the edge ending at node i+1
    g[1:-2:2] -= _K * s                      # d/dz_i
    g[3::2] += _K * s                        # d/dz_{i+1}
    g[0] += 2 * math.pi * r[0] * (z[0] - z_ref)
    g[1] += math.pi * r[0] ** 2
    return g


def volume_hessian(x: np.ndarray, z_ref: float) -> sp.csr_matrix:
    """Exact Hessian of :func:`enclosed_volume`, symmetric CSR with half-bandwidth 3.

    Per edge, with dofs ``(a, c, b, d) = (r_i, z_i, r_{i+1}, z_{i+1})``, ``h = d - c``,
    ``k = pi/3``: ``aa = bb = 2 k h``, ``ab = k h``, ``ac = -k (2a + b)``, ``ad = k (2a + b)``,
    ``bc = -k (a + 2b)``, ``bd = k (a + 2b)``; the skirt adds ``2 pi (z_0 - z_ref)`` at
    ``(r_0, r_0)`` and ``2 pi r_0`` at ``(r_0, z_0)``.  The sparsity pattern depends on ``N`` only
    (stored zeros are kept), and lies inside the shell's band.

    Parameters
    ----------
    x : ndarray, shape ``(2 N,)``
        State vector.
    z_ref : float
        Height of the fixed base plane (it enters the ``(r_0, r_0)`` entry only).

    Returns
    -------
    scipy.sparse.csr_matrix, shape ``(2 N, 2 N)``
    """
    r, z = _state(x)
    n = 2 * r.size
    a, b = r[:-1], r[1:]
    h = np.diff(z)
    # Rows follow _PAIRS: (aa, ac, ab, ad, cb, bb, bd); (c, b) is the pair (b, c) transposed.
    upper = _K * np.stack([2 * h, -(2 * a + b), h, 2 * a + b, -(a + 2 * b), 2 * h, a + 2 * b])
    upper[0, 0] += 2 * math.pi * (z[0] - z_ref)
    upper[1, 0] += 2 * math.pi * r[0]
    base = 2 * np.arange(r.size - 1)
    rows = (base[None, :] + _PAIRS[:, 0, None]).ravel()
    cols = (base[None, :] + _PAIRS[:, 1, None]).ravel()
    vals = upper.ravel()
    off = rows != cols
    # The lower triangle is the same numbers mirrored, so the sum of duplicates is exactly symmetric.
    H = sp.coo_matrix((np.concatenate([vals, vals[off]]),
                       (np.concatenate([rows, cols[off]]), np.concatenate([cols, rows[off]]))),
                      shape=(n, n)).tocsr()
    H.sum_duplicates()
    return H


class PressureTerm:
    """Potential ``p (V(x) - V0)`` of an external pressure ``p`` on the shell, and its derivatives.

    The pieces to add to an elastic energy when composing a :class:`contin.Problem` with the
    pressure as the parameter: energy, gradient ``p dV``, Hessian ``p d2V`` and the parameter
    derivative of the gradient, ``dV``.  Positive ``p`` pushes inwards (the potential grows with
    the volume).

    Parameters
    ----------
    z_ref : float
        Height of the fixed base plane (module docstring: why it is fixed).
    V0 : float
        Volume subtracted in the potential; only shifts the energy (not its derivatives).

    Notes
    -----
    Gradients and Hessians are with respect to the full interleaved state; restricting them to the
    unknowns (sliding base: ``z_0`` fixed at ``z_ref``; pole: ``r_{N-1} = 0``) is the composer's job.
    """

    def __init__(self, z_ref: float, V0: float = 0.0) -> None:
        z_ref, V0 = float(z_ref), float(V0)
        if not (math.isfinite(z_ref) and math.isfinite(V0)):
            raise ValueError(f"PressureTerm: z_ref and V0 must be finite, got {z_ref!r}, {V0!r}")
        self.z_ref = z_ref
        self.V0 = V0

    @classmethod
    def from_reference(cls, x_ref: np.ndarray) -> "PressureTerm":
        """The term whose plane passes through the reference base node and ``V0 = V(x_ref)``.

        Parameters
        ----------
        x_ref : ndarray, shape ``(2 N,)``
            Reference state (e.g. ``ReferenceCap.x``).

        Returns
        -------
        PressureTerm
        """
        z_ref = float(split(x_ref)[1][0])
        return cls(z_ref, enclosed_volume(x_ref, z_ref))

    def volume(self, x: np.ndarray) -> float:
        """``V(x)`` (:func:`enclosed_volume` with this term's plane)."""
        return enclosed_volume(x, self.z_ref)

    def energy(self, x: np.ndarray, p: float) -> float:
        """``p (V(x) - V0)``."""
        return float(p) * (self.volume(x) - self.V0)

    def gradient(self, x: np.ndarray, p: float) -> np.ndarray:
        """``p dV/dx``, shape ``(2 N,)``."""
        return float(p) * volume_gradient(x, self.z_ref)

    def hessian(self, x: np.ndarray, p: float) -> sp.csr_matrix:
        """``p d2V/dx2``, symmetric CSR, half-bandwidth :data:`VOLUME_HALF_BANDWIDTH`."""
        return float(p) * volume_hessian(x, self.z_ref)

    def gradient_dp(self, x: np.ndarray) -> np.ndarray:
        """``d/dp`` of :meth:`gradient`: ``dV/dx`` (the load vector per unit pressure)."""
        return volume_gradient(x, self.z_ref)

    def energy_dp(self, x: np.ndarray) -> float:
        """``d/dp`` of :meth:`energy`: ``V(x) - V0`` (the pressure's conjugate variable)."""
        return self.volume(x) - self.V0

    def __repr__(self) -> str:
        return f"PressureTerm(z_ref={self.z_ref!r}, V0={self.V0!r})"
