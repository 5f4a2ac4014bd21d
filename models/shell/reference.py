"""The shell's reference data per element, computed once: :class:`ShellReference`.

Every view of the shell (the traced axisymmetric energy :class:`contin_models.shell.ShellEnergy` with
its pole and edge elements, the harmonic blocks and the ring mesh of
:mod:`contin_models.shell.harmonic`) evaluates the same elements against the same reference numbers:
edge lengths and radii, Voronoi lengths, reference curvatures and stiffnesses.  They are computed here,
from the reference meridian, the material and the supports, and every view reads them from one
:class:`ShellReference`, so no view keeps a copy of its own that could drift from the others.

Units: lengths in the meridian's unit (``R`` for the scenes), ``E`` a stress, the stretching stiffness
``ks = E h / (1 - nu^2)`` a force per length, the bending stiffness ``kb = E h^3 / (12 (1 - nu^2))`` a
force times a length, curvatures the inverse of a length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from .elements import ClampedEdge, MomentFreeEdge, PoleMirror
from .energy import _bend_local, _edges, kernels
from .supports import SUPPORTS

__all__ = ["ShellReference", "StretchReference", "BendReference", "PoleReference", "EdgeReference"]


def _frozen(a: Any) -> Any:
    """A read-only view of an array (the numbers as they are); anything else unchanged."""
    if isinstance(a, np.ndarray):
        a = a.view()
        a.setflags(write=False)
    return a


@dataclass(frozen=True)
class StretchReference:
    """The stretching elements: one per edge ``i = 0 .. N-2`` (nodes ``i``, ``i+1``).

    Attributes
    ----------
    nodes : ndarray of int, shape ``(N-1, 2)``
        The edge's two nodes.
    lbar : ndarray, shape ``(N-1,)``
        Reference edge length (length).
    rbar : ndarray, shape ``(N-1,)``
        Reference edge radius ``(r_i + r_{i+1}) / 2`` (length).
    ks : float or ndarray, shape ``(N-1,)``
        Stretching stiffness ``E h / (1 - nu^2)`` (force per length) as the kernels take it: one number
        for a constant thickness, else per edge (the mean thickness of its nodes).
    """

    nodes: np.ndarray
    lbar: np.ndarray
    rbar: np.ndarray
    ks: float | np.ndarray


@dataclass(frozen=True)
class BendReference:
    """The bending elements: one per interior node ``i = 1 .. N-2`` (the end nodes have one edge).

    Attributes
    ----------
    nodes : ndarray of int, shape ``(N-2,)``
        The element's node (its neighbours ``i-1``, ``i+1`` enter too).
    lbar : ndarray, shape ``(N-2,)``
        Reference Voronoi length ``(lbar^{i-1} + lbar^i) / 2`` (length).
    rbar : ndarray, shape ``(N-2,)``
        Reference node radius (length).
    k11bar, k22bar : ndarray, shape ``(N-2,)``
        Reference meridional and circumferential curvatures (1 / length), computed by the energy's own
        curvature kernel of :attr:`kernels` at the reference state (so that the reference state is
        exactly stress free; the meridian's ``kappa11`` may differ in the last bit).
    kb : float or ndarray, shape ``(N-2,)``
        Bending stiffness ``E h^3 / (12 (1 - nu^2))`` (force times length) as the kernels take it: one
        number for a constant thickness, else per node.
    kernels : {"bend", "bend_cur"}
        The generated kernels: ``kappa11`` over the reference or the current Voronoi length.
    """

    nodes: np.ndarray
    lbar: np.ndarray
    rbar: np.ndarray
    k11bar: np.ndarray
    k22bar: np.ndarray
    kb: float | np.ndarray
    kernels: str


@dataclass(frozen=True)
class PoleReference:
    """The mirror bending element of an end node on the axis.

    Attributes
    ----------
    node, neighbour : int
        The pole and its neighbour on the meridian.
    north : bool
        The pole is the last node (the meridian runs neighbour -> pole), else the first.
    dofs : ndarray of int, shape ``(3,)``
        Full-state dofs of the element's local variables: ``(r_nb, z_nb, z_pole)`` at the north pole,
        ``(r_1, z_0, z_1)`` at the south one.
    a_bar, b_bar : float
        Reference ``a = r_nb`` and ``b``, the height of the pole above its neighbour (north) or of node 1
        above the pole (south) (lengths).
    lbar : float
        Reference length of the pole's edge (length).
    kb : float
        Bending stiffness at the pole (force times length).
    element : PoleMirror
        The element; its ``area`` (``pi (lbar/2)^2``), ``K`` and ``kappa_bar`` (1 / length) are read
        from it.
    """

    node: int
    neighbour: int
    north: bool
    dofs: np.ndarray
    a_bar: float
    b_bar: float
    lbar: float
    kb: float
    element: PoleMirror

    @property
    def kappa_bar(self) -> float:
        """Reference curvature of the pole (1 / length)."""
        return self.element.kappa_bar


@dataclass(frozen=True)
class EdgeReference:
    """The bending element of the edge node 0 (off the axis).

    Attributes
    ----------
    kind : {"clamped", "moment_free"}
        :class:`contin_models.shell.structure.ClampedEdge` (the ghost node on the reference tangent) or
        :class:`contin_models.shell.structure.MomentFreeEdge` (a rotating edge's half cell).
    kb : float
        Bending stiffness at the edge node (force times length).
    element : ClampedEdge or MomentFreeEdge
        The element, with its reference curvature ``kappa_bar`` (1 / length; a pair ``(kappa11,
        kappa22)`` for the clamp) and weights.
    """

    kind: str
    kb: float
    element: Any


class ShellReference:
    """Read-only reference data of every element of a shell of revolution, built once.

    Build it with :meth:`build`.  The arrays are read-only; the numbers are those the energy's kernels
    take, computed by the same code the energy always used.

    Attributes
    ----------
    meridian : ReferenceCap or ReferenceMeridian
        The reference polyline (its ``N``, ``r``, ``z``, ``x``, ``edge_length``, ``edge_radius``,
        ``voronoi_length``, ``node_radius`` are read; lengths).
    N : int
        Number of nodes.
    E, nu : float
        Young's modulus (a stress) and Poisson's ratio.
    h : float or ndarray
        The thickness as given (length; a read-only copy of an array).
    h_nodes : ndarray, shape ``(N,)``
        Thickness at every node (length).
    ks_edges : ndarray, shape ``(N-1,)``
        Stretching stiffness of every edge (force per length).
    kb_nodes : ndarray, shape ``(N,)``
        Bending stiffness of every node (force times length).
    ks, kb : float
        The stiffnesses at the pole end, ``ks_edges[-1]`` and ``kb_nodes[-1]``.
    kappa11_length : {"reference", "current"}
        The length in the interior nodes' ``kappa11``.
    stretch : StretchReference
        The stretching elements (edges).
    bend : BendReference
        The bending elements (interior nodes).
    axis_nodes : tuple of int
        The end nodes on the axis (``r = 0``): 0, ``N-1``, both or none.
    poles : tuple of PoleReference
        The mirror bending element of each node of :attr:`axis_nodes` (none with ``pole="skip"``, or
        when the reference was built without supports).
    boundary : str or None
        The support of the edge at node 0 (``"free"`` or ``"pinned"`` when node 0 is a pole); None when
        built without supports (the energy alone).
    edge : EdgeReference or None
        The edge node's bending element (clamped, or a rotating edge's with ``edge_bending="moment_free"``).
    fixed : ndarray of int
        Sorted full-state dofs the supports and the axis fix (empty without supports).
    free : ndarray of int
        The other full-state dofs.
    rigid_fix : int or None
        The dof fixed only to remove the rigid translation along the axis, when nothing else holds ``z``.
    """

    def __init__(self) -> None:  # noqa: D107 (filled by build)
        raise TypeError("ShellReference: build it with ShellReference.build(meridian, E, nu, h, ...)")

    @classmethod
    def build(cls, meridian: Any, E: float, nu: float, h: float | np.ndarray,
              kappa11_length: Literal["reference", "current"] = "current",
              boundary: Literal["sliding", "pinned", "clamped", "free"] | None = None,
              edge_bending: Literal["moment_free", "none"] = "none",
              pole: Literal["mirror", "skip"] = "mirror") -> "ShellReference":
        """The reference data of a shell on ``meridian``.

        Parameters
        ----------
        meridian
            The reference polyline (a :class:`contin_models.shell.geometry.ReferenceCap` or a meridian of
            :mod:`contin_models.shell.meridian`).
        E, nu : float
            Young's modulus, ``> 0``, and Poisson's ratio, in ``(-1, 1)``.
        h : float or array of shape ``(N,)``
            Thickness, ``> 0``, or the thickness of every node.
        kappa11_length : {"reference", "current"}
            Length in the interior nodes' ``kappa11`` (:class:`contin_models.shell.ShellEnergy`).
        boundary : {"sliding", "pinned", "clamped", "free"} or None
            Support of the edge at node 0; None: the elements of the energy alone (no poles, no edge
            element, nothing fixed).  When node 0 is a pole on the axis (a closed end) only ``"free"``
            (``"sliding"``, the default, is read as it) and ``"pinned"`` (the pole held at its point: a
            point support, reacting a force at the other pole) apply; ``"clamped"`` raises ValueError.
        edge_bending : {"moment_free", "none"}
            Bending element of an edge node that may rotate (:class:`contin_models.shell.ShellStructure`).
        pole : {"mirror", "skip"}
            A mirror bending element at every end on the axis, or none.
        """
        self = object.__new__(cls)
        h_array = None
        if np.ndim(h) == 0:
            E, h, nu = float(E), float(h), float(nu)
            if not (h > 0 and math.isfinite(h)):
                raise ValueError(f"ShellReference: h must be a positive number, got {h!r}")
        else:
            E, nu = float(E), float(nu)
            h_array = np.array(h, dtype=float)
            if h_array.shape != (meridian.N,):
                raise ValueError(f"ShellReference: h must be a number or an array of shape (N,) = ({meridian.N},), "
                                 f"got shape {h_array.shape}")
            if not (np.all(h_array > 0) and np.isfinite(h_array).all()):
                raise ValueError("ShellReference: h must be positive and finite at every node")
            h_array.setflags(write=False)
            h = h_array
        if not (E > 0 and math.isfinite(E)):
            raise ValueError(f"ShellReference: E must be a positive number, got {E!r}")
        if not (-1.0 < nu < 1.0):
            raise ValueError(f"ShellReference: nu must be in (-1, 1), got {nu!r}")
        if kappa11_length not in ("reference", "current"):
            raise ValueError(f"ShellReference: kappa11_length must be 'reference' or 'current', "
                             f"got {kappa11_length!r}")
        if edge_bending not in ("moment_free", "none"):
            raise ValueError(f"ShellReference: edge_bending must be 'moment_free' or 'none', got {edge_bending!r}")
        if boundary is not None and boundary not in SUPPORTS:
            raise ValueError(f"ShellReference: boundary must be one of {SUPPORTS}, got {boundary!r}")
        if pole not in ("mirror", "skip"):
            raise ValueError(f"ShellReference: pole must be 'mirror' or 'skip', got {pole!r}")
        self.meridian = meridian
        self.E, self.h, self.nu = E, h, nu
        self.kappa11_length = kappa11_length
        N = self.N = int(meridian.N)
        bend_nodes = np.arange(1, N - 1)  # the end nodes have one edge: no interior bending element
        if h_array is None:
            self.ks = E * h / (1.0 - nu**2)
            self.kb = E * h**3 / (12.0 * (1.0 - nu**2))
            ks_param, kb_param = self.ks, self.kb
            self.h_nodes = np.full(N, h)
            self.ks_edges = np.full(N - 1, self.ks)
            self.kb_nodes = np.full(N, self.kb)
        else:
            self.h_nodes = h_array
            self.ks_edges = E * (0.5 * (h_array[:-1] + h_array[1:])) / (1.0 - nu**2)
            self.kb_nodes = E * h_array**3 / (12.0 * (1.0 - nu**2))
            self.ks, self.kb = float(self.ks_edges[-1]), float(self.kb_nodes[-1])
            ks_param, kb_param = self.ks_edges, self.kb_nodes[bend_nodes]
        for a in (self.h_nodes, self.ks_edges, self.kb_nodes):
            a.setflags(write=False)

        edge_nodes = np.arange(N - 1)
        self.stretch = StretchReference(_frozen(np.stack([edge_nodes, edge_nodes + 1], axis=1)),
                                        _frozen(meridian.edge_length), _frozen(meridian.edge_radius),
                                        _frozen(ks_param))
        variant = "bend" if kappa11_length == "reference" else "bend_cur"
        lbar, rbar = meridian.voronoi_length[bend_nodes], meridian.node_radius[bend_nodes]
        # the reference curvatures from the very same kernel code and local variables as the energy,
        # so that the reference state is exactly flat
        curvatures = getattr(kernels, f"{variant}_fast_curvatures")
        k11bar, k22bar = curvatures(*_bend_local(*_edges(meridian.x)), lbar, rbar, 0.0, 0.0, kb_param, nu)
        self.bend = BendReference(_frozen(bend_nodes), _frozen(lbar), _frozen(rbar), _frozen(k11bar),
                                  _frozen(k22bar), _frozen(kb_param), variant)
        self._supports(boundary, edge_bending, pole)
        return self

    def _supports(self, boundary: str | None, edge_bending: str, pole: str) -> None:
        """The axis nodes, the poles' and the edge's elements, and the fixed dofs."""
        meridian, N, nu = self.meridian, self.N, self.nu
        r, z = np.asarray(meridian.r, dtype=float), np.asarray(meridian.z, dtype=float)
        self.boundary = boundary
        self.edge = None
        self.poles = ()
        self.rigid_fix = None
        if boundary is None:
            self.axis_nodes = ()
            self.fixed = _frozen(np.array([], dtype=int))
            self.free = _frozen(np.arange(2 * N))
            return
        if np.any(r < 0):
            raise ValueError("ShellReference: the meridian must lie in r >= 0")
        self.axis_nodes = tuple(k for k in (0, N - 1) if r[k] == 0.0)
        if 0 in self.axis_nodes and boundary not in ("free", "sliding", "pinned"):
            raise ValueError(f"ShellReference: node 0 is a pole on the axis: its support is 'pinned' (the pole "
                             f"held at its point, as by a point support) or 'free', got boundary {boundary!r}")
        if 0 in self.axis_nodes and boundary == "sliding":  # the default of an edge: a pole has none to slide
            boundary = "free"
        self.boundary = boundary

        fixed = {2 * k for k in self.axis_nodes}  # r = 0 on the axis
        if boundary in ("sliding", "pinned", "clamped"):
            fixed.add(1)
        if boundary in ("pinned", "clamped"):
            fixed.add(0)  # already held on the axis when node 0 is a pole
        if not any(d % 2 == 1 for d in fixed):  # nothing holds z: remove the rigid translation
            self.rigid_fix = 2 * (N // 2) + 1
            fixed.add(self.rigid_fix)
        self.fixed = _frozen(np.array(sorted(fixed)))
        self.free = _frozen(np.array([i for i in range(2 * N) if i not in fixed]))

        kb_nodes = self.kb_nodes
        poles = []
        for k in self.axis_nodes if pole == "mirror" else ():
            north = k == N - 1
            nb = k - 1 if north else 1  # the pole's neighbour
            # local variables (r_nb, z_nb, z_pole) for the north pole, (r_1, z_0, z_1) for the south one:
            # a = r_nb, b = (z_pole - z_nb) or (z_1 - z_0); both meridians turn counter-clockwise
            dofs = np.array([2 * nb, 2 * nb + 1, 2 * k + 1]) if north else np.array([2 * nb, 1, 3])
            a_bar = float(r[nb])
            b_bar = float(z[k] - z[nb]) if north else float(z[1] - z[0])
            lbar = float(meridian.edge_length[-1] if north else meridian.edge_length[0])
            kb = float(kb_nodes[k])
            element = PoleMirror(lbar, kb, nu, self.kappa11_length == "current", a_bar, b_bar)
            poles.append(PoleReference(k, nb, north, _frozen(dofs), a_bar, b_bar, lbar, kb, element))
        self.poles = tuple(poles)

        kb0 = float(kb_nodes[0])
        if boundary == "clamped":
            # the smooth curve's tangent when the meridian knows it (theta: the angle of its outward
            # normal, tangent (-sin, cos)); the circle through the first nodes otherwise
            theta = getattr(meridian, "theta", None)
            tangent = None if theta is None else (-math.sin(float(theta[0])), math.cos(float(theta[0])))
            self.edge = EdgeReference("clamped", kb0, ClampedEdge(r, z, kb0, nu, tangent))
        elif edge_bending == "moment_free" and 0 not in self.axis_nodes:
            self.edge = EdgeReference("moment_free", kb0, MomentFreeEdge(r, z, kb0, nu))

    def __repr__(self) -> str:
        return (f"ShellReference(N={self.N}, E={self.E}, nu={self.nu}, kappa11_length={self.kappa11_length!r}, "
                f"boundary={self.boundary!r}, poles={[p.node for p in self.poles]}, "
                f"edge={None if self.edge is None else self.edge.kind!r})")
