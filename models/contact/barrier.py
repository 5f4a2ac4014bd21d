"""Log-barrier contact between the shell's meridian and a rigid indenter (paper section 3(b)).

Barrier
-------
A point at distance ``d`` from the indenter surface carries the energy (``docs/model.md#contact``,
the paper's eq. 3.16)::

    W(d) = -K_c (d - dhat)^2 log(d / dhat)   for 0 < d < dhat,    0 for d >= dhat,

C2 at ``d = dhat`` and ``+inf`` as ``d -> 0+``.  The kernels and their exact derivatives come from
:mod:`contin_models.contact._generated` (emitted by ``python -m contin_models.contact.codegen``).  The contact is
frictionless: the barrier only depends on the distance.

Contact cells: the barrier sees a smooth meridian between the nodes
--------------------------------------------------------------------
The paper sums ``W`` over the nodes.  Where the indenter touches the shell along a ring (a plate
on a dimpled cap), the contact zone is then about one node spacing wide and the ring can only sit
on a node: as it moves over the meridian it hops from node to node and the force along the path is
a discretisation artefact (about 150 sign changes of ``dF/dw_b`` on the plate's dimple branch at
``N = 200``).  Here the barrier sees the quadratic B-spline whose control points are the nodes, a C1
curve; every node ``i`` owns a *cell*, its piece around the node::

    x_i(t) = B_0(t) x_{i-1} + B_1(t) x_i + B_2(t) x_{i+1},    t in [-1/2, 1/2],
    B_0 = (1/2 - t)^2 / 2,   B_1 = 3/4 - t^2,   B_2 = (1/2 + t)^2 / 2

(:func:`contin_models.contact._generated.cell_basis`).  Consecutive cells meet at the midpoints of
the segments with the segment as their common tangent.  The curve cuts the polygon's corners: it
passes a quarter of the way from a node towards the midpoint of its neighbours, a distance of
``kappa h^2 / 8`` on a meridian of curvature ``kappa`` and spacing ``h`` (second order, as the
polygon itself).  The barrier is integrated over the cells::

    E(x, c) = a_0 W(d(x_0, c)) + sum_{i >= 1} a_i int_{-1/2}^{1/2} W(d(x_i(t), c)) dt.

Contact on the barrier's support.  The integrand vanishes wherever the curve is beyond ``dhat``,
and on a thin shell the barrier is stiff: a ring carries its load at ``d`` within a fraction of a
percent of ``dhat``, over a small part of a cell.  A fixed Gauss rule per cell then sees the narrow
contact come and go as it passes its points (the force along the path ripples at their spacing,
each ripple a limit load under force control; issue 14, B8).  So each cell is integrated over the
pieces of ``[-1/2, 1/2]`` where the curve is within ``dhat``, found exactly: the condition is a
polynomial in ``t`` (plate: ``d(t) - dhat``, quadratic; sphere: ``|x(t) - centre|^2 - (rho +
dhat)^2``, quartic), cut at its critical points into monotone pieces whose roots are bracketed and
refined by Newton's method.  Each piece gets :data:`SUPPORT_POINTS` Gauss-Legendre points; the
integrand is analytic on it and vanishes to third order at its ends (``W ~ K (dhat - d)^3 /
dhat``), so the rule converges fast and an error ``eps`` in an end moves the energy by
``O(eps^4)``.  The points move with the state, but because ``W`` and ``W'`` vanish at the ends the
derivatives of the integral are the integrals of the pointwise derivatives over the same pieces
(Leibniz's rule with vanishing boundary terms): the gradient and Hessian are the point kernels' at
the moving points, times the basis weights.  The fixed points of :data:`QUADRATURE_POINTS` per cell
remain the barrier's domain check and the step filter's watch points, and select the cells worth
searching (those with a point within ``2 dhat``).  ``support_points = 0`` integrates at the fixed
points instead (the earlier rule, kept for comparison).  For a uniform gap ``d`` a cell gives
``a_i W(d)``.  This work per state (the samples, the support, the chain rule below and the step
filter) runs in C where the install built ``contin_models.contact._cbarrier``
(:func:`barrier_extension`): the same steps as the numpy code here, which runs elsewhere, to rounding.

Cell weights ``a_i``.  With ``a_i = 1`` (the default of :class:`ContactBarrier`) every cell counts
one node's worth, as the paper's nodal sum.  But a nodal sum makes the barrier's stiffness per unit
length of meridian grow with ``N``, and the plate's dimple snap (the flattened contact region
lifting off the plate) depends on it: its travel moves by 8.9e-5 R from N = 200 to 400 and by
1.6e-4 R from 400 to 800 with the paper's nodal barrier (7.9e-5 R and 1.6e-4 R with the cells and
``a_i = 1``: not converging), by 9.6e-5 R and 2.3e-5 R with the barrier per unit length (second
order).  :class:`contin_models.contact.ShellIndentation` therefore weighs each cell by
its reference length in units of the mean spacing of the paper's ``N = 200`` mesh
(:func:`length_weights`): ``K_c`` and ``dhat`` keep the paper's values and meaning on the paper's
mesh, and the contact law per unit length stays the same on any other.  Special cells:

* the pole ``N-1`` lies on the axis; its cell uses the mirror image ``(-r_{N-2}, z_{N-2})`` of its
  neighbour as the third node (the meridian continues symmetrically across the axis);
* the base node ``0`` has no neighbour beyond the support and keeps the nodal term ``W(d_0)``
  (the indenter never comes near the base: the runners stop at ``2 dhat`` from it).

``quadrature = 1`` is the paper's nodal barrier exactly (one point, the node, weight 1).  A cell's
point is linear in the three nodes, so the cell's exact gradient and Hessian are the point kernels'
times the basis weights (chain rule; the generator checks it against sympy).

Indenters and their position parameter ``c``
--------------------------------------------
:class:`Sphere` ``(radius)``
    Rigid sphere of radius ``rho`` whose centre is on the axis at height ``c = zc``:
    ``d_i = sqrt(r_i^2 + (z_i - zc)^2) - rho``.  Its lowest point is at ``zc - rho``; it first
    touches the undeformed cap's pole ``(0, R)`` at ``zc = R + rho``.  ``radius = 0`` is a point
    indenter (the distance to a point on the axis).
:class:`Plate` ``()``
    Flat horizontal plate at height ``c = zp`` pushing down: ``d_i = zp - z_i``.

The indenter comes from above and pushes down, so its travel is ``w_b = c_start - c`` (``c``
decreases as it indents).

Sign conventions
----------------
* ``E(x, c)`` is the total barrier energy (the sum over the cells above); ``x`` is the interleaved
  full state ``[r_0, z_0, ..., r_{N-1}, z_{N-1}]`` of the shell.
* ``-dE/dx`` is the contact force on the nodes (pointing away from the indenter); the barrier
  adds ``+dE/dx`` to the shell's residual (the gradient of the total energy).
* The contact force is ``F = -dE/dc = dE/dw_b``: the (downward) load the indenter transmits to the
  shell, equal to the upward reaction the shell exerts on the indenter.  A pushing indenter has
  ``F > 0`` (``W' < 0`` and ``dd/dc > 0`` for both shapes).  ``F = 0`` when no cell comes within
  ``dhat``.

Hessian layout
--------------
A cell depends on the ``(r, z)`` of its three nodes and ``c`` only, so its Hessian with respect to
``x`` is a 6x6 block on the nodes ``i-1, i, i+1``: the same stencil as the shell's bending energy
at node ``i``, so the blocks fit inside the shell's band (half-bandwidth 5 in the interleaved
state) without widening it (:meth:`ContactState.hessian_triplets` gives global
``(row, col, value)`` entries, :meth:`ContactBarrier.hessian_slots` the places of the blocks in a
CSR pattern).  The border column ``d2E/dx dc`` (:attr:`ContactState.hess_xc`, length ``2N``) and
``d2E/dc2`` (:attr:`ContactState.hess_cc`) complete the Jacobian for displacement control
(``df/dp``) and for force control (the indenter position as an extra unknown).

Step filter
-----------
The barrier is finite while every quadrature point of every cell (and the base node) is strictly
outside the indenter; these *sample points* are its domain.  A sample point is linear in the nodes,
so it moves along a straight segment in a step, and :meth:`ContactBarrier.max_safe_fraction`
returns the largest fraction of a step ``(dx, dc)`` that keeps every sample point strictly outside
along the whole segment (incremental-potential contact's filter), times a safety factor; it
considers all sample points, not only the active ones.

Scaling of ``K_c`` and ``dhat`` (:func:`default_barrier`)
------------------------------------------------------
The paper's values ``K_c = 1e8``, ``dhat = 1e-3`` are for ``E = 1 MPa``, ``R = 1 m``.  With ``h/R``
and ``nu`` fixed, the shell's energy is ``E R^3 e(x / R)`` with ``e`` dimensionless (both the
stretching ``E h R^2`` and the bending ``E h^3`` scales are ``E R^3`` times a function of
``h/R``).  The barrier is ``W = K_c dhat^2 f(d / dhat)`` with ``f(t) = -(t - 1)^2 log t``.  For the
total energy to keep the form ``E R^3 e_total(x / R, c / R)`` the barrier must be a function of
``d / R`` times ``E R^3``, i.e. ``dhat / R`` and ``K_c dhat^2 / (E R^3)`` must be constant::

    dhat = 1e-3 R,        K_c = 1e8 * (E / 1 MPa) * (R / 1 m) = 100 E R      (units: energy / length^2)

Then every equilibrium is the same configuration scaled by ``R``: ``w / R`` is invariant, the
energy scales as ``E R^3``, the contact force ``F = -dE/dc`` as ``E R^2`` and the bending stiffness
``D = E h^3 / (12 (1 - nu^2))`` as ``E R^3``, so ``F R / (2 pi D)`` is invariant too.
(``K_c`` proportional to ``E`` alone would make the barrier relatively stiffer on larger shells, and a fixed
``dhat`` would be a different fraction of the shell.)

To refine the barrier (``dhat`` smaller at fixed ``E``, ``R``), :func:`default_barrier` takes
``dhat_over_R`` and keeps ``K_c dhat`` fixed: the barrier force ``-W'(d) = K_c dhat phi(d / dhat)``
is then the same function of the relative gap ``d / dhat``, so a node carrying a given load sits at
the same fraction of ``dhat`` and the gap shrinks in proportion to ``dhat``.

Where a loaded node sits
------------------------
Near ``d = dhat``, ``-W'(dhat (1 - eps)) = 3 K_c dhat eps^2 (1 + O(eps))``: a cell carrying a
load ``f`` at a uniform gap sits at ``d = dhat (1 - eps)`` with ``eps = sqrt(f / (3 K_c dhat))``.  With the paper's
constants (``K_c dhat = 1e5`` N/m at ``E = 1 MPa``, ``R = 1 m``) and shell forces of order
``2 pi D`` (about 5 N for ``h/R = 0.02``), ``eps`` is a few 1e-3: the contact acts at a gap of
almost exactly ``dhat``, so the indenter travel measured from geometric first contact carries an
offset of about ``dhat`` (``1e-3 R``).  Measuring it from the position where the barrier switches
on (gap ``dhat`` at the pole) removes that offset to first order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike

from contin.numerics.compiled import optional_extension, prefer_compiled
from contin.numerics.linalg import same_values

from . import _generated

#: The generated point kernels, in C where the install built ``contin_models.contact._ckernels``
#: (:func:`contin.numerics.compiled.prefer_compiled`; ``COMPILED`` tells whether it did; the same numbers).
kernels, COMPILED = prefer_compiled(_generated, "contin_models.contact._ckernels")

__all__ = ["Sphere", "Plate", "ContactBarrier", "ContactState", "ContactCells", "IntegrationPoints", "default_barrier",
           "barrier_value", "barrier_extension", "kernels", "COMPILED", "length_weights", "PAPER_K", "PAPER_DHAT",
           "PAPER_E", "PAPER_R", "PAPER_N", "QUADRATURE_POINTS", "SUPPORT_POINTS", "support_pieces", "barrier_jet", "CELL_MONOMIALS"]

#: The paper's barrier constants and the modulus and radius they were chosen for.
PAPER_K, PAPER_DHAT, PAPER_E, PAPER_R = 1e8, 1e-3, 1e6, 1.0
#: The number of nodes of the paper's meridian, for which its nodal ``K_c`` was chosen.
PAPER_N = 200

#: Fixed Gauss-Legendre points per contact cell (module docstring): the barrier's domain check and
#: the step filter watch them, and with ``support_points = 0`` the barrier is integrated at them.
QUADRATURE_POINTS = 15

#: Gauss-Legendre points on each piece of a cell where the meridian is within ``dhat`` of the
#: indenter (module docstring, "Contact on the barrier's support").  The integrand is analytic on
#: the piece and vanishes to third order at its ends, so the rule converges fast: it agrees with
#: adaptive quadrature to 1e-10 from a light touch to deep contact (``tests/test_contact_barrier.py``).
SUPPORT_POINTS = 12

_EXTENSION: list = []


def barrier_extension() -> Any:
    """The C extension ``contin_models.contact._cbarrier``, or None when it is not built or ``CONTIN_COMPILED=0``.

    It runs the barrier's work per state (the support of the integral, the chain rule and the step
    filter) in C, the same steps as the numpy code of :class:`ContactBarrier`, which runs where it is
    not built; the two agree to rounding (``tests/test_contact_compiled.py``).
    """
    if not _EXTENSION:
        _EXTENSION.append(optional_extension("contin_models.contact._cbarrier"))
    return _EXTENSION[0]


def default_barrier(E: float, R: float, dhat_over_R: float = PAPER_DHAT / PAPER_R) -> tuple[float, float]:
    """Barrier constants ``(K_c, dhat)`` for a shell of modulus ``E`` and radius ``R``.

    The paper's ``K_c = 1e8``, ``dhat = 1e-3`` (``E = 1 MPa``, ``R = 1 m``) scaled so that the
    normalized results (``w / R``, ``F R / (2 pi D)``) do not depend on ``E`` and ``R`` at fixed
    ``h / R`` (module docstring): ``dhat = dhat_over_R R``, ``K_c`` proportional to ``E R``, and to ``1 / dhat``
    when ``dhat_over_R`` departs from the paper's ``1e-3`` (``K_c dhat`` fixed).

    Parameters
    ----------
    E : float
        Young's modulus, ``> 0``.
    R : float
        Sphere radius of the cap, ``> 0``.
    dhat_over_R : float
        Barrier width relative to ``R`` (default ``1e-3``, the paper's).

    Returns
    -------
    K_c : float
        Barrier stiffness, ``1e8 (E / 1e6) (R / 1) (1e-3 / dhat_over_R)``, units energy / length^2.
    dhat : float
        Barrier width, ``dhat_over_R R``.
    """
    E, R, ratio = float(E), float(R), float(dhat_over_R)
    for name, v in (("E", E), ("R", R), ("dhat_over_R", ratio)):
        if not (v > 0 and math.isfinite(v)):
            raise ValueError(f"default_barrier: {name} must be a positive number, got {v!r}")
    K = PAPER_K * (E / PAPER_E) * (R / PAPER_R) * ((PAPER_DHAT / PAPER_R) / ratio)
    return K, ratio * R


def length_weights(x_ref: ArrayLike, n_paper: int = PAPER_N) -> np.ndarray:
    """Cell weights that make the barrier a density per unit meridian length (module docstring).

    Cell ``i`` weighs its reference Voronoi length (half of each adjacent edge; the pole's cell a
    whole last edge, its mirror half included; the base a half edge) divided by the mean spacing of
    the same meridian cut into ``n_paper`` nodes.  On a uniform mesh of ``n_paper`` nodes every
    interior weight is 1: the paper's nodal barrier.

    Parameters
    ----------
    x_ref : array_like, shape ``(2N,)``
        The reference (undeformed) interleaved state, the pole last.
    n_paper : int
        Number of nodes at which the weights are 1 (default :data:`PAPER_N`).

    Returns
    -------
    ndarray, shape ``(N,)``
    """
    x = np.asarray(x_ref, dtype=float)
    r, z = x[0::2], x[1::2]
    edges = np.hypot(np.diff(r), np.diff(z))
    if r.size < 2 or not np.all(edges > 0):
        raise ValueError("length_weights: need at least two distinct nodes")
    cell = np.zeros(r.size)
    cell[:-1] += 0.5 * edges
    cell[1:] += 0.5 * edges
    cell[-1] *= 2.0  # the pole's cell reaches across the axis into the mirrored half-edge
    return cell * (n_paper - 1) / float(np.sum(edges))


def barrier_value(d, K: float, dhat: float) -> np.ndarray:
    """``W(d)`` of eq. 3.16 for any ``d > 0``: zero for ``d >= dhat`` (a reference helper).

    Parameters
    ----------
    d : array_like
        Distances, all ``> 0``.
    K, dhat : float
        Barrier constants.

    Returns
    -------
    ndarray
        The barrier energy per distance.
    """
    d = np.asarray(d, dtype=float)
    if np.any(~(d > 0)):
        raise ValueError("barrier_value: the barrier is only defined for d > 0")
    t = np.minimum(d / dhat, 1.0)
    return -K * dhat**2 * (t - 1.0) ** 2 * np.log(t)


@dataclass(frozen=True)
class Sphere:
    """Rigid spherical indenter centred on the axis; its position ``c`` is the centre height ``zc``.

    Parameters
    ----------
    radius : float
        Sphere radius ``rho >= 0`` (``0``: a point on the axis).
    """

    radius: float

    def __post_init__(self) -> None:
        if not (self.radius >= 0 and math.isfinite(self.radius)):
            raise ValueError(f"Sphere: radius must be a finite number >= 0, got {self.radius!r}")

    @property
    def name(self) -> str:
        return "sphere"

    @property
    def params(self) -> tuple[float, ...]:
        return (float(self.radius),)

    def contact_position(self, z_pole: float) -> float:
        """Indenter position ``zc`` at which the sphere touches a node ``(0, z_pole)`` on the axis."""
        return float(z_pole) + float(self.radius)


@dataclass(frozen=True)
class Plate:
    """Flat horizontal plate pushing down; its position ``c`` is the plate height ``zp``."""

    @property
    def name(self) -> str:
        return "plate"

    @property
    def params(self) -> tuple[float, ...]:
        return ()

    def contact_position(self, z_pole: float) -> float:
        """Indenter position ``zp`` at which the plate touches a node at height ``z_pole``."""
        return float(z_pole)


class ContactCells:
    """Sample points of the contact cells of an ``N``-node meridian (module docstring).

    Sample point ``s`` of cell ``cell[s]`` is at ``r = sum_j cr[s, j] r[stencil[cell, j]]``,
    ``z = sum_j cz[s, j] z[stencil[cell, j]]`` and carries the quadrature weight ``weight[s]``.
    The samples of a cell are contiguous, cells in increasing order: the base node's single sample
    first (the node itself), then ``quadrature`` samples for each of the cells ``1 .. N-1``.

    Parameters
    ----------
    n_nodes : int
        Number of nodes ``N >= 1`` (node ``N-1`` is the pole on the axis).
    quadrature : int
        Gauss-Legendre points per cell, ``>= 1``.
    cell_weights : array_like, shape ``(N,)``, optional
        A factor on each cell's energy (:func:`length_weights`); default 1 (one node's worth each).

    Attributes
    ----------
    stencil : ndarray of int, shape ``(N, 3)``
        The three nodes of each cell (``i-1, i, i+1``; the pole's is ``N-2, N-1, N-2`` with the third
        mirrored; the base's ``0, 0, 0`` with weights ``0, 1, 0``).
    cell : ndarray of int, shape ``(S,)``
    cr, cz : ndarray, shape ``(S, 3)``
        Coefficients of the stencil's ``r`` and ``z`` in each sample point.
    weight : ndarray, shape ``(S,)``
        Quadrature weight times the cell's weight.
    first : ndarray of int, shape ``(N + 1,)``
        Samples of cell ``i`` are ``first[i] .. first[i+1] - 1``.
    """

    def __init__(self, n_nodes: int, quadrature: int, cell_weights: ArrayLike | None = None) -> None:
        N, q = int(n_nodes), int(quadrature)
        if N < 1 or q < 1:
            raise ValueError(f"ContactCells: need at least one node and one quadrature point, got N = {N}, q = {q}")
        if q == 1:  # the paper's nodal barrier: the node itself, weight 1
            L, w = np.array([[0.0, 1.0, 0.0]]), np.ones(1)
        else:
            t, w = np.polynomial.legendre.leggauss(q)
            t, w = 0.5 * t, 0.5 * w  # the cell is t in [-1/2, 1/2]
            L = kernels.cell_basis(t).T  # (q, 3)
        i = np.arange(N)
        self.stencil = np.stack([i - 1, i, i + 1], axis=1)
        self.stencil[0] = 0
        mirror = np.ones(3)
        if N >= 2:
            # the pole: the meridian continues across the axis, its neighbour mirrored (r -> -r)
            self.stencil[-1] = [N - 2, N - 1, N - 2]
            mirror[2] = -1.0
        n_cells = N - 1
        self.cell = np.concatenate([[0], np.repeat(np.arange(1, N), q)]).astype(int)
        self.cz = np.concatenate([[[0.0, 1.0, 0.0]], np.tile(L, (n_cells, 1))])
        self.cr = self.cz.copy()
        # the mirror as a sign on each cell's stencil r (the pole's third node is -r_{N-2})
        self._sign_r = np.ones((N, 3))
        if N >= 2:
            self.cr[-q:] *= mirror
            self._sign_r[-1] = mirror
        self._basis = np.ascontiguousarray(L.T)  # (3, q)
        self._sign_r.setflags(write=False)
        self._basis.setflags(write=False)
        self.weight = np.concatenate([[1.0], np.tile(w, n_cells)])
        if cell_weights is not None:
            cw = np.asarray(cell_weights, dtype=float)
            if cw.shape != (N,) or not np.all(cw > 0):
                raise ValueError(f"ContactCells: cell_weights must be {N} positive numbers, got shape {cw.shape}")
            self.weight = self.weight * cw[self.cell]
            self.cell_weight = cw.copy()
        else:
            self.cell_weight = np.ones(N)
        self.first = np.concatenate([[0], 1 + q * np.arange(N)]).astype(int)
        self.n_nodes, self.quadrature = N, q

    @property
    def sign_r(self) -> np.ndarray:
        """``(N, 3)``, read-only: the sign of each stencil node's ``r`` in its cell (``-1`` for the pole cell's
        mirrored neighbour, ``+1`` elsewhere); ``cr = sign_r[cell] * cz``."""
        return self._sign_r

    @property
    def basis(self) -> np.ndarray:
        """``(3, quadrature)``, read-only: the cell's basis functions at its Gauss points (the base cell's single
        sample, the node itself, is not among them)."""
        return self._basis

    def points(self, r: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sample points ``(r_s, z_s)`` of the nodal coordinates ``r, z`` (each shape ``(N,)``)."""
        # every cell but the base's: its three nodes times the basis at the q points (one product)
        inner = self.stencil[1:]
        rs = (r[inner] * self._sign_r[1:]) @ self._basis
        zs = z[inner] @ self._basis
        return np.concatenate([r[:1], rs.ravel()]), np.concatenate([z[:1], zs.ravel()])

    def curve(self, r: np.ndarray, z: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Monomial coefficients of the cells' curves: ``r(t) = R[:, 0] + R[:, 1] t + R[:, 2] t^2``, ``z`` alike.

        Parameters
        ----------
        r, z : ndarray, shape ``(N,)``
            Nodal coordinates.
        cells : ndarray of int, shape ``(m,)``
            Cells ``>= 1`` (the base's cell is its node alone).

        Returns
        -------
        R, Z : ndarray, shape ``(m, 3)``
        """
        nodes = self.stencil[cells]
        rr, zz = r[nodes] * self._sign_r[cells], z[nodes]
        return rr @ CELL_MONOMIALS.T, zz @ CELL_MONOMIALS.T

    def cell_minimum(self, values: np.ndarray) -> np.ndarray:
        """Smallest value of each cell's samples, shape ``(N,)``."""
        return np.minimum.reduceat(values, self.first[:-1])

    def samples_of(self, cells: np.ndarray) -> np.ndarray:
        """Indices of the samples of the given cells (in order)."""
        counts = self.first[cells + 1] - self.first[cells]
        offsets = np.arange(int(np.sum(counts))) - np.repeat(np.cumsum(counts) - counts, counts)
        return np.repeat(self.first[cells], counts) + offsets


#: The quadratic B-spline cell in monomials: ``x(t) = sum_k t^k sum_j _MONOMIAL[k, j] x_j`` over the
#: stencil ``i-1, i, i+1`` (the expansion of :func:`contin_models.contact._generated.cell_basis`).
#: The cell basis in monomials: row ``k`` holds the coefficients of ``t^k`` in ``(B_0, B_1, B_2)``.
CELL_MONOMIALS = np.array([[0.125, 0.75, 0.125], [-0.5, 0.0, 0.5], [0.5, -1.0, 0.5]])


def _polyval(coefs: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Rows of ascending coefficients ``(m, k)`` at ``t`` of shape ``(m,)`` or ``(m, j)`` (Horner)."""
    c = coefs if t.ndim == 1 else coefs[:, None, :]
    out = np.zeros_like(t) + c[..., -1]
    for k in range(coefs.shape[1] - 2, -1, -1):
        out = out * t + c[..., k]
    return out


def _derivative(coefs: np.ndarray) -> np.ndarray:
    """Ascending coefficients of the derivative of each row."""
    return coefs[:, 1:] * np.arange(1, coefs.shape[1])


def _roots_in_brackets(coefs: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """A root of each row's polynomial in ``[lo, hi]`` (shape ``(m, j)``), where its ends differ in sign.

    Newton's method kept inside the bracket (bisection when a step leaves it), until the updates
    fall to 1e-14 (``t`` lies in ``[-1/2, 1/2]``): the roots end the barrier's support, where its
    integrand vanishes to third order, so an error of ``eps`` in a root changes the energy by
    ``O(eps^4)``.
    """
    slope = _derivative(coefs)
    f_lo = _polyval(coefs, lo)
    a, b = lo.copy(), hi.copy()
    t = 0.5 * (a + b)
    for _ in range(60):  # bisection alone would be done by then
        f = _polyval(coefs, t)
        left = np.sign(f) == np.sign(f_lo)
        a, b = np.where(left, t, a), np.where(left, b, t)
        df = _polyval(slope, t)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = t - f / df
        new = np.where((step >= a) & (step <= b), step, 0.5 * (a + b))
        done = np.max(np.abs(new - t)) <= 1e-14
        t = new
        if done:
            break
    return t


def _monotone_breaks(coefs: np.ndarray) -> np.ndarray:
    """Points of ``[-1/2, 1/2]`` between which each row's polynomial (degree <= 4) is monotone.

    Returns an ``(m, 5)`` sorted array: the ends and the critical points inside (unused slots hold
    ``1/2``).  The critical points are found piece by piece between the roots of the second
    derivative (a quadratic, solved in closed form), where the first derivative is monotone.
    """
    m = coefs.shape[0]
    half = np.full(m, 0.5)
    c2, c3, c4 = coefs[:, 2], coefs[:, 3], coefs[:, 4]
    # g'' = 2 c2 + 6 c3 t + 12 c4 t^2
    A, B, C = 12.0 * c4, 6.0 * c3, 2.0 * c2
    inflect = np.full((m, 2), 0.5)
    disc = B * B - 4.0 * A * C
    quad = (A != 0) & (disc > 0)
    sq = np.sqrt(np.where(quad, disc, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        q = -0.5 * (B + np.copysign(sq, B))
        inflect[quad, 0] = (q / A)[quad]
        inflect[quad, 1] = np.where(q != 0, C / q, 0.5)[quad]
        lin = (A == 0) & (B != 0)
        inflect[lin, 0] = (-C / B)[lin]
    inflect = np.where((inflect > -0.5) & (inflect < 0.5), inflect, 0.5)
    convex = np.sort(np.column_stack([-half, inflect, half]), axis=1)  # (m, 4): 3 pieces
    slope = _derivative(coefs)
    lo, hi = convex[:, :-1], convex[:, 1:]
    s_lo, s_hi = _polyval(slope, lo), _polyval(slope, hi)
    change = (np.sign(s_lo) * np.sign(s_hi) < 0) & (hi > lo)
    crit = np.full(lo.shape, 0.5)
    if np.any(change):
        rows = np.nonzero(change)[0]
        crit[change] = _roots_in_brackets(slope[rows], lo[change], hi[change])
    return np.sort(np.column_stack([-half, crit, half]), axis=1)


def support_pieces(gap: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pieces of ``[-1/2, 1/2]`` where each row's polynomial is negative, one per monotone piece.

    ``gap``: ascending coefficients ``(m, 5)`` (:meth:`ContactBarrier.gap_polynomial`).  The rows are cut at
    their critical points into monotone pieces; a piece's end where the sign changes is the root in it
    (Newton's method kept in the bracket).  Returns ``(rows, a, b)``: the row of each piece and its ends.
    """
    breaks = _monotone_breaks(gap)
    lo, hi = breaks[:, :-1], breaks[:, 1:]
    in_lo, in_hi = _polyval(gap, lo) < 0, _polyval(gap, hi) < 0
    cross = (in_lo != in_hi) & (hi > lo)
    root = np.zeros_like(lo)
    if np.any(cross):
        root[cross] = _roots_in_brackets(gap[np.nonzero(cross)[0]], lo[cross], hi[cross])
    a, b = np.where(in_lo, lo, root), np.where(in_hi, hi, root)
    use = (in_lo | in_hi) & (b > a)
    return np.nonzero(use)[0], a[use], b[use]


def barrier_jet(d: np.ndarray, K: float, dhat: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``W(d) = -K (d - dhat)^2 log(d / dhat)`` for ``d < dhat`` (0 beyond) and its first two derivatives in ``d``."""
    d = np.asarray(d, dtype=float)
    lg = np.log(np.minimum(d / dhat, 1.0))
    a = np.minimum(d - dhat, 0.0)
    return -K * a * a * lg, -K * (2.0 * a * lg + a * a / d), -K * (2.0 * lg + 4.0 * a / d - a * a / (d * d))


@dataclass
class IntegrationPoints:
    """The points where the barrier integral is sampled at one state, with their weights.

    Attributes
    ----------
    cell : ndarray of int, shape ``(P,)``
        Each point's cell (its node).
    cr, cz : ndarray, shape ``(P, 3)``
        The point's ``r`` and ``z`` as combinations of its cell's stencil nodes
        (:attr:`ContactCells.stencil`; the pole cell's third ``r`` coefficient carries the mirror's sign).
    weight : ndarray, shape ``(P,)``
        Quadrature weight times the cell's weight.
    r, z : ndarray, shape ``(P,)``
        The points' coordinates.
    """

    cell: np.ndarray
    cr: np.ndarray
    cz: np.ndarray
    weight: np.ndarray
    r: np.ndarray
    z: np.ndarray


@dataclass
class ContactState:
    """Barrier energy and exact derivatives at one state (from :meth:`ContactBarrier.evaluate`).

    Cells are named by their node (module docstring): cell ``i`` is the meridian around node ``i``.

    Attributes
    ----------
    position : float
        The indenter position ``c`` (``zc`` or ``zp``).
    distances : ndarray, shape ``(N,)``
        ``d_i`` of every node (the pole's is the last, the base's the first).
    gaps : ndarray, shape ``(N,)``
        Smallest distance over each cell's sample points (all ``> 0``).
    active : ndarray of int, shape ``(m,)``
        The cells with a sample point within ``dhat`` (``gaps < dhat``), increasing.
    stencils : ndarray of int, shape ``(m, 3)``
        The nodes of each active cell (``i-1, i, i+1``; see :class:`ContactCells`).
    energy : float
        ``E``, the barrier energy.
    gradient : ndarray, shape ``(2N,)``
        ``dE/dx`` (interleaved; zero outside the active cells' nodes).
    dE_dc : float
        ``dE/dc`` (``<= 0`` for a pushing indenter).
    node_energy : ndarray, shape ``(m,)``
        Energy of each active cell.
    node_force : ndarray, shape ``(m,)``
        ``-dE_i/dc`` of each active cell: its share of :attr:`force` (``>= 0``).
    hess_blocks : ndarray, shape ``(m, 6, 6)`` or None
        ``d2E_i / d(r_{i-1}, z_{i-1}, r_i, z_i, r_{i+1}, z_{i+1})^2`` of each active cell, in the
        order of its :attr:`stencils` (None when evaluated without Hessian).
    hess_xc : ndarray, shape ``(2N,)`` or None
        ``d2E / dx dc`` (interleaved).
    hess_cc : float or None
        ``d2E / dc^2``.
    """

    position: float
    distances: np.ndarray
    gaps: np.ndarray
    active: np.ndarray
    stencils: np.ndarray
    energy: float
    gradient: np.ndarray
    dE_dc: float
    node_energy: np.ndarray
    node_force: np.ndarray
    hess_blocks: np.ndarray | None = None
    hess_xc: np.ndarray | None = None
    hess_cc: float | None = None

    @property
    def force(self) -> float:
        """Contact force ``F = -dE/dc`` (``> 0`` when the indenter pushes the shell down)."""
        return -self.dE_dc

    @property
    def n_active(self) -> int:
        """Number of cells within ``dhat`` of the indenter."""
        return int(self.active.size)

    def force_gradient(self) -> tuple[np.ndarray, float]:
        """``(dF/dx, dF/dc) = (-d2E/dx dc, -d2E/dc2)`` (needs the Hessian)."""
        self._need_hessian()
        return -self.hess_xc, -float(self.hess_cc)

    def _need_hessian(self) -> None:
        if self.hess_blocks is None:
            raise ValueError("ContactState: evaluated without the Hessian (use hessian=True)")

    def hessian_triplets(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Global entries of ``d2E/dx2``: the 6x6 block of each active cell, full (both triangles).

        Returns
        -------
        rows, cols : ndarray of int, shape ``(36 m,)``
            Indices into the interleaved state, per active cell in row-major order of its block
            (local index ``2 j + a`` is coordinate ``a`` of stencil node ``j``).  A node that occurs
            twice in a stencil (the pole's mirrored neighbour) gives repeated entries, to be summed.
        values : ndarray, shape ``(36 m,)``
        """
        self._need_hessian()
        dofs = _stencil_dofs(self.stencils)
        rows = np.repeat(dofs, 6, axis=1).ravel()
        cols = np.tile(dofs, (1, 6)).ravel()
        return rows, cols, self.hess_blocks.reshape(-1).copy()

    def hessian_matrix(self) -> sp.csr_matrix:
        """``d2E/dx2`` as a ``2N x 2N`` CSR matrix (the active cells' blocks summed)."""
        n = self.gradient.size
        rows, cols, vals = self.hessian_triplets()
        H = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        H.sum_duplicates()
        return H


def _stencil_dofs(stencils: np.ndarray) -> np.ndarray:
    """Interleaved dofs ``(r_j, z_j)`` of each stencil node, shape ``(m, 6)``."""
    return (2 * stencils[:, :, None] + np.array([0, 1])).reshape(len(stencils), 6)


class ContactBarrier:
    """Log-barrier contact of the shell's meridian with a rigid indenter (eq. 3.16, integrated over cells).

    Parameters
    ----------
    indenter : Sphere or Plate
        Shape of the indenter.
    K : float
        Barrier stiffness ``K_c > 0`` (energy / length^2).
    dhat : float
        Barrier width ``dhat > 0`` (length): points farther than ``dhat`` feel nothing.
    quadrature : int
        Gauss-Legendre points per contact cell (:data:`QUADRATURE_POINTS`); ``1`` with no
        ``cell_weights`` is the paper's nodal barrier.
    cell_weights : array_like, shape ``(N,)``, optional
        A factor on each cell (:func:`length_weights` for a barrier per unit length); default 1.
        Given, the barrier only accepts states of ``N`` nodes.
    support_points : int
        Gauss-Legendre points on each piece of a cell within ``dhat`` (:data:`SUPPORT_POINTS`);
        ``0`` integrates at the fixed points instead (module docstring).

    Notes
    -----
    See the module docstring for the cells, the sign conventions (``F = -dE/dc > 0`` when pushing)
    and the Hessian layout.  No method ever returns NaN or inf: a state with a sample point at
    ``d <= 0`` (or a non-finite state) raises :class:`ValueError` naming the cell and its distance.

    Examples
    --------
    >>> K, dhat = default_barrier(E=1e6, R=1.0)
    >>> contact = ContactBarrier(Sphere(0.5), K, dhat)
    >>> x = np.array([0.0, 1.0])              # one node on the axis at z = 1
    >>> st = contact.evaluate(x, 1.5 + 0.5 * dhat)
    >>> st.active.tolist(), st.force > 0
    ([0], True)
    """

    def __init__(self, indenter: Sphere | Plate, K: float, dhat: float, quadrature: int = QUADRATURE_POINTS,
                 cell_weights: ArrayLike | None = None, support_points: int = SUPPORT_POINTS) -> None:
        if not isinstance(indenter, (Sphere, Plate)):
            raise TypeError(f"ContactBarrier: indenter must be a Sphere or a Plate, got {indenter!r}")
        K, dhat = float(K), float(dhat)
        if not (K > 0 and math.isfinite(K)):
            raise ValueError(f"ContactBarrier: K must be a positive number, got {K!r}")
        if not (dhat > 0 and math.isfinite(dhat)):
            raise ValueError(f"ContactBarrier: dhat must be a positive number, got {dhat!r}")
        if int(quadrature) != quadrature or quadrature < 1:
            raise ValueError(f"ContactBarrier: quadrature must be a positive integer, got {quadrature!r}")
        self.indenter = indenter
        self.K = K
        self.dhat = dhat
        if int(support_points) != support_points or support_points < 0:
            raise ValueError(f"ContactBarrier: support_points must be a non-negative integer, got {support_points!r}")
        self.quadrature = int(quadrature)
        self.support_points = int(support_points)
        self._support_rule = np.polynomial.legendre.leggauss(self.support_points) if self.support_points else None
        self.cell_weights = None if cell_weights is None else np.array(cell_weights, dtype=float)
        self._params = indenter.params
        self._distance = getattr(kernels, f"{indenter.name}_distance")
        self._energy = getattr(kernels, f"{indenter.name}_energy")
        self._derivatives = getattr(kernels, f"{indenter.name}_derivatives")
        self._gradient = getattr(kernels, f"{indenter.name}_gradient")
        self._cells_cache: ContactCells | None = None
        # the last state's samples and integration points: a residual and a Hessian at one state
        # find the support once
        self._points_cache: tuple[np.ndarray, float, ContactCells, np.ndarray, IntegrationPoints] | None = None
        # the extension's room for the points of the integral, reused from state to state
        self._workspace: tuple[np.ndarray, ...] | None = None

    @classmethod
    def for_shell(cls, indenter: Sphere | Plate, E: float, R: float,
                  dhat_over_R: float = PAPER_DHAT / PAPER_R, quadrature: int = QUADRATURE_POINTS) -> ContactBarrier:
        """A barrier with the constants of :func:`default_barrier` for modulus ``E`` and radius ``R``."""
        K, dhat = default_barrier(E, R, dhat_over_R)
        return cls(indenter, K, dhat, quadrature)

    def cells(self, n_nodes: int) -> ContactCells:
        """The contact cells of an ``n_nodes``-node meridian (cached for the last ``n_nodes``)."""
        if self._cells_cache is None or self._cells_cache.n_nodes != n_nodes:
            if self.cell_weights is not None and self.cell_weights.size != n_nodes:
                raise ValueError(f"ContactBarrier: the cell weights are for {self.cell_weights.size} nodes, "
                                 f"the state has {n_nodes}")
            self._cells_cache = ContactCells(n_nodes, self.quadrature, self.cell_weights)
        return self._cells_cache

    # ---- distances and checks ---------------------------------------------------------------------
    @staticmethod
    def _state(x, what: str = "x") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x = np.asarray(x, dtype=float)
        if x.ndim != 1 or x.size % 2 or x.size == 0:
            raise ValueError(f"ContactBarrier: {what} must be the interleaved state [r_0, z_0, ...] "
                             f"of even length, got shape {x.shape}")
        if not np.isfinite(x).all():
            bad = int(np.flatnonzero(~np.isfinite(x))[0])
            raise ValueError(f"ContactBarrier: {what} is not finite (entry {bad} = {x[bad]!r})")
        return x, x[0::2], x[1::2]

    @staticmethod
    def _position(c, what: str = "c") -> float:
        c = float(c)
        if not math.isfinite(c):
            raise ValueError(f"ContactBarrier: indenter position {what} = {c!r} is not finite")
        return c

    def _dist(self, r: np.ndarray, z: np.ndarray, c: float) -> np.ndarray:
        return self._distance(r, z, c, *self._params, self.K, self.dhat)

    def distances(self, x, c: float) -> np.ndarray:
        """Distance of every node from the indenter surface (negative inside); no checks on the sign.

        Parameters
        ----------
        x : array_like, shape ``(2N,)``
            Interleaved state.
        c : float
            Indenter position.

        Returns
        -------
        ndarray, shape ``(N,)``
        """
        _, r, z = self._state(x)
        return self._dist(r, z, self._position(c))

    def sample_distances(self, x: ArrayLike, c: float) -> np.ndarray:
        """Distance of every sample point of the cells (:class:`ContactCells`) from the indenter surface.

        Returns
        -------
        ndarray, shape ``(S,)``
            Negative inside; no checks on the sign.
        """
        _, r, z = self._state(x)
        return self._dist(*self.cells(r.size).points(r, z), self._position(c))

    def _checked_samples(self, r: np.ndarray, z: np.ndarray, c: float) -> tuple[ContactCells, np.ndarray]:
        cells = self.cells(r.size)
        ds = self._dist(*cells.points(r, z), c)
        if not np.all(ds > 0):
            bad = np.flatnonzero(~(ds > 0))
            s = int(bad[np.argmin(ds[bad])]) if np.isfinite(ds[bad]).all() else int(bad[0])
            i = int(cells.cell[s])
            raise ValueError(
                f"ContactBarrier: node {i} at (r, z) = ({r[i]:.17g}, {z[i]:.17g}) is not outside the "
                f"{self.indenter.name} indenter at c = {c:.17g}: its cell's sample point {s - cells.first[i]} "
                f"has distance d = {ds[s]:.6g} <= 0 ({bad.size} sample point(s) with d <= 0); the barrier "
                "is infinite there")
        return cells, ds

    def gap_polynomial(self, R: np.ndarray, Z: np.ndarray, c: float, T: np.ndarray | None = None) -> np.ndarray:
        """Ascending coefficients ``(m, 5)`` of a polynomial in ``t`` negative exactly where a cell is within ``dhat``.

        Plate: ``d(t) - dhat``.  Sphere: ``|x(t) - (0, zc)|^2 - (rho + dhat)^2``.  ``R, Z`` are the
        cells' curves (:meth:`ContactCells.curve`: ascending coefficients ``(m, 3)`` of quadratics in ``t``);
        ``T``, a third (circumferential) component of a curve in three dimensions, adds its square.
        """
        g = np.zeros((R.shape[0], 5))
        if isinstance(self.indenter, Plate):
            g[:, 0] = c - self.dhat - Z[:, 0]
            g[:, 1:3] = -Z[:, 1:]
            return g
        q = Z.copy()
        q[:, 0] -= c
        g[:, 0] = -(self.indenter.radius + self.dhat) ** 2
        for p in (R, q) if T is None else (R, T, q):
            g[:, 0] += p[:, 0] ** 2
            g[:, 1] += 2.0 * p[:, 0] * p[:, 1]
            g[:, 2] += p[:, 1] ** 2 + 2.0 * p[:, 0] * p[:, 2]
            g[:, 3] += 2.0 * p[:, 1] * p[:, 2]
            g[:, 4] += p[:, 2] ** 2
        return g

    @property
    def support_rule(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The Gauss-Legendre points and weights on ``[-1, 1]`` of each support piece (None: the fixed points)."""
        return None if self.quadrature == 1 else self._support_rule

    def _integration_points(self, cells: ContactCells, r: np.ndarray, z: np.ndarray, c: float,
                            ds: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Where the barrier integral is sampled: each point's cell, stencil coefficients and weight.

        With ``support_points`` > 0 (and more than one quadrature point, else the barrier is the
        paper's nodal one) each cell's integral runs over the pieces of the cell within ``dhat``,
        found exactly (module docstring); otherwise over the fixed Gauss points of the cells.

        Returns
        -------
        cell : ndarray of int, shape ``(P,)``
            Non-decreasing: the points come cell by cell (:meth:`evaluate` sums them by segments).
        cr, cz : ndarray, shape ``(P, 3)``
            The point's ``r`` and ``z`` as combinations of its cell's three nodes.
        weight : ndarray, shape ``(P,)``
        """
        if self.quadrature == 1 or self._support_rule is None:
            near = np.flatnonzero(ds < self.dhat)
            return cells.cell[near], cells.cr[near], cells.cz[near], cells.weight[near]
        base = np.flatnonzero(ds[:1] < self.dhat)  # the base node's own term
        # a cell whose fixed samples all lie beyond 2 dhat cannot dip within dhat between them: the
        # curve's sag over a sample spacing (1/15 of a cell) is far below dhat for any mesh we accept
        near = np.flatnonzero(cells.cell_minimum(ds)[1:] < 2.0 * self.dhat) + 1
        if near.size == 0:
            return cells.cell[base], cells.cr[base], cells.cz[base], cells.weight[base]
        Rc, Zc = cells.curve(r, z, near)
        rows, a, b = support_pieces(self.gap_polynomial(Rc, Zc, c))
        xi, wq = self._support_rule
        t = 0.5 * (a + b)[:, None] + 0.5 * (b - a)[:, None] * xi
        cell = np.repeat(near[rows], xi.size)
        weight = (0.5 * (b - a)[:, None] * wq).ravel() * cells.cell_weight[cell]
        basis = kernels.cell_basis(t.ravel()).T
        cr, cz = basis * cells.sign_r[cell], basis
        return (np.concatenate([cells.cell[base], cell]), np.concatenate([cells.cr[base], cr]),
                np.concatenate([cells.cz[base], cz]), np.concatenate([cells.weight[base], weight]))

    def _points_within(self, cells: ContactCells, r: np.ndarray, z: np.ndarray, c: float,
                       ds: np.ndarray) -> IntegrationPoints:
        """:meth:`_integration_points` and their coordinates, keeping those within ``dhat``.

        Raises ``ValueError`` when a point of the integral lies on or inside the indenter (the
        meridian dips into it between the fixed samples that the step filter watches).
        """
        cell, cr, cz, w = self._integration_points(cells, r, z, c, ds)
        nodes = cells.stencil[cell]
        rs, zs = np.sum(cr * r[nodes], axis=1), np.sum(cz * z[nodes], axis=1)
        d = self._dist(rs, zs, c)
        if not np.all(d > 0):
            k = int(np.argmin(np.where(np.isfinite(d), d, -np.inf)))
            raise ValueError(f"ContactBarrier: cell {int(cell[k])} dips into the {self.indenter.name} indenter "
                             f"between its sample points (d = {d[k]:.6g} <= 0); the barrier is infinite there")
        keep = d < self.dhat  # the ends of a support piece sit at dhat up to rounding
        return IntegrationPoints(cell[keep], cr[keep], cz[keep], w[keep], rs[keep], zs[keep])

    def _samples_and_points(self, x: np.ndarray, r: np.ndarray, z: np.ndarray,
                            c: float) -> tuple[ContactCells, np.ndarray, IntegrationPoints]:
        """The cells, each cell's smallest sample distance and the points of the integral at ``(x, c)``.

        :meth:`_checked_samples` and :meth:`_points_within`, in C where the extension is built
        (:func:`barrier_extension`); remembered for the last state.
        """
        cached = self._points_cache
        if cached is not None and cached[1] == c and same_values(cached[0], x):
            return cached[2], cached[3], cached[4]
        found = self._compiled_support(x, c)
        if found is None:  # numpy, which also raises the errors that name a point inside the indenter
            cells, ds = self._checked_samples(r, z, c)
            gaps, pts = cells.cell_minimum(ds), self._points_within(cells, r, z, c, ds)
        else:
            cells, gaps, pts = found
        self._points_cache = (x.copy(), c, cells, gaps, pts)
        return cells, gaps, pts

    @property
    def _radius(self) -> float:
        """The sphere's radius for the extension (0 for a plate, which it does not read)."""
        return self.indenter.radius if isinstance(self.indenter, Sphere) else 0.0

    def _support_extension(self) -> Any:
        """The C extension where it runs this barrier's support integration (not the fixed-point rules)."""
        if self.quadrature == 1 or self._support_rule is None:
            return None
        return barrier_extension()

    def _compiled_support(self, x: np.ndarray,
                          c: float) -> tuple[ContactCells, np.ndarray, IntegrationPoints] | None:
        """:meth:`_samples_and_points`'s work in C; None without the extension or when a point is not outside."""
        ext = self._support_extension()
        if ext is None:
            return None
        n = x.size // 2
        cells = self.cells(n)
        xi, wq = self._support_rule
        room = 1 + 4 * xi.size * (n - 1)  # at most four monotone pieces per cell
        if self._workspace is None or self._workspace[0].size != room:
            self._workspace = (np.empty(room, dtype=np.int64), np.empty((room, 3)), np.empty((room, 3)),
                               np.empty(room), np.empty(room), np.empty(room))
        cell, cr, cz, w, rs, zs = self._workspace
        gaps = np.empty(n)
        count = ext.support(np.ascontiguousarray(x), c, self._radius, isinstance(self.indenter, Plate), self.dhat,
                            cells.basis, cells.cell_weight, xi, wq, gaps, cell, cr, cz, w, rs, zs)
        if count < 0:
            return None
        pts = IntegrationPoints(cell[:count].copy(), cr[:count].copy(), cz[:count].copy(), w[:count].copy(),
                                rs[:count].copy(), zs[:count].copy())
        return cells, gaps, pts

    def integration_points(self, x: ArrayLike, c: float) -> IntegrationPoints:
        """The points of the barrier integral within ``dhat`` of the indenter at ``(x, c)``, with weights.

        The energy is ``sum_k weight_k W(d(r_k, z_k))`` over them; its derivatives are the point
        kernels' at the same points (module docstring).  Raises ``ValueError`` as :meth:`check`.
        """
        x, r, z = self._state(x)
        c = self._position(c)
        return self._samples_and_points(x, r, z, c)[2]

    def check(self, x, c: float) -> np.ndarray:
        """Distances of every node, raising :class:`ValueError` if any sample point has ``d <= 0``.

        Returns
        -------
        ndarray, shape ``(N,)``
        """
        _, r, z = self._state(x)
        c = self._position(c)
        self._checked_samples(r, z, c)
        return self._dist(r, z, c)

    def active_set(self, x, c: float) -> np.ndarray:
        """Indices of the cells with a sample point within ``dhat`` of the indenter (after :meth:`check`)."""
        _, r, z = self._state(x)
        cells, ds = self._checked_samples(r, z, self._position(c))
        return np.flatnonzero(cells.cell_minimum(ds) < self.dhat)

    def hessian_slots(self, pattern: sp.csr_matrix) -> np.ndarray:
        """Places of every cell's 6x6 Hessian block in the data array of a CSR matrix.

        Parameters
        ----------
        pattern : scipy.sparse.csr_matrix, shape ``(2N, 2N)``
            A matrix in canonical form (sorted indices, no duplicates) whose pattern holds every
            entry coupling the nodes ``i-1, i, i+1`` (the shell's Hessian does).

        Returns
        -------
        ndarray of int, shape ``(N, 36)``
            ``slots[i]`` indexes ``pattern.data`` in the order of :meth:`ContactState.hessian_triplets`
            (repeated slots for the pole's mirrored neighbour: accumulate with ``numpy.add.at``).

        Raises
        ------
        ValueError
            If an entry is missing from the pattern.
        """
        H = sp.csr_matrix(pattern)
        n = H.shape[0]
        if not H.has_canonical_format:
            raise ValueError("hessian_slots: the pattern must be a canonical CSR matrix")
        cells = self.cells(n // 2)
        dofs = _stencil_dofs(cells.stencil)
        rows = np.repeat(dofs, 6, axis=1)
        cols = np.tile(dofs, (1, 6))
        # sorted keys of the stored entries: the slot of (i, j) is where i * n + j sits among them
        keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(H.indptr)) * n + H.indices
        want = rows.astype(np.int64) * n + cols
        slots = np.searchsorted(keys, want)
        found = (slots < keys.size) & (keys[np.minimum(slots, keys.size - 1)] == want)
        if not np.all(found):
            k = np.flatnonzero(~found.ravel())[0]
            raise ValueError(f"hessian_slots: entry ({rows.ravel()[k]}, {cols.ravel()[k]}) is not in the pattern")
        return slots

    # ---- energy and derivatives -------------------------------------------------------------------
    def energy(self, x, c: float) -> float:
        """Total barrier energy ``E(x, c)`` (raises :class:`ValueError` if a sample point has ``d <= 0``)."""
        x, r, z = self._state(x)
        c = self._position(c)
        _, _, pts = self._samples_and_points(x, r, z, c)
        if pts.weight.size == 0:
            return 0.0
        return float(np.sum(pts.weight * self._energy(pts.r, pts.z, c, *self._params, self.K, self.dhat)))

    def gradient(self, x, c: float) -> tuple[np.ndarray, float]:
        """``(dE/dx, dE/dc)``: gradient with respect to the interleaved state and the position."""
        st = self.evaluate(x, c, hessian=False)
        return st.gradient, st.dE_dc

    def force(self, x, c: float) -> float:
        """Contact force ``F = -dE/dc`` on the indenter (``> 0`` when it pushes the shell down)."""
        return self.evaluate(x, c, hessian=False).force

    def evaluate(self, x, c: float, hessian: bool = True) -> ContactState:
        """Energy, gradient, contact force and (optionally) the Hessian at ``(x, c)``.

        Parameters
        ----------
        x : array_like, shape ``(2N,)``
            Interleaved state ``[r_0, z_0, ..., r_{N-1}, z_{N-1}]`` (node ``N-1`` the pole).
        c : float
            Indenter position (``zc`` for a sphere, ``zp`` for a plate).
        hessian : bool
            Also compute the 6x6 cell blocks, ``d2E/dx dc`` and ``d2E/dc2``.

        Returns
        -------
        ContactState

        Raises
        ------
        ValueError
            If ``x`` or ``c`` is not finite or a sample point has ``d <= 0`` (the message names the
            cell with the smallest distance).
        """
        x, r, z = self._state(x)
        c = self._position(c)
        cells, gaps, pts = self._samples_and_points(x, r, z, c)
        n = x.size
        d_nodes = self._dist(r, z, c)
        if pts.weight.size == 0:
            empty = np.zeros(0)
            act = np.zeros(0, dtype=int)
            st = ContactState(c, d_nodes, gaps, act, cells.stencil[act], 0.0, np.zeros(n), 0.0, empty, empty)
            if hessian:
                st.hess_blocks, st.hess_xc, st.hess_cc = np.zeros((0, 6, 6)), np.zeros(n), 0.0
            return st
        rs, zs = pts.r, pts.z
        if hessian:
            e, g, h = self._derivatives(rs, zs, c, *self._params, self.K, self.dhat)
        else:
            e, g, h = self._energy(rs, zs, c, *self._params, self.K, self.dhat), \
                self._gradient(rs, zs, c, *self._params, self.K, self.dhat), None
        sums = self._chain_rule(pts, e, g, h, n)
        if sums is None:
            # only for d so small (d / dhat < ~1e-150) that W'' overflows; never return inf
            bad = int(pts.cell[np.argmin(self._dist(rs, zs, c))])
            raise ValueError(f"ContactBarrier: node {bad}'s cell is too close to the {self.indenter.name} indenter "
                             f"(d = {gaps[bad]:.6g}): the barrier derivatives overflow")
        act, cell_e, cell_f, grad, blocks, xc = sums
        st = ContactState(c, d_nodes, gaps, act, cells.stencil[act], float(cell_e.sum()), grad, -float(cell_f.sum()),
                          cell_e, cell_f)
        if hessian:
            st.hess_blocks, st.hess_xc, st.hess_cc = blocks, xc, float((pts.weight * h[5]).sum())
        return st

    def _chain_rule(self, pts: IntegrationPoints, e: np.ndarray, g: np.ndarray, h: np.ndarray | None,
                    n: int) -> tuple[np.ndarray, ...] | None:
        """The cells' sums of the point kernels' values through the points' stencil coefficients.

        A point ``x_s = sum_j c_sj x_j`` is linear in its cell's nodes, so the cell's derivatives are the
        point kernel's times the coefficients (times the weights), summed over the cell's points.  In C
        where the extension is built (:func:`barrier_extension`).

        Parameters
        ----------
        pts : IntegrationPoints
            The points (at least one), cell by cell in increasing order.
        e, g, h : ndarray
            The point kernels' energies ``(P,)``, gradients ``(3, P)`` and packed Hessians ``(6, P)``
            (None: no Hessian).
        n : int
            Size of the interleaved state.

        Returns
        -------
        (active, cell_e, cell_f, gradient, blocks, xc) or None
            The cells with a point, their energies and forces ``-dE_i/dc``, ``dE/dx``, the 6x6 blocks and
            ``d2E/dx dc`` (the last two None without ``h``); None when a derivative is not finite.
        """
        hessian = h is not None
        ext = barrier_extension()
        if ext is not None:
            size = pts.weight.size
            act, cell_e, cell_f = np.empty(size, dtype=np.int64), np.empty(size), np.empty(size)
            grad = np.zeros(n)
            blocks, xc = (np.empty((size, 6, 6)), np.zeros(n)) if hessian else (None, None)
            m = ext.assemble(n // 2, pts.cell.astype(np.int64, copy=False), pts.cr, pts.cz, pts.weight, e, g, grad,
                             act, cell_e, cell_f, h, blocks, xc)
            if m < 0:
                return None
            return act[:m], cell_e[:m], cell_f[:m], grad, (blocks[:m] if hessian else None), xc
        if not (np.isfinite(g).all() and (not hessian or np.isfinite(h).all())):
            return None
        cell_of, cr_of, cz_of, w = pts.cell, pts.cr, pts.cz, pts.weight
        act = np.unique(cell_of)
        # the points come cell by cell in increasing order, so each cell's sums are one segment's
        where = np.searchsorted(act, cell_of)  # each point's row among the active cells
        starts = np.searchsorted(where, np.arange(act.size))

        def per_cell(values: np.ndarray) -> np.ndarray:
            return np.add.reduceat(values, starts, axis=0)

        cr, cz = cr_of * w[:, None], cz_of * w[:, None]
        node_g = per_cell(np.stack([cr * g[0][:, None], cz * g[1][:, None]], axis=2))
        dofs = _stencil_dofs(self.cells(n // 2).stencil[act])
        grad = np.zeros(n)
        np.add.at(grad, dofs.ravel(), node_g.reshape(-1))
        cell_e = per_cell(w * e)
        cell_f = -per_cell(w * g[2])
        if not hessian:
            return act, cell_e, cell_f, grad, None, None
        # the block of a point on the cell's (r_0, z_0, r_1, z_1, r_2, z_2): its coefficients'
        # outer products times the point kernel's (r, z) Hessian.  The outer product is formed
        # first: s * (c_i c_j) is exactly symmetric in i, j, while (s c_i) c_j is not (it rounds
        # differently from (s c_j) c_i, and the engine's symmetric solvers see the difference)
        blocks = np.empty((act.size, 6, 6))
        blocks[:, 0::2, 0::2] = per_cell((w * h[0])[:, None, None] * (cr_of[:, :, None] * cr_of[:, None, :]))
        rz = per_cell((w * h[1])[:, None, None] * (cr_of[:, :, None] * cz_of[:, None, :]))
        blocks[:, 0::2, 1::2], blocks[:, 1::2, 0::2] = rz, rz.transpose(0, 2, 1)
        blocks[:, 1::2, 1::2] = per_cell((w * h[3])[:, None, None] * (cz_of[:, :, None] * cz_of[:, None, :]))
        xc_cell = np.empty((act.size, 6))
        xc_cell[:, 0::2], xc_cell[:, 1::2] = per_cell(cr * h[2][:, None]), per_cell(cz * h[4][:, None])
        xc = np.zeros(n)
        np.add.at(xc, dofs.ravel(), xc_cell.ravel())
        return act, cell_e, cell_f, grad, blocks, xc

    def nearest_sample(self, x: ArrayLike, c: float) -> tuple[int, float]:
        """The sample point closest to the indenter: its index and distance (after :meth:`check`)."""
        _, r, z = self._state(x)
        _, ds = self._checked_samples(r, z, self._position(c))
        s = int(np.argmin(ds))
        return s, float(ds[s])

    def sample_gap(self, x: ArrayLike, c: float, sample: int) -> tuple[float, np.ndarray, float]:
        """Distance of one sample point from the indenter and its exact first derivatives.

        Parameters
        ----------
        x, c
            The interleaved state ``(2N,)`` and the indenter position.
        sample : int
            Index of the sample point (:class:`ContactCells`).

        Returns
        -------
        d : float
            Its distance (negative inside).
        dd_dx : ndarray, shape ``(2N,)``
            ``dd/dx`` (nonzero on its cell's three nodes only).
        dd_dc : float
        """
        x, r, z = self._state(x)
        c = self._position(c)
        cells = self.cells(r.size)
        cell = int(cells.cell[sample])
        nodes = cells.stencil[cell]
        rs, zs = float(np.dot(cells.cr[sample], r[nodes])), float(np.dot(cells.cz[sample], z[nodes]))
        d, dr, dz, dc = self._point_distance_gradient(rs, zs, c)
        grad = np.zeros(x.size)
        np.add.at(grad, 2 * nodes, cells.cr[sample] * dr)
        np.add.at(grad, 2 * nodes + 1, cells.cz[sample] * dz)
        return d, grad, dc

    def closest_point(self, x: ArrayLike, c: float) -> tuple[float, np.ndarray, float, int, float]:
        """The point of the meridian the barrier sees (its cells' C1 curve) nearest to the indenter.

        Returns
        -------
        d : float
            Its distance from the indenter surface.
        dd_dx : ndarray, shape ``(2N,)``
            ``dd/dx``: with the point free to slide along the curve, the derivative at fixed ``t``
            (the distance is stationary in ``t`` at an interior minimum).
        dd_dc : float
        cell : int
            Its cell (0: the base node).
        t : float
            Its place in the cell, in ``[-1/2, 1/2]``.
        """
        x, r, z = self._state(x)
        c = self._position(c)
        cells = self.cells(r.size)
        inner = np.arange(1, r.size)
        Rc, Zc = cells.curve(r, z, inner)
        g = self.gap_polynomial(Rc, Zc, c)
        breaks = _monotone_breaks(g)
        vals = _polyval(g, breaks)
        k = np.argmin(vals, axis=1)
        t_all = breaks[np.arange(inner.size), k]
        basis = kernels.cell_basis(t_all).T
        nodes = cells.stencil[inner]
        rs = np.sum(basis * cells.sign_r[inner] * r[nodes], axis=1)
        zs = np.sum(basis * z[nodes], axis=1)
        d_all = np.concatenate([self._dist(r[:1], z[:1], c), self._dist(rs, zs, c)])
        best = int(np.argmin(d_all))
        if best == 0:
            cell, t, coef = 0, 0.0, np.array([0.0, 1.0, 0.0])
        else:
            cell, t, coef = best, float(t_all[best - 1]), basis[best - 1]
        nodes = cells.stencil[cell]
        cr, cz = coef * cells.sign_r[cell], coef
        rp, zp = float(np.dot(cr, r[nodes])), float(np.dot(cz, z[nodes]))
        d, dr, dz, dc = self._point_distance_gradient(rp, zp, c)
        grad = np.zeros(x.size)
        np.add.at(grad, 2 * nodes, cr * dr)
        np.add.at(grad, 2 * nodes + 1, cz * dz)
        return d, grad, dc, cell, t

    def pole_distance(self, x: ArrayLike, c: float) -> float:
        """Distance from the indenter of the meridian's point on the axis (no check of its sign).

        The barrier's curve passes the axis at the middle of the pole's cell, ``3/4`` of the pole
        node's height and ``1/4`` of its neighbour's (the nodal barrier: the pole node itself).
        """
        return float(self._dist(np.zeros(1), np.array([self.pole_height(x)]), self._position(c))[0])

    def pole_height(self, x: ArrayLike) -> float:
        """Height of the meridian's point on the axis as the barrier sees it (see :meth:`pole_distance`)."""
        _, r, z = self._state(x)
        if self.quadrature == 1 or r.size == 1:
            return float(z[-1])
        middle = float(kernels.cell_basis(0.0)[1])  # the mirrored neighbour has the rest
        return float(middle * z[-1] + (1.0 - middle) * z[-2])

    def _point_distance_gradient(self, rp: float, zp: float, c: float) -> tuple[float, float, float, float]:
        """``(d, dd/dr, dd/dz, dd/dc)`` of one point."""
        if isinstance(self.indenter, Plate):  # d = c - z
            return c - zp, 0.0, -1.0, 1.0
        q = math.hypot(rp, zp - c)
        return q - self.indenter.radius, rp / q, (zp - c) / q, -(zp - c) / q

    # ---- step filter ------------------------------------------------------------------------------
    def max_safe_fraction(self, x, c: float, dx, dc: float = 0.0, safety: float = 0.9) -> float:
        """Largest safe fraction of the step ``(dx, dc)`` from ``(x, c)``, times ``safety``.

        With ``t*`` the first ``s`` in ``(0, 1]`` at which some sample point reaches the indenter
        surface (``d_k(x + s dx, c + s dc) = 0``), returns ``safety * t*``; returns ``1.0`` when no
        sample point reaches it for ``s`` in ``[0, 1]`` (the whole step is safe).  All sample points
        are considered, not only the active ones; a sample point is linear in the nodes, so it moves
        along a straight segment.  Plate: ``d_k(s) = d_k - s (dz_k - dc)`` is linear.  Sphere: the
        first root in ``(0, 1]`` of ``|u_k + s v_k|^2 = rho^2`` with ``u_k = (r_k, z_k - zc)``,
        ``v_k = (dr_k, dz_k - dc)``, computed exactly (in the cancellation-free form
        ``s = (|u|^2 - rho^2) / (-u.v + sqrt((u.v)^2 - |v|^2 (|u|^2 - rho^2)))``).

        Parameters
        ----------
        x : array_like, shape ``(2N,)``
            Current interleaved state (every sample point must have ``d > 0``).
        c : float
            Current indenter position.
        dx : array_like, shape ``(2N,)``
            Step of the state.
        dc : float
            Step of the indenter position.
        safety : float
            Factor in ``(0, 1)`` applied to a limited step (IPC-style: stop short of contact).

        Returns
        -------
        float
            In ``(0, 1]``; ``1.0`` exactly when the whole step is safe, else ``< 1``.

        Raises
        ------
        ValueError
            If the current state has a sample point at ``d <= 0``, or an argument is not finite.
        """
        safety = float(safety)
        if not (0 < safety < 1):
            raise ValueError(f"ContactBarrier.max_safe_fraction: safety must be in (0, 1), got {safety!r}")
        x, r, z = self._state(x)
        c = self._position(c)
        dx, dr, dz = self._state(dx, "dx")
        if dx.size != x.size:
            raise ValueError(f"ContactBarrier.max_safe_fraction: dx has {dx.size} entries, x has {x.size}")
        dc = self._position(dc, "dc")
        ext = barrier_extension()
        if ext is not None:
            t = ext.safe_fraction(np.ascontiguousarray(x), np.ascontiguousarray(dx), c, dc, self._radius,
                                  isinstance(self.indenter, Plate), self.cells(r.size).basis)
            if t >= 0:
                return 1.0 if t > 1.0 else safety * t
            # a sample point is not outside: numpy's check below names it
        cells, d = self._checked_samples(r, z, c)
        r, z = cells.points(r, z)
        dr, dz = cells.points(dr, dz)
        if isinstance(self.indenter, Plate):
            rate = dz - dc  # d_k(s) = d_k - s * rate
            closing = rate > 0
            if not np.any(closing):
                return 1.0
            roots = d[closing] / rate[closing]
        else:
            rho = self.indenter.radius
            ur, uz = r, z - c
            vr, vz = dr, dz - dc
            a = vr * vr + vz * vz
            b = ur * vr + uz * vz
            cc = d * (np.hypot(ur, uz) + rho)  # |u|^2 - rho^2 > 0, without cancellation
            disc = b * b - a * cc
            hit = (b < 0) & (disc >= 0)
            if not np.any(hit):
                return 1.0
            roots = cc[hit] / (-b[hit] + np.sqrt(disc[hit]))
        t = float(np.min(roots))
        return 1.0 if t > 1.0 else safety * t

    def __repr__(self) -> str:
        return f"ContactBarrier({self.indenter!r}, K={self.K!r}, dhat={self.dhat!r}, quadrature={self.quadrature!r})"
