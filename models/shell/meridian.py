"""General reference meridians of a shell of revolution (issue 16, ``docs/model.md#geometry``).

The discrete energy (:class:`contin_models.shell.ShellEnergy`) works on any reference polyline: the
reference edge lengths, radii, Voronoi lengths and curvatures are computed from the reference nodes,
so the reference state is stress free by construction, whatever the shape.  This module builds such
polylines from smooth curves in the half plane ``r >= 0``.

Segments
--------
A meridian is a chain of segments joined with continuous position (corners allowed), each a curve
with its arclength and a point-at-arclength map:

* :class:`SphericalArc` -- circle centred on the axis at ``(0, zc)``, radius ``R``, between polar
  angles ``theta0`` and ``theta1`` measured from the horizontal (``geometry.py``'s convention: the
  point at ``theta`` is ``(R cos theta, zc + R sin theta)``, ``theta`` in ``[-pi/2, pi/2]``);
* :class:`Cone` -- the straight line between two points (a cone, a flat annulus or a disc);
* :class:`TorusArc` -- circle centred off the axis at ``(rc, zc)``, radius ``a``, between angles
  ``theta0`` and ``theta1`` (point ``(rc + a cos theta, zc + a sin theta)``);
* :class:`EllipseArc` -- ellipse centred on the axis at ``(0, zc)`` with radial semi-axis ``a`` and
  axial semi-axis ``b``, between *parametric* angles ``t0`` and ``t1`` (point
  ``(a cos t, zc + b sin t)``, ``t`` in ``[-pi/2, pi/2]``); arclength by Gauss-Legendre quadrature,
  inverted by Newton's method (round-off accurate);
* :class:`TableProfile` -- points ``(r_k, z_k)`` interpolated by a not-a-knot cubic spline in the
  cumulative chord length; arclength by quadrature of the spline.

Every segment may carry a ``thickness``: ``None``, a positive number, or a callable of the
arclength ``s`` along the *whole* meridian (from node 0), vectorised.

Nodes (:func:`meridian`)
------------------------
Node 0 is the edge (base), node ``N-1`` the pole, as in :class:`~contin_models.shell.geometry.ReferenceCap`.
A meridian whose last point is on the axis (``r = 0``, snapped exactly) has ``end_on_axis``; one whose
first point is on the axis too (a complete sphere) has ``start_on_axis``.  Every junction between
segments is a node (corners must be), and each segment gets a number of edges in proportion to its
length (at least 2).  The nodes are uniform in arclength by default; ``pole_ratio < 1`` grades them
towards node ``N-1`` with the map of :func:`~contin_models.shell.geometry.theta_nodes`
(:func:`~contin_models.shell.geometry.grading_map`, same ``pole_ratio`` and ``width``), towards both
ends symmetrically when both ends are on the axis (each half of the node range graded towards its
own pole, ``width`` then a fraction of the half); ``ring=s_ring`` additionally refines the mesh
around an interior arclength and puts a node exactly there (``ring_node``), for a ring load.  In
detail: the node-index coordinate ``tau`` in ``[0, 1]`` is mapped to the arclength fraction by the
grading map; the junctions (and the ring) are mapped back to ``tau``, the ``N-1`` edges are shared
among the pieces in proportion to their ``tau`` extent, and inside each piece the nodes are uniform
in ``tau``.  On a single segment with no ring this is exactly the global grading.

Attributes shared with ``ReferenceCap``
---------------------------------------
:class:`ReferenceMeridian` has every attribute that :class:`~contin_models.shell.ShellEnergy` and the
shell problems read from a ``ReferenceCap`` (``N, r, z, x, edge_length, edge_radius,
voronoi_length, node_radius, kappa11, kappa22, pole_ratio, R, phi_hat, theta``).  ``theta`` is the
angle of the smooth curve's outward normal ``(cos theta, sin theta)`` from the r-axis, i.e. the unit
tangent from base to pole is ``(-sin theta, cos theta)``: on a spherical cap it is the polar angle
of ``ReferenceCap.theta``, and :class:`~contin_models.shell.pressure.ClampedEdge` reads the base
tangent from it.  ``R`` and ``phi_hat`` are the sphere's radius and base angle on spherical caps
and the complete sphere, ``None`` otherwise.

Imperfections (:func:`with_dimple`, :func:`with_mode`) return a new ``ReferenceMeridian`` whose nodes
are moved; all reference quantities are recomputed from the new nodes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from .geometry import GRADING_WIDTH, POLE_RATIO, grading_map, interleave, reference_quantities, theta_nodes

__all__ = ["Segment", "SphericalArc", "Cone", "TorusArc", "EllipseArc", "TableProfile", "ReferenceMeridian",
           "meridian", "spherical_cap_meridian", "complete_sphere_meridian", "cone_meridian", "plate_meridian",
           "annulus_meridian", "torus_meridian", "ellipsoid_cap_meridian", "table_meridian", "with_dimple",
           "with_mode", "dimple_width"]

_HALF_PI = 0.5 * math.pi
#: Relative tolerance (of the meridian's size) for the position continuity at junctions and for
#: snapping an end onto the axis.
JOIN_TOL = 1e-12
#: A junction is a corner when the tangent turns by more than this angle (radians).
CORNER_TOL = 1e-9

def _positive(name: str, value, where: str) -> float:
    v = float(value)
    if not (v > 0 and math.isfinite(v)):
        raise ValueError(f"{where}: {name} must be a positive number, got {value!r}")
    return v


def _finite(name: str, value, where: str) -> float:
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{where}: {name} must be a finite number, got {value!r}")
    return v


def _check_thickness(thickness, where: str):
    if thickness is None or callable(thickness):
        return thickness
    return _positive("thickness", thickness, where)


# ---- arclength of a parametric curve ---------------------------------------------------------------
_GL_X, _GL_W = np.polynomial.legendre.leggauss(20)


class _ArcLength:
    """Arclength ``S(p)`` of a smooth parametric curve on ``[p0, p1]`` (``p0 < p1``) from its speed.

    Gauss-Legendre quadrature (20 points) on panels (breakpoints ``knots``), and the inverse map by
    safeguarded Newton iterations (``dS/dp`` is the speed).
    """

    def __init__(self, speed: Callable[[np.ndarray], np.ndarray], knots: np.ndarray) -> None:
        self.speed = speed
        self.knots = np.asarray(knots, dtype=float)
        a, b = self.knots[:-1], self.knots[1:]
        self.cum = np.concatenate([[0.0], np.cumsum(self._panel(a, b))])
        self.length = float(self.cum[-1])

    def _panel(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        half = 0.5 * (b - a)
        p = (0.5 * (a + b))[:, None] + half[:, None] * _GL_X[None, :]
        return half * (self.speed(p) @ _GL_W)

    def S(self, p: np.ndarray) -> np.ndarray:
        """Arclength from ``knots[0]`` to ``p`` (1-d array)."""
        k = np.clip(np.searchsorted(self.knots, p, side="right") - 1, 0, self.knots.size - 2)
        return self.cum[k] + self._panel(self.knots[k], p)

    def p_at(self, s: np.ndarray) -> np.ndarray:
        """Parameter at arclength ``s`` (any shape)."""
        s = np.asarray(s, dtype=float)
        return self._p_at(np.clip(s.ravel(), 0.0, self.length)).reshape(s.shape)

    def _p_at(self, s: np.ndarray) -> np.ndarray:
        k = np.clip(np.searchsorted(self.cum, s, side="right") - 1, 0, self.knots.size - 2)
        lo, hi = self.knots[k], self.knots[k + 1]
        frac = (s - self.cum[k]) / (self.cum[k + 1] - self.cum[k])
        p = lo + frac * (hi - lo)
        for _ in range(50):
            f = self.S(p) - s
            step = f / self.speed(p)
            p_new = np.clip(p - step, lo, hi)
            if np.all(np.abs(p_new - p) <= 1e-15 * np.maximum(1.0, np.abs(p))):
                return p_new
            p = p_new
        return p


# ---- segments ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Segment:
    """A smooth piece of a meridian in the half plane ``r >= 0`` (abstract base).

    Subclasses give :attr:`length`, :attr:`start`, :attr:`end` (exact, an end on the axis has
    ``r = 0.0`` exactly) and :meth:`point` / :meth:`tangent` at local arclength ``s`` in
    ``[0, length]`` measured from :attr:`start`.  ``thickness``: ``None``, a positive number, or a
    callable of the arclength along the whole meridian.
    """

    @property
    def length(self) -> float:
        raise NotImplementedError

    @property
    def start(self) -> tuple[float, float]:
        raise NotImplementedError

    @property
    def end(self) -> tuple[float, float]:
        raise NotImplementedError

    def point(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(r, z)`` at local arclength ``s`` (arrays)."""
        raise NotImplementedError

    def tangent(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Unit tangent ``(t_r, t_z)`` (in the direction of increasing ``s``) at local arclength ``s``."""
        raise NotImplementedError


def _angle_range(name: str, t0: float, t1: float, lo: float, hi: float, where: str) -> None:
    for nm, t in ((f"{name}0", t0), (f"{name}1", t1)):
        if not (lo <= t <= hi):
            raise ValueError(f"{where}: {nm} must be in [{lo!r}, {hi!r}] (r >= 0), got {t!r}")
    if t0 == t1:
        raise ValueError(f"{where}: {name}0 and {name}1 must differ (zero-length segment), got {t0!r} twice")


def _on_axis(c: float, v: float) -> float:
    """``c`` with an exact 0 on the axis (``|angle| = pi/2``)."""
    return 0.0 if abs(v) == _HALF_PI else c


class _CircularArc:
    """What arcs of a circle parametrised by their angle share: the direction of travel, the length,
    the angle at a local arclength and the unit tangent.  ``_radius`` is the circle's radius."""

    theta0: float
    theta1: float

    @property
    def _radius(self) -> float:
        raise NotImplementedError

    @property
    def _sign(self) -> float:
        return 1.0 if self.theta1 > self.theta0 else -1.0

    @property
    def length(self) -> float:
        return self._radius * abs(self.theta1 - self.theta0)

    def angle(self, s: np.ndarray) -> np.ndarray:
        """Angle at local arclength ``s``."""
        return self.theta0 + self._sign * np.asarray(s, dtype=float) / self._radius

    def tangent(self, s):
        t = self.angle(s)
        return -self._sign * np.sin(t), self._sign * np.cos(t)


@dataclass(frozen=True)
class SphericalArc(_CircularArc, Segment):
    """Arc of the circle of radius ``R`` centred on the axis at ``(0, zc)``, from polar angle ``theta0`` to ``theta1``.

    The point at polar angle ``theta`` (from the horizontal, ``[-pi/2, pi/2]``) is
    ``(R cos theta, zc + R sin theta)``; ``theta = pi/2`` is the north pole.  Either direction.
    """

    R: float
    theta0: float
    theta1: float
    zc: float = 0.0
    thickness: object = None

    def __post_init__(self) -> None:
        w = "SphericalArc"
        object.__setattr__(self, "R", _positive("R", self.R, w))
        object.__setattr__(self, "zc", _finite("zc", self.zc, w))
        _angle_range("theta", float(self.theta0), float(self.theta1), -_HALF_PI, _HALF_PI, w)
        object.__setattr__(self, "theta0", float(self.theta0))
        object.__setattr__(self, "theta1", float(self.theta1))
        object.__setattr__(self, "thickness", _check_thickness(self.thickness, w))

    @property
    def _radius(self) -> float:
        return self.R

    @property
    def start(self) -> tuple[float, float]:
        t = self.theta0
        return _on_axis(self.R * math.cos(t), t), self.zc + self.R * math.sin(t)

    @property
    def end(self) -> tuple[float, float]:
        t = self.theta1
        return _on_axis(self.R * math.cos(t), t), self.zc + self.R * math.sin(t)

    def point(self, s):
        t = self.angle(s)
        return np.maximum(self.R * np.cos(t), 0.0), self.zc + self.R * np.sin(t)


@dataclass(frozen=True)
class Cone(Segment):
    """Straight segment from ``(r0, z0)`` to ``(r1, z1)``: a cone, a flat annulus (``z0 == z1``) or a disc (``r1 = 0``)."""

    r0: float
    z0: float
    r1: float
    z1: float
    thickness: object = None

    def __post_init__(self) -> None:
        w = "Cone"
        for nm in ("r0", "z0", "r1", "z1"):
            object.__setattr__(self, nm, _finite(nm, getattr(self, nm), w))
        for nm in ("r0", "r1"):
            if getattr(self, nm) < 0:
                raise ValueError(f"{w}: {nm} must be >= 0 (the half plane r >= 0), got {getattr(self, nm)!r}")
        if self.r0 == self.r1 and self.z0 == self.z1:
            raise ValueError(f"{w}: the two end points coincide (zero-length segment): ({self.r0!r}, {self.z0!r})")
        object.__setattr__(self, "thickness", _check_thickness(self.thickness, w))

    @property
    def length(self) -> float:
        return math.hypot(self.r1 - self.r0, self.z1 - self.z0)

    @property
    def start(self):
        return self.r0, self.z0

    @property
    def end(self):
        return self.r1, self.z1

    def point(self, s):
        u = np.asarray(s, dtype=float) / self.length
        return np.maximum(self.r0 + u * (self.r1 - self.r0), 0.0), self.z0 + u * (self.z1 - self.z0)

    def tangent(self, s):
        L = self.length
        one = np.ones_like(np.asarray(s, dtype=float))
        return one * (self.r1 - self.r0) / L, one * (self.z1 - self.z0) / L


@dataclass(frozen=True)
class TorusArc(_CircularArc, Segment):
    """Arc of the circle of radius ``a`` centred at ``(rc, zc)`` (off the axis), angles ``theta0 -> theta1``.

    The point at angle ``theta`` is ``(rc + a cos theta, zc + a sin theta)``; ``|theta1 - theta0| <= 2 pi``
    and ``r >= 0`` on the whole arc.
    """

    rc: float
    zc: float
    a: float
    theta0: float
    theta1: float
    thickness: object = None

    def __post_init__(self) -> None:
        w = "TorusArc"
        object.__setattr__(self, "a", _positive("a", self.a, w))
        for nm in ("rc", "zc", "theta0", "theta1"):
            object.__setattr__(self, nm, _finite(nm, getattr(self, nm), w))
        if self.theta0 == self.theta1:
            raise ValueError(f"{w}: theta0 and theta1 must differ (zero-length segment), got {self.theta0!r} twice")
        if abs(self.theta1 - self.theta0) > 2 * math.pi:
            raise ValueError(f"{w}: |theta1 - theta0| must be <= 2 pi, got {abs(self.theta1 - self.theta0)!r}")
        lo, hi = sorted((self.theta0, self.theta1))
        k = math.ceil((lo - math.pi) / (2 * math.pi))
        cmin = -1.0 if math.pi + 2 * math.pi * k <= hi else min(math.cos(lo), math.cos(hi))
        rmin = self.rc + self.a * cmin
        if rmin < -JOIN_TOL * (abs(self.rc) + self.a):
            raise ValueError(f"{w}: the arc leaves the half plane r >= 0 (smallest r = {rmin!r}); "
                             f"need rc + a cos(theta) >= 0 over [theta0, theta1]")
        object.__setattr__(self, "thickness", _check_thickness(self.thickness, w))

    @property
    def _radius(self) -> float:
        return self.a

    def _pt(self, t: float):
        r = self.rc + self.a * math.cos(t)
        return (0.0 if abs(r) <= JOIN_TOL * (abs(self.rc) + self.a) else r), self.zc + self.a * math.sin(t)

    @property
    def start(self):
        return self._pt(self.theta0)

    @property
    def end(self):
        return self._pt(self.theta1)

    def point(self, s):
        t = self.angle(s)
        return np.maximum(self.rc + self.a * np.cos(t), 0.0), self.zc + self.a * np.sin(t)


@dataclass(frozen=True)
class EllipseArc(Segment):
    """Arc of the ellipse centred on the axis at ``(0, zc)``, radial semi-axis ``a``, axial semi-axis ``b``.

    Between *parametric* angles ``t0`` and ``t1`` in ``[-pi/2, pi/2]``: the point at ``t`` is
    ``(a cos t, zc + b sin t)`` (``t = pi/2`` is the north pole ``(0, zc + b)``).  The arclength is
    computed by Gauss-Legendre quadrature of ``sqrt(a^2 sin^2 t + b^2 cos^2 t)`` (64 panels, 20
    points each) and inverted by Newton's method, both to round-off.
    """

    a: float
    b: float
    t0: float
    t1: float
    zc: float = 0.0
    thickness: object = None
    _arc: object = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        w = "EllipseArc"
        object.__setattr__(self, "a", _positive("a", self.a, w))
        object.__setattr__(self, "b", _positive("b", self.b, w))
        object.__setattr__(self, "zc", _finite("zc", self.zc, w))
        _angle_range("t", float(self.t0), float(self.t1), -_HALF_PI, _HALF_PI, w)
        object.__setattr__(self, "t0", float(self.t0))
        object.__setattr__(self, "t1", float(self.t1))
        object.__setattr__(self, "thickness", _check_thickness(self.thickness, w))
        a, b = self.a, self.b
        lo, hi = sorted((self.t0, self.t1))
        arc = _ArcLength(lambda t: np.sqrt((a * np.sin(t)) ** 2 + (b * np.cos(t)) ** 2), np.linspace(lo, hi, 65))
        object.__setattr__(self, "_arc", arc)

    @property
    def length(self) -> float:
        return self._arc.length

    @property
    def start(self):
        return _on_axis(self.a * math.cos(self.t0), self.t0), self.zc + self.b * math.sin(self.t0)

    @property
    def end(self):
        return _on_axis(self.a * math.cos(self.t1), self.t1), self.zc + self.b * math.sin(self.t1)

    def angle(self, s):
        """Parametric angle at local arclength ``s``."""
        s = np.asarray(s, dtype=float)
        if self.t1 > self.t0:
            return self._arc.p_at(s)
        return self._arc.p_at(self.length - s)

    def point(self, s):
        t = self.angle(s)
        return np.maximum(self.a * np.cos(t), 0.0), self.zc + self.b * np.sin(t)

    def tangent(self, s):
        t = self.angle(s)
        sg = 1.0 if self.t1 > self.t0 else -1.0
        tr, tz = -self.a * np.sin(t), self.b * np.cos(t)
        n = np.hypot(tr, tz)
        return sg * tr / n, sg * tz / n


@dataclass(frozen=True, eq=False)
class TableProfile(Segment):
    """A tabulated profile: points ``(r_k, z_k)`` along the curve, interpolated smoothly.

    The interpolant is a not-a-knot cubic spline of ``r`` and ``z`` in the cumulative chord length
    of the table (the parameter ``p``); its arclength is computed by Gauss-Legendre quadrature on
    every table interval and inverted by Newton's method.  The table must progress along the curve:
    at least 4 points (3 for a straight table is not useful), no repeated consecutive points, no
    reversal (consecutive chords turning by more than 90 degrees is refused as non-monotone), all
    ``r_k >= 0`` and the spline itself in ``r >= 0`` (checked on 16 points per interval).  An end
    point with ``r`` within ``JOIN_TOL`` of the table's length of the axis (e.g. ``cos(pi/2)``) is
    put on it.
    """

    r_table: np.ndarray
    z_table: np.ndarray
    thickness: object = None
    _spline: object = field(default=None, init=False, repr=False)
    _arc: object = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        w = "TableProfile"
        r = np.array(self.r_table, dtype=float).ravel()
        z = np.array(self.z_table, dtype=float).ravel()
        if r.shape != z.shape:
            raise ValueError(f"{w}: r and z must have the same length, got {r.size} and {z.size}")
        if r.size < 4:
            raise ValueError(f"{w}: the table needs at least 4 points, got {r.size}")
        if not (np.isfinite(r).all() and np.isfinite(z).all()):
            raise ValueError(f"{w}: the table must be finite")
        if np.any(r < 0):
            raise ValueError(f"{w}: r must be >= 0 everywhere (the half plane r >= 0); r[{int(np.argmin(r))}] = {r.min()!r}")
        dr, dz = np.diff(r), np.diff(z)
        chord = np.hypot(dr, dz)
        if np.any(chord == 0):
            k = int(np.flatnonzero(chord == 0)[0])
            raise ValueError(f"{w}: points {k} and {k + 1} coincide (zero-length interval): the table must be monotone along the curve")
        dots = dr[:-1] * dr[1:] + dz[:-1] * dz[1:]
        if np.any(dots <= 0):
            k = int(np.flatnonzero(dots <= 0)[0]) + 1
            raise ValueError(f"{w}: the table is not monotone along the curve: it turns back by 90 degrees or more at point {k}")
        p = np.concatenate([[0.0], np.cumsum(chord)])
        for k in (0, -1):  # an end within round-off of the axis is on it
            if r[k] <= JOIN_TOL * p[-1]:
                r[k] = 0.0
        from scipy.interpolate import CubicSpline  # here: scipy.interpolate imports scipy.optimize, slow to load

        sp = CubicSpline(p, np.stack([r, z], axis=1), bc_type="not-a-knot")
        d = sp.derivative()

        def speed(q):
            v = d(q)
            return np.hypot(v[..., 0], v[..., 1])

        fine = np.linspace(0.0, 1.0, 17)[None, :] * (p[1:] - p[:-1])[:, None] + p[:-1, None]
        rr = sp(fine.ravel())[:, 0]
        scale = max(float(np.max(np.abs(r))), float(np.max(np.abs(z))), float(p[-1]))
        if rr.min() < -JOIN_TOL * scale:
            raise ValueError(f"{w}: the spline through the table leaves the half plane r >= 0 (r = {rr.min()!r}); "
                             f"give more points near the axis")
        r.setflags(write=False)
        z.setflags(write=False)
        object.__setattr__(self, "r_table", r)
        object.__setattr__(self, "z_table", z)
        object.__setattr__(self, "_spline", sp)
        object.__setattr__(self, "_deriv", d)
        object.__setattr__(self, "_arc", _ArcLength(speed, p))
        object.__setattr__(self, "thickness", _check_thickness(self.thickness, w))

    @property
    def length(self) -> float:
        return self._arc.length

    @property
    def start(self):
        return float(self.r_table[0]), float(self.z_table[0])

    @property
    def end(self):
        return float(self.r_table[-1]), float(self.z_table[-1])

    def point(self, s):
        v = self._spline(self._arc.p_at(s))
        return np.maximum(v[..., 0], 0.0), v[..., 1]

    def tangent(self, s):
        v = self._deriv(self._arc.p_at(s))
        n = np.hypot(v[..., 0], v[..., 1])
        return v[..., 0] / n, v[..., 1] / n


# ---- the reference meridian ----------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class ReferenceMeridian:
    """A discretised reference meridian (stress-free shape).  Build it with :func:`meridian` or a constructor.

    Attributes
    ----------
    N : int
        Number of nodes: node 0 the edge (base), node ``N-1`` the pole (or the inner edge of an annulus).
    r, z : ndarray, shape ``(N,)``
        Node coordinates; ``r[-1] = 0`` exactly when :attr:`end_on_axis`, ``r[0] = 0`` exactly when
        :attr:`start_on_axis`.
    s : ndarray, shape ``(N,)``
        Arclength of each node along the smooth curve, from node 0 (for an imperfect meridian, the
        perfect one's arclength stretched edge by edge like the chords, see :func:`with_dimple`).
    theta : ndarray, shape ``(N,)``
        Angle of the smooth curve's outward normal ``(cos theta, sin theta)``: the unit tangent from
        base to pole is ``(-sin theta, cos theta)``.  The polar angle on a spherical cap.  At a
        corner node, the bisector of the two segments' tangents.
    edge_length, edge_radius : ndarray, shape ``(N-1,)``
        Reference chord lengths and edge radii ``(r_i + r_{i+1}) / 2``.
    voronoi_length, node_radius : ndarray, shape ``(N,)``
        Reference Voronoi lengths (half an edge at the two end nodes) and node radii ``r_i``.
    kappa11, kappa22 : ndarray, shape ``(N,)``
        Reference discrete curvatures at nodes ``1 .. N-2`` from ``_generated.bend_curvatures``
        (exactly as :func:`~contin_models.shell.geometry.spherical_cap`), NaN at the two ends.
    thickness : ndarray, shape ``(N,)``, or None
        Node thicknesses when the segments carry one, ``None`` when it is left to the problem.
    length_scale : float
        A characteristic length for normalisation (documented by each constructor).
    end_on_axis, start_on_axis : bool
        Node ``N-1`` (node 0) on the axis.
    segment_of_node : ndarray of int, shape ``(N,)``
        Index of each node's segment (a junction node belongs to the segment that starts there).
    junction_nodes, corner_nodes : ndarray of int
        Nodes at the junctions between segments, and those of them where the tangent turns.
    ring_node : int or None
        The node placed at the requested ring arclength (:func:`meridian`'s ``ring``).
    segments : tuple of Segment
        The segments (of the perfect shape for an imperfect meridian: see :attr:`kind`).
    pole_ratio : float
        Grading ratio used for the node spacing (1: uniform).
    R, phi_hat : float or None
        Sphere radius and polar angle of node 0 for spherical caps and the complete sphere
        (``ReferenceCap`` compatibility), ``None`` otherwise.
    kind : str
        Which constructor built it (``"spherical_cap"``, ``"cone"``, ..., ``"meridian"``), with
        ``"+dimple"`` / ``"+mode"`` appended for imperfect shapes.

    All arrays are read-only.
    """

    N: int
    r: np.ndarray
    z: np.ndarray
    s: np.ndarray
    theta: np.ndarray
    edge_length: np.ndarray
    edge_radius: np.ndarray
    voronoi_length: np.ndarray
    node_radius: np.ndarray
    kappa11: np.ndarray
    kappa22: np.ndarray
    thickness: np.ndarray | None
    length_scale: float
    end_on_axis: bool
    start_on_axis: bool
    segment_of_node: np.ndarray
    junction_nodes: np.ndarray
    corner_nodes: np.ndarray
    ring_node: int | None = None
    segments: tuple = ()
    pole_ratio: float = 1.0
    R: float | None = None
    phi_hat: float | None = None
    kind: str = "meridian"

    @property
    def x(self) -> np.ndarray:
        """Reference state vector ``[r_0, z_0, r_1, z_1, ...]`` (a new array)."""
        return interleave(self.r, self.z)

    @property
    def length(self) -> float:
        """Arclength of the meridian, ``s[-1]``."""
        return float(self.s[-1])

    @property
    def dtheta(self) -> float | None:
        """As ``ReferenceCap.dtheta`` on spherical caps (``None`` when :attr:`phi_hat` is): the edge angle
        ``(pi/2 - phi_hat) / (N - 1)`` on the uniform mesh, the largest one on a graded mesh."""
        if self.phi_hat is None or self.R is None:
            return None
        if self.pole_ratio == 1.0:
            return (0.5 * math.pi - self.phi_hat) / (self.N - 1)
        return float(np.max(np.diff(self.s))) / self.R

    @property
    def alpha(self) -> float | None:
        """Half-opening angle ``pi/2 - phi_hat`` of a spherical cap (``None`` when :attr:`phi_hat` is)."""
        return None if self.phi_hat is None else 0.5 * math.pi - self.phi_hat

    def normals(self) -> tuple[np.ndarray, np.ndarray]:
        """Outward unit normals ``(cos theta, sin theta)`` of the smooth curve at the nodes."""
        return np.cos(self.theta), np.sin(self.theta)


def _readonly(*arrays):
    for a in arrays:
        if a is not None:
            a.setflags(write=False)


def _assemble(r: np.ndarray, z: np.ndarray, **meta) -> ReferenceMeridian:
    """Every reference quantity from the nodes, as :func:`~contin_models.shell.geometry.spherical_cap` computes them."""
    N = r.size
    if np.any((np.diff(r) == 0) & (np.diff(z) == 0)):
        k = int(np.flatnonzero((np.diff(r) == 0) & (np.diff(z) == 0))[0])
        raise ValueError(f"meridian: nodes {k} and {k + 1} coincide (zero-length edge)")
    if np.any(r < 0):
        k = int(np.argmin(r))
        raise ValueError(f"meridian: node {k} has r = {r[k]!r} < 0 (the half plane r >= 0)")
    edge_length, edge_radius, voronoi_length, kappa11, kappa22 = reference_quantities(r, z)
    arrays = dict(s=meta.pop("s"), theta=meta.pop("theta"), thickness=meta.pop("thickness"),
                  segment_of_node=meta.pop("segment_of_node"), junction_nodes=meta.pop("junction_nodes"),
                  corner_nodes=meta.pop("corner_nodes"))
    arrays = {k: (None if v is None else np.array(v, dtype=(int if k.endswith("nodes") or k == "segment_of_node" else float)))
              for k, v in arrays.items()}
    _readonly(r, z, edge_length, edge_radius, voronoi_length, kappa11, kappa22, *arrays.values())
    return ReferenceMeridian(N=N, r=r, z=z, edge_length=edge_length, edge_radius=edge_radius,
                             voronoi_length=voronoi_length, node_radius=r, kappa11=kappa11, kappa22=kappa22,
                             **arrays, **meta)


def _check_N(N, where: str, minimum: int = 3) -> int:
    if isinstance(N, bool) or int(N) != N or N < minimum:
        raise ValueError(f"{where}: N must be an integer >= {minimum}, got {N!r}")
    return int(N)


def _check_pole_ratio(q, where: str) -> float:
    q = float(q)
    if not (0.0 < q <= 1.0):
        raise ValueError(f"{where}: pole_ratio must be in (0, 1], got {q!r}")
    return q


def _allocate(ideal: np.ndarray, total: int, minimum: int = 2) -> np.ndarray:
    """Integers ``>= minimum`` summing to ``total``, close to ``ideal`` (largest remainders)."""
    n = np.maximum(np.floor(ideal).astype(int), minimum)
    while n.sum() < total:
        n[int(np.argmax(ideal - n))] += 1
    while n.sum() > total:
        cand = np.where(n > minimum, ideal - n, np.inf)
        n[int(np.argmin(cand))] -= 1
    return n


def _grading(q: float, width: float, two_poles: bool, ring: tuple | None):
    """The map ``tau -> sigma`` (node-index coordinate to arclength fraction), vectorised, increasing."""
    if q == 1.0:
        def P(tau):
            return np.asarray(tau, dtype=float)
    elif two_poles:
        def P(tau):  # each half graded towards its own pole, uniform (and matched) at the middle
            tau = np.asarray(tau, dtype=float)
            return np.where(tau <= 0.5, 0.5 * grading_map(2.0 * tau, q, width),
                            1.0 - 0.5 * grading_map(2.0 - 2.0 * tau, q, width))
    else:
        def P(tau):
            return 1.0 - grading_map(1.0 - np.asarray(tau, dtype=float), q, width)
    if ring is None:
        return P
    sigma_r, qr, wr = ring

    def Q(tau, c):
        a = (1.0 - qr) * wr
        f = lambda t: t - a * (np.tanh((t - c) / wr) - math.tanh(-c / wr))  # noqa: E731
        return f(np.asarray(tau, dtype=float)) / f(1.0)

    from scipy.optimize import brentq  # here: slow to import (about 0.1 s), and only a ring needs it

    u_r = brentq(lambda u: float(P(u)) - sigma_r, 0.0, 1.0, xtol=1e-16)
    c = brentq(lambda c: float(Q(c, c)) - u_r, 0.0, 1.0, xtol=1e-16)
    return lambda tau: P(Q(tau, c))


def _normal_angle(tr, tz):
    return np.arctan2(-np.asarray(tr), np.asarray(tz))


def meridian(segments: Sequence[Segment], N: int, pole_ratio: float = 1.0, *, width: float = GRADING_WIDTH,
             ring: float | None = None, ring_ratio: float = 0.5, ring_width: float = 0.05,
             thickness=None, length_scale: float | None = None, kind: str = "meridian",
             R: float | None = None, phi_hat: float | None = None) -> ReferenceMeridian:
    """Discretise a chain of segments into a :class:`ReferenceMeridian` with ``N`` nodes.

    Parameters
    ----------
    segments : sequence of Segment
        From the edge (node 0) to the pole (node ``N-1``); consecutive segments must join (gap at
        most ``JOIN_TOL`` times the meridian's size), corners allowed.  A meridian starting on the
        axis must end on it too (a closed shell); otherwise reverse the segments.
    N : int
        Number of nodes, ``>= 2 * len(segments) + 1`` (two edges per segment at least), and ``>= 3``.
    pole_ratio : float
        In ``(0, 1]``: spacing at node ``N-1`` (and at node 0 when both ends are on the axis)
        relative to the spacing elsewhere, with the map of ``geometry.theta_nodes``; 1 (default)
        is uniform in arclength.
    width : float
        Width of the graded zone, a fraction of the meridian (``geometry.GRADING_WIDTH``).
    ring : float, optional
        Arclength from node 0 (strictly inside the meridian) of a ring load: a node is put there
        (:attr:`ReferenceMeridian.ring_node`) and the spacing around it is ``ring_ratio`` times the
        spacing elsewhere, over about ``ring_width`` of the meridian (tanh profile as for the pole).
    thickness : float or callable, optional
        Thickness of every segment that carries none (a callable takes the arclength from node 0).
        Either every segment ends up with a thickness or none does; at a junction node the mean of
        the two segments' values.
    length_scale : float, optional
        Default: the largest node radius (the total arclength if the meridian lies on the axis).
    kind, R, phi_hat :
        Recorded on the result (the constructors set them).

    Returns
    -------
    ReferenceMeridian
    """
    where = "meridian"
    segs = tuple(segments)
    if not segs:
        raise ValueError(f"{where}: segments must be a non-empty sequence of Segment")
    for k, sg in enumerate(segs):
        if not isinstance(sg, Segment):
            raise ValueError(f"{where}: segments[{k}] must be a Segment, got {type(sg).__name__}")
    N = _check_N(N, f"{where} ({len(segs)} segments of at least 2 edges each)", max(3, 2 * len(segs) + 1))
    q = _check_pole_ratio(pole_ratio, where)
    width = _positive("width", width, where)
    thickness = _check_thickness(thickness, where)
    lengths = np.array([sg.length for sg in segs])
    for k, L in enumerate(lengths):
        if not (L > 0 and math.isfinite(L)):
            raise ValueError(f"{where}: segment {k} ({type(segs[k]).__name__}) has length {L!r}; it must be positive")
    ends = np.array([sg.start for sg in segs] + [sg.end for sg in segs])
    size = max(float(np.max(np.abs(ends))), float(lengths.sum()))
    for k in range(len(segs) - 1):
        gap = math.dist(segs[k].end, segs[k + 1].start)
        if gap > JOIN_TOL * size:
            raise ValueError(f"{where}: segment {k + 1} ({type(segs[k + 1]).__name__}) does not start where segment {k} "
                             f"({type(segs[k]).__name__}) ends: gap {gap!r} between {segs[k].end} and {segs[k + 1].start}")
    start_on_axis = segs[0].start[0] == 0.0
    end_on_axis = segs[-1].end[0] == 0.0
    if start_on_axis and not end_on_axis:
        raise ValueError(f"{where}: the meridian starts on the axis but ends off it; node 0 must be the edge: "
                         f"reverse the segments")
    for k in range(len(segs) - 1):
        if segs[k].end[0] == 0.0:
            raise ValueError(f"{where}: segment {k} ends on the axis inside the meridian (only the ends may)")

    S = np.concatenate([[0.0], np.cumsum(lengths)])
    Ltot = float(S[-1])
    ring_spec = None
    if ring is not None:
        ring = float(ring)
        if not (0.0 < ring < Ltot):
            raise ValueError(f"{where}: ring must be an arclength strictly inside (0, {Ltot!r}), got {ring!r}")
        if not (0.0 < ring_ratio <= 1.0):
            raise ValueError(f"{where}: ring_ratio must be in (0, 1], got {ring_ratio!r}")
        ring_width = _positive("ring_width", ring_width, where)
        ring_spec = (ring / Ltot, float(ring_ratio), ring_width)
    g = _grading(q, width, start_on_axis and end_on_axis, ring_spec)

    # breakpoints: junctions (and the ring), in arclength and in node-index coordinate
    brk = list(S)
    ring_at = None
    if ring is not None:
        near = np.abs(S - ring) <= JOIN_TOL * size
        if near.any():
            ring_at = int(np.flatnonzero(near)[0])
        else:
            brk.append(ring)
    brk = np.array(sorted(brk))
    sig = brk / Ltot
    sig[0], sig[-1] = 0.0, 1.0
    if q == 1.0 and ring_spec is None:
        tau = sig  # g is the identity
    else:
        from scipy.optimize import brentq  # here: slow to import, and a single segment needs none

        tau = np.array([0.0] + [brentq(lambda t, sv=sv: float(g(t)) - sv, 0.0, 1.0, xtol=1e-16)
                                for sv in sig[1:-1]] + [1.0])
    counts = _allocate(np.diff(tau) * (N - 1), N - 1)
    s_nodes = []
    for k, n in enumerate(counts):
        t = tau[k] + (tau[k + 1] - tau[k]) * np.arange(n) / n
        sk = g(t) * Ltot
        sk[0] = brk[k]
        s_nodes.append(sk)
    s_nodes.append(np.array([Ltot]))
    s = np.concatenate(s_nodes)
    brk_node = np.concatenate([[0], np.cumsum(counts)])  # node index of each breakpoint
    junction_nodes = np.array([int(brk_node[np.flatnonzero(brk == S[k])[0]]) for k in range(1, len(segs))], dtype=int)
    ring_node = None
    if ring is not None:
        ring_node = int(junction_nodes[ring_at - 1]) if ring_at is not None else int(brk_node[np.flatnonzero(brk == ring)[0]])

    # each piece lies in one segment: the one that starts at or before the piece's start
    piece_seg = np.clip(np.searchsorted(S, brk[:-1], side="right") - 1, 0, len(segs) - 1)
    seg_of = np.concatenate([np.repeat(piece_seg, counts), [len(segs) - 1]])
    r = np.empty(N)
    z = np.empty(N)
    tr = np.empty(N)
    tz = np.empty(N)
    for k, sg in enumerate(segs):
        m = seg_of == k
        loc = np.clip(s[m] - S[k], 0.0, lengths[k])
        r[m], z[m] = sg.point(loc)
        tr[m], tz[m] = sg.tangent(loc)
    # exact end points and junctions
    r[0], z[0] = segs[0].start
    r[-1], z[-1] = segs[-1].end
    theta = _normal_angle(tr, tz)
    corners = []
    for k, i in enumerate(junction_nodes):
        r[i], z[i] = segs[k].end
        a_r, a_z = segs[k].tangent(np.array([lengths[k]]))
        b_r, b_z = segs[k + 1].tangent(np.array([0.0]))
        turn = math.atan2(float(a_r[0] * b_z[0] - a_z[0] * b_r[0]), float(a_r[0] * b_r[0] + a_z[0] * b_z[0]))
        if abs(turn) > CORNER_TOL:
            corners.append(int(i))
        ta = float(_normal_angle(a_r, a_z)[0])
        theta[i] = ta + 0.5 * turn
    # keep theta continuous through the corners' bisectors
    theta = np.concatenate([[theta[0]], theta[0] + np.cumsum((np.diff(theta) + math.pi) % (2 * math.pi) - math.pi)])

    # thickness
    has = [sg.thickness is not None or thickness is not None for sg in segs]
    if any(has) and not all(has):
        missing = [k for k, hv in enumerate(has) if not hv]
        raise ValueError(f"{where}: segments {missing} carry no thickness while others do; give every segment one "
                         f"(or the thickness argument)")
    h_nodes = None
    if all(has):
        def seg_h(k, sv):
            t = segs[k].thickness if segs[k].thickness is not None else thickness
            v = np.asarray(t(sv), dtype=float) if callable(t) else np.full(np.shape(sv), float(t))
            return np.broadcast_to(v, np.shape(sv)).astype(float)
        h_nodes = np.empty(N)
        for k in range(len(segs)):
            m = seg_of == k
            h_nodes[m] = seg_h(k, s[m])
        for k, i in enumerate(junction_nodes):
            h_nodes[i] = 0.5 * (seg_h(k, s[i:i + 1])[0] + seg_h(k + 1, s[i:i + 1])[0])
        if not (np.isfinite(h_nodes).all() and np.all(h_nodes > 0)):
            k = int(np.flatnonzero(~(h_nodes > 0) | ~np.isfinite(h_nodes))[0])
            raise ValueError(f"{where}: thickness must be positive and finite at every node; node {k} has {h_nodes[k]!r}")

    if length_scale is None:
        length_scale = float(np.max(r)) if np.max(r) > 0 else Ltot
    length_scale = _positive("length_scale", length_scale, where)
    return _assemble(r, z, s=s, theta=theta, thickness=h_nodes, segment_of_node=seg_of, junction_nodes=junction_nodes,
                     corner_nodes=np.array(corners, dtype=int), ring_node=ring_node, segments=segs, pole_ratio=q,
                     length_scale=length_scale, end_on_axis=end_on_axis, start_on_axis=start_on_axis, kind=kind,
                     R=R, phi_hat=phi_hat)


# ---- constructors --------------------------------------------------------------------------------
def _node_thickness(thickness, s: np.ndarray, where: str):
    thickness = _check_thickness(thickness, where)
    if thickness is None:
        return None
    h = np.asarray(thickness(s), dtype=float) if callable(thickness) else np.full(s.shape, thickness)
    h = np.broadcast_to(h, s.shape).astype(float)
    if not (np.isfinite(h).all() and np.all(h > 0)):
        raise ValueError(f"{where}: thickness must be positive and finite at every node")
    return h


def spherical_cap_meridian(R: float, phi_hat: float, N: int, pole_ratio: float = POLE_RATIO, *,
                           thickness=None) -> ReferenceMeridian:
    """The spherical cap of :func:`~contin_models.shell.geometry.spherical_cap` as a meridian.

    Node positions are those of ``spherical_cap(R, phi_hat, N, pole_ratio)`` bit for bit (same
    ``theta_nodes`` angles, same formulas), and so are every reference quantity.  ``phi_hat`` may be
    in ``(-pi/2, pi/2)`` here: 0 is the hemisphere, negative values caps beyond it.
    ``length_scale = R``; ``theta`` the polar angles; ``s = R (theta - phi_hat)``.
    """
    where = "spherical_cap_meridian"
    R = _positive("R", R, where)
    phi_hat = float(phi_hat)
    if not (-_HALF_PI < phi_hat < _HALF_PI):
        raise ValueError(f"{where}: phi_hat must be in (-pi/2, pi/2), got {phi_hat!r}")
    N = _check_N(N, where)
    q = _check_pole_ratio(pole_ratio, where)
    theta = theta_nodes(phi_hat, N, q)
    r = R * np.cos(theta)
    z = R * np.sin(theta)
    r[-1], z[-1] = 0.0, R
    s = R * (theta - phi_hat)
    s[0] = 0.0
    seg = SphericalArc(R, phi_hat, _HALF_PI, thickness=_check_thickness(thickness, where))
    return _assemble(r, z, s=s, theta=theta.copy(), thickness=_node_thickness(thickness, s, where),
                     segment_of_node=np.zeros(N, dtype=int), junction_nodes=np.zeros(0, dtype=int),
                     corner_nodes=np.zeros(0, dtype=int), segments=(seg,), pole_ratio=q, length_scale=R,
                     end_on_axis=True, start_on_axis=False, kind="spherical_cap", R=R, phi_hat=phi_hat)


def complete_sphere_meridian(R: float, N: int, pole_ratio: float = POLE_RATIO, *, thickness=None) -> ReferenceMeridian:
    """A complete sphere: node 0 at the south pole ``(0, -R)``, node ``N-1`` at the north pole ``(0, R)``.

    Centre at the origin; grading towards both poles, mirror-symmetric about the equator exactly
    (``r_i = r_{N-1-i}``, ``z_i = -z_{N-1-i}``).  ``start_on_axis = end_on_axis = True``,
    ``length_scale = R``, ``phi_hat = -pi/2`` (the polar angle of node 0).  ``N >= 5``.
    """
    where = "complete_sphere_meridian"
    R = _positive("R", R, where)
    N = _check_N(N, where, 5)
    m = meridian([SphericalArc(R, -_HALF_PI, _HALF_PI, thickness=_check_thickness(thickness, where))], N, pole_ratio,
                 length_scale=R, kind="complete_sphere", R=R, phi_hat=-_HALF_PI)
    r, z, s, th = m.r.copy(), m.z.copy(), m.s.copy(), m.theta.copy()
    half = N // 2
    r[N - half:] = r[:half][::-1]
    z[N - half:] = -z[:half][::-1]
    s[N - half:] = math.pi * R - s[:half][::-1]
    th[N - half:] = -th[:half][::-1]
    if N % 2:
        z[half] = 0.0
        th[half] = 0.0
    h = None if m.thickness is None else _node_thickness(thickness, s, where)
    return _assemble(r, z, s=s, theta=th, thickness=h, segment_of_node=m.segment_of_node, junction_nodes=m.junction_nodes,
                     corner_nodes=m.corner_nodes, segments=m.segments, pole_ratio=m.pole_ratio, length_scale=R,
                     end_on_axis=True, start_on_axis=True, kind="complete_sphere", R=R, phi_hat=-_HALF_PI)


def cone_meridian(base_radius: float, N: int, *, height: float | None = None, half_angle: float | None = None,
                  pole_ratio: float = POLE_RATIO, z_base: float = 0.0, thickness=None) -> ReferenceMeridian:
    """A cone from its base ring ``(base_radius, z_base)`` (node 0) to its apex on the axis (node ``N-1``).

    Give the apex ``height`` above the base (negative: apex below), or the apex ``half_angle``
    from the axis in ``(0, pi/2]`` (apex above the base; ``pi/2`` is a flat disc).
    ``length_scale = base_radius``.
    """
    where = "cone_meridian"
    a = _positive("base_radius", base_radius, where)
    if (height is None) == (half_angle is None):
        raise ValueError(f"{where}: give exactly one of height and half_angle")
    if height is None:
        ha = float(half_angle)
        if not (0.0 < ha <= _HALF_PI):
            raise ValueError(f"{where}: half_angle must be in (0, pi/2], got {half_angle!r}")
        height = 0.0 if ha == _HALF_PI else a / math.tan(ha)
    height = _finite("height", height, where)
    zb = _finite("z_base", z_base, where)
    return meridian([Cone(a, zb, 0.0, zb + height)], N, pole_ratio, thickness=thickness, length_scale=a, kind="cone")


def plate_meridian(a: float, N: int, pole_ratio: float = POLE_RATIO, *, z: float = 0.0, thickness=None) -> ReferenceMeridian:
    """A flat disc of radius ``a`` at height ``z``: edge at node 0, centre (on the axis) at node ``N-1``.  ``length_scale = a``."""
    where = "plate_meridian"
    a = _positive("a", a, where)
    z = _finite("z", z, where)
    return meridian([Cone(a, z, 0.0, z)], N, pole_ratio, thickness=thickness, length_scale=a, kind="plate")


def annulus_meridian(a_outer: float, a_inner: float, N: int, *, z: float = 0.0, thickness=None) -> ReferenceMeridian:
    """A flat annulus: outer edge (node 0) to inner edge (node ``N-1``, off the axis), uniform.  ``length_scale = a_outer``."""
    where = "annulus_meridian"
    ao = _positive("a_outer", a_outer, where)
    ai = _positive("a_inner", a_inner, where)
    if not ai < ao:
        raise ValueError(f"{where}: a_inner must be in (0, a_outer = {ao!r}), got {ai!r}")
    z = _finite("z", z, where)
    return meridian([Cone(ao, z, ai, z)], N, 1.0, thickness=thickness, length_scale=ao, kind="annulus")


def torus_meridian(rc: float, zc: float, a: float, theta0: float, theta1: float, N: int, pole_ratio: float = 1.0, *,
                   thickness=None) -> ReferenceMeridian:
    """One :class:`TorusArc` (centre ``(rc, zc)``, radius ``a``, angles ``theta0 -> theta1``).  ``length_scale = a``."""
    return meridian([TorusArc(rc, zc, a, theta0, theta1)], N, pole_ratio, thickness=thickness,
                    length_scale=_positive("a", a, "torus_meridian"), kind="torus")


def ellipsoid_cap_meridian(a: float, b: float, t_edge: float, N: int, pole_ratio: float = POLE_RATIO, *,
                           thickness=None) -> ReferenceMeridian:
    """Cap of the spheroid with radial semi-axis ``a`` and axial semi-axis ``b`` (centre at the origin).

    From the edge at parametric angle ``t_edge`` in ``[-pi/2, pi/2)`` (the point ``(a cos t_edge,
    b sin t_edge)``) to the pole ``(0, b)``.  ``length_scale = a^2 / b``, the meridional radius of
    curvature at the pole (so that :func:`with_dimple`'s ``beta`` is the pole's local polar angle);
    ``a = b`` is the spherical cap with ``R = a``.
    """
    where = "ellipsoid_cap_meridian"
    a = _positive("a", a, where)
    b = _positive("b", b, where)
    t = float(t_edge)
    if not (-_HALF_PI < t < _HALF_PI):
        raise ValueError(f"{where}: t_edge must be in (-pi/2, pi/2), got {t_edge!r}")
    return meridian([EllipseArc(a, b, t, _HALF_PI)], N, pole_ratio, thickness=thickness, length_scale=a * a / b,
                    kind="ellipsoid_cap")


def table_meridian(r, z, N: int, pole_ratio: float = 1.0, *, thickness=None,
                   length_scale: float | None = None) -> ReferenceMeridian:
    """A tabulated profile (:class:`TableProfile`), from the edge (first point) to the pole (last point).

    ``length_scale`` defaults to the largest node radius.
    """
    return meridian([TableProfile(np.asarray(r, dtype=float), np.asarray(z, dtype=float))], N, pole_ratio,
                    thickness=thickness, length_scale=length_scale, kind="table")


# ---- imperfections -------------------------------------------------------------------------------
def dimple_width(lambda_I: float, R: float, h: float, nu: float) -> float:
    """``beta0 = lambda_I / ((12 (1 - nu^2))^(1/4) sqrt(R / h))`` (``docs/model.md#imperfections``)."""
    where = "dimple_width"
    lam = _positive("lambda_I", lambda_I, where)
    R = _positive("R", R, where)
    h = _positive("h", h, where)
    if not (-1.0 < nu < 1.0):
        raise ValueError(f"{where}: nu must be in (-1, 1), got {nu!r}")
    return lam / ((12.0 * (1.0 - nu * nu)) ** 0.25 * math.sqrt(R / h))


def _displaced(m: ReferenceMeridian, dr: np.ndarray, dz: np.ndarray, tag: str) -> ReferenceMeridian:
    """A new reference meridian with the nodes moved by ``(dr, dz)``; every quantity recomputed.

    ``s`` is the old one stretched edge by edge in the ratio of the new to the old chords, and
    ``theta`` turned by the mean rotation of the node's chords (the one chord at the ends): both
    follow the smooth curve to the order of the discretisation (an end on the axis keeps its
    ``theta``: the moved shape is still smooth across the axis).
    """
    r = m.r + dr
    z = m.z + dz
    if m.end_on_axis:
        r[-1] = 0.0
    if m.start_on_axis:
        r[0] = 0.0
    er0, ez0 = np.diff(m.r), np.diff(m.z)
    er1, ez1 = np.diff(r), np.diff(z)
    l1 = np.hypot(er1, ez1)
    if np.any(l1 == 0):
        raise ValueError(f"{tag}: the displacement makes two nodes coincide")
    rot = np.arctan2(er0 * ez1 - ez0 * er1, er0 * er1 + ez0 * ez1)  # chord rotations
    node_rot = np.empty(m.N)
    node_rot[0], node_rot[-1] = rot[0], rot[-1]
    node_rot[1:-1] = 0.5 * (rot[:-1] + rot[1:])
    # an end on the axis keeps its normal along the axis (the shape stays smooth across the axis)
    if m.end_on_axis:
        node_rot[-1] = 0.0
    if m.start_on_axis:
        node_rot[0] = 0.0
    s = np.concatenate([[0.0], np.cumsum(np.diff(m.s) * l1 / m.edge_length)])
    h = None if m.thickness is None else m.thickness.copy()
    return _assemble(r, z, s=s, theta=m.theta + node_rot, thickness=h, segment_of_node=m.segment_of_node,
                     junction_nodes=m.junction_nodes, corner_nodes=m.corner_nodes, ring_node=m.ring_node,
                     segments=m.segments, pole_ratio=m.pole_ratio, length_scale=m.length_scale,
                     end_on_axis=m.end_on_axis, start_on_axis=m.start_on_axis, kind=m.kind + tag,
                     R=m.R, phi_hat=m.phi_hat)


def with_dimple(m: ReferenceMeridian, delta: float, beta0: float | None = None, *, lambda_I: float | None = None,
                R: float | None = None, h: float | None = None, nu: float | None = None) -> ReferenceMeridian:
    """A Gaussian dimple at the pole (``docs/model.md#imperfections``), as a new stress-free reference.

    Each node moves along the smooth curve's normal by ``w_I(beta) = -delta exp(-(beta / beta0)^2)``
    (outward positive, so ``delta > 0`` pushes the pole in, towards the centre, decreasing the
    rise), with ``beta = (s_pole - s) / length_scale`` the arclength from the pole over the length
    scale: on a spherical cap (``length_scale = R``) exactly the polar angle from the pole; on
    another meridian the polar angle of the osculating sphere when ``length_scale`` is the pole's
    radius of curvature (as for :func:`ellipsoid_cap_meridian`).  The pole moves by exactly
    ``delta`` along the axis and stays on it; node 0 is held (the support stays where it was; the
    Gaussian's tail there, ``delta exp(-(beta_edge / beta0)^2)``, is dropped).

    Parameters
    ----------
    m : ReferenceMeridian
        Perfect shape, ending on the axis.
    delta : float
        Depth (any sign; 0 gives back the same nodes).
    beta0 : float, optional
        Angular width; or give ``lambda_I`` with ``h`` and ``nu`` (and ``R``, default
        ``m.length_scale``): ``beta0 = lambda_I / ((12 (1 - nu^2))^(1/4) sqrt(R/h))``.
    """
    where = "with_dimple"
    if not isinstance(m, ReferenceMeridian):
        raise ValueError(f"{where}: m must be a ReferenceMeridian, got {type(m).__name__}")
    if not m.end_on_axis:
        raise ValueError(f"{where}: the meridian must end on the axis (a pole at node N-1)")
    delta = _finite("delta", delta, where)
    if (beta0 is None) == (lambda_I is None):
        raise ValueError(f"{where}: give exactly one of beta0 and lambda_I")
    if beta0 is None:
        if h is None or nu is None:
            raise ValueError(f"{where}: lambda_I needs h and nu (and R, default the meridian's length_scale)")
        beta0 = dimple_width(lambda_I, m.length_scale if R is None else R, h, nu)
    beta0 = _positive("beta0", beta0, where)
    beta = (m.s[-1] - m.s) / m.length_scale
    w = -delta * np.exp(-(beta / beta0) ** 2)  # outward
    nr, nz = m.normals()
    dr, dz = w * nr, w * nz
    dr[-1], dz[-1] = 0.0, -delta * math.copysign(1.0, float(nz[-1]))  # along the axis, inward
    dr[0] = dz[0] = 0.0
    return _displaced(m, dr, dz, "+dimple")


def with_mode(m: ReferenceMeridian, mode, delta: float, *, normalize: str = "normal") -> ReferenceMeridian:
    """The meridian plus a displacement field ``mode`` (full interleaved state, e.g. a buckling mode), scaled.

    Parameters
    ----------
    mode : array, shape ``(2 N,)``
        ``[dr_0, dz_0, dr_1, dz_1, ...]``.  Its ``r`` entry must vanish (``<= 1e-12`` of its largest
        entry, then set to 0 exactly) at a node on the axis.
    delta : float
        Amplitude.  ``normalize="normal"``: the node with the largest normal component
        ``|mode . n|`` (``n`` the smooth curve's outward normal) moves inward (towards the centre of
        curvature side, ``-n``) by ``delta``; ``normalize="pole"``: the pole moves inward along the
        axis (``-n``, i.e. down at a north pole) by ``delta``.
    """
    where = "with_mode"
    if not isinstance(m, ReferenceMeridian):
        raise ValueError(f"{where}: m must be a ReferenceMeridian, got {type(m).__name__}")
    mode = np.array(mode, dtype=float)
    if mode.shape != (2 * m.N,):
        raise ValueError(f"{where}: mode must have shape ({2 * m.N},), got {mode.shape}")
    if not np.isfinite(mode).all():
        raise ValueError(f"{where}: mode must be finite")
    delta = _finite("delta", delta, where)
    big = float(np.max(np.abs(mode)))
    if big == 0:
        raise ValueError(f"{where}: mode is zero")
    for node, flag in ((m.N - 1, m.end_on_axis), (0, m.start_on_axis)):
        if flag:
            if abs(mode[2 * node]) > 1e-12 * big:
                raise ValueError(f"{where}: node {node} is on the axis, so mode[{2 * node}] (its r) must be 0, "
                                 f"got {mode[2 * node]!r}")
            mode[2 * node] = 0.0
    dr, dz = mode[0::2], mode[1::2]
    nr, nz = m.normals()
    wn = dr * nr + dz * nz
    if normalize == "normal":
        k = int(np.argmax(np.abs(wn)))
    elif normalize == "pole":
        if not m.end_on_axis:
            raise ValueError(f"{where}: normalize='pole' needs a meridian ending on the axis")
        k = m.N - 1
    else:
        raise ValueError(f"{where}: normalize must be 'normal' or 'pole', got {normalize!r}")
    if wn[k] == 0:
        raise ValueError(f"{where}: the mode has no normal component at node {k}")
    c = -delta / wn[k]
    return _displaced(m, c * dr, c * dz, "+mode")
