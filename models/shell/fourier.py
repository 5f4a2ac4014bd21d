"""The 3-D view of the shell: rings of material points moving in three directions, Fourier series in the angle.

The traced model knows only axisymmetric states; the harmonic blocks (:mod:`contin_models.shell.harmonic`)
know the second variation about them.  This view carries states that are not axisymmetric at all, with
the same energy: the 2-D densities of :mod:`contin_models.shell.density`, read through the shared
layouts of :mod:`contin_models.shell.layouts`, differentiated by the generated kernels of
:mod:`contin_models.shell._density_generated` (value, gradient and Hessian at any state).

Unknowns
--------
Node ``i`` of the meridian is a ring of material points labelled by the reference angle ``theta``.
In the local frame ``(e_r(theta), e_theta(theta), e_z)`` a point sits at ``P_i(theta) = (R, T, Z)``,
and each of the three components is a short Fourier series in ``theta`` (:class:`AngularBasis`):

* a state symmetric under the dihedral group ``D_n`` (``n``-fold rotation about the axis and the
  mirror in the meridional plane ``theta = 0``): ``R`` and ``Z`` are cosine series and ``T`` a sine
  series of the wave numbers ``0, n, 2n, ..., K n``;
* a state symmetric under rotations only (``C_n``), or without any symmetry (``n = 1``): cosines and
  sines of each wave number in every component.

The unknowns are the series' coefficients, node by node (``m`` per node, :attr:`AngularBasis.terms`),
so the Hessian is banded along the meridian with a half-bandwidth of about ``3 m``: a Newton step costs
O(N) at a fixed angular resolution.  An axisymmetric state is ``R = r_i``, ``Z = z_i`` (the ``k = 0``
cosines) and every other coefficient zero.

The angle
---------
The energy is integrated over ``theta`` by the trapezoidal rule on ``M`` equally spaced angles.  On the
harmonics of a ``D_n`` basis the integrand has period ``2 pi / n`` and is even in ``theta``, so the
rule is evaluated on the ``M / (2 n) + 1`` angles of one half period, the ends weighted half.  The rule
integrates a trigonometric polynomial of degree below ``M`` exactly, so with ``M > 2 K n`` the second
variation about an axisymmetric state (a quadratic form in the coefficients with ``theta``-independent
density Hessians) is integrated exactly: the Hessian of this view at an axisymmetric state, restricted
to wave number ``k``, *is* the harmonic block of ``k`` (the ``theta``-derivatives are exact on both
sides), so a branch point located by the blocks is a branch point of this view.  Away from
axisymmetric states the rule converges spectrally in ``M``.

The pole is one material point: its coefficients are tied so that ``P(theta)`` does not depend on
``theta`` (:meth:`FourierShell.reduction`); its element reads the neighbour ring at ``theta + pi``, which
this view evaluates from the series directly.

The reference
-------------
By default the strains are measured against the structure's axisymmetric reference, whose numbers per
element (:class:`contin_models.shell.reference.ShellReference`) do not depend on the angle.  A stress-free
shape that is not axisymmetric (an imperfection) is given as a state ``c_bar`` of the view
(``reference=``).  Its numbers are then computed per element *and* quadrature angle by the densities' own
formulas at its local vectors (:func:`~contin_models.shell.density.stretch_reference`,
:func:`~contin_models.shell.density.bend_curvatures`, :func:`~contin_models.shell.density.free_edge_curvatures`,
:func:`~contin_models.shell.density.pole_curvature`), and the general kernels measure the strains against
them: ``|D| / |D_bar| - 1``, ``|M'| / |M'_bar| - 1``, ``eps12 - eps12_bar``, ``kappa - kappa_bar`` for all
three curvatures, the weights the reference's lengths at that angle (the Voronoi length times ``|P'_bar|``;
the moment-free edge's half cell likewise; a pole's cell ``pi (l/2)^2`` with ``l`` its edge's mean
reference length over the angle).  ``kappa11_length="reference"`` carries over as the reference Voronoi
length at each angle, ``(|e1_bar| + |e2_bar|) / 2`` (the clamp's half first edge, the pole's two edges),
which is the structure's own number when ``c_bar`` is axisymmetric; ``"current"`` stays the current
length.  At ``c = c_bar`` every strain vanishes, so the energy and its gradient vanish; with ``c_bar`` the
axisymmetric reference the numbers are the default path's to roundoff.  A clamp's ghost ring stays the
structure's (fixed in space), with its curvatures measured at ``c_bar``.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass, field
from collections.abc import Callable, Iterable
from typing import Any

import numpy as np
import scipy.sparse as sp

from contin.numerics.linalg import FixedPattern

from .density_kernels import kernels as _dgen
from . import density, layouts

__all__ = ["AngularBasis", "FourierShell", "FourierReduction", "csr_positions", "representation_name",
           "transfer_coefficients"]

#: The frame component of each unknown component: ``R`` radial, ``T`` circumferential, ``Z`` axial.
_FRAME = {"R": 0, "T": 1, "Z": 2}


@dataclass(frozen=True)
class AngularBasis:
    """The Fourier series in the angle of one symmetry class, and the quadrature that integrates over it.

    Parameters
    ----------
    n : int
        The order of the rotational symmetry: the wave numbers are ``0, n, ..., K n`` (``>= 1``;
        ``n = 1`` with ``mirror=False`` is no symmetry at all).
    K : int
        The number of harmonics above ``0`` (``>= 0``; ``K = 0`` is an axisymmetric state).
    mirror : bool
        The states are symmetric about the meridional plane ``theta = 0`` (``D_n``; else ``C_n``).
    M : int, optional
        Angles of the trapezoidal rule on the whole circle: a multiple of ``2 n`` (``D_n``) or of ``n``,
        above ``2 K n`` (so that quadratic forms about axisymmetric states are integrated exactly).
        Default: the smallest multiple of ``2 n`` above ``3 K n`` (the rule that integrates products of
        three fields of the basis exactly; the energy's higher harmonics are small).
    j : int
        The Bloch wave number of a class of perturbations (``0 .. n // 2``): the waves ``q n +- j``.  A
        state's basis has ``j = 0``.
    parity : {"even", "odd", "both"}, optional
        Symmetric about ``theta = 0`` (``R``, ``Z`` cosines, ``T`` sines), antisymmetric (``R``, ``Z`` sines,
        ``T`` cosines) or both; default ``"even"`` with ``mirror`` and ``"both"`` without.
    """

    n: int
    K: int
    mirror: bool = True
    M: int | None = None
    j: int = 0
    parity: str | None = None
    terms: tuple = field(init=False, repr=False)
    theta: np.ndarray = field(init=False, repr=False)
    weights: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        n, K = self.n, self.K
        if not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"AngularBasis: n (the order of the rotational symmetry) must be an integer >= 1, got {n!r}")
        if not isinstance(K, (int, np.integer)) or K < 0:
            raise ValueError(f"AngularBasis: K (the number of harmonics above 0) must be an integer >= 0, got {K!r}")
        period = 2 * n if self.mirror else n
        M = 2 * n * ((3 * K + 2) // 2) if self.M is None else self.M
        if not isinstance(M, (int, np.integer)) or M % period or M <= 2 * K * n:
            raise ValueError(f"AngularBasis: M (angles of the quadrature on the circle) must be a multiple of {period} "
                             f"above 2 K n = {2 * K * n}, got {M!r}")
        object.__setattr__(self, "M", int(M))
        j = self.j
        if not isinstance(j, (int, np.integer)) or not 0 <= j <= n // 2:
            raise ValueError(f"AngularBasis: j (the Bloch wave number) must be an integer in [0, n // 2 = {n // 2}], "
                             f"got {j!r}")
        parity = self.parity if self.parity is not None else ("even" if self.mirror else "both")
        if parity not in ("even", "odd", "both"):
            raise ValueError(f"AngularBasis: parity must be 'even', 'odd' or 'both', got {parity!r}")
        object.__setattr__(self, "parity", parity)
        terms = []
        for k in self.wave_numbers.tolist():
            if parity in ("even", "both"):  # symmetric about theta = 0
                terms += [("R", "cos", k), ("Z", "cos", k)] + ([("T", "sin", k)] if k > 0 else [])
            if parity in ("odd", "both"):   # antisymmetric about theta = 0
                terms += ([("R", "sin", k), ("Z", "sin", k)] if k > 0 else []) + [("T", "cos", k)]
        object.__setattr__(self, "terms", tuple(terms))
        dth = 2.0 * math.pi / M
        if self.mirror:  # one half period, the ends weighted half
            q = np.arange(M // (2 * n) + 1)
            w = np.full(q.size, 2.0 * n * dth)
            w[0] = w[-1] = n * dth
        else:  # one period
            q = np.arange(M // n)
            w = np.full(q.size, n * dth)
        object.__setattr__(self, "theta", q * dth)
        object.__setattr__(self, "weights", w)

    @property
    def m(self) -> int:
        """Unknowns per node."""
        return len(self.terms)

    @property
    def wave_numbers(self) -> np.ndarray:
        """``0, n, ..., K n``; for a Bloch class ``j > 0`` the waves ``m = q n +- j`` up to ``K n + j``."""
        n, j = self.n, self.j
        m = np.arange(0, n * self.K + j + 1)
        return m[(m % n == j % n) | (m % n == (n - j) % n)]

    def bloch(self, j: int, parity: str) -> "AngularBasis":
        """The perturbations of Bloch wave number ``j`` and one ``parity`` about a state of this basis
        (the same ``n``, ``K`` and ``M``): the waves ``m = q n +- j`` (:class:`FourierShell.bloch_block`)."""
        return AngularBasis(self.n, self.K, mirror=parity == "even", M=self.M, j=int(j), parity=parity)

    def index(self, component: str, trig: str, k: int) -> int:
        """Position of the coefficient of ``trig(k theta)`` in ``component`` among a node's unknowns."""
        try:
            return self.terms.index((component, trig, int(k)))
        except ValueError:
            raise KeyError(f"AngularBasis: no term {component} {trig}({k} theta) in {self}") from None

    def functions(self, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The terms' functions of ``theta`` and their first and second derivatives, each ``(len(theta), m)``."""
        th = np.asarray(theta, dtype=float)[:, None]
        k = np.array([t[2] for t in self.terms], dtype=float)[None, :]
        cos = np.array([t[1] == "cos" for t in self.terms])[None, :]
        c, s = np.cos(k * th), np.sin(k * th)
        f = np.where(cos, c, s)
        f1 = np.where(cos, -k * s, k * c)
        return f, f1, -k * k * f

    def ring_maps(self, theta: np.ndarray | None = None) -> dict[str, np.ndarray]:
        """Per ring quantity of :data:`contin_models.shell.layouts.KINDS` the ``(len(theta), 3, m)`` map from
        a node's unknowns to its frame components at ``theta`` (default: the quadrature's angles).

        ``P' = (R' - T, R + T', Z')`` and ``P'' = (R'' - R - 2 T', 2 R' - T + T'', Z'')`` in the frame
        at ``theta``; ``Q``, ``Qp``: ``P`` and ``P'`` at ``theta + pi`` expressed in the frame at ``theta``
        (horizontal components reversed).
        """
        th = self.theta if theta is None else np.asarray(theta, dtype=float)
        comp = [_FRAME[t[0]] for t in self.terms]
        j = np.arange(self.m)
        out = {}
        for name, angle in (("P", th), ("Q", th + math.pi)):
            f, f1, f2 = self.functions(angle)
            P = np.zeros((th.size, 3, self.m))
            Pp = np.zeros_like(P)
            Ppp = np.zeros_like(P)
            P[:, comp, j] = f
            for jj, c in enumerate(comp):
                if c == 0:    # R
                    Pp[:, 0, jj], Pp[:, 1, jj] = f1[:, jj], f[:, jj]
                    Ppp[:, 0, jj], Ppp[:, 1, jj] = f2[:, jj] - f[:, jj], 2.0 * f1[:, jj]
                elif c == 1:  # T
                    Pp[:, 0, jj], Pp[:, 1, jj] = -f[:, jj], f1[:, jj]
                    Ppp[:, 0, jj], Ppp[:, 1, jj] = -2.0 * f1[:, jj], f2[:, jj] - f[:, jj]
                else:         # Z
                    Pp[:, 2, jj], Ppp[:, 2, jj] = f1[:, jj], f2[:, jj]
            if name == "P":
                out.update(P=P, Pp=Pp, Ppp=Ppp)
            else:
                flip = np.array([-1.0, -1.0, 1.0])[None, :, None]
                out.update(Q=P * flip, Qp=Pp * flip)
        return out


#: How many sets of a contact's element unknowns keep their Hessian slots (:meth:`hessian_slots`, ``transient``):
#: the nodes a contact touches change as the load moves, and each set's slots are large (every harmonic of every
#: node); kept without bound, they filled the memory on a long indentation (more than 20 GB with ten harmonics).
SLOT_CACHE_SIZE = 4


def csr_positions(P: sp.csr_matrix, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Positions in ``P.data`` of the entries ``(rows[k], cols[k])`` of a canonical CSR matrix (each must be stored)."""
    # a canonical CSR matrix lists its entries sorted by (row, column): search the pairs' keys
    size = np.int64(P.shape[1])
    keys = np.repeat(np.arange(P.shape[0], dtype=np.int64), np.diff(P.indptr)) * size + P.indices
    return np.searchsorted(keys, np.asarray(rows, dtype=np.int64) * size + np.asarray(cols, dtype=np.int64))


@dataclass(frozen=True)
class FourierReduction:
    """The admissible unknowns of a :class:`FourierShell`: ``c = T q + c_fixed``.

    Attributes
    ----------
    T : scipy.sparse.csr_matrix
        ``(N m, len(free))`` map from the free unknowns to all (unit columns, except the pole's tied pairs).
    free : ndarray of int
        The unknown carried by each column of ``T``.
    fixed : ndarray of int
        Unknowns held at their values in ``c_fixed`` (supports, poles, rigid motions, controls).
    """

    T: sp.csr_matrix
    free: np.ndarray
    fixed: np.ndarray

    def full(self, q: np.ndarray, held: np.ndarray) -> np.ndarray:
        """All unknowns from the free ones ``q``, the fixed ones taken from ``held`` (a full vector)."""
        c = np.array(held, dtype=float)
        c[self.free] = 0.0
        return c + self.T @ q

    def restriction(self, P: sp.csr_matrix) -> Callable[[np.ndarray], sp.csr_matrix]:
        """A map from the data of a matrix with the pattern ``P`` (canonical) to ``T^T H T``, without a sparse
        product: every unknown is free, tied to one free unknown, or fixed, so each entry of ``H`` lands in
        at most one entry of ``T^T H T``."""
        T = self.T.tocsr()
        n_full = T.shape[0]
        col = np.full(n_full, -1, dtype=np.int64)
        fac = np.zeros(n_full)
        has = np.diff(T.indptr) > 0
        col[has] = T.indices[T.indptr[:-1][has]]
        fac[has] = T.data[T.indptr[:-1][has]]
        rows = np.repeat(np.arange(n_full), np.diff(P.indptr))
        ri, ci = col[rows], col[P.indices]
        keep = np.flatnonzero((ri >= 0) & (ci >= 0))
        factor = fac[rows[keep]] * fac[P.indices[keep]]
        m = T.shape[1]
        R = sp.csr_matrix((np.ones(keep.size), (ri[keep], ci[keep])), shape=(m, m))
        R.sum_duplicates()
        slots = csr_positions(R, ri[keep], ci[keep])
        # the restricted matrices share one read-only pattern: no index checks per matrix, and the
        # factorizations find their band positions by it (contin.numerics.linalg.FixedPattern)
        pattern = FixedPattern(R.indices, R.indptr, R.shape)
        # almost every entry of T^T H T is one entry of H: gathered, then the few sums of tied pairs added
        order = np.argsort(slots, kind="stable")
        first = np.r_[True, slots[order][1:] != slots[order][:-1]]
        source, scale = keep[order[first]], factor[order[first]]
        unit = bool(np.all(scale == 1.0))
        rest = order[~first]
        rest_slots, rest_source, rest_factor = slots[rest], keep[rest], factor[rest]

        def restrict(data: np.ndarray) -> sp.csr_matrix:
            out = data[source] if unit else data[source] * scale
            if rest.size:
                np.add.at(out, rest_slots, data[rest_source] * rest_factor)
            return pattern.matrix(out)

        return restrict


def representation_name(n: int, j: int, parity: str) -> str:
    """The name of the irreducible representation of ``D_n`` of the Bloch class ``(j, parity)``.

    ``A1``: ``j = 0``, even (the ``D_n``-symmetric states themselves: ``R``, ``Z`` cosine and ``T`` sine series of
    the waves ``0, n, 2n, ...``); ``A2``: ``j = 0``, odd (the same waves, the mirrored parity); ``B1``, ``B2``: ``j = n/2``
    (``n`` even; the waves ``n/2, 3n/2, ...``), even and odd; ``Ej``: ``0 < j < n/2``, two-dimensional (the waves
    ``q n +- j``, each with both parities).
    """
    if j == 0:
        return "A1" if parity == "even" else "A2"
    if 2 * j == n:
        return "B1" if parity == "even" else "B2"
    return f"E{j}"


# ---- a general stress-free reference: its numbers per element and angle --------------------------------
# Each builder takes an element family's local vectors at the reference (3-tuples of (Q, E) arrays, the
# layout's order) and returns the parameters of the family's general kernel, by the densities' own formulas.

def _general_stretch(ks: Any, nu: float) -> Callable[[list], tuple]:
    def params(v: list) -> tuple:
        lbar, rbar, e12bar = density.stretch_reference(*v)
        return lbar, rbar, e12bar, ks, nu
    return params


def _general_bend(kb: Any, nu: float, current: bool) -> Callable[[list], tuple]:
    def params(v: list) -> tuple:
        # the Voronoi length at this angle; kappa11's length with kappa11_length="reference"
        L = (density.vector_length(v[0]) + density.vector_length(v[1])) * 0.5
        k11, k22, k12 = density.bend_curvatures(*v, None if current else L)
        return L, density.vector_length(v[3]), k11, k22, k12, kb, nu
    return params


def _general_clamp(kb: float, nu: float) -> Callable[[list], tuple]:
    def params(v: list) -> tuple:
        # the edge node's cell inside the shell: half the first edge (the clamp's length and weight)
        L = density.vector_length(v[1]) * 0.5
        k11, k22, k12 = density.bend_curvatures(*v, L)
        return L, density.vector_length(v[3]), k11, k22, k12, kb, nu
    return params


def _general_free_edge(kb: float, nu: float) -> Callable[[list], tuple]:
    def params(v: list) -> tuple:
        k22, k12 = density.free_edge_curvatures(*v)
        # the half cell's weight as the 1-D element's, pi r0 (l0 / 2) kb (1 - nu^2), at this angle
        K = math.pi * density.vector_length(v[2]) * 0.5 * density.vector_length(v[0]) * kb * (1.0 - nu * nu)
        return K, k22, k12, nu
    return params


class _GeneralPole:
    """A pole's reference from the reference state's local vectors ``y`` ``(15, Q)`` (:data:`layouts.POLE`):
    ``(L, kappa_bar)`` per angle, ``L`` the Voronoi length of the pole's two edges at that angle (the
    curvature's length unless ``current``)."""

    def __init__(self, north: bool, current: bool) -> None:
        self.north, self.current = north, current

    @staticmethod
    def lengths(y: np.ndarray) -> np.ndarray:
        """``(|Pc - Pm| + |Pq - Pc|) / 2`` per angle."""
        Pm, Pc, Pq = y[0:3], y[6:9], y[9:12]
        return (density.vector_length(tuple(Pc - Pm)) + density.vector_length(tuple(Pq - Pc))) * 0.5

    def __call__(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        L = self.lengths(y)
        v = [tuple(y[j:j + 3]) for j in range(0, 15, 3)]
        return L, density.pole_curvature(*v, self.north, None if self.current else L)


class FourierShell:
    """The 3-D view of a :class:`~contin_models.shell.structure.ShellStructure` (module docstring).

    Parameters
    ----------
    structure : ShellStructure
        The shell: meridian, material, supports and poles (its :attr:`reference` table).
    basis : AngularBasis
        The Fourier series in the angle and the quadrature.
    z_ref : float, optional
        Height of the pressure's base plane (default: the reference height of node 0).
    reference : ndarray, optional
        The stress-free shape as a state of this view (``(N m,)`` coefficients in ``basis``), for an
        imperfection that need not be axisymmetric (:mod:`contin_models.shell.imperfection3d`); every pole
        must be one point.  Default: the structure's axisymmetric reference, with its numbers from
        :attr:`reference` (module docstring, "The reference").
    """

    def __init__(self, structure: Any, basis: AngularBasis, z_ref: float | None = None,
                 reference: np.ndarray | None = None) -> None:
        self.structure = st = structure
        self.reference = ref = st.reference
        self.basis = basis
        self.N = int(ref.N)
        self.m = basis.m
        self.nu = nu = float(ref.nu)
        xr = np.asarray(ref.meridian.x, dtype=float)
        self.z_ref = float(xr[1]) if z_ref is None else float(z_ref)
        self._cache: dict = {}
        self._slots: OrderedDict = OrderedDict()  # the most recent sets of element unknowns: see hessian_slots
        # a stress-free reference given as a state: its numbers per element and angle come from the
        # densities' own strain and curvature formulas at its local vectors (:meth:`_reference_params`)
        self._c_bar = None if reference is None else self._checked_reference(reference)
        general = self._c_bar is not None
        maps = basis.ring_maps()
        i = np.arange(self.N - 1)
        if general:
            stretch = (_dgen.stretch_general_jet, _general_stretch(ref.ks_edges, nu))
        else:
            stretch = (_dgen.stretch_jet, (ref.stretch.lbar, ref.stretch.rbar, ref.ks_edges, nu))
        families = [("stretch", np.stack([i, i + 1], axis=1), layouts.STRETCH, *stretch, None)]
        b = ref.bend
        if b.nodes.size:
            current = ref.kappa11_length == "current"
            if general:
                bend = (_dgen.bend_cur_general_jet if current else _dgen.bend_ref_general_jet,
                        _general_bend(ref.kb_nodes[b.nodes], nu, current))
            else:
                bend = (_dgen.bend_cur_jet if current else _dgen.bend_ref_jet,
                        (b.lbar, b.rbar, b.k11bar, b.k22bar, ref.kb_nodes[b.nodes], nu))
            families.append(("bend", np.stack([b.nodes - 1, b.nodes, b.nodes + 1], axis=1), layouts.BEND, *bend,
                             None))
        edge = ref.edge
        if edge is not None and edge.kind == "clamped":
            cl = edge.element
            gr, gz = cl.ghost
            offset = np.zeros(15)  # e1 = P_0 - G, Dp = P'_1 - G' (the ghost ring fixed in space)
            offset[0:3] = (-gr, 0.0, -gz)
            offset[6:9] = (0.0, -gr, 0.0)
            if general:
                clamp = (_dgen.bend_ref_general_jet, _general_clamp(cl.kb, cl.nu))
            else:
                clamp = (_dgen.bend_ref_jet, (cl.lbar, cl.rbar, cl.kappa_bar[0], cl.kappa_bar[1], cl.kb, cl.nu))
            families.append(("clamp", np.array([[0, 1]]), layouts.CLAMP, *clamp, offset))
        elif edge is not None and edge.kind == "moment_free":
            fe = edge.element
            if general:
                free = (_dgen.free_edge_general_jet, _general_free_edge(float(edge.kb), nu))
            else:
                free = (_dgen.free_edge_jet, (fe.K, fe.kappa_bar, nu))
            families.append(("free_edge", np.array([[0, 1]]), layouts.FREE_EDGE, *free, None))
        self._families = [(name, nodes, self._local_map(layout, nodes.shape[1], maps), kernel, params, offset)
                          for name, nodes, layout, kernel, params, offset in families]
        #: Each element family's layout (:mod:`contin_models.shell.layouts`).
        self._layouts = {name: layout for name, _, layout, *_ in families}
        self._layouts.update(volume=layouts.VOLUME, skirt=layouts.SKIRT)
        self._volume = [("volume", np.stack([i, i + 1], axis=1), self._local_map(layouts.VOLUME, 2, maps),
                         _dgen.volume_jet, (), None)]
        self._pole_map = self._local_map(layouts.POLE, 2, maps)
        self._poles = []
        for p in ref.poles:
            el = p.element
            kernel = getattr(_dgen, f"pole_{'north' if p.north else 'south'}_{'cur' if el.current_length else 'ref'}_jet")
            nodes = np.array([[p.neighbour, p.node]])
            if general:
                # the pole's cell from the reference: its edge's mean length over the angle
                lbar, kbar = None, _GeneralPole(p.north, el.current_length)
                length = float(self.basis.weights @ kbar.lengths(np.matmul(self._pole_map, self._c_bar[
                    self.element_dofs(nodes)[0]]).T)) / (2.0 * math.pi)
                Akb = math.pi * (0.5 * length) ** 2 * p.kb
            else:
                lbar, kbar, Akb = float(el.lbar), float(el.kappa_bar), float(el.K) / (1.0 + nu)
            self._poles.append((nodes, kernel, lbar, kbar, Akb))
        if 0 not in [p.node for p in ref.poles]:
            self._volume.append(("skirt", np.array([[0]]), self._local_map(layouts.SKIRT, 1, maps), _dgen.skirt_jet,
                                 (self.z_ref,), None))

    def _checked_reference(self, reference: np.ndarray) -> np.ndarray:
        """``reference`` as a read-only state of this view, refused unless finite, of the view's size and with
        every pole at one point."""
        c = np.array(reference, dtype=float)
        if c.shape != (self.size,):
            raise ValueError(f"FourierShell: reference must be a state of the view, shape ({self.size},), "
                             f"got shape {c.shape}")
        if not np.isfinite(c).all():
            raise ValueError("FourierShell: reference must be finite")
        poles = list(self.structure.poles)
        if poles:
            # the pole is one material point: its position may not depend on the angle
            theta = 2.0 * math.pi * np.arange(7) / 7.0
            X = self.points(c, theta)[poles]                          # (poles, 7, 3)
            spread = float(np.max(np.abs(X - X[:, :1])))
            scale = float(np.max(np.abs(self.points(c, theta[:1]))))
            if spread > 1e-12 * scale:
                raise ValueError(f"FourierShell: reference must keep every pole (nodes {poles}) at one point: its "
                                 f"position varies by {spread:.3g} with the angle")
        c.setflags(write=False)
        return c

    def _reference_params(self, family: tuple) -> tuple:
        """A family's reference numbers per station for its local map (the quadrature's or another set of
        angles): the family's builder evaluated at the reference's local vectors, cached per map."""
        name, nodes, B, _, build, offset = family
        key = ("reference", name, id(B))
        entry = self._cache.get(key)
        if entry is None or entry[0] is not B:
            y = np.matmul(B.transpose(1, 0, 2), self._c_bar[self._dofs(nodes)].T)    # (k, Q, E)
            if offset is not None:
                y += offset[:, None, None]
            self._cache[key] = entry = (B, build([tuple(y[j:j + 3]) for j in range(0, y.shape[0], 3)]))
        return entry[1]

    def _pole_reference(self, nodes: np.ndarray, lbar: Any, kbar: Any, B: np.ndarray) -> tuple[Any, Any]:
        """The pole's reference length and curvature at the angles of the map ``B``: ``(lbar, kbar)`` as
        given for an axisymmetric reference, per angle from the reference state otherwise, cached per map."""
        if not isinstance(kbar, _GeneralPole):
            return lbar, kbar
        key = ("pole reference", nodes.tobytes(), id(B))
        entry = self._cache.get(key)
        if entry is None or entry[0] is not B:
            y = np.matmul(B, self._c_bar[self.element_dofs(nodes)[0]]).T             # (k, Q)
            self._cache[key] = entry = (B, kbar(y))
        return entry[1]

    # ---- unknowns ----------------------------------------------------------------------------------
    @property
    def size(self) -> int:
        """The number of unknowns, ``N m``."""
        return self.N * self.m

    def axisymmetric_state(self, x: np.ndarray) -> np.ndarray:
        """The unknowns of the axisymmetric state ``x = [r_0, z_0, r_1, z_1, ...]`` of the traced model."""
        x = np.asarray(x, dtype=float)
        if x.shape != (2 * self.N,):
            raise ValueError(f"FourierShell: an axisymmetric state has {2 * self.N} entries, got shape {x.shape}")
        c = np.zeros(self.size)
        c[self.basis.index("R", "cos", 0)::self.m] = x[0::2]
        c[self.basis.index("Z", "cos", 0)::self.m] = x[1::2]
        return c

    def reference_state(self) -> np.ndarray:
        """The unknowns of the stress-free reference shell: the ``reference`` given, else the structure's
        axisymmetric one."""
        if self._c_bar is not None:
            return self._c_bar.copy()
        return self.axisymmetric_state(self.structure.reference_state())

    def axisymmetric_dofs(self) -> np.ndarray:
        """The unknowns ``R cos 0`` and ``Z cos 0`` of every node, in the traced model's order ``[r_0, z_0, ...]``."""
        d = np.empty(2 * self.N, dtype=int)
        d[0::2] = np.arange(self.N) * self.m + self.basis.index("R", "cos", 0)
        d[1::2] = np.arange(self.N) * self.m + self.basis.index("Z", "cos", 0)
        return d

    def turning_direction(self, c: np.ndarray) -> np.ndarray:
        """The derivative of the state ``c`` (of this view's ``D_n`` basis) turned by an angle ``delta`` about the
        axis, at ``delta = 0``, in the unknowns of the antisymmetric class ``(j = 0, "odd")`` (``A2``).

        Turning ``R cos k theta`` gives ``k R sin k theta``, ``T sin k theta`` gives ``-k T cos k theta``.  The
        energy of a shell of revolution does not change when a state is turned, so at an equilibrium this is a
        null vector of the ``A2`` block (up to the quadrature's aliasing); it vanishes at an axisymmetric state.
        """
        basis = self.basis
        if not basis.mirror or basis.j != 0:
            raise ValueError("FourierShell.turning_direction: the state's basis must be a D_n basis (mirror=True, j=0)")
        odd = basis.bloch(0, "odd")
        rows = np.asarray(c, dtype=float).reshape(self.N, self.m)
        out = np.zeros((self.N, odd.m))
        for i, (comp, trig, k) in enumerate(basis.terms):
            if k == 0:
                continue
            if comp == "T":
                out[:, odd.index("T", "cos", k)] = -k * rows[:, i]
            else:
                out[:, odd.index(comp, "sin", k)] = k * rows[:, i]
        return out.ravel()

    def dofs_of_wave(self, k: int) -> np.ndarray:
        """The unknowns of wave number ``k`` in the harmonic blocks' order ``[a_0, b_0, c_0, a_1, ...]``:
        ``R cos``, ``Z cos``, ``T sin`` (``k = 0``: ``T cos``, without a mirror)."""
        tr = "cos" if k == 0 else "sin"
        idx = [self.basis.index("R", "cos", k), self.basis.index("Z", "cos", k), self.basis.index("T", tr, k)]
        return (np.arange(self.N)[:, None] * self.m + np.array(idx)[None, :]).ravel()

    def points(self, c: np.ndarray, theta: np.ndarray) -> np.ndarray:
        """Cartesian positions ``(N, len(theta), 3)`` of the rings' material points at the angles ``theta``."""
        th = np.asarray(theta, dtype=float)
        P = np.einsum("qcj,ij->iqc", self.basis.ring_maps(th)["P"], np.asarray(c, float).reshape(self.N, self.m))
        cs, sn = np.cos(th)[None, :], np.sin(th)[None, :]
        return np.stack([P[..., 0] * cs - P[..., 1] * sn, P[..., 0] * sn + P[..., 1] * cs, P[..., 2]], axis=-1)

    def point_map(self, node: int, theta: float) -> np.ndarray:
        """``(3, N m)``: the Cartesian position of ring ``node``'s material point at the angle ``theta``, a
        linear function of the unknowns (a point force's potential is ``-F . point_map @ c``)."""
        if not 0 <= int(node) < self.N:
            raise ValueError(f"FourierShell: node must be in [0, {self.N - 1}], got {node!r}")
        th = float(theta)
        P = self.basis.ring_maps(np.array([th]))["P"][0]          # (3, m): frame components
        rot = np.array([[math.cos(th), -math.sin(th), 0.0], [math.sin(th), math.cos(th), 0.0], [0.0, 0.0, 1.0]])
        out = np.zeros((3, self.size))
        out[:, int(node) * self.m:(int(node) + 1) * self.m] = rot @ P
        return out

    @property
    def turns_freely(self) -> bool:
        """Whether a state turned about the axis keeps its energy: the reference has no waves."""
        if self._c_bar is None:
            return True
        rest = np.delete(self._c_bar, self.axisymmetric_dofs())
        return not np.any(rest)

    def reduction(self, remove_rigid: bool = True, control_fixed=(), held=()) -> FourierReduction:
        """The admissible unknowns: poles are single points, supports hold their rings, and (``remove_rigid``)
        a shell without a support in ``z`` has its rigid motions removed at the structure's ``rigid_fix``
        node, as the harmonic blocks do per wave number (:func:`contin_models.shell.harmonic.harmonic_dofs`).
        ``held``: further unknowns (positions in the coefficient vector) fixed at their values.

        ``control_fixed``: traced-model dofs (``2 i`` for ``r_i``, ``2 i + 1`` for ``z_i``) a control holds;
        their ``k = 0`` unknowns are fixed.
        """
        st, B, m = self.structure, self.basis, self.m
        fixed: set[int] = set()
        tied: list = []
        terms = B.terms
        for k in st.poles:
            for j, (comp, trig, wave) in enumerate(terms):
                keep = (comp, trig, wave) == ("Z", "cos", 0) or (wave == 1 and comp == "R")
                if (comp, wave) == ("T", 1):  # P'(theta) of one point: T sin 1 = -R cos 1, T cos 1 = R sin 1
                    tied.append((k * m + j, k * m + B.index("R", "sin" if trig == "cos" else "cos", 1),
                                 1.0 if trig == "cos" else -1.0))
                elif not keep:
                    fixed.add(k * m + j)
        if 0 not in st.poles:
            if st.boundary == "sliding":
                fixed |= {j for j, t in enumerate(terms) if t[0] in ("Z", "T")}
            elif st.boundary in ("pinned", "clamped"):
                fixed |= set(range(m))
        elif st.boundary == "pinned":  # a point support of the pole: its point held in space (its tied T too)
            fixed |= {j for j, t in enumerate(terms) if t in {("Z", "cos", 0), ("R", "cos", 1), ("R", "sin", 1)}}
            if remove_rigid:  # the spin about the axis, which two points on it do not hold
                k = st.N // 2
                fixed |= {k * m + j for j, t in enumerate(terms) if t == ("T", "cos", 0)}
        if remove_rigid and st.rigid_fix is not None:
            k = st.rigid_fix // 2
            rigid = {("Z", "cos", 0), ("T", "cos", 0), ("R", "cos", 1), ("Z", "cos", 1), ("R", "sin", 1), ("Z", "sin", 1)}
            fixed |= {k * m + j for j, t in enumerate(terms) if t in rigid}
        for d in control_fixed:
            i, which = divmod(int(d), 2)
            fixed.add(i * m + B.index("Z" if which else "R", "cos", 0))
        fixed |= {int(d) for d in held}
        tied_dofs = {t[0] for t in tied}
        free = np.array([d for d in range(self.size) if d not in fixed and d not in tied_dofs], dtype=int)
        col = {d: j for j, d in enumerate(free)}
        rows, cols, vals = list(free), list(range(free.size)), [1.0] * free.size
        for d, master, f in tied:
            if master in col:
                rows.append(d)
                cols.append(col[master])
                vals.append(f)
        T = sp.csr_matrix((vals, (rows, cols)), shape=(self.size, free.size))
        return FourierReduction(T=T, free=free, fixed=np.array(sorted(fixed | tied_dofs), dtype=int))

    # ---- the energy --------------------------------------------------------------------------------
    @staticmethod
    def _local_map(layout: tuple, nn: int, maps: dict) -> np.ndarray:
        """``(Q, 3 len(layout), nn m)``: an element's local variables at each angle from its nodes' unknowns."""
        Q, _, m = maps["P"].shape
        B = np.zeros((Q, 3 * len(layout), nn * m))
        for v, (combo, kind) in enumerate(layout):
            for slot, coef in combo:
                B[:, 3 * v:3 * v + 3, slot * m:(slot + 1) * m] += coef * maps[kind]
        return B

    def element_dofs(self, nodes: np.ndarray) -> np.ndarray:
        """``(E, nn m)``: the unknowns of elements on the nodes ``(E, nn)``, node by node."""
        return (nodes[:, :, None] * self.m + np.arange(self.m)[None, None, :]).reshape(nodes.shape[0], -1)

    def _jets(self, c: np.ndarray, family: tuple) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A family's local values, gradients and Hessians at every angle and element: ``(Q, E)``,
        ``(k, Q, E)``, ``(k, k, Q, E)`` (the angle first: the Hessian's products then run on its slices
        without a transposed copy, :meth:`_element_hessians`)."""
        name, nodes, B, kernel, params, offset = family
        ce = c[self._dofs(nodes)]                                  # (E, A)
        y = np.matmul(B.transpose(1, 0, 2), ce.T)                  # (k, Q, E)
        if offset is not None:
            y += offset[:, None, None]
        E, Q = ce.shape[0], B.shape[0]
        if callable(params):  # a general reference: its numbers per station of this map
            params = self._reference_params(family)
        # per-element parameters broadcast over the angles (the stations' last axis is the element)
        v, g, h = kernel(y, *[np.asarray(p, float) if np.ndim(p) else p for p in params])
        return np.broadcast_to(v, (Q, E)), g, h

    def _dofs(self, nodes: np.ndarray) -> np.ndarray:
        """:meth:`element_dofs` of a family's ``nodes``, cached."""
        key = ("dofs", nodes.tobytes(), nodes.shape)
        if key not in self._cache:
            self._cache[key] = self.element_dofs(nodes)
        return self._cache[key]

    def _element_hessians(self, h: np.ndarray, B: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The element Hessians ``H_e = sum_q w_q B_q^T h_eq B_q`` from the local Hessians ``h`` ``(k, k, Q, E)``
        and the local map ``B`` ``(Q, k, A)``: ``(A, A, E)`` (entry ``(a, b, e)``, the element last), the
        rows in the order ``rows`` (row ``r`` is the element's unknown ``rows[r]``).

        Two large matrix products instead of many small ones: first ``X_iq = (w_q B_q)^T h_q[i]`` for each
        local variable and angle (``(A, E)`` each, on slices of ``h`` as they lie), then ``B`` stacked over
        the local variables and angles times all ``X`` stacked, ``(k Q, A E)``.  The local variables are
        3-vectors in the frame at the angle; an unknown of ``Z`` moves only their axial components and one
        of ``R`` or ``T`` only the horizontal ones (:meth:`AngularBasis.ring_maps`), so the second product
        splits in two, each over its own components (:meth:`_component_split`).
        """
        Q, k, A = B.shape
        E = h.shape[-1]
        Bw = (w[:, None, None] * B).transpose(0, 2, 1)             # (Q, A, k)
        split = self._component_split(B)
        if split is None:
            X = np.matmul(Bw[None], h.transpose(0, 2, 1, 3))       # (k, Q, A, E)
            He = np.matmul(B.transpose(1, 0, 2).reshape(k * Q, A).T, X.reshape(k * Q, A * E))
            return He.reshape(A, A, E), np.arange(A)
        rows, horizontal, vertical = split
        V = k // 3
        X = np.empty((3, V, Q, A, E))                              # (component, vector, angle, unknown, element)
        np.matmul(Bw, h.reshape(V, 3, k, Q, E).transpose(1, 0, 3, 2, 4), out=X)
        He = np.empty((A, A * E))
        nh = horizontal.shape[0]
        np.matmul(horizontal, X[:2].reshape(2 * V * Q, A * E), out=He[:nh])
        np.matmul(vertical, X[2].reshape(V * Q, A * E), out=He[nh:])
        return He.reshape(A, A, E), rows

    def _component_split(self, B: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """For a local map ``B`` ``(Q, k, A)`` of 3-vectors whose horizontal components only the unknowns of
        ``R`` and ``T`` move and whose axial ones only those of ``Z``: ``(rows, horizontal, vertical)``, the
        unknowns in the order horizontal then vertical, and ``B`` of each set on its components stacked as
        the product of :meth:`_element_hessians` reads them, ``[a, (component, vector, angle)]``; None for any
        other map.  Cached per map."""
        key = ("split", id(B))
        entry = self._cache.get(key)
        if entry is None or entry[0] is not B:
            Q, k, A = B.shape
            split = None
            if k % 3 == 0:
                reach = np.abs(B).max(axis=0) != 0                # (k, A): local variable i moves with unknown a
                axial = np.arange(k) % 3 == 2
                vertical = ~reach[~axial].any(axis=0)              # the unknowns of Z
                if not reach[axial][:, ~vertical].any():
                    V = k // 3
                    Bc = B.reshape(Q, V, 3, A)
                    horizontal = Bc[:, :, :2][..., ~vertical].transpose(3, 2, 1, 0)   # (a, component, vector, q)
                    axial_map = Bc[:, :, 2][..., vertical].transpose(2, 1, 0)          # (a, vector, q)
                    split = (np.concatenate([np.flatnonzero(~vertical), np.flatnonzero(vertical)]),
                             np.ascontiguousarray(horizontal).reshape(-1, 2 * V * Q),
                             np.ascontiguousarray(axial_map).reshape(-1, V * Q))
            self._cache[key] = entry = (B, split)
        return entry[1]

    def _state(self, c: np.ndarray, volume: bool) -> dict:
        """The densities' jets at the state ``c`` (and the volume's with ``volume``), kept for the last state."""
        c = np.asarray(c, dtype=float)
        if c.shape != (self.size,):
            raise ValueError(f"FourierShell: a state has {self.size} unknowns, got shape {c.shape}")
        key = c.tobytes()
        st = self._cache.get("state")
        if st is None or st["key"] != key:
            st = self._cache["state"] = {"key": key, "c": c}
        if "elastic" not in st:
            st["elastic"] = [self._jets(c, fam) for fam in self._families]
            st["poles"] = [self._pole_term(c, *pole) for pole in self._poles]
        if volume and "volume" not in st:
            st["volume"] = [self._jets(c, fam) for fam in self._volume]
        return st

    def _groups(self, c: np.ndarray, pressure: float):
        """``(family, jets, factor)`` of every integrated term at ``c``."""
        st = self._state(c, pressure != 0.0)
        for fam, jets in zip(self._families, st["elastic"]):
            yield fam, jets, 1.0
        if pressure != 0.0:
            for fam, jets in zip(self._volume, st["volume"]):
                yield fam, jets, float(pressure)

    def _pole_term(self, c: np.ndarray, nodes: np.ndarray, kernel: Any, lbar: float, kbar: float, Akb: float) -> tuple:
        """The pole's element ``A kb ((3 nu - 1) <B>^2 + 2 (1 - nu) <B^2>)`` with ``<>`` the mean over the angle:
        ``(element dofs (1, A), energy, gradient (1, A), Hessian (1, A, A))``."""
        nu, B = self.nu, self._pole_map
        w = self.basis.weights / (2.0 * math.pi)
        dofs = self.element_dofs(nodes)
        lbar, kbar = self._pole_reference(nodes, lbar, kbar, B)
        y = np.matmul(B, c[dofs[0]]).T                            # (k, Q)
        v, g, h = kernel(y, lbar)
        Bq = v - kbar                                              # (Q,)
        G = np.matmul(B.transpose(0, 2, 1), g.T[:, :, None])[:, :, 0]  # (Q, A): dB_q in the unknowns
        mean, mean2 = float(w @ Bq), float(w @ (Bq * Bq))
        dmean = w @ G
        energy = Akb * ((3.0 * nu - 1.0) * mean * mean + 2.0 * (1.0 - nu) * mean2)
        grad = Akb * (2.0 * (3.0 * nu - 1.0) * mean * dmean + 4.0 * (1.0 - nu) * ((w * Bq) @ G))
        hess = self._pole_second(B, G, h, Bq, w, Akb)
        return dofs, energy, grad[None, :], hess[None, :, :]

    def _pole_second(self, B: np.ndarray, G: np.ndarray, h: np.ndarray, Bq: np.ndarray, w: np.ndarray,
                     Akb: float) -> np.ndarray:
        """The pole element's second variation ``(A, A)`` along the perturbations mapped by ``B`` ``(Q, k, A)``:
        ``G`` the curvature's first variation ``(Q, A)``, ``h`` its Hessian in the local variables
        ``(k, k, Q)``, ``Bq`` its value less the reference at each angle, ``w`` the angle's weights over
        ``2 pi``."""
        nu = self.nu
        mean, dmean = float(w @ Bq), w @ G
        # the curvature's second variation enters weighted: sum_q c_q B_q^T h_q B_q, c_q its weight
        cq = 2.0 * (3.0 * nu - 1.0) * mean * w + 4.0 * (1.0 - nu) * (w * Bq)
        hw = h.transpose(2, 0, 1) * cq[:, None, None]                # (Q, k, k)
        Q, k, A = B.shape
        second = np.matmul(B.reshape(Q * k, A).T, np.matmul(hw, B).reshape(Q * k, A))
        return Akb * (2.0 * (3.0 * nu - 1.0) * np.outer(dmean, dmean) + 4.0 * (1.0 - nu) * np.matmul(G.T * w, G)
                      + second)

    def energy(self, c: np.ndarray, pressure: float = 0.0) -> float:
        """The elastic energy of the state ``c`` (plus ``pressure`` times the enclosed volume)."""
        w = self.basis.weights
        e = sum(factor * float(np.einsum("qe,q->", jets[0], w)) for _, jets, factor in self._groups(c, pressure))
        return float(e + sum(t[1] for t in self._cache["state"]["poles"]))

    def volume(self, c: np.ndarray) -> float:
        """The volume between the shell and its base plane (``z = z_ref``), or enclosed by a closed shell."""
        return self.energy(c, 1.0) - self.energy(c, 0.0)

    def gradient(self, c: np.ndarray, pressure: float = 0.0) -> np.ndarray:
        """The energy's gradient in all unknowns."""
        w = self.basis.weights
        g = np.zeros(self.size)
        for fam, jets, factor in self._groups(c, pressure):
            B, gl = fam[2], jets[1]
            Q, k, A = B.shape
            # g_e = sum_q w_q B_q^T g_eq, with (i, q) stacked as the kernel gives them: one product (A, k Q) (k Q, E)
            ge = np.matmul((w[None, :, None] * B.transpose(1, 0, 2)).reshape(k * Q, A).T, gl.reshape(k * Q, -1))
            g += np.bincount(self._dofs(fam[1]).T.ravel(), factor * ge.ravel(), minlength=self.size)
        for dofs, _, ge, _ in self._cache["state"]["poles"]:
            np.add.at(g, dofs.ravel(), ge.ravel())
        return g

    def pattern(self, pressure: bool = False) -> sp.csr_matrix:
        """Every entry the Hessian may hold (ones, canonical), with the volume's under ``pressure``: its band."""
        key = ("pattern", bool(pressure))
        if key not in self._cache:
            terms = list(self._families) + (list(self._volume) if pressure else [])
            dofs = [self.element_dofs(t[1]) for t in terms] + [self.element_dofs(p[0]) for p in self._poles]
            rows = np.concatenate([np.repeat(d, d.shape[1], axis=1).ravel() for d in dofs])
            cols = np.concatenate([np.tile(d, (1, d.shape[1])).ravel() for d in dofs])
            P = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(self.size, self.size))
            P.sum_duplicates()
            P.data[:] = 1.0
            self._cache[key] = P
        return self._cache[key]

    def hessian_slots(self, dofs: np.ndarray, pressure: bool, transient: bool = False) -> np.ndarray:
        """Positions in the data of :meth:`pattern` (``pressure``: with the volume's entries) of the
        ``(E, A, A)`` Hessian entries of elements on the unknowns ``dofs`` (``(E, A)``), cached.

        ``transient``: the unknowns change along a path (the nodes a contact touches), so only the
        :data:`SLOT_CACHE_SIZE` sets asked for last are kept; the element families' fixed sets are kept for good.
        """
        key = ("slots", dofs.tobytes(), dofs.shape, bool(pressure))  # named apart from the other entries of _cache
        cache = self._slots if transient else self._cache
        slots = cache.get(key)
        if slots is None:
            P = self.pattern(pressure)
            A = dofs.shape[1]
            rows = np.repeat(dofs, A, axis=1).ravel()
            cols = np.tile(dofs, (1, A)).ravel()
            slots = cache[key] = csr_positions(P, rows, cols)
            if transient and len(self._slots) > SLOT_CACHE_SIZE:
                self._slots.popitem(last=False)
        elif transient:
            self._slots.move_to_end(key)
        return slots

    def hessian(self, c: np.ndarray, pressure: float = 0.0, volume_pattern: bool = False) -> sp.csr_matrix:
        """The energy's Hessian in all unknowns (banded along the meridian; the entries of :meth:`pattern`,
        with the volume's where there is a pressure or ``volume_pattern`` asks for them)."""
        w = self.basis.weights
        with_volume = pressure != 0.0 or volume_pattern
        P = self.pattern(with_volume)
        # kept with the state's jets: a Jacobian and the derivative in the load at one point ask for it twice
        key = ("hessian", float(pressure), with_volume)
        st = self._state(c, pressure != 0.0)
        if key in st:
            return sp.csr_matrix((st[key].copy(), P.indices, P.indptr), shape=P.shape)
        def elements():
            for fam, jets, factor in self._groups(c, pressure):
                He, rows = self._element_hessians(jets[2], fam[2], w)
                if factor != 1.0:
                    He *= factor
                yield He, rows, fam[1]
            for pole, (dofs, _, _, He) in zip(self._poles, self._cache["state"]["poles"]):
                yield He[0][:, :, None], np.arange(dofs.shape[1]), pole[0]

        data = st[key] = self.assemble(elements(), with_volume)
        return sp.csr_matrix((data.copy(), P.indices, P.indptr), shape=P.shape)

    def assemble(self, elements: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]], pressure: bool) -> np.ndarray:
        """The sum of element Hessians as the data of a matrix of :meth:`pattern` (``pressure``: with the
        volume's entries).

        Parameters
        ----------
        elements : iterable of ``(He, rows, nodes)``
            ``He`` ``(A, A, E)``: the Hessians of the elements on the nodes ``nodes`` ``(E, nn)``, in this view's
            unknowns of those nodes (:meth:`element_dofs`), the element last; row ``r`` (and column ``r``) is
            the element's unknown ``rows[r]``.
        pressure : bool

        Returns
        -------
        ndarray
            ``(pattern(pressure).nnz,)``.
        """
        band, place, positions = self._band(pressure)
        for He, rows, nodes in elements:
            self._add_to_band(band, He, rows, nodes, place)
        return band.ravel()[positions]

    def _band(self, pressure: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The Hessian's entries gathered by node pairs before they are read out in the order of
        :meth:`pattern` (``pressure``: with the volume's): ``(band, place, positions)``.

        ``band[d, place[a], b, i]`` (zeros to fill) is the entry of unknown ``a`` of node ``i`` and unknown
        ``b`` of node ``i + d - w`` (``w`` the widest coupling), the node last so that the elements of a
        family add to it by slices (:meth:`_add_to_band`); ``place`` orders a node's unknowns as
        :meth:`_component_split` orders an element's (those of ``R`` and ``T``, then those of ``Z``);
        ``positions`` are the pattern's entries in the flattened band.
        """
        key = ("band", bool(pressure))
        if key not in self._cache:
            P, m, N = self.pattern(pressure), self.m, self.N
            vertical = np.array([t[0] == "Z" for t in self.basis.terms])
            place = np.empty(m, dtype=np.int64)
            place[np.concatenate([np.flatnonzero(~vertical), np.flatnonzero(vertical)])] = np.arange(m)
            rows = np.repeat(np.arange(P.shape[0], dtype=np.int64), np.diff(P.indptr))
            (i, a), (j, b) = divmod(rows, m), divmod(P.indices.astype(np.int64), m)
            w = int(np.abs(j - i).max())
            positions = (((j - i + w) * m + place[a]) * m + b) * N + i
            self._cache[key] = ((2 * w + 1, m, m, N), place, positions)
        shape, place, positions = self._cache[key]
        return np.zeros(shape), place, positions

    def _add_to_band(self, band: np.ndarray, He: np.ndarray, rows: np.ndarray, nodes: np.ndarray,
                     place: np.ndarray) -> None:
        """Add the element Hessians ``He`` ``(A, A, E)`` (rows ordered by ``rows``) of the elements on ``nodes``
        ``(E, nn)`` to ``band`` (:meth:`_band`): a slice per run of rows that one node holds in the band's
        order where element ``e`` has the nodes ``n + e, n + e + 1, ...`` (as along a meridian); one entry
        at a time otherwise."""
        m, E = self.m, nodes.shape[0]
        w, N = band.shape[0] // 2, band.shape[3]
        key = ("runs", rows.tobytes(), nodes.tobytes(), nodes.shape)
        if key not in self._cache:
            slot, unknown = divmod(rows, m)
            target = place[unknown]
            starts = np.flatnonzero(np.r_[True, (slot[1:] != slot[:-1]) | (target[1:] != target[:-1] + 1)])
            ends = np.r_[starts[1:], rows.size]
            # node i + s in slot s of element i: each slot's nodes and each element's follow one another
            regular = bool(np.all(nodes == nodes[0, 0] + np.arange(E)[:, None] + np.arange(nodes.shape[1])[None, :]))
            if regular and starts.size <= 2 * nodes.shape[1]:
                self._cache[key] = [(r0, r1, int(slot[r0]), int(target[r0])) for r0, r1 in zip(starts, ends)]
            else:
                i = nodes[:, slot].T[:, None, :]                   # (A, 1, E): the node of each row
                j = np.repeat(nodes, m, axis=1).T[None, :, :]     # (1, A, E): the node of each column
                b = (np.arange(nodes.shape[1] * m) % m)[None, :, None]
                self._cache[key] = ((((j - i + w) * m + target[:, None, None]) * m + b) * N + i).ravel()
        runs = self._cache[key]
        nn = nodes.shape[1]
        if isinstance(runs, list):
            # a run's columns, node by node, are successive rows of the band
            for r0, r1, s, a0 in runs:
                i0 = int(nodes[0, s])
                band[w - s:w - s + nn, a0:a0 + r1 - r0, :, i0:i0 + E] += \
                    He[r0:r1].reshape(r1 - r0, nn, m, E).transpose(1, 0, 2, 3)
        else:
            np.add.at(band.reshape(-1), runs, He.ravel())

    # ---- stability against every perturbation: the Bloch blocks ------------------------------------
    # A block is the Hessian's quadratic form on one class of perturbations, integrated by the trapezoidal
    # rule on the whole circle.  The state's local Hessians repeat with period 2 pi / n and are even about
    # theta = 0, so the sum over the circle folds onto the state's own half period (its angles and weights,
    # where the traced view has its jets already): a perturbation of wave m = q n +- j, rotated by 2 pi s / n,
    # is the same perturbation turned by the phase +-2 pi s j / n, i.e. cos(psi) times itself plus sin(psi)
    # times its partner of the other parity (cos <-> sin, with signs).  Summed over the n rotations the
    # cross terms cancel and the squares add: n copies of the block's integrand on one period for
    # j = 0 and j = n / 2 (psi = 0 or pi), n / 2 copies of the integrand plus n / 2 copies of the partner's
    # for 0 < j < n / 2.  Both are even about theta = 0, so one half period with its ends weighted half
    # carries them.  The pole's element depends on the means over the angle of single variations, which do
    # not fold this way: it keeps the whole circle (one element).
    def _full_circle(self) -> tuple[np.ndarray, np.ndarray]:
        """The trapezoidal rule's ``M`` angles on the whole circle and their weights."""
        M = self.basis.M
        return 2.0 * math.pi * np.arange(M) / M, np.full(M, 2.0 * math.pi / M)

    def _perturbation_view(self, j: int, parity: str) -> tuple["FourierShell", dict, np.ndarray]:
        """The view of the perturbation class ``(j, parity)``, its local maps and their weights, cached.

        ``maps[name]``: the family's perturbation map on the state's half period, for ``0 < j < n / 2``
        followed by its partner's (the angles stacked twice, each copy weighted half: ``weights``);
        ``maps["pole"]``: the pole element's perturbation map on the whole circle.
        """
        key = ("bloch", int(j), parity)
        if key not in self._cache:
            basis = self.basis
            pb = basis.bloch(j, parity)
            pview = FourierShell(self.structure, pb, self.z_ref)
            rings = [pb.ring_maps(basis.theta)]
            weights = basis.weights
            if 0 < 2 * j < basis.n:
                rings.append(self._partner_maps(pb, basis.theta))
                weights = np.concatenate([weights, weights]) * 0.5
            maps = {}
            for fam in self._families + self._volume:
                layout, nn = self._layouts[fam[0]], fam[1].shape[1]
                maps[fam[0]] = np.concatenate([self._local_map(layout, nn, r) for r in rings], axis=0)
            maps["pole"] = self._local_map(layouts.POLE, 2, pb.ring_maps(self._full_circle()[0]))
            self._cache[key] = (pview, maps, weights)
        return self._cache[key]

    @staticmethod
    def _partner_maps(pb: AngularBasis, theta: np.ndarray) -> dict[str, np.ndarray]:
        """The ring maps (:meth:`AngularBasis.ring_maps`) at ``theta`` of the partner of each term of the Bloch
        class ``pb`` (``0 < j < n / 2``): the term of the other parity, same component and wave, with the sign
        that makes ``f(m (theta + phi)) = cos(psi) f(m theta) + sin(psi) partner(m theta)`` for a rotation
        ``phi`` by which ``m phi = psi`` (waves ``m = q n + j``) or ``-psi`` (``m = q n - j``)."""
        other = AngularBasis(pb.n, pb.K, mirror=pb.parity == "odd", M=pb.M, j=pb.j,
                             parity="odd" if pb.parity == "even" else "even")
        swap = {"cos": "sin", "sin": "cos"}
        order = [other.index(comp, swap[trig], k) for comp, trig, k in pb.terms]
        # cos(m t + e psi) = cos psi cos(m t) - e sin psi sin(m t); sin(m t + e psi) = cos psi sin(m t) + e sin psi cos(m t)
        turn = np.array([1.0 if k % pb.n == pb.j else -1.0 for _, _, k in pb.terms])
        sign = np.where([trig == "cos" for _, trig, _ in pb.terms], -turn, turn)
        return {kind: a[..., order] * sign for kind, a in other.ring_maps(theta).items()}

    def _restricted(self, pview: "FourierShell", j: int, parity: str, pressure: bool, remove_rigid: bool,
                    held: tuple) -> Callable[[np.ndarray], sp.csr_matrix]:
        """The map from the data of ``pview``'s Hessian pattern to the block on its admissible unknowns
        (:meth:`FourierReduction.restriction`), cached per class and reduction."""
        key = ("bloch restriction", int(j), parity, bool(pressure), bool(remove_rigid), held)
        if key not in self._cache:
            self._cache[key] = pview.reduction(remove_rigid, held).restriction(pview.pattern(pressure))
        return self._cache[key]

    def bloch_unknowns(self, j: int, parity: str) -> np.ndarray:
        """Which of the class ``(j, parity)``'s coefficients (in the order of :meth:`AngularBasis.bloch`'s view) are
        the unknowns of :meth:`bloch_block`, in the block's order (rigid motions removed, no control held)."""
        pview, _, _ = self._perturbation_view(j, parity)
        key = ("bloch unknowns", int(j), parity)
        if key not in self._cache:
            self._cache[key] = pview.reduction(True, ()).free
        return self._cache[key]

    def bloch_block(self, c: np.ndarray, j: int, parity: str = "even", pressure: float = 0.0,
                    remove_rigid: bool = True, control_fixed=()) -> sp.csr_matrix:
        """The Hessian at the state ``c`` (of this view's ``D_n`` basis) on the perturbations of Bloch wave
        number ``j`` and one parity (:meth:`AngularBasis.bloch`), reduced to their admissible unknowns.

        At a ``D_n``-symmetric state the Hessian on every perturbation splits into these blocks (the
        irreducible representations of ``D_n``): the waves ``m = q n +- j`` couple only among themselves,
        and symmetric and antisymmetric fields about the mirror do not couple.  For ``0 < j < n / 2`` the
        two parities carry the same two-dimensional representation and have the same spectrum.  The angle
        is integrated by the basis's ``M``-angle rule on the whole circle, folded onto the state's half
        period (the comment above :meth:`_full_circle`): the blocks share the state's local Hessians with
        :meth:`hessian`.  ``control_fixed`` (traced-model dofs held by a control) acts on ``j = 0``,
        ``"even"`` only.
        """
        if not self.basis.mirror or self.basis.j != 0:
            raise ValueError("FourierShell.bloch_block: the state's basis must be a D_n basis (mirror=True, j=0)")
        pview, maps, w = self._perturbation_view(j, parity)
        with_volume = pressure != 0.0
        st = self._state(c, with_volume)

        def elements():
            for fam, jets, factor in self._groups(c, pressure):
                h = jets[2]
                if w.size != h.shape[2]:  # the half period twice: the perturbations and their partners
                    h = np.concatenate([h, h], axis=2)
                He, rows = self._element_hessians(h, maps[fam[0]], w)
                if factor != 1.0:
                    He *= factor
                yield He, rows, fam[1]
            for k, (nodes, _, _, _, Akb) in enumerate(self._poles):
                He = self._pole_hessian(self._pole_circle(st, k), maps["pole"], Akb)
                yield He[:, :, None], np.arange(He.shape[0]), nodes

        held = tuple(int(d) for d in control_fixed) if (j == 0 and parity == "even") else ()
        # summed in the perturbation view's pattern as it sums its own Hessian (:meth:`hessian`)
        return self._restricted(pview, j, parity, with_volume, remove_rigid, held)(
            pview.assemble(elements(), with_volume))

    def _pole_circle(self, st: dict, k: int) -> tuple:
        """Pole ``k``'s curvature at the state of ``st`` (:meth:`_state`) on the whole circle, kept with the
        state: ``(B - kappa_bar (Q,), its gradient (k, Q), its Hessian (k, k, Q))`` in the local variables."""
        key = ("pole circle", k)
        if key not in st:
            nodes, kernel, lbar, kbar, _ = self._poles[k]
            if "pole circle map" not in self._cache:
                self._cache["pole circle map"] = self._local_map(layouts.POLE, 2, self.basis.ring_maps(self._full_circle()[0]))
            Bs = self._cache["pole circle map"]
            lbar, kbar = self._pole_reference(nodes, lbar, kbar, Bs)
            v, g, h = kernel(np.matmul(Bs, st["c"][self.element_dofs(nodes)[0]]).T, lbar)
            st[key] = (v - kbar, g, h)
        return st[key]

    def _pole_hessian(self, curvature: tuple, Bp: np.ndarray, Akb: float) -> np.ndarray:
        """The pole element's second variation along the perturbations mapped by ``Bp`` on the whole circle,
        from its curvature there (:meth:`_pole_circle`)."""
        Bq, g, h = curvature
        _, w = self._full_circle()
        G = np.matmul(Bp.transpose(0, 2, 1), g.T[:, :, None])[:, :, 0]
        return self._pole_second(Bp, G, h, Bq, w / (2.0 * math.pi), Akb)

    def bloch_classes(self) -> list[tuple[int, str, int]]:
        """``(j, parity, multiplicity)`` of every class of perturbations about a ``D_n`` state: the
        irreducible representations of ``D_n``, each once (a two-dimensional one by one parity, counted twice)."""
        n = self.basis.n
        out = []
        for j in range(n // 2 + 1):
            if j == 0 or 2 * j == n:
                out += [(j, "even", 1), (j, "odd", 1)]
            else:
                out.append((j, "even", 2))
        return out

    def representations(self) -> dict[str, tuple[int, str, int]]:
        """:meth:`bloch_classes` by the names of the representations of ``D_n`` (:func:`representation_name`)."""
        n = self.basis.n
        return {representation_name(n, j, parity): (j, parity, copies) for j, parity, copies in self.bloch_classes()}

    def morse_index(self, c: np.ndarray, pressure: float = 0.0, remove_rigid: bool = True,
                    control_fixed=()) -> dict[tuple[int, str], int]:
        """The number of negative eigenvalues of each Bloch block at the ``D_n`` state ``c`` (by the blocks'
        ``L D L^T`` inertia), keyed ``(j, parity)``; the Morse index against every perturbation is
        ``sum(multiplicity * count)`` over :meth:`bloch_classes`."""
        from contin.numerics.stability import stability_info

        return {(j, par): int(stability_info(self.bloch_block(c, j, par, pressure, remove_rigid, control_fixed),
                                             0).n_negative)
                for j, par, _ in self.bloch_classes()}


# ---- coefficients from one basis into another --------------------------------------------------------
def transfer_coefficients(c: np.ndarray, source: AngularBasis, target: AngularBasis, turn: float = 0.0) -> np.ndarray:
    """The rings' fields given by the coefficients ``c`` of ``source`` as coefficients of ``target``.

    Each ring's ``R``, ``T`` and ``Z`` are the same functions of the material angle; with ``turn`` they are read
    from an angle ``theta' = theta - turn`` (the target's ``theta' = 0`` is the source's ``theta = turn``), so
    ``cos(k theta)`` becomes ``cos(k turn) cos(k theta') - sin(k turn) sin(k theta')`` and likewise for the sines.
    The frame turns with the angle, so the components keep their names.

    Parameters
    ----------
    c : ndarray
        ``(N source.m,)`` coefficients, node by node (a state, a mode or a perturbation of the source basis).
    source, target : AngularBasis
    turn : float
        The angle (radians) of the target's ``theta' = 0`` in the source's angle.

    Returns
    -------
    ndarray
        ``(N target.m,)``; the target's terms the source does not feed are zero.

    Raises
    ------
    ValueError
        ``c`` is not a whole number of the source's nodes, or a nonzero coefficient lands on a term the target
        does not carry (its wave or parity is not in the target's class).
    """
    c = np.asarray(c, dtype=float)
    if c.ndim != 1 or c.size % source.m:
        raise ValueError(f"transfer_coefficients: c must hold {source.m} coefficients per node of {source!r}, got "
                         f"shape {c.shape}")
    rows = c.reshape(-1, source.m)
    out = np.zeros((rows.shape[0], target.m))
    other = {"cos": "sin", "sin": "cos"}
    for col, (comp, trig, k) in enumerate(source.terms):
        if not np.any(rows[:, col]):
            continue
        ck, sk = math.cos(k * turn), math.sin(k * turn)
        # cos(k theta' + k turn) = ck cos - sk sin;  sin(k theta' + k turn) = ck sin + sk cos
        parts = ((trig, ck), (other[trig], -sk if trig == "cos" else sk))
        for name, factor in parts:
            if abs(factor) < 1e-14:  # k turn a multiple of pi / 2: the rounding of its sine or cosine
                continue
            try:
                j = target.index(comp, name, k)
            except KeyError:
                raise ValueError(f"transfer_coefficients: the source's {comp} {trig}({k} theta) (turned by "
                                 f"{turn:.6g}) needs {comp} {name}({k} theta), which {target!r} does not carry") from None
            out[:, j] += factor * rows[:, col]
    return out.ravel()
