"""Hessian blocks per circumferential wave number ``n`` at an axisymmetric state (issue 17).

The traced model is axisymmetric: its energy (:class:`contin_models.shell.structure.ShellStructure`)
is a function of the meridian's nodes ``(r_i, z_i)``.  To judge stability against non-axisymmetric
modes this module defines a **2-D shell energy** of rings of material points whose restriction to
axisymmetric states is exactly the traced 1-D energy, and computes the blocks of its Hessian per
wave number ``n`` ("harmonic" or semi-analytic discretisation, ``docs/model.md#harmonic-blocks``, as
BOSOR and AQUINAS do).

Kinematics
----------
Node ``i`` of the meridian is a ring of material points labelled by the reference angle ``theta``.
In the local frame ``(e_r(theta), e_theta(theta), e_z)`` the point's position is
``P_i(theta) = (R_i, T_i, Z_i)`` (radial, circumferential, axial components; ``T = 0`` on an
axisymmetric state), and its ``theta``-derivatives are (``e_r' = e_theta``, ``e_theta' = -e_r``)

    ``P'  = (R' - T, R + T', Z')``,
    ``P'' = (R'' - R - 2 T', 2 R' - T + T'', Z'')``.

Every energy density below is built from dot and cross products of differences of node positions
and of ``P'``, ``P''`` only, so the 2-D energy is invariant under every rigid motion of space (not
only rotations about the axis): an unsupported shell has exactly its six rigid zero modes.

The 2-D energy (per radian of ``theta``, integrated over ``[0, 2 pi)``)
------------------------------------------------------------------------
Stretching, edge ``i`` (nodes ``i``, ``j = i+1``): ``g1 = (P_j - P_i) / lbar`` (the meridional chord
between the two rings at the same ``theta``), ``g2 = (P'_i + P'_j) / (2 rbar)`` (the circumferential
tangent at the edge's middle),

    ``eps11 = |g1| - 1``, ``eps22 = |g2| - 1``, ``eps12 = g1.g2 / (2 |g1| |g2|)``,
    ``e = (rbar lbar / 2) ks (eps11^2 + 2 nu eps11 eps22 + eps22^2 + 2 (1 - nu) eps12^2)``.

On an axisymmetric state ``|g1| = l / lbar``, ``|g2| = (r_i + r_j) / (2 rbar)``, ``eps12 = 0`` and
``2 pi e`` is the 1-D element energy ``pi rbar lbar ks (...)`` exactly.

Bending, interior node ``i`` (edges ``e1 = P_i - P_{i-1}``, ``e2 = P_{i+1} - P_i`` at the same
``theta``, circumferential unit tangent ``tau = P'_i / |P'_i|``):

    ``kappa11 = 2 cross / ((|e1| |e2| + e1.e2) L)``, ``cross = -(e1 x e2).tau`` (the turning about
    the circumferential direction; ``2 tan(xi/2) / L`` of the 1-D code, same sign, same ``L``:
    current ``(|e1| + |e2|)/2`` or the reference Voronoi length),
    ``n = tau x t / |tau x t|``, ``t = e1/|e1| + e2/|e2|`` (the 1-D bisector normal),
    ``kappa22 = -n.P''_i / |P'_i|^2`` (the circumferential normal curvature, ``n_r / r`` when
    axisymmetric),
    ``kappa12 = n.(P'_{i+1} - P'_{i-1}) / ((|e1| + |e2|) |P'_i|)`` (twist, zero when axisymmetric),
    ``e = (rbar lbar / 2) kb (B11^2 + 2 nu B11 B22 + B22^2 + 2 (1 - nu) kappa12^2)``,
    ``B = kappa - kappabar`` with the 1-D reference curvatures.

The clamp (:class:`contin_models.shell.structure.ClampedEdge`) is the same bending density on
``(ghost, P_0, P_1)`` with the ghost ring fixed in space and ``L`` its reference length, weight
``pi r_0 lbar`` as in 1-D.

The pole (a node on the axis) carries the 1-D mirror element (:class:`contin_models.shell.problem.PoleMirror`)
made real: in the meridional plane at ``theta`` the three points ``P_nb(theta)``, the pole and
``P_nb(theta + pi)`` (``nb`` the pole's neighbour; on an axisymmetric state the last point *is* the
1-D mirror node) give a directional curvature ``kappa(theta) = 2 tan(xi/2) / L`` (the sign from the
direction ``P'_nb(theta) - P'_nb(theta + pi)``), ``B(theta) = kappa(theta) - kappabar``.  A plate's
energy density with curvature-change tensor ``B`` is ``kb ((1 + nu) H^2 + (1 - nu) D^2)`` with the
mean ``H = <B(theta)>`` and the deviator ``D^2 = 2 (<B^2> - <B>^2)`` (``<>`` the average over
``theta``), so the pole's element is

    ``E_pole = A kb ((3 nu - 1) <B>^2 + 2 (1 - nu) <B^2>)``, ``A = pi (lbar/2)^2``,

which is the 1-D ``A kb (1 + nu) B^2`` on axisymmetric states.  Its second variation along mode
``n >= 1`` is ``A kb (4 (1 - nu) <dB^2> + 2 (1 + nu) B <d2B>)`` (``<dB> = 0`` for ``n >= 1``).

Pressure: the enclosed volume of the 2-D surface made of the ruled strips
``X(s, theta) = (1 - s) P_i(theta) + s P_j(theta)`` (and the skirt from the base plane
``z = z_ref`` up to ring 0, as in :mod:`contin_models.shell.volume`) is the flux of
``F = (x, y, 0) / 2`` (``div F = 1``): per radian and per strip, integrated exactly over ``s``,
``(1/2) [1/3 h_i.(P'_i x D) + 1/6 (h_i.(P'_j x D) + h_j.(P'_i x D)) + 1/3 h_j.(P'_j x D)]`` with
``D = P_j - P_i`` and ``h`` the horizontal part of ``P``; the skirt gives
``(1/2) (R_0 P'_0,t - T_0 P'_0,r) (Z_0 - z_ref)``.  On axisymmetric states this is the 1-D
``V`` exactly.  It is the volume of a closed surface (strips, skirt, base plane: ``F`` has no flux
through a horizontal plane), so ``p (V - V0)`` is the exact potential of the follower pressure on
a closed shell and on a shell whose edge ring stays on the base plane (``z_0 = z_ref``: sliding,
pinned, clamped); on a free edge it is refused, as in 1-D.

Harmonic blocks
---------------
At an axisymmetric state every density depends on the local variables (``P``, ``P'``, ``P''`` of
its rings at one ``theta``) with a Hessian ``H`` independent of ``theta``.  The perturbation of
mode ``n``, with amplitudes ``u_i = (a_i, b_i, c_i)`` per node,

    ``dR_i = a_i cos(n theta)``, ``dZ_i = b_i cos(n theta)``, ``dT_i = c_i sin(n theta)``

(for ``n = 0``: ``dR = a``, ``dZ = b``, ``dT = c``, constants), changes the local variables by
``cos(n theta) Yc u + sin(n theta) Ys u``, so the second variation of the energy integrates to

    ``u^T K_n u = pi (Yc^T H Yc + Ys^T H Ys)`` (``n >= 1``),  ``2 pi (Yc + Ys)^T H (Yc + Ys)`` (``n = 0``),

i.e. :func:`harmonic_block` returns the exact second variation of the 2-D energy along the field
(``u^T K_n u = d^2 E``); its Rayleigh quotient against the field's L2 norm is ``u^T K u / (pi |u|^2)``
for ``n >= 1`` and ``/ (2 pi |u|^2)`` for ``n = 0``.  The copy with ``cos`` and ``sin`` swapped has
the same block.  The local Hessians ``H`` are computed once per state (all ``n`` share them): the
bending density's from generated curvature jets by the chain rule, the stretching and rotating edge's
densities' and the poles' curvature jets by generated code (:mod:`contin_models.shell.harmonic_codegen`,
sympy, emitted to :mod:`contin_models.shell._harmonic_generated`), the rest (and all of them with
``method="jets"``, the reference) by exact second-order forward differentiation (:class:`Jet`),
vectorised over the elements.  The mode maps are quadratic in ``n``, so the block of ``n >= 1`` is
``pi sum_d n^d C_d`` (``d = 0..4``).  The maps are sparse (a dof moves few local variables) and at an
axisymmetric state ``H`` couples no variable moved by the ``cos`` part with one moved by the ``sin``
part, so each ``C_d`` entry is a short sum of ``H`` entries: a sparse matrix, built once per
reduction to admissible dofs, maps the stacked local Hessians straight to the coefficients in
LAPACK's upper band storage (:meth:`HarmonicShell.band_block`, a :class:`contin.numerics.linalg.SymmetricBand`).
A block is then one combination of five band arrays plus the poles' and the contact's few elements.
Cost O(N) per state and per block.

Dof ordering and fixed dofs
---------------------------
The full block is ``3N x 3N`` in the interleaved order ``[a_0, b_0, c_0, a_1, b_1, c_1, ...]``
(half-bandwidth 8).  :func:`harmonic_dofs` gives the reduction to the admissible dofs of mode ``n``
(a matrix ``T``, ``3N x m``, whose columns are unit vectors except at a pole for ``n = 1``):

* a pole (node on the axis) is one material point, so its displacement must not depend on
  ``theta``: ``n = 0``: ``a = c = 0`` (``b`` free); ``n = 1``: ``b = 0`` and ``c = -a`` (one dof,
  the lateral displacement ``a`` along ``e_x``); ``n >= 2``: ``a = b = c = 0``;
* the edge (node 0, not on the axis): ``"sliding"`` fixes ``b`` and ``c`` for every ``n`` (the
  edge ring moves only radially on its frictionless base, like a radial guide: ``c`` fixed removes
  the rigid rotation about the axis at ``n = 0`` and the rigid lateral slide at ``n = 1``, which a
  frictionless plane would leave neutral); ``"pinned"`` and ``"clamped"`` fix ``a``, ``b``, ``c``
  (the clamp's ghost ring holds the edge tangent for every ``n``); ``"free"`` fixes nothing;
* a pole at node 0 with ``"pinned"`` (a point support of a closed shell's pole) is held in space: its
  ``b`` at ``n = 0``, its lateral ``a`` (and the tied ``c``) at ``n = 1``; with ``remove_rigid`` the spin
  about the axis, which two points on it do not hold, is removed at ``n = 0`` by ``c`` of the node
  ``N // 2``;
* when the structure has no support in ``z`` (free edge or closed shell, ``rigid_fix`` set), with
  ``remove_rigid=True`` (default) the rigid motions are removed at the node ``k`` of ``rigid_fix``:
  ``n = 0``: ``b_k`` and ``c_k`` (axial translation, torsion); ``n = 1``: ``a_k`` and ``b_k``
  (lateral translation, tilt).

* ``control_fixed``: the dofs a control holds at ``n = 0`` (the loaded node's height under
  displacement control); a prescribed pole deflection, volume or indenter position is unchanged to
  first order by the ``n >= 1`` fields, so the controls share the ``n >= 1`` blocks.

Why these choices.  The pole's conditions are kinematics, not modelling: ``P_pole(theta)`` must be
one point.  The sliding base's ``c = 0`` is the one modelling choice: the paper's base is a
frictionless plane in 1-D, which in 2-D would leave the rigid rotation about the axis (``n = 0``)
and the rigid lateral slide (``n = 1``) neutral (zero eigenvalues that say nothing about the shell);
a radial guide is the support under which the 1-D sliding base is the axisymmetric restriction and
the blocks are definite.  A sliding edge with ``c`` free is :func:`harmonic_dofs` with the
structure's ``boundary`` read as ``"free"`` for ``c``: not offered (say if needed).

Loads and contact
-----------------
A point force at the pole and a ring force are linear potentials (``-F w``): no block.  The
pressure adds ``p`` times the volume's block (above).  A contact barrier
(:mod:`contin_models.contact.barrier`) adds, per sample point of its cells (the same Gauss points,
weights and pole mirror), ``(1 / 2 pi) int w_s W(d(X_s(theta))) dtheta`` with ``X_s(theta)`` the
cell's quadratic through the three rings at ``theta`` and ``d`` the 3-D distance to the indenter
(sphere or point on the axis: ``|X - C| - rho``; plate: ``c - X_z``), which is the 1-D ``d`` on the
meridian plane.  Its per-point Hessian (:func:`contact_point_hessian`) has, beside the 1-D
``(r, z)`` block, the circumferential entry ``W'(d) / |X - C|`` (negative while the barrier
pushes: a point pressed against a convex indenter is tangentially unstable unless the shell holds
it), zero for the plate.

Measured (``tests/test_harmonic.py``, ``python -m studies.harmonic_probe``)
--------------------------------------------------------------------------
* ``n = 0`` block on ``(r, z)`` = the traced Hessian (with ``p d2V``, with contact) to 1e-13
  relative (observed 2e-16 .. 5e-16), torsion uncoupled (exactly zero).
* Free cap and pressurised complete sphere: exactly 2 zero eigenvalues at ``n = 0`` and ``n = 1``
  (below 1e-12 of the block norm; the analytic rigid fields are null vectors), none at ``n = 2, 3``.
* Ring mesh of ``M`` sectors: the difference to the blocks falls as ``M^-2`` (orders 1.96 .. 2.00
  at ``M = 64 .. 128`` for ``n = 0 .. 3``), its Richardson extrapolation as ``M^-4``; the contact
  term agrees to roundoff for any ``M > 2n``.
* Complete sphere ``R/h = 100``, ``nu = 0.3``: every block ``n <= 30`` positive definite up to the
  traced path's first fold (axisymmetric, at 0.980 / 0.9955 / 1.0014 ``p_c`` for ``N`` = 201 / 301 /
  401 nodes pole to pole); the ``n >= 1`` blocks' critical pressures (extrapolated from two stable
  states) form a cluster at 1.011 .. 1.018 ``p_c`` for ``n = 4 .. 18`` (``N = 401``).
* Cost (default cap with its rotating edge's element, ``N`` = 200 / 800 / 3200; ``python -m
  studies.harmonic_probe --cost``, five runs on 2026-11-28 on a shared machine): per state (local Hessians
  and the band coefficients) 0.5-0.96 / 1.3-1.7 / 5.8-6.5 ms, per further block 0.04 / 0.07-0.09 /
  0.34-0.47 ms, its count and eigenvalue estimate (a banded L D L^T and three inverse-iteration steps,
  :func:`contin.watch.modes.count_and_lowest`) 0.07 / 0.18-0.21 / 0.65-0.72 ms, its two eigenvalues nearest
  zero (subspace inverse iteration, once per located bifurcation) 2.0-2.9 / 4.6-5.4 / 14-17 ms.  (The
  traced model's Hessian: 0.05 / 0.13 / 0.5-0.7 ms.)  Along the default trace (``python -m
  studies.bench_harmonics``): about 2.9 times the axisymmetric trace with ``n <= 13``.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from contin.numerics.compiled import prefer_compiled
from contin_models.contact.barrier import barrier_jet
from contin.numerics.linalg import SymmetricBand
from contin.numerics.stability import stability_info

from . import _harmonic_generated, layouts
from .density import (bend_curvatures, bend_density, free_edge_density, pole_curvature, skirt_density, stretch_density,
                      volume_density)
from .jets import Jet

__all__ = ["Jet", "HarmonicShell", "HarmonicDofs", "harmonic_block", "harmonic_dofs", "harmonic_family", "harmonic_mode",
           "block_eigs",
           "block_inertia", "stretch_density", "bend_density", "pole_curvature", "volume_density",
           "skirt_density", "free_edge_density", "bend_curvatures", "contact_point_hessian", "mode_maps",
           "HARMONIC_HALF_BANDWIDTH", "COMPILED", "POLE_FREE", "FREE_EDGE_FREE"]

_hgen, COMPILED = prefer_compiled(_harmonic_generated, "contin_models.shell._harmonic_ckernels")
"""``_hgen``: the generated kernels of the harmonic blocks (:mod:`contin_models.shell._harmonic_generated`),
computed by the C extension ``contin_models.shell._harmonic_ckernels`` where it was built (``COMPILED``
is then True; the same numbers, see :mod:`contin.numerics.compiled`)."""

#: The pole curvature's local variables that are not zero at an axisymmetric state (the generated jets'
#: arguments, :mod:`contin_models.shell.harmonic_codegen`).
POLE_FREE = (0, 2, 4, 6, 8, 9, 11, 13)
#: The same for a rotating edge's density (:func:`free_edge_density`): ``e = (y0, 0, y2)``, ``Dp = (0, y4, 0)``,
#: ``Pp = (0, y7, 0)``, ``Ppp = (y9, 0, 0)``.
FREE_EDGE_FREE = (0, 2, 4, 7, 9)

HARMONIC_HALF_BANDWIDTH = 8
"""Half-bandwidth of a full block in the interleaved ``[a, b, c]`` ordering (a bending element
couples nodes ``i-1 .. i+1``)."""


def contact_point_hessian(barrier: Any, X: np.ndarray, c: float) -> np.ndarray:
    """Hessian ``(3, 3, S)`` of the barrier ``W(d(X))`` with respect to 3-D points ``X`` (``(3, S)``).

    ``W(d) = -K (d - dhat)^2 log(d / dhat)`` for ``d < dhat`` (:mod:`contin_models.contact.barrier`);
    ``d`` the distance to the indenter: a sphere of radius ``rho`` centred at ``(0, 0, c)``,
    ``d = |X - C| - rho`` (rotationally symmetric about the axis: on the ``(r, z)`` plane it is the
    1-D model's distance), or a plate at height ``c``, ``d = c - X_z``.
    """
    K, dh = barrier.K, barrier.dhat
    X = np.asarray(X, dtype=float)
    if barrier.indenter.name == "sphere":
        rho = float(barrier.indenter.params[0])
        D = X - np.array([0.0, 0.0, c])[:, None]
        q = np.sqrt(np.sum(D * D, axis=0))
        d = q - rho
        gd = D / q
        Hd = (np.eye(3)[:, :, None] - gd[:, None, :] * gd[None, :, :]) / q
    else:
        d = c - X[2]
        gd = np.zeros_like(X)
        gd[2] = -1.0
        Hd = np.zeros((3, 3, X.shape[1]))
    _, W1, W2 = barrier_jet(d, K, dh)
    return W2 * gd[:, None, :] * gd[None, :, :] + W1 * Hd


# ---------------------------------------------------------------------------------------------------
# mode maps: (a, b, c) of one node -> the change of its local vectors, cos and sin parts
# ---------------------------------------------------------------------------------------------------
def mode_maps(n: int) -> dict:
    """Per-node maps ``(a, b, c) -> `` components of ``dP``, ``dP'``, ``dP''`` and of the mirror
    point ``dP(theta + pi)``, ``dP'(theta + pi)`` expressed in the frame at ``theta``.

    Returns ``{kind: (Mc, Ms)}`` with 3x3 matrices (rows: ``(r, t, z)`` components, columns
    ``(a, b, c)``): the change is ``cos(n theta) Mc u + sin(n theta) Ms u``.  For ``n = 0`` the
    fields are constants and the change is ``(Mc + Ms) u``.
    """
    n = float(n)
    sg = -1.0 if int(n) % 2 else 1.0
    P_c = np.array([[1, 0, 0], [0, 0, 0], [0, 1, 0]], float)
    P_s = np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0]], float)
    Pp_c = np.array([[0, 0, 0], [1, 0, n], [0, 0, 0]], float)
    Pp_s = np.array([[-n, 0, -1], [0, 0, 0], [0, -n, 0]], float)
    Ppp_c = np.array([[-(n * n + 1), 0, -2 * n], [0, 0, 0], [0, -n * n, 0]], float)
    Ppp_s = np.array([[0, 0, 0], [-2 * n, 0, -(1 + n * n)], [0, 0, 0]], float)
    F = np.diag([-1.0, -1.0, 1.0])  # frame at theta + pi -> frame at theta
    return {"P": (P_c, P_s), "Pp": (Pp_c, Pp_s), "Ppp": (Ppp_c, Ppp_s),
            "Q": (sg * F @ P_c, sg * F @ P_s), "Qp": (sg * F @ Pp_c, sg * F @ Pp_s)}


def _axisym_vectors(r, z):
    """Local vectors of rings at an axisymmetric state: ``P = (r, 0, z)``, ``P' = (0, r, 0)``,
    ``P'' = (-r, 0, 0)``, mirror ``Q = (-r, 0, z)``, ``Q' = (0, -r, 0)``."""
    zero = np.zeros_like(r)
    return {"P": (r, zero, z), "Pp": (zero, r, zero), "Ppp": (-r, zero, zero),
            "Q": (-r, zero, z), "Qp": (zero, -r, zero)}


@dataclass
class _Family:
    """One family of elements with the same local-variable layout.

    ``nodes``: ``(m, nn)`` global node of each element slot (``-1``: a fixed node, e.g. the ghost);
    ``layout``: list of ``(slot combination, kind)`` per local vector: each local vector (3
    components) is ``sum_c coef * V_kind(node slot)``; ``density``: callable of the local vectors
    (as tuples) returning the energy per radian (or a curvature for the pole); ``values``: the local
    vectors at the state, ``(k, m)``.
    """

    name: str
    nodes: np.ndarray
    layout: list
    kind: str  # "energy" (per radian, integrated) or "pole" (special second variation)


class HarmonicShell:
    """Harmonic blocks of a :class:`~contin_models.shell.structure.ShellStructure`.

    Parameters
    ----------
    structure : ShellStructure
        The shell (its meridian, material, supports and poles).
    z_ref : float, optional
        Height of the pressure's base plane (default: the reference height of node 0, as
        :meth:`contin_models.shell.volume.PressureTerm.from_reference`).
    method : {"generated", "jets"}
        How the bending, stretching and rotating edge's local Hessians and the poles' curvature jets
        are evaluated: the generated kernels (:mod:`contin_models.shell.harmonic_codegen`, the
        default) or the jets (the reference; the volume and skirt always use the jets: they are
        needed only under pressure).

    Notes
    -----
    The local Hessians of a state are cached (the last few states), so the blocks of every ``n`` at
    one state cost one evaluation of the densities.
    """

    _CACHE = 8

    def __init__(self, structure: Any, z_ref: float | None = None, method: str = "generated") -> None:
        if method not in ("generated", "jets"):
            raise ValueError(f"HarmonicShell: method must be 'generated' or 'jets', got {method!r}")
        self.method = method
        self.structure = st = structure
        #: The reference data of every element (:class:`contin_models.shell.reference.ShellReference`), the
        #: structure's: the parameters below are its arrays.
        self.reference = ref = st.reference
        mer = ref.meridian
        self.N = int(ref.N)
        self.nu = float(ref.nu)
        self.current = ref.kappa11_length == "current"
        xr = np.asarray(mer.x, dtype=float)
        self.z_ref = float(xr[1]) if z_ref is None else float(z_ref)
        # stretch parameters per edge, exactly those of the 1-D energy
        self.s_lbar, self.s_rbar, self.s_ks = ref.stretch.lbar, ref.stretch.rbar, ref.ks_edges
        # bending parameters per interior node
        b = ref.bend
        self.b_nodes = b.nodes
        self.b_lbar, self.b_rbar, self.b_k11, self.b_k22 = b.lbar, b.rbar, b.k11bar, b.k22bar
        self.b_kb = ref.kb_nodes[b.nodes]
        edge = ref.edge
        self.clamp = edge.element if edge is not None and edge.kind == "clamped" else None
        # a rotating edge's moment-free half cell (not the clamp's element)
        self.free_edge = edge.element if edge is not None and edge.kind == "moment_free" else None
        # (node, neighbour, north, PoleMirror)
        self.poles = [(p.node, p.neighbour, p.north, p.element) for p in ref.poles]
        self._cache: dict = {}  # state bytes -> local Hessians, oldest first

    # ---- local variables -------------------------------------------------------------------------
    def _layouts(self) -> list:
        """``(name, nodes, layout)`` of the stretch, bend and volume families (they do not depend on the state)."""
        families = self.__dict__.get("_family_layouts")
        if families is None:
            i = np.arange(self.N - 1)
            j = self.b_nodes
            families = self._family_layouts = [
                ("stretch", np.stack([i, i + 1], axis=1), layouts.STRETCH),
                ("bend", np.stack([j - 1, j, j + 1], axis=1), layouts.BEND),
                ("volume", np.stack([i, i + 1], axis=1), layouts.VOLUME)]
        return families

    def _families(self, x: np.ndarray, names: tuple = ("stretch", "bend")) -> dict:
        """Local vectors ``(nodes, layout, values)`` of the families ``names`` at an axisymmetric state ``x``."""
        out = {}
        maps = self.__dict__.setdefault("_local_maps", {})
        for name, nodes, layout in self._layouts():
            if name not in names:
                continue
            if name not in maps:  # the local variables are fixed linear combinations of the state
                maps[name] = self._local_map(nodes, layout)
            vals = list((maps[name] @ x).reshape(3 * len(layout), nodes.shape[0]))
            out[name] = (nodes, layout, vals)
        return out

    def _local_map(self, nodes: np.ndarray, layout: list) -> sp.csr_matrix:
        """The sparse map from the state ``[r_0, z_0, ...]`` to a family's local variables at axisymmetric
        states (rows: variable ``3 v + c`` of element ``e`` at ``(3 v + c) m + e``): every component of
        ``P = (r, 0, z)``, ``P' = (0, r, 0)``, ``P'' = (-r, 0, 0)``, ``Q = (-r, 0, z)``, ``Q' = (0, -r, 0)`` is
        plus or minus ``r`` or ``z`` of a node, or zero."""
        comps = {"P": ((0, 1.0), None, (1, 1.0)), "Pp": (None, (0, 1.0), None), "Ppp": ((0, -1.0), None, None),
                 "Q": ((0, -1.0), None, (1, 1.0)), "Qp": (None, (0, -1.0), None)}
        m = nodes.shape[0]
        rows, cols, vals = [], [], []
        e = np.arange(m)
        for v, (combo, kind) in enumerate(layout):
            for c in range(3):
                entry = comps[kind][c]
                if entry is None:
                    continue
                which, sign = entry
                for slot, coef in combo:
                    rows.append((3 * v + c) * m + e)
                    cols.append(2 * nodes[:, slot] + which)
                    vals.append(np.full(m, sign * coef))
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                             shape=(3 * len(layout) * m, 2 * self.N))

    def _bend_hessian(self, vals: list, params: tuple, current: bool) -> np.ndarray:
        """``(15, 15, m)`` Hessians of the bending density at axisymmetric local variables ``vals``
        (15 arrays) and ``params = (lbar, rbar, k11bar, k22bar, kb, nu)``: from the generated kernel
        (:mod:`contin_models.shell._harmonic_generated`: the curvatures' jets and the chain rule), or the
        jets with ``method="jets"``; ``L`` is the current length when ``current``, else the weight's
        ``lbar``.
        """
        if self.method == "generated":
            m = np.size(vals[0])
            f = _hgen.bend_cur_hessian if current else _hgen.bend_ref_hessian
            return f(*(np.broadcast_to(np.asarray(vals[k], float), (m,)) for k in (0, 2, 3, 5, 7, 10)),
                     *(np.broadcast_to(np.asarray(p, float), (m,)) for p in params[:5]), float(params[5]))
        y = Jet.variables(vals)
        e = bend_density(tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]), tuple(y[12:15]),
                         *params, None if current else params[0])
        return e.h

    def _volume_hessians(self, x: np.ndarray, loc: dict) -> tuple:
        """The volume strips' ``(nodes, layout, H)``, and the skirt's under ``loc["skirt"]`` when node 0 is off
        the axis (cached with the state's other Hessians)."""
        if "volume" not in loc:
            nodes, layout, vals = self._families(x, ("volume",))["volume"]
            y = Jet.variables(vals)
            e = volume_density(tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]))
            loc["volume"] = (nodes, layout, e.h)
            if 0 not in [p[0] for p in self.poles]:  # a pole at node 0 closes the surface: no skirt
                V = loc["skirt_vectors"]
                vals = [V["P"][c][:1] for c in range(3)] + [V["Pp"][c][:1] for c in range(3)]
                y = Jet.variables(vals)
                e = skirt_density(tuple(y[0:3]), tuple(y[3:6]), self.z_ref)
                loc["skirt"] = (np.array([[0]]), layouts.SKIRT, e.h)
        return loc["volume"]

    def local_hessians(self, x: np.ndarray) -> dict:
        """Per family: ``(nodes, layout, H)`` with ``H`` the ``(k, k, m)`` Hessians per radian; and
        the special terms (clamp, poles, skirt)."""
        x = np.asarray(x, dtype=float)
        key = x.tobytes()
        res = self._cache.get(key)
        if res is not None:
            return res
        fams = self._families(x)
        V = _axisym_vectors(x[0::2], x[1::2])
        res = {}
        # stretch
        nodes, layout, vals = fams["stretch"]
        if self.method == "generated":
            Hs = _hgen.stretch_hessian(vals[0], vals[2], vals[4], self.s_lbar, self.s_rbar, self.s_ks, self.nu)
        else:
            y = Jet.variables(vals)
            Hs = stretch_density(tuple(y[0:3]), tuple(y[3:6]), self.s_lbar, self.s_rbar, self.s_ks, self.nu).h
        res["stretch"] = (nodes, layout, Hs)
        # bend
        nodes, layout, vals = fams["bend"]
        if nodes.shape[0]:
            bp = (self.b_lbar, self.b_rbar, self.b_k11, self.b_k22, self.b_kb, self.nu)
            res["bend"] = (nodes, layout, self._bend_hessian(vals, bp, self.current))
        # volume and skirt: their jets only when a pressure asks for them (_volume_hessians)
        res["skirt_vectors"] = V
        # clamp: bending density on (ghost, 0, 1), ghost fixed; slots: node 0, node 1 (ghost = -1)
        if self.clamp is not None:
            cl = self.clamp
            gr, gz = cl.ghost
            G = {"P": (np.array([gr]), np.zeros(1), np.array([gz])), "Pp": (np.zeros(1), np.array([gr]), np.zeros(1))}
            P0 = [V["P"][c][:1] for c in range(3)]
            P1 = [V["P"][c][1:2] for c in range(3)]
            vals = ([P0[c] - G["P"][c] for c in range(3)] + [P1[c] - P0[c] for c in range(3)]
                    + [V["Pp"][c][1:2] - G["Pp"][c] for c in range(3)] + [V["Pp"][c][:1] for c in range(3)]
                    + [V["Ppp"][c][:1] for c in range(3)])
            Hc = self._bend_hessian(vals, (cl.lbar, cl.rbar, cl.kappa_bar[0], cl.kappa_bar[1], cl.kb, cl.nu), False)
            res["clamp"] = (np.array([[0, 1]]), layouts.CLAMP, Hc)
        if self.free_edge is not None:
            fe = self.free_edge
            vals = ([V["P"][c][1:2] - V["P"][c][:1] for c in range(3)] + [V["Pp"][c][1:2] - V["Pp"][c][:1] for c in range(3)]
                    + [V["Pp"][c][:1] for c in range(3)] + [V["Ppp"][c][:1] for c in range(3)])
            if self.method == "generated":
                Hf = _hgen.free_edge_hessian(*(float(vals[i][0]) for i in FREE_EDGE_FREE), float(fe.K),
                                             float(fe.kappa_bar), self.nu)[:, :, None]
            else:
                y = Jet.variables(vals)
                Hf = free_edge_density(tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]), fe.K,
                                       fe.kappa_bar, self.nu).h
            res["free_edge"] = (np.array([[0, 1]]), layouts.FREE_EDGE, Hf)
        # poles: the curvature B(theta) as a jet (value, gradient, Hessian) in Pm, Pm', Pc, Pq, Pq'
        res["poles"] = []
        for k, nb, north, element in self.poles:
            vals = ([V["P"][c][nb:nb + 1] for c in range(3)] + [V["Pp"][c][nb:nb + 1] for c in range(3)]
                    + [V["P"][c][k:k + 1] for c in range(3)] + [V["Q"][c][nb:nb + 1] for c in range(3)]
                    + [V["Qp"][c][nb:nb + 1] for c in range(3)])
            if self.method == "generated":
                kernel = getattr(_hgen, f"pole_{'north' if north else 'south'}_{'cur' if element.current_length else 'ref'}_jet")
                v, g, h = kernel(*(float(vals[i][0]) for i in POLE_FREE), float(element.lbar))
            else:
                y = Jet.variables(vals)
                L = None if element.current_length else element.lbar
                kap = pole_curvature(tuple(y[0:3]), tuple(y[3:6]), tuple(y[6:9]), tuple(y[9:12]), tuple(y[12:15]),
                                     north, L)
                v, g, h = kap.v[0], kap.g[:, 0], kap.h[:, :, 0]
            B0 = float(v) - element.kappa_bar
            layout = layouts.POLE
            Akb = element.K / (1.0 + self.nu)  # A kb
            res["poles"].append((np.array([[nb, k]]), layout, B0, g, h, Akb))
        self._cache[key] = res
        while len(self._cache) > self._CACHE:
            del self._cache[next(iter(self._cache))]
        return res

    # ---- assembly --------------------------------------------------------------------------------
    @staticmethod
    def _ymaps(layout: list, nn: int, maps: dict) -> tuple[np.ndarray, np.ndarray]:
        """``Yc``, ``Ys`` (``k x 3 nn``): local variables' change per node amplitudes ``(a, b, c)``."""
        k = 3 * len(layout)
        Yc, Ys = np.zeros((k, 3 * nn)), np.zeros((k, 3 * nn))
        for v, (combo, kind) in enumerate(layout):
            Mc, Ms = maps[kind]
            for s, coef in combo:
                Yc[3 * v:3 * v + 3, 3 * s:3 * s + 3] += coef * Mc
                Ys[3 * v:3 * v + 3, 3 * s:3 * s + 3] += coef * Ms
        return Yc, Ys

    @staticmethod
    def _project(H: np.ndarray, Yc: np.ndarray, Ys: np.ndarray, n: int) -> np.ndarray:
        """Element blocks ``(m, d, d)``: ``pi (Yc^T H Yc + Ys^T H Ys)`` or ``2 pi Y0^T H Y0``."""
        if n == 0:
            Y = Yc + Ys
            return 2.0 * math.pi * np.einsum("ai,abm,bj->mij", Y, H, Y, optimize=True)
        return math.pi * (np.einsum("ai,abm,bj->mij", Yc, H, Yc, optimize=True)
                          + np.einsum("ai,abm,bj->mij", Ys, H, Ys, optimize=True))

    def _element_blocks(self, x: np.ndarray, n: int, pressure: float):
        """Yield ``(global nodes (m, nn), blocks (m, 3 nn, 3 nn))`` of every term."""
        loc = self.local_hessians(x)
        maps = mode_maps(n)
        for name in ("stretch", "bend", "clamp", "free_edge"):
            if name in loc:
                nodes, layout, H = loc[name]
                Yc, Ys = self._ymaps(layout, nodes.shape[1], maps)
                yield nodes, self._project(H, Yc, Ys, n)
        if pressure != 0.0:
            self._volume_hessians(x, loc)
            for name in ("volume", "skirt"):
                if name in loc:
                    nodes, layout, H = loc[name]
                    Yc, Ys = self._ymaps(layout, nodes.shape[1], maps)
                    yield nodes, pressure * self._project(H, Yc, Ys, n)
        yield from self._pole_blocks(loc, n)

    def _pole_blocks(self, loc: dict, n: int):
        """``(nodes (1, 2), block (1, 6, 6))`` of each pole's element (module docstring)."""
        nu = self.nu
        cache = self.__dict__.setdefault("_pole_maps", {})
        for nodes, layout, B0, g, Hb, Akb in loc["poles"]:
            if n not in cache:  # every pole shares its layout
                cache[n] = self._ymaps(layout, nodes.shape[1], mode_maps(n))
            Yc, Ys = cache[n]
            if n == 0:
                Y = Yc + Ys
                G = Y.T @ g
                K = 2.0 * Akb * (1.0 + nu) * (np.outer(G, G) + B0 * Y.T @ Hb @ Y)
            else:
                Gc, Gs = Yc.T @ g, Ys.T @ g
                K = Akb * (2.0 * (1.0 - nu) * (np.outer(Gc, Gc) + np.outer(Gs, Gs))
                           + (1.0 + nu) * B0 * (Yc.T @ Hb @ Yc + Ys.T @ Hb @ Ys))
            yield nodes, K[None]

    def _pole_blocks_many(self, loc: dict, ns: list) -> list:
        """:meth:`_pole_blocks` for several ``n >= 1`` at once: per pole ``(nodes (1, 2), blocks (len(ns), 6, 6))``."""
        nu = self.nu
        cache = self.__dict__.setdefault("_pole_maps", {})
        out = []
        for nodes, layout, B0, g, Hb, Akb in loc["poles"]:
            stacked = tuple(ns)
            if stacked not in cache:  # every pole shares its layout
                for n in ns:
                    if n not in cache:
                        cache[n] = self._ymaps(layout, nodes.shape[1], mode_maps(n))
                Yc = np.stack([cache[n][0] for n in ns])
                Ys = np.stack([cache[n][1] for n in ns])
                cache[stacked] = (Yc, Ys, Yc.transpose(0, 2, 1), Ys.transpose(0, 2, 1))
            Yc, Ys, YcT, YsT = cache[stacked]
            Gc, Gs = YcT @ g, YsT @ g  # (G, 6)
            K = Akb * (2.0 * (1.0 - nu) * (Gc[:, :, None] * Gc[:, None, :] + Gs[:, :, None] * Gs[:, None, :])
                       + (1.0 + nu) * B0 * (YcT @ Hb @ Yc + YsT @ Hb @ Ys))
            out.append((nodes, K))
        return out

    def _contact_blocks(self, x: np.ndarray, n: int, contact: tuple):
        """``(nodes (S, 3), blocks (S, 9, 9))`` of the active sample points of a contact barrier."""
        barrier, c = contact
        N = self.N
        c = float(c)
        # the points of the axisymmetric barrier integral: W and W' vanish at the ends of its support,
        # so the second variation of the integral is the integral of the pointwise one over them
        pts = barrier.integration_points(x, c)
        S = pts.cell
        if S.size == 0:
            return None
        X = np.stack([pts.r, np.zeros(S.size), pts.z])  # the points in the frame at theta
        H = contact_point_hessian(barrier, X, c) * (pts.weight / (2.0 * math.pi))  # per radian
        maps = mode_maps(n)
        coef = pts.cz  # coefficients of the stencil nodes (the mirror is the kind "Q")
        mirror = (pts.cell == N - 1) & (N >= 2)
        Yc, Ys = np.zeros((S.size, 3, 9)), np.zeros((S.size, 3, 9))
        for j in range(3):
            for kind, sel in (("P", ~mirror if j == 2 else np.ones(S.size, bool)), ("Q", mirror if j == 2 else None)):
                if sel is None:
                    continue
                Mc, Ms = maps[kind]
                w = coef[:, j] * sel
                Yc[:, :, 3 * j:3 * j + 3] += w[:, None, None] * Mc
                Ys[:, :, 3 * j:3 * j + 3] += w[:, None, None] * Ms
        if n == 0:
            Y = Yc + Ys
            K = 2.0 * math.pi * np.einsum("sai,abs,sbj->sij", Y, H, Y)
        else:
            K = math.pi * (np.einsum("sai,abs,sbj->sij", Yc, H, Yc) + np.einsum("sai,abs,sbj->sij", Ys, H, Ys))
        return barrier.cells(N).stencil[S], K

    # ---- the polynomial in n, mapped straight to the band ----------------------------------------
    def _family_maps(self, name: str, layout: list, nn: int) -> list:
        """The state-independent mode maps of a family: per part (``cos``, ``sin``) the local variables
        it moves (``rows``) and ``[A B C]`` on them, ``Y(n) = A + n B + n^2 C`` (the maps are quadratic
        in ``n``)."""
        cache = self.__dict__.setdefault("_fmaps", {})
        if name not in cache:
            Y = [self._ymaps(layout, nn, mode_maps(k)) for k in (0, 1, 2)]
            parts = []
            for part in (0, 1):
                A = Y[0][part]
                C = 0.5 * (Y[2][part] - 2.0 * Y[1][part] + A)
                B = Y[1][part] - A - C
                parts.append(np.hstack([A, B, C]))
            cache[name] = parts
        return cache[name]

    def _element_map(self, name: str, layout: list, nn: int, k: int) -> tuple:
        """The element's block coefficients as a sparse linear map of its local Hessian ``H`` (``k x k``).

        Rows ``d * D^2 + i * D + j`` (``D = 3 nn``) for the coefficient of ``n^d`` (``d = 0..4``) of
        ``sum_parts Y^T H Y`` (``n >= 1``); rows ``5 D^2 + i D + j`` for the ``n = 0`` block's own part,
        ``(A_c + A_s)^T H (A_c + A_s)``.  Columns ``a k + b``.  The maps are sparse (a dof moves few
        local variables), so each entry is a short sum of ``H`` entries: ``(rows, cols, values)``.
        """
        cache = self.__dict__.setdefault("_emaps", {})
        if name not in cache:
            D = 3 * nn
            Qc, Qs = self._family_maps(name, layout, nn)
            rows, cols, vals = [], [], []

            def pairs(P: np.ndarray, Q: np.ndarray, row_of) -> None:
                pa, pj = np.nonzero(P)
                qa, qj = np.nonzero(Q)
                a, b = np.repeat(pa, qa.size), np.tile(qa, pa.size)
                i, j = np.repeat(pj, qj.size), np.tile(qj, pj.size)
                rows.append(row_of(i, j))
                cols.append(a * k + b)
                vals.append(np.repeat(P[pa, pj], qa.size) * np.tile(Q[qa, qj], pa.size))

            for Q in (Qc, Qs):  # n >= 1: degree p + q of P_p^T H P_q
                pairs(Q, Q, lambda i, j: (i // D + j // D) * D * D + (i % D) * D + j % D)
            A0 = Qc[:, :D] + Qs[:, :D]  # n = 0: the constant fields
            pairs(A0, A0, lambda i, j: 5 * D * D + i * D + j)
            cache[name] = (np.concatenate(rows), np.concatenate(cols), np.concatenate(vals))
        return cache[name]

    def _group_map(self, loc: dict, names: tuple, var: "_BandVariant") -> tuple[sp.csr_matrix, list]:
        """The linear map from the group's local Hessians (each family's ``H``, raveled and concatenated
        in the order of ``names``) to the band coefficients of ``var`` (built once per group and reduction)."""
        cache = var.maps
        present = [name for name in names if name in loc]
        key = tuple(present)
        if key not in cache:
            rows, cols, vals = [], [], []
            offset = 0
            for name in present:
                nodes, layout, H = loc[name]
                k, m = H.shape[0], H.shape[2]
                nn = nodes.shape[1]
                D = 3 * nn
                er, ec, ev = self._element_map(name, layout, nn, k)
                deg, ij = np.divmod(er, D * D)
                part = (deg == 5) if var.n0 else (deg < 5)  # the n = 0 block's own rows, or the polynomial's
                deg, ij, ec, ev = deg[part], ij[part], ec[part], ev[part]
                i, j = np.divmod(ij, D)
                dof = 3 * nodes[:, :, None] + np.arange(3)[None, None, :]  # (m, nn, 3)
                dof = dof.reshape(m, D)
                ri, ci, sg = var.reduced(dof[:, i].ravel(), dof[:, j].ravel())  # (m, entries), raveled
                kept = np.flatnonzero((ri >= 0) & (ci >= 0) & (ri <= ci))
                e, q = np.divmod(kept, ec.size)  # element and entry of the element map
                ri, ci = ri[kept], ci[kept]
                block = np.where(deg == 5, 0, deg)[q]
                rows.append(block * var.size + (var.kd + ri - ci) * var.m + ci)
                cols.append(offset + ec[q] * m + e)  # H raveled as (k, k, m)
                vals.append(ev[q] * sg[kept])
                offset += H.size
            R = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                              shape=(var.rows * var.size, offset))
            R.sum_duplicates()
            cache[key] = R
        return cache[key], present

    def _coefficients(self, x: np.ndarray, pressure: float, var: "_BandVariant") -> np.ndarray:
        """Band coefficients ``(rows, kd + 1, m)`` of the state's polynomial in ``n`` under ``var``: of
        ``n^0 .. n^4`` (``n >= 1``: the block is ``pi sum_d n^d C[d]``) or the ``n = 0`` block over ``2 pi``."""
        loc = self.local_hessians(x)
        key = ("coefficients", id(var), pressure)
        if key not in loc:
            R, names = self._group_map(loc, ("stretch", "bend", "clamp", "free_edge"), var)
            C = R @ self._stacked(loc, names)
            if pressure != 0.0:
                self._volume_hessians(x, loc)
                Rv, vnames = self._group_map(loc, ("volume", "skirt"), var)
                C = C + pressure * (Rv @ self._stacked(loc, vnames))
            loc[key] = C.reshape(var.rows, var.kd + 1, var.m)
        return loc[key]

    @staticmethod
    def _stacked(loc: dict, names: list) -> np.ndarray:
        """The local Hessians of the families ``names``, raveled and concatenated (the columns of their
        group maps), kept with the state's other Hessians: every reduction maps the same vector."""
        key = ("stacked", *names)
        if key not in loc:
            loc[key] = np.concatenate([loc[nm][2].ravel() for nm in names])
        return loc[key]

    def _small_terms(self, x: np.ndarray, loc: dict, n: int, contact: tuple | None) -> list:
        """The few elements outside the polynomial: poles and the contact's active sample points."""
        terms = list(self._pole_blocks(loc, n))
        if contact is not None:
            cb = self._contact_blocks(x, n, contact)
            if cb is not None:
                terms.append(cb)
        return terms

    def _reduction_key(self, n: int, remove_rigid: bool, control_fixed, hold_pole: bool) -> tuple:
        """What mode ``n``'s admissible dofs depend on (every ``n >= 2`` has the same)."""
        hold = bool(hold_pole) and int(n) == 1 and self.N - 1 in self.structure.poles
        return min(int(n), 2), bool(remove_rigid), tuple(int(d) for d in control_fixed) if int(n) == 0 else (), hold

    def reduction(self, n: int, remove_rigid: bool = True, control_fixed=(), hold_pole: bool = False) -> sp.csc_matrix:
        """The map ``T`` (``3N x m``) from mode ``n``'s admissible dofs to all its dofs (:func:`harmonic_dofs`;
        ``hold_pole``: without the pole's lateral dof at ``n = 1``, :func:`harmonic_family`'s ``pole_held``),
        cached."""
        key = self._reduction_key(n, remove_rigid, control_fixed, hold_pole)
        cache = self.__dict__.setdefault("_reductions", {})
        if key not in cache:
            d = harmonic_dofs(self.structure, n, remove_rigid, control_fixed)
            T = d.T.tocsc()
            if key[3]:  # the load holds the pole laterally: drop the column of its lateral a (c is tied to it)
                T = T[:, d.free != 3 * (self.N - 1)]
            cache[key] = T
        return cache[key]

    def _variant(self, n: int, remove_rigid: bool = True, control_fixed=(), hold_pole: bool = False) -> "_BandVariant":
        """The reduction of mode ``n``'s block to its admissible dofs, in LAPACK upper band storage (cached)."""
        key = self._reduction_key(n, remove_rigid, control_fixed, hold_pole)
        cache = self.__dict__.setdefault("_variants", {})
        if key not in cache:
            T = self.reduction(n, remove_rigid, control_fixed, hold_pole)
            cache[key] = _BandVariant(self.N, T.tocoo(), n0=int(n) == 0)
        return cache[key]

    def band_block(self, x: np.ndarray, n: int, pressure: float = 0.0, contact: tuple | None = None,
                   remove_rigid: bool = True, control_fixed=(), hold_pole: bool = False) -> SymmetricBand:
        """The block of mode ``n`` on its admissible dofs (:meth:`block`) in LAPACK's upper band storage.

        The fast route along branches: per state the band coefficients of the polynomial in ``n``
        (one sparse map of the local Hessians per reduction, :meth:`_coefficients`, cached), per block
        one combination of them and the poles' and contact's few entries.  ``hold_pole``: also drop
        the pole's lateral dof at ``n = 1`` (:func:`harmonic_family`'s ``pole_held``).
        """
        n = self._check_n(n)
        return self._assemble(self._check_state(x), n, float(pressure), contact,
                              self._variant(n, remove_rigid, control_fixed, hold_pole))

    def band_blocks(self, x: np.ndarray, ns: Any, pressure: float = 0.0, contact: tuple | None = None,
                    hold_pole: bool = False) -> list[SymmetricBand]:
        """:meth:`band_block` for several wave numbers ``ns >= 1`` at one state (each reduction's
        polynomial combined for all of them in one product)."""
        x = self._check_state(x)
        ns = [self._check_n(n) for n in ns]
        if any(n == 0 for n in ns):
            raise ValueError("band_blocks: wave numbers must be >= 1 (n = 0 is band_block's)")
        pressure = float(pressure)
        out: dict[int, SymmetricBand] = {}
        for group in ([n for n in ns if n == 1], [n for n in ns if n >= 2]):
            if not group:
                continue
            var = self._variant(group[0], True, (), hold_pole)
            C = self._coefficients(x, pressure, var)
            powers = np.array(group, dtype=float)[:, None] ** np.arange(5)[None, :]
            bands = (math.pi * powers @ C.reshape(5, -1)).reshape((len(group),) + C.shape[1:])
            loc = self.local_hessians(x)
            poles = self._pole_blocks_many(loc, group)
            for g_, (n, ab) in enumerate(zip(group, bands)):
                for nodes, K in poles:
                    var.add_elements(ab, nodes, K[g_][None])
                if contact is not None:
                    cb = self._contact_blocks(x, n, contact)
                    if cb is not None:
                        var.add_elements(ab, *cb)
                out[n] = SymmetricBand(ab)
        return [out[n] for n in ns]

    def _assemble(self, x: np.ndarray, n: int, pressure: float, contact: tuple | None, var: "_BandVariant") -> SymmetricBand:
        """Mode ``n``'s block reduced by ``var``."""
        C = self._coefficients(x, pressure, var)
        if n == 0:
            ab = 2.0 * math.pi * C[0]
        else:
            ab = math.pi * (np.array([1.0, n, n * n, n ** 3, n ** 4]) @ C.reshape(5, -1)).reshape(C.shape[1:])
        for nodes, K in self._small_terms(x, self.local_hessians(x), n, contact):
            var.add_elements(ab, nodes, K)
        return SymmetricBand(ab)

    @staticmethod
    def _check_n(n: int) -> int:
        n = int(n)
        if n < 0:
            raise ValueError(f"wave number n must be >= 0, got {n}")
        return n

    def _check_state(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape != (2 * self.N,):
            raise ValueError(f"state vector must have shape ({2 * self.N},), got {x.shape}")
        return x

    def full_block(self, x: np.ndarray, n: int, pressure: float = 0.0, contact: tuple | None = None,
                   reference: bool = False) -> sp.csr_matrix:
        """The ``3N x 3N`` block of mode ``n`` on all dofs ``[a_0, b_0, c_0, a_1, ...]`` (no dof fixed).

        ``pressure``: the external pressure (its volume's load stiffness is added); ``contact``:
        ``(barrier, c)``, a :class:`contin_models.contact.ContactBarrier` and the indenter position
        (the barrier's block is added).  The stretching, bending, clamp and volume parts come from
        the band coefficients of a polynomial in ``n`` computed once per state (:meth:`_coefficients`);
        ``reference=True`` projects every element for this ``n`` instead (the direct route, for checks).
        """
        n = self._check_n(n)
        x = self._check_state(x)
        pressure = float(pressure)
        if not reference:
            cache = self.__dict__.setdefault("_variants", {})
            if "full" not in cache:
                cache["full"] = (_BandVariant(self.N, sp.identity(3 * self.N, format="coo"), n0=True),
                                 _BandVariant(self.N, sp.identity(3 * self.N, format="coo"), n0=False))
            return self._assemble(x, n, pressure, contact, cache["full"][0 if n == 0 else 1]).tocsr()
        n3 = 3 * self.N
        rows, cols, vals = [], [], []
        for nodes, K in self._element_blocks(x, n, pressure):
            dof = (3 * nodes[:, :, None] + np.arange(3)[None, None, :]).reshape(nodes.shape[0], -1)
            rows.append(np.broadcast_to(dof[:, :, None], K.shape).ravel())
            cols.append(np.broadcast_to(dof[:, None, :], K.shape).ravel())
            vals.append(K.ravel())
        if contact is not None:
            cb = self._contact_blocks(x, n, contact)
            if cb is not None:
                nodes, K = cb
                dof = (3 * nodes[:, :, None] + np.arange(3)[None, None, :]).reshape(nodes.shape[0], -1)
                rows.append(np.broadcast_to(dof[:, :, None], K.shape).ravel())
                cols.append(np.broadcast_to(dof[:, None, :], K.shape).ravel())
                vals.append(K.ravel())
        return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n3, n3))

    def dofs(self, n: int, remove_rigid: bool = True, control_fixed=()) -> "HarmonicDofs":
        """The admissible dofs of mode ``n`` (module docstring, "Dof ordering and fixed dofs")."""
        return harmonic_dofs(self.structure, n, remove_rigid, control_fixed)

    def block(self, x: np.ndarray, n: int, pressure: float = 0.0, remove_rigid: bool = True,
              contact: tuple | None = None, control_fixed=()) -> sp.csr_matrix:
        """The block of mode ``n`` on the admissible dofs, ``T^T K T`` (:meth:`dofs`), as CSR."""
        return self.band_block(x, n, pressure, contact, remove_rigid, control_fixed).tocsr()


