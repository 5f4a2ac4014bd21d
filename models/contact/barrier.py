"""Log-barrier contact between the shell's nodes and a rigid indenter (paper section 3(b)).

Barrier
-------
Every shell node ``i`` at distance ``d_i`` from the indenter surface carries the energy
(``docs/physics.md`` eq. 3.16)::

    W(d) = -K_c (d - dhat)^2 log(d / dhat)   for 0 < d < dhat,    0 for d >= dhat,

C2 at ``d = dhat`` and ``+inf`` as ``d -> 0+``.  Only the *active* nodes (``d_i < dhat``) are
evaluated; the kernels and their exact derivatives come from :mod:`models.contact._generated`
(emitted by ``python -m models.contact.codegen``).  The contact is frictionless: the barrier only
depends on the distance.

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
* ``E(x, c) = sum_i W(d_i)`` is the total barrier energy; ``x`` is the interleaved full state
  ``[r_0, z_0, ..., r_{N-1}, z_{N-1}]`` of the shell.
* ``-dE/dx`` is the contact force on the nodes (pointing away from the indenter); the barrier
  adds ``+dE/dx`` to the shell's residual (the gradient of the total energy).
* The contact force is ``F = -dE/dc = dE/dw_b``: the (downward) load the indenter transmits to the
  shell, equal to the upward reaction the shell exerts on the indenter.  A pushing indenter has
  ``F > 0`` (``W' < 0`` and ``dd/dc > 0`` for both shapes).  ``F = 0`` when no node is within
  ``dhat``.

Hessian layout
--------------
Each node's barrier depends on its own ``(r_i, z_i)`` and ``c`` only, so the Hessian with respect
to ``x`` is block diagonal with one 2x2 block ``[[W_rr, W_rz], [W_rz, W_zz]]`` per active node on
the diagonal: it fits inside the shell's band without changing it
(:meth:`ContactState.hessian_triplets` gives global ``(row, col, value)`` entries).  The border
column ``d2E/dx dc`` (:attr:`ContactState.hess_xc`, length ``2N``) and ``d2E/dc2``
(:attr:`ContactState.hess_cc`) complete the Jacobian for displacement control (``df/dp``) and for
force control (the indenter position as an extra unknown).

Step filter
-----------
:meth:`ContactBarrier.max_safe_fraction` returns the largest fraction of a step ``(dx, dc)`` that
keeps every node strictly outside the indenter along the whole segment (incremental-potential
contact's filter), times a safety factor; it considers all nodes, not only the active ones.

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
Near ``d = dhat``, ``-W'(dhat (1 - eps)) = 3 K_c dhat eps^2 (1 + O(eps))``: a node carrying a
load ``f`` sits at ``d = dhat (1 - eps)`` with ``eps = sqrt(f / (3 K_c dhat))``.  With the paper's
constants (``K_c dhat = 1e5`` N/m at ``E = 1 MPa``, ``R = 1 m``) and shell forces of order
``2 pi D`` (about 5 N for ``h/R = 0.02``), ``eps`` is a few 1e-3: the contact acts at a gap of
almost exactly ``dhat``, so the indenter travel measured from geometric first contact carries an
offset of about ``dhat`` (``1e-3 R``).  Measuring it from the position where the barrier switches
on (gap ``dhat`` at the pole) removes that offset to first order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from . import _generated as gen

__all__ = ["Sphere", "Plate", "ContactBarrier", "ContactState", "default_barrier", "barrier_value",
           "PAPER_K", "PAPER_DHAT", "PAPER_E", "PAPER_R"]

#: The paper's barrier constants and the modulus and radius they were chosen for.
PAPER_K, PAPER_DHAT, PAPER_E, PAPER_R = 1e8, 1e-3, 1e6, 1.0


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


@dataclass
class ContactState:
    """Barrier energy and exact derivatives at one state (from :meth:`ContactBarrier.evaluate`).

    Attributes
    ----------
    position : float
        The indenter position ``c`` (``zc`` or ``zp``).
    distances : ndarray, shape ``(N,)``
        ``d_i`` of every node (all ``> 0``).
    active : ndarray of int, shape ``(m,)``
        Indices of the nodes with ``d_i < dhat``, increasing.
    energy : float
        ``E = sum_i W(d_i)``.
    gradient : ndarray, shape ``(2N,)``
        ``dE/dx`` (interleaved; zero outside the active nodes).
    dE_dc : float
        ``dE/dc`` (``<= 0`` for a pushing indenter).
    node_energy : ndarray, shape ``(m,)``
        ``W(d_i)`` of the active nodes.
    node_force : ndarray, shape ``(m,)``
        ``-dW_i/dc`` of the active nodes: each node's share of :attr:`force` (``>= 0``).
    hess_blocks : ndarray, shape ``(m, 2, 2)`` or None
        ``d2E / d(r_i, z_i)^2`` of each active node (None when evaluated without Hessian).
    hess_xc : ndarray, shape ``(2N,)`` or None
        ``d2E / dx dc`` (interleaved; zero outside the active nodes).
    hess_cc : float or None
        ``d2E / dc^2``.
    """

    position: float
    distances: np.ndarray
    active: np.ndarray
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
        """Number of nodes within ``dhat`` of the indenter."""
        return int(self.active.size)

    def force_gradient(self) -> tuple[np.ndarray, float]:
        """``(dF/dx, dF/dc) = (-d2E/dx dc, -d2E/dc2)`` (needs the Hessian)."""
        self._need_hessian()
        return -self.hess_xc, -float(self.hess_cc)

    def _need_hessian(self) -> None:
        if self.hess_blocks is None:
            raise ValueError("ContactState: evaluated without the Hessian (use hessian=True)")

    def hessian_triplets(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Global entries of ``d2E/dx2``: the 2x2 block of each active node, full (both triangles).

        Returns
        -------
        rows, cols : ndarray of int, shape ``(4 m,)``
            Indices into the interleaved state: per active node ``i``, in this order,
            ``(2i, 2i), (2i, 2i+1), (2i+1, 2i), (2i+1, 2i+1)``.
        values : ndarray, shape ``(4 m,)``
        """
        self._need_hessian()
        base = 2 * self.active
        rows = (base[:, None] + np.array([0, 0, 1, 1])).ravel()
        cols = (base[:, None] + np.array([0, 1, 0, 1])).ravel()
        return rows, cols, self.hess_blocks.reshape(-1).copy()

    def hessian_matrix(self) -> sp.csr_matrix:
        """``d2E/dx2`` as a ``2N x 2N`` CSR matrix (block diagonal, only the active nodes' blocks)."""
        n = self.gradient.size
        rows, cols, vals = self.hessian_triplets()
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))


class ContactBarrier:
    """Log-barrier contact of the shell's nodes with a rigid indenter (eq. 3.16).

    Parameters
    ----------
    indenter : Sphere or Plate
        Shape of the indenter.
    K : float
        Barrier stiffness ``K_c > 0`` (energy / length^2).
    dhat : float
        Barrier width ``dhat > 0`` (length): nodes farther than ``dhat`` feel nothing.

    Notes
    -----
    See the module docstring for the sign conventions (``F = -dE/dc > 0`` when pushing) and the
    Hessian layout.  No method ever returns NaN or inf: a state with a node at ``d <= 0`` (or a
    non-finite state) raises :class:`ValueError` naming the node and its distance.

    Examples
    --------
    >>> K, dhat = default_barrier(E=1e6, R=1.0)
    >>> contact = ContactBarrier(Sphere(0.5), K, dhat)
    >>> x = np.array([0.0, 1.0])              # one node on the axis at z = 1
    >>> st = contact.evaluate(x, 1.5 + 0.5 * dhat)
    >>> st.active.tolist(), st.force > 0
    ([0], True)
    """

    def __init__(self, indenter: Sphere | Plate, K: float, dhat: float) -> None:
        if not isinstance(indenter, (Sphere, Plate)):
            raise TypeError(f"ContactBarrier: indenter must be a Sphere or a Plate, got {indenter!r}")
        K, dhat = float(K), float(dhat)
        if not (K > 0 and math.isfinite(K)):
            raise ValueError(f"ContactBarrier: K must be a positive number, got {K!r}")
        if not (dhat > 0 and math.isfinite(dhat)):
            raise ValueError(f"ContactBarrier: dhat must be a positive number, got {dhat!r}")
        self.indenter = indenter
        self.K = K
        self.dhat = dhat
        self._params = indenter.params
        self._distance = getattr(gen, f"{indenter.name}_distance")
        self._energy = getattr(gen, f"{indenter.name}_energy")
        self._derivatives = getattr(gen, f"{indenter.name}_derivatives")
        self._gradient = getattr(gen, f"{indenter.name}_gradient")

    @classmethod
    def for_shell(cls, indenter: Sphere | Plate, E: float, R: float,
                  dhat_over_R: float = PAPER_DHAT / PAPER_R) -> ContactBarrier:
        """A barrier with the constants of :func:`default_barrier` for modulus ``E`` and radius ``R``."""
        K, dhat = default_barrier(E, R, dhat_over_R)
        return cls(indenter, K, dhat)

    # ---- distances and checks ---------------------------------------------------------------------
    @staticmethod
    def _state(x, what: str = "x") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x = np.asarray(x, dtype=float)
        if x.ndim != 1 or x.size % 2:
            raise ValueError(f"ContactBarrier: {what} must be the interleaved state [r_0, z_0, ...] "
                             f"of even length, got shape {x.shape}")
        if not np.all(np.isfinite(x)):
            bad = int(np.flatnonzero(~np.isfinite(x))[0])
            raise ValueError(f"ContactBarrier: {what} is not finite (entry {bad} = {x[bad]!r})")
        return x, x[0::2], x[1::2]

    @staticmethod
    def _position(c, what: str = "c") -> float:
        c = float(c)
        if not math.isfinite(c):
            raise ValueError(f"ContactBarrier: indenter position {what} = {c!r} is not finite")
        return c

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
        return self._distance(r, z, self._position(c), *self._params, self.K, self.dhat)

    def _checked_distances(self, r: np.ndarray, z: np.ndarray, c: float) -> np.ndarray:
        d = self._distance(r, z, c, *self._params, self.K, self.dhat)
        if not np.all(d > 0):
            bad = np.flatnonzero(~(d > 0))
            i = int(bad[np.argmin(d[bad])]) if np.all(np.isfinite(d[bad])) else int(bad[0])
            raise ValueError(
                f"ContactBarrier: node {i} at (r, z) = ({r[i]:.17g}, {z[i]:.17g}) is not outside the "
                f"{self.indenter.name} indenter at c = {c:.17g}: distance d = {d[i]:.6g} <= 0 "
                f"({bad.size} node(s) with d <= 0); the barrier is infinite there")
        return d

    def check(self, x, c: float) -> np.ndarray:
        """Distances of every node, raising :class:`ValueError` if any node has ``d <= 0``.

        Returns
        -------
        ndarray, shape ``(N,)``
        """
        _, r, z = self._state(x)
        return self._checked_distances(r, z, self._position(c))

    def active_set(self, x, c: float) -> np.ndarray:
        """Indices of the nodes within ``dhat`` of the indenter (after :meth:`check`)."""
        return np.flatnonzero(self.check(x, c) < self.dhat)

    # ---- energy and derivatives -------------------------------------------------------------------
    def energy(self, x, c: float) -> float:
        """Total barrier energy ``E(x, c)`` (raises :class:`ValueError` if a node has ``d <= 0``)."""
        _, r, z = self._state(x)
        c = self._position(c)
        d = self._checked_distances(r, z, c)
        act = np.flatnonzero(d < self.dhat)
        if act.size == 0:
            return 0.0
        return float(np.sum(self._energy(r[act], z[act], c, *self._params, self.K, self.dhat)))

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
            Interleaved state ``[r_0, z_0, ..., r_{N-1}, z_{N-1}]``.
        c : float
            Indenter position (``zc`` for a sphere, ``zp`` for a plate).
        hessian : bool
            Also compute the 2x2 node blocks, ``d2E/dx dc`` and ``d2E/dc2``.

        Returns
        -------
        ContactState

        Raises
        ------
        ValueError
            If ``x`` or ``c`` is not finite or a node has ``d <= 0`` (the message names the node
            with the smallest distance).
        """
        x, r, z = self._state(x)
        c = self._position(c)
        d = self._checked_distances(r, z, c)
        act = np.flatnonzero(d < self.dhat)
        n = x.size
        grad = np.zeros(n)
        if act.size == 0:
            empty = np.zeros(0)
            st = ContactState(c, d, act, 0.0, grad, 0.0, empty, empty)
            if hessian:
                st.hess_blocks, st.hess_xc, st.hess_cc = np.zeros((0, 2, 2)), np.zeros(n), 0.0
            return st
        ra, za = r[act], z[act]
        if hessian:
            e, g, h = self._derivatives(ra, za, c, *self._params, self.K, self.dhat)
        else:
            e, g = self._energy(ra, za, c, *self._params, self.K, self.dhat), \
                self._gradient(ra, za, c, *self._params, self.K, self.dhat)
        if not (np.all(np.isfinite(g)) and (not hessian or np.all(np.isfinite(h)))):
            # only for d so small (d / dhat < ~1e-150) that W'' overflows; never return inf
            bad = int(act[np.argmin(d[act])])
            raise ValueError(f"ContactBarrier: node {bad} is too close to the {self.indenter.name} indenter "
                             f"(d = {d[bad]:.6g}): the barrier derivatives overflow")
        grad[2 * act] = g[0]
        grad[2 * act + 1] = g[1]
        st = ContactState(c, d, act, float(np.sum(e)), grad, float(np.sum(g[2])), e, -g[2])
        if hessian:
            blocks = np.empty((act.size, 2, 2))
            blocks[:, 0, 0] = h[0]
            blocks[:, 0, 1] = blocks[:, 1, 0] = h[1]
            blocks[:, 1, 1] = h[3]
            xc = np.zeros(n)
            xc[2 * act] = h[2]
            xc[2 * act + 1] = h[4]
            st.hess_blocks, st.hess_xc, st.hess_cc = blocks, xc, float(np.sum(h[5]))
        return st

    # ---- step filter ------------------------------------------------------------------------------
    def max_safe_fraction(self, x, c: float, dx, dc: float = 0.0, safety: float = 0.9) -> float:
        """Largest safe fraction of the step ``(dx, dc)`` from ``(x, c)``, times ``safety``.

        With ``t*`` the first ``s`` in ``(0, 1]`` at which some node reaches the indenter surface
        (``d_i(x + s dx, c + s dc) = 0``), returns ``safety * t*``; returns ``1.0`` when no node
        reaches it for ``s`` in ``[0, 1]`` (the whole step is safe).  All nodes are considered, not
        only the active ones.  Plate: ``d_i(s) = d_i - s (dz_i - dc)`` is linear.  Sphere: the
        first root in ``(0, 1]`` of ``|u_i + s v_i|^2 = rho^2`` with ``u_i = (r_i, z_i - zc)``,
        ``v_i = (dr_i, dz_i - dc)``, computed exactly (in the cancellation-free form
        ``s = (|u|^2 - rho^2) / (-u.v + sqrt((u.v)^2 - |v|^2 (|u|^2 - rho^2)))``).

        Parameters
        ----------
        x : array_like, shape ``(2N,)``
            Current interleaved state (every node must have ``d > 0``).
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
            If the current state has a node at ``d <= 0``, or an argument is not finite.
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
        d = self._checked_distances(r, z, c)
        if isinstance(self.indenter, Plate):
            rate = dz - dc  # d_i(s) = d_i - s * rate
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
        return f"ContactBarrier({self.indenter!r}, K={self.K!r}, dhat={self.dhat!r})"