class _BandVariant:
    """A reduction ``T^T K T`` of a block to admissible dofs, in LAPACK's upper band storage.

    Every column of ``T`` (``3N x m``) is a unit vector except for ties (a full dof equal to +-1 times a
    kept one): each full dof maps to at most one reduced dof (``col``, ``-1`` if fixed) with a factor
    (``fac``).  ``n0``: the reduction of an ``n = 0`` block (its coefficients are the block itself).
    ``maps`` caches the sparse maps of the local Hessians to its band (:meth:`HarmonicShell._group_map`).
    """

    def __init__(self, N: int, T: sp.coo_matrix, n0: bool) -> None:
        n3 = 3 * N
        self.m = m = T.shape[1]
        self.n0 = bool(n0)
        self.rows = 1 if n0 else 5
        col, fac = np.full(n3, -1), np.zeros(n3)
        col[T.row], fac[T.row] = T.col, T.data
        self.col, self.fac = col, fac
        # half-bandwidth: full dofs at most HARMONIC_HALF_BANDWIDTH apart are coupled
        r = np.repeat(np.arange(n3), HARMONIC_HALF_BANDWIDTH + 1)
        c = r + np.tile(np.arange(HARMONIC_HALF_BANDWIDTH + 1), n3)
        r, c = r[c < n3], c[c < n3]
        ok = (col[r] >= 0) & (col[c] >= 0)
        kd = int(np.max(np.abs(col[c[ok]] - col[r[ok]]), initial=0))
        self.kd = kd
        self.size = (kd + 1) * m
        self.maps: dict = {}
        self._places: dict = {}

    def reduced(self, r: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Reduced dofs of full dofs ``r``, ``c`` and the product of their factors."""
        return self.col[r], self.col[c], self.fac[r] * self.fac[c]

    def add_elements(self, ab: np.ndarray, nodes: np.ndarray, K: np.ndarray) -> None:
        """Add element blocks ``K`` (``(e, 3 nn, 3 nn)``, both triangles) on ``nodes`` (``(e, nn)``) into ``ab``."""
        nodes = np.asarray(nodes)
        key = (nodes.shape, nodes.tobytes())
        places = self._places.get(key)
        if places is None:
            dof = (3 * nodes[:, :, None] + np.arange(3)[None, None, :]).reshape(len(nodes), -1)
            r = np.broadcast_to(dof[:, :, None], K.shape).ravel()
            c = np.broadcast_to(dof[:, None, :], K.shape).ravel()
            ri, ci, sg = self.reduced(r, c)
            keep = np.flatnonzero((ri >= 0) & (ci >= 0) & (ri <= ci))
            if np.any(ci[keep] - ri[keep] > self.kd):
                raise ValueError("an element couples dofs farther apart than the block's band")
            places = (keep, (self.kd + ri[keep] - ci[keep]) * self.m + ci[keep], sg[keep])
            if len(self._places) < 64:  # the poles' few elements recur at every state; contact's vary
                self._places[key] = places
        keep, pos, sign = places
        np.add.at(ab.reshape(-1), pos, sign * K.ravel()[keep])


@dataclass
class HarmonicDofs:
    """Admissible dofs of one wave number.

    Attributes
    ----------
    n : int
        Wave number.
    T : scipy.sparse.csr_matrix
        ``3N x m`` map from the reduced amplitudes to the full ``[a_0, b_0, c_0, ...]``.
    fixed : ndarray
        Full dofs held at zero.
    tied : list of (int, int, float)
        ``(dof, master, factor)``: ``dof = factor * master`` (the pole's ``c = -a`` at ``n = 1``).
    free : ndarray
        The full dof carried by each column of :attr:`T`.
    """

    n: int
    T: sp.csr_matrix
    fixed: np.ndarray
    tied: list
    free: np.ndarray


def harmonic_dofs(structure: Any, n: int, remove_rigid: bool = True, control_fixed=()) -> HarmonicDofs:
    """Fixed and tied dofs of mode ``n`` for a structure (module docstring) and the reduction map.

    Parameters
    ----------
    structure : ShellStructure
    n : int
        Wave number, ``>= 0``.
    remove_rigid : bool
        Remove the rigid motions of a shell without a support in ``z`` at its ``rigid_fix`` node.
    control_fixed : sequence of int
        Full-state (1-D, interleaved ``[r_0, z_0, ...]``) dofs that the control holds, fixed at
        ``n = 0`` only: e.g. the loaded node's height ``2k + 1`` under displacement control.  A
        prescribed pole deflection, volume or indenter position is an axisymmetric constraint; the
        ``n >= 1`` fields change none of them to first order, so every control shares the
        ``n >= 1`` blocks (``docs/model.md#harmonic-blocks``).
    """
    n = int(n)
    N = int(structure.N)
    fixed: set[int] = set()
    tied: list = []
    for k in structure.poles:
        if n == 0:
            fixed |= {3 * k, 3 * k + 2}
        elif n == 1:
            fixed.add(3 * k + 1)
            tied.append((3 * k + 2, 3 * k, -1.0))
        else:
            fixed |= {3 * k, 3 * k + 1, 3 * k + 2}
    if 0 not in structure.poles:
        b = structure.boundary
        if b == "sliding":
            fixed |= {1, 2}
        elif b in ("pinned", "clamped"):
            fixed |= {0, 1, 2}
    elif structure.boundary == "pinned":  # a point support of the pole: its point held in space
        fixed |= {1} if n == 0 else ({0} if n == 1 else set())  # c_0 = -a_0 at n = 1 goes with a_0
        if remove_rigid and n == 0:  # two points on the axis leave the spin about it: held mid-meridian
            fixed.add(3 * (N // 2) + 2)
    if remove_rigid and structure.rigid_fix is not None:
        k = structure.rigid_fix // 2
        fixed |= {3 * k + 1, 3 * k + 2} if n == 0 else ({3 * k, 3 * k + 1} if n == 1 else set())
    if n == 0:
        fixed |= {3 * (int(d) // 2) + int(d) % 2 for d in control_fixed}
    tied_dofs = {t[0] for t in tied}
    free = np.array([d for d in range(3 * N) if d not in fixed and d not in tied_dofs], dtype=int)
    col = {d: j for j, d in enumerate(free)}
    rows = list(free)
    cols = list(range(free.size))
    vals = [1.0] * free.size
    for d, master, f in tied:
        if master in col:
            rows.append(d)
            cols.append(col[master])
            vals.append(f)
    T = sp.csr_matrix((vals, (rows, cols)), shape=(3 * N, free.size))
    return HarmonicDofs(n=n, T=T, fixed=np.array(sorted(fixed), dtype=int), tied=tied, free=free)


_SHELLS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def _harmonic_shell(structure: Any, z_ref: float | None) -> HarmonicShell:
    key = (None if z_ref is None else float(z_ref))
    per = _SHELLS.setdefault(structure, {})
    if key not in per:
        per[key] = HarmonicShell(structure, z_ref)
    return per[key]


def harmonic_block(structure: Any, x: np.ndarray, n: int, pressure: float = 0.0, z_ref: float | None = None,
                   reduced: bool = True, remove_rigid: bool = True, contact: tuple | None = None,
                   control_fixed=()) -> sp.csr_matrix:
    """Hessian block of wave number ``n`` of the 2-D shell energy at the axisymmetric state ``x``.

    Parameters
    ----------
    structure : ShellStructure
        The shell.
    x : ndarray, shape ``(2 N,)``
        Full interleaved axisymmetric state ``[r_0, z_0, ..., r_{N-1}, z_{N-1}]``.
    n : int
        Circumferential wave number, ``>= 0``.
    pressure : float
        External pressure ``p`` (the load stiffness ``p d2V`` of the enclosed volume is added).
    z_ref : float, optional
        The pressure's base plane (default: the reference height of node 0).
    reduced : bool
        ``True``: on the admissible dofs of ``n`` (:func:`harmonic_dofs`); ``False``: the full
        ``3N x 3N`` block on ``[a_0, b_0, c_0, a_1, ...]``.
    remove_rigid : bool
        With ``reduced``: remove the rigid motions of a shell without support in ``z``.
    contact : (ContactBarrier, float), optional
        A contact barrier (:class:`contin_models.contact.ContactBarrier`) and the indenter position
        ``c``: the barrier's block is added (module docstring, "Contact").
    control_fixed : sequence of int
        With ``reduced``: 1-D dofs held by the control at ``n = 0`` (:func:`harmonic_dofs`).

    Returns
    -------
    scipy.sparse.csr_matrix
        Symmetric; ``u^T K u`` is the second variation of the energy along the field
        ``(a cos n theta, b cos n theta, c sin n theta)`` (module docstring).
    """
    hs = _harmonic_shell(structure, z_ref)
    if reduced:
        return hs.block(x, n, pressure, remove_rigid, contact, control_fixed)
    return hs.full_block(x, n, pressure, contact)


def harmonic_family(structure: Any, state: Any, n_max: int, pressure: Any = None, z_ref: float | None = None,
                    contact: Any = None, pole_held: bool = False) -> Any:
    """The blocks ``n = 1 .. n_max`` of a problem on ``structure`` as a :class:`contin.OperatorFamily` named ``"n"``.

    Parameters
    ----------
    structure : ShellStructure
        The shell whose 2-D energy the blocks are of (for the paper's point-load model: the structure
        with ``boundary="sliding"``, ``edge_bending="none"``, whose energy is that model's).
    state : callable ``(u, p) -> x``
        The full axisymmetric state of the problem's unknowns and parameter.
    n_max : int
        The largest wave number watched (:func:`contin_models.shell.structure.default_harmonics`).
    pressure : callable ``(u, p) -> float``, optional
        The pressure acting at ``(u, p)`` (its load stiffness enters every block).
    z_ref : float, optional
        The pressure's base plane.
    contact : callable ``(u, p) -> (ContactBarrier, c)``, optional
        The contact barrier and the indenter's position at ``(u, p)``.
    pole_held : bool
        The load holds the pole (node ``N-1``) laterally: its ``n = 1`` translation is removed.  A
        point force applied by a frictionless point leaves it free (default): the pole may then slide
        sideways under the force, the ``n = 1`` mode.

    Notes
    -----
    ``n >= 1`` fields change neither a pole's or ring's deflection nor the enclosed volume nor an
    indenter's travel to first order, so every control shares these blocks; each appears twice in
    the whole Hessian (its ``cos`` and ``sin`` modes): ``multiplicity`` 2.
    """
    from contin.watch.modes import OperatorFamily

    hs = _harmonic_shell(structure, z_ref)
    if int(n_max) < 1:
        raise ValueError(f"harmonic_family: n_max must be >= 1, got {n_max!r}")
    keys = tuple(range(1, int(n_max) + 1))

    def loads(u: np.ndarray, p: float) -> tuple[float, Any]:
        return (0.0 if pressure is None else float(pressure(u, p))), (None if contact is None else contact(u, p))

    def block(n: int, u: np.ndarray, p: float) -> SymmetricBand:
        q, c = loads(u, p)
        return hs.band_block(state(u, p), int(n), pressure=q, contact=c, hold_pole=pole_held)

    def blocks(u: np.ndarray, p: float) -> list[SymmetricBand]:
        q, c = loads(u, p)
        return hs.band_blocks(state(u, p), keys, pressure=q, contact=c, hold_pole=pole_held)

    def shape(n: int, mode: np.ndarray) -> np.ndarray:
        return harmonic_mode(structure, int(n), mode, hold_pole=pole_held)

    return OperatorFamily("n", keys, block, multiplicity=lambda n: 2, all_operators=blocks, mode_shape=shape)


def harmonic_mode(structure: Any, n: int, mode: np.ndarray, hold_pole: bool = False) -> np.ndarray:
    """A mode of the block of wave number ``n >= 1`` (a vector on its admissible dofs, as
    :func:`harmonic_family`'s blocks have them) as per-node amplitudes ``(N, 3)``: the columns ``a``, ``b``,
    ``c`` of ``dR = a cos(n theta)``, ``dZ = b cos(n theta)``, ``dT = c sin(n theta)`` (module docstring)."""
    T = _harmonic_shell(structure, None).reduction(n, hold_pole=hold_pole)
    mode = np.asarray(mode, dtype=float)
    if mode.shape != (T.shape[1],):
        raise ValueError(f"harmonic_mode: a mode of n = {n} has {T.shape[1]} entries, got shape {mode.shape}")
    return (T @ mode).reshape(structure.N, 3)


def block_eigs(K: sp.spmatrix, k: int = 1) -> np.ndarray:
    """The ``k`` smallest eigenvalues of a symmetric block, ascending (LAPACK's banded solver on the
    band, through :func:`contin.numerics.stability.stability_info`)."""
    return np.asarray(stability_info(sp.csr_matrix(K), k).eigenvalues)


def block_inertia(K: sp.spmatrix) -> int:
    """Number of negative eigenvalues of a symmetric block: a pivot-free ``L D L^T`` (O(N)), or an
    eigensolver when it cannot be trusted (:func:`contin.numerics.stability.stability_info`)."""
    return int(stability_info(sp.csr_matrix(K), 0).n_negative)
