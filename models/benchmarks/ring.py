"""A circular ring under uniform external pressure, discretised as a polygon of ``N`` nodes.

Nodes sit at ``theta_i = i theta``, ``theta = 2 pi / N``, on a circle of radius ``R``; node ``i``
moves by its radial and tangential displacements ``(w_i, v_i)`` (the state is
``u = (w_0, v_0, w_1, v_1, ...)``) to ``X_i = (R + w_i) e_r(theta_i) + v_i e_theta(theta_i)``.  The
segments ``s_i = X_{i+1} - X_i`` have rest length ``l0 = 2 R sin(theta / 2)``, length ``l_i``, and
turn by ``psi_i`` (the angle from ``s_{i-1}`` to ``s_i``, ``theta`` at rest).  The energy is

    E(u, p) = EA / (2 l0) sum (l_i - l0)^2 + EI / (2 l0) sum (psi_i - theta)^2 + p A(u) + E_anchor,

a stiff membrane penalty (``EA R^2 / EI``, default ``1e6``: the inextensible limit), the discrete
bending energy of a ring of bending stiffness ``EI`` with curvature ``psi / l0``, and the potential
``p A`` of the external pressure, ``A`` the enclosed area (the shoelace sum ``1/2 sum X_i x X_{i+1}``).
The pressure is *hydrostatic*: it acts normal to the deformed ring and stays conservative, with the
potential ``p A``.  That is the load behaviour for which the ring's classical buckling loads are

    p_n = (n^2 - 1) EI / R^3,   n = 2, 3, ...      (3 EI / R^3 for the oval mode n = 2)

(Levy 1884; Timoshenko & Gere, *Theory of Elastic Stability*, 2nd ed., McGraw-Hill 1961, ch. 7;
Brush & Almroth, *Buckling of Bars, Plates, and Shells*, McGraw-Hill 1975).  A load of fixed
direction, or one directed to the ring's centre, has other critical loads; Gaibotti, Bigoni, Cutolo,
Fraldi & Piccolroaz (arXiv:2407.02897, 2024) compare the three and the constraints the latter two
need.
``E_anchor = (k_a N / 2) (|c|^2 + m^2)`` fixes the rigid-body motions, which leave the rest of the
energy unchanged: ``c = (1/N) sum (w_i e_r + v_i e_theta)`` is the centroid's displacement and
``m = (1/N) sum v_i`` the mean rotation.  Every equilibrium has ``c = 0`` and ``m = 0`` (the rest of
the energy is invariant under translations and rotations, so its gradient has no component along
them), so the anchor changes no equilibrium; it only makes the Hessian regular.

Closed forms
------------
*Trivial branch.*  The regular polygon of radius ``r`` with ``v = 0``: the hoop force
``N = EA (l/l0 - 1)`` balances the pressure, ``N = -p r cos(theta/2)``, so
``r(p) = R / (1 + p R cos(theta/2) / EA)`` and ``w_i = r - R`` (:meth:`PressurisedRing.trivial_state`).

*Its Hessian.*  The energy is invariant under the rotation by one node, so on the trivial branch the
Hessian in ``(w_i, v_i)`` is block-circulant and its eigenvalues are those of the 2 x 2 Hermitian
symbols ``S(n)``, ``n = 0 .. N-1`` (``z = exp(i n theta)``, ``s = sin(theta/2)``, ``c = cos(theta/2)``,
``l = 2 r s``, ``N_h = -p r c``)::

    S(n) = EA/l0 a^H a + (N_h / l + 4 EI sin^2(n theta / 2) / (l0 l^2)) b^H b + p (B z + B^T conj(z)) / 2
           + anchor,
    a = [s (1 + z), c (z - 1)],  b = [-c (z - 1), s (z + 1)],  B = [[sin theta, cos theta], [-cos theta, sin theta]],

from the linearised segment stretch ``t_i . delta s_i`` (``a``), the segment rotation
``nu_i . delta s_i / l`` (``b``; its difference between neighbours is ``delta psi``), the hoop force's
geometric stiffness and the second variation ``sum delta X_i x delta X_{i+1}`` of the area.  The
anchor adds ``k_a diag(0, 1)`` to ``S(0)`` and ``(k_a / 2) [[1, -i], [i, 1]]`` to ``S(1)`` and its
conjugate to ``S(N-1)``.  ``S(n)`` and ``S(N-n)`` are conjugate: every mode ``2 <= n < N/2`` is a
double eigenvalue, and every buckling load of the trivial branch is a double branch point (the
ring's ``O(2)``, here the dihedral group of the polygon, acting on ``cos n theta`` and ``sin n theta``).

*Buckling loads of the discrete ring.*  ``p_n^(N)`` is where ``det S(n) = 0``
(:meth:`PressurisedRing.buckling_load`, a scalar root).  In the inextensible limit (``EA -> inf``,
``r = R``) the kernel of ``a`` gives ``V = i tan(theta/2) cot(n theta/2) W`` and, with
``phi = n theta`` and ``X = sin^2((phi - theta)/2) sin^2((phi + theta)/2)``::

    p_n^(N) = (16 EI X / (l0^3 c^2)) / (4 R X / (l0 c sin^2(phi/2)) - cos(phi) sin(theta) (1 + g^2) + 2 g sin(phi) cos(theta)),
    g = tan(theta/2) cot(phi/2),

which tends to ``(n^2 - 1) EI / R^3`` as ``N -> inf`` (``X -> (n^2 - 1)^2 theta^4 / 16``, ``g -> 1/n``):
:meth:`PressurisedRing.inextensible_buckling_load`.

Symmetry
--------
``symmetry_generators``: the rotation by one node, ``(w, v)_i <- (w, v)_{i-1}``, and the reflection
``theta -> -theta``, ``(w, v)_i <- (w, -v)_{-i}``, as signed permutations; they generate the dihedral
group of order ``2 N``.  In ``coordinates="positions"`` the same maps act on the positions
(``X_i <- Rot(theta) X_{i-1}`` and ``X_i <- diag(1, -1) X_{-i}``), still linearly, since the unloaded
ring's centre is the origin.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.optimize import brentq

from contin import Problem

from .symmetry import signed_permutation

__all__ = ["PressurisedRing"]


def _perp(s: np.ndarray) -> np.ndarray:
    """``(-s_y, s_x)`` row by row: the vector turned by +90 degrees."""
    return np.column_stack([-s[:, 1], s[:, 0]])


class PressurisedRing(Problem):
    """The ring of the module docstring; parameter ``p`` (external pressure).

    Parameters
    ----------
    N : int
        Number of nodes (at least 8).
    EI : float
        Bending stiffness.
    R : float
        Radius of the unloaded ring.
    membrane_ratio : float
        ``EA R^2 / EI``: the membrane penalty relative to bending (large: the inextensible limit).
    anchor_stiffness : float, optional
        ``k_a`` of the rigid-body anchor; default ``9 EI theta / R^3``, about the Hessian's softest
        bending eigenvalue at ``p = 0`` (mode ``n = 2``), so the anchored rigid modes sit among the
        elastic ones.
    coordinates : str
        ``"displacements"``: the state is ``(w_i, v_i)``, zero on the unloaded ring (the module
        docstring).  ``"positions"``: the state is the nodes' Cartesian positions ``(x_i, y_i)``,
        ``R (cos theta_i, sin theta_i)`` on the unloaded ring.  The two are the same model in other
        unknowns (an orthogonal change of variables plus a shift), with the same Hessian eigenvalues;
        the engine's automatic scales, measured from the size of the state, differ.
    """

    def __init__(self, N: int = 64, EI: float = 1.0, R: float = 1.0, membrane_ratio: float = 1e6,
                 anchor_stiffness: float | None = None, coordinates: str = "displacements") -> None:
        if int(N) != N or N < 8:
            raise ValueError(f"PressurisedRing: N = {N!r} must be an integer >= 8")
        if not (EI > 0 and R > 0 and membrane_ratio > 0):
            raise ValueError(f"PressurisedRing: EI, R and membrane_ratio must be > 0 "
                             f"(got {EI}, {R}, {membrane_ratio})")
        self.N, self.EI, self.R = int(N), float(EI), float(R)
        self.EA = float(membrane_ratio) * self.EI / self.R ** 2
        self.theta = 2 * math.pi / self.N
        self.l0 = 2 * self.R * math.sin(self.theta / 2)
        self.k_anchor = 9 * self.EI * self.theta / self.R ** 3 if anchor_stiffness is None else float(anchor_stiffness)
        if not self.k_anchor > 0:
            raise ValueError(f"PressurisedRing: anchor_stiffness must be > 0, got {anchor_stiffness}")
        if coordinates not in ("displacements", "positions"):
            raise ValueError(f"PressurisedRing: coordinates must be 'displacements' or 'positions', got {coordinates!r}")
        self.coordinates = coordinates
        super().__init__(symmetric=True, name=f"pressurised_ring(N={self.N})", parameter_name="p")
        angles = self.theta * np.arange(self.N)
        self._cos, self._sin = np.cos(angles), np.sin(angles)
        # X = X0 + T u, T block-diagonal with the rotations [e_r, e_theta] of the nodes
        rows = np.repeat(np.arange(2 * self.N), 2)
        cols = np.column_stack([2 * np.arange(self.N), 2 * np.arange(self.N) + 1]).repeat(2, axis=0).ravel()
        vals = np.column_stack([self._cos, -self._sin, self._sin, self._cos]).ravel()
        self._T = sp.csr_matrix((vals, (rows, cols)), shape=(2 * self.N, 2 * self.N))
        self._X0 = self.R * np.column_stack([self._cos, self._sin]).ravel()
        # the state's offset from the unloaded ring, mapped to Cartesian displacements (an orthogonal map)
        if coordinates == "displacements":
            self._origin, self._to_cartesian = np.zeros(2 * self.N), self._T
        else:
            self._origin, self._to_cartesian = self._X0.copy(), sp.identity(2 * self.N, format="csr")
        self._to_polar = (self._T.T @ self._to_cartesian).tocsr()
        mid = angles + self.theta / 2
        self._s0 = self.l0 * np.column_stack([-np.sin(mid), np.cos(mid)])  # rest segments, l0 e_theta(mid)
        # s = D X: segment i runs from node i to node i + 1 (cyclic)
        nxt = np.roll(np.arange(self.N), -1)
        d_rows = np.concatenate([np.arange(2 * self.N)] * 2)
        d_cols = np.concatenate([np.arange(2 * self.N), (2 * nxt[:, None] + np.arange(2)).ravel()])
        d_vals = np.concatenate([-np.ones(2 * self.N), np.ones(2 * self.N)])
        self._D = sp.csr_matrix((d_vals, (d_rows, d_cols)), shape=(2 * self.N, 2 * self.N))
        # the area's Hessian: d2A / dx_i dy_{i+1} = 1/2, d2A / dy_i dx_{i+1} = -1/2 (constant)
        i = np.arange(self.N)
        a_rows = np.concatenate([2 * i, 2 * nxt + 1, 2 * i + 1, 2 * nxt])
        a_cols = np.concatenate([2 * nxt + 1, 2 * i, 2 * nxt, 2 * i + 1])
        a_vals = np.concatenate([0.5 * np.ones(2 * self.N), -0.5 * np.ones(2 * self.N)])
        self._area_hessian = sp.csr_matrix((a_vals, (a_rows, a_cols)), shape=(2 * self.N, 2 * self.N))
        # the anchor's functionals [c_x, c_y, m] as rows acting on u
        anchor = np.zeros((3, 2 * self.N))
        anchor[0, 0::2], anchor[0, 1::2] = self._cos / self.N, -self._sin / self.N
        anchor[1, 0::2], anchor[1, 1::2] = self._sin / self.N, self._cos / self.N
        anchor[2, 1::2] = 1.0 / self.N
        self._anchor = anchor @ self._to_polar
        self._anchor_hessian = sp.csr_matrix(self.k_anchor * self.N * self._anchor.T @ self._anchor)
        self._obs = {
            "w_mean": lambda u, p: float(np.mean(self.polar(u)[0::2])),
            "w2c": lambda u, p: float(2.0 / self.N * np.dot(self.polar(u)[0::2], np.cos(2 * angles))),
            "w2s": lambda u, p: float(2.0 / self.N * np.dot(self.polar(u)[0::2], np.sin(2 * angles))),
            "area_ratio": lambda u, p: float(self.area(u) / (0.5 * self.N * self.R ** 2 * math.sin(self.theta))),
        }
        self.symmetry_generators = tuple((self._to_polar.T @ g @ self._to_polar).tocsr()
                                         for g in (self._rotation(), self._reflection()))

    @property
    def observables(self):
        return self._obs

    # ---- geometry --------------------------------------------------------------------------------
    def positions(self, u: np.ndarray) -> np.ndarray:
        """Node positions ``(N, 2)``."""
        return (self._X0 + self._to_cartesian @ (np.asarray(u, dtype=float) - self._origin)).reshape(self.N, 2)

    def polar(self, u: np.ndarray) -> np.ndarray:
        """The radial and tangential displacements ``(w_0, v_0, w_1, v_1, ...)`` of the state ``u``."""
        return self._to_polar @ (np.asarray(u, dtype=float) - self._origin)

    def area(self, u: np.ndarray) -> float:
        """Enclosed area ``1/2 sum X_i x X_{i+1}``."""
        X = self.positions(u)
        Y = np.roll(X, -1, axis=0)
        return float(0.5 * np.sum(X[:, 0] * Y[:, 1] - X[:, 1] * Y[:, 0]))

    def _segments(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Segment vectors ``(N, 2)``, their lengths, extensions ``l - l0`` and turning angles ``psi_i``.

        ``psi_i`` turns ``s_{i-1}`` into ``s_i``.  The extension is ``(2 s0 . d + d . d) / (l + l0)`` with
        ``d`` the segment's change from its rest vector ``s0``: the membrane force ``EA (l - l0) / l0``
        multiplies it by the penalty, and ``l - l0`` taken as a difference of two lengths would carry
        their rounding error times ``EA`` into the residual.
        """
        d = (self._D @ (self._to_cartesian @ (u - self._origin))).reshape(self.N, 2)
        s = self._s0 + d
        length = np.hypot(s[:, 0], s[:, 1])
        extension = (2 * np.sum(self._s0 * d, axis=1) + np.sum(d * d, axis=1)) / (length + self.l0)
        prev = np.roll(s, 1, axis=0)
        psi = np.arctan2(prev[:, 0] * s[:, 1] - prev[:, 1] * s[:, 0], np.sum(prev * s, axis=1))
        return s, length, extension, psi

    # ---- the model -------------------------------------------------------------------------------
    def energy(self, u, p):
        u = np.asarray(u, dtype=float)
        _, _, extension, psi = self._segments(u)
        anchor = self._anchor @ (u - self._origin)
        return float(self.EA / (2 * self.l0) * np.sum(extension ** 2)
                     + self.EI / (2 * self.l0) * np.sum((psi - self.theta) ** 2) + p * self.area(u)
                     + 0.5 * self.k_anchor * self.N * np.dot(anchor, anchor))

    def _segment_gradient(self, s, length, extension, psi) -> np.ndarray:
        moment = self.EI / self.l0 * (psi - self.theta)  # at node i, between s_{i-1} and s_i
        dphi = _perp(s) / length[:, None] ** 2  # d(angle of s_i) / d s_i
        torque = moment - np.roll(moment, -1)  # phi_i enters psi_i with +1 and psi_{i+1} with -1
        stretch = self.EA / self.l0 * extension
        return stretch[:, None] * s / length[:, None] + torque[:, None] * dphi

    def residual(self, u, p):
        u = np.asarray(u, dtype=float)
        s, length, extension, psi = self._segments(u)
        g_x = self._D.T @ self._segment_gradient(s, length, extension, psi).ravel()
        g_x = g_x + p * (self._area_hessian @ self.positions(u).ravel())  # A is quadratic: grad A = H_A X
        return self._to_cartesian.T @ g_x + self._anchor_hessian @ (u - self._origin)

    def jacobian(self, u, p):
        u = np.asarray(u, dtype=float)
        s, length, extension, psi = self._segments(u)
        n = self.N
        moment = self.EI / self.l0 * (psi - self.theta)
        torque = moment - np.roll(moment, -1)
        stretch = self.EA / self.l0 * extension
        unit = s / length[:, None]
        dphi = _perp(s) / length[:, None] ** 2
        l4 = length ** 4
        sx, sy = s[:, 0], s[:, 1]
        d2phi = np.empty((n, 2, 2))
        d2phi[:, 0, 0] = 2 * sx * sy / l4
        d2phi[:, 0, 1] = d2phi[:, 1, 0] = (sy ** 2 - sx ** 2) / l4
        d2phi[:, 1, 1] = -2 * sx * sy / l4
        eye = np.eye(2)[None]
        ss = unit[:, :, None] * unit[:, None, :]
        diag = (self.EA / self.l0 * ss + (stretch / length)[:, None, None] * (eye - ss)
                + torque[:, None, None] * d2phi + 2 * self.EI / self.l0 * dphi[:, :, None] * dphi[:, None, :])
        nxt = np.roll(np.arange(n), -1)
        off = -self.EI / self.l0 * dphi[:, :, None] * dphi[nxt][:, None, :]  # block (i, i+1)
        r = np.arange(2)
        rows_d = (2 * np.arange(n)[:, None, None] + r[None, :, None]).repeat(2, axis=2)
        cols_d = (2 * np.arange(n)[:, None, None] + r[None, None, :]).repeat(2, axis=1)
        rows_o = rows_d  # the transposed block (i+1, i) takes the same values with rows and columns swapped
        cols_o = (2 * nxt[:, None, None] + r[None, None, :]).repeat(2, axis=1)
        Hs = sp.csr_matrix((np.concatenate([diag.ravel(), off.ravel(), off.ravel()]),
                            (np.concatenate([rows_d.ravel(), rows_o.ravel(), cols_o.ravel()]),
                             np.concatenate([cols_d.ravel(), cols_o.ravel(), rows_o.ravel()]))),
                           shape=(2 * n, 2 * n))
        Hx = self._D.T @ Hs @ self._D + p * self._area_hessian
        return (self._to_cartesian.T @ Hx @ self._to_cartesian + self._anchor_hessian).tocsr()

    def dresidual_dp(self, u, p):
        return self._to_cartesian.T @ (self._area_hessian @ self.positions(u).ravel())

    # ---- symmetry --------------------------------------------------------------------------------
    def _rotation(self) -> sp.csr_matrix:
        """The rotation by one node acting on ``(w_i, v_i)``."""
        node = np.roll(np.arange(self.N), 1)  # node i takes node i - 1's displacements
        return signed_permutation((2 * node[:, None] + np.arange(2)).ravel())

    def _reflection(self) -> sp.csr_matrix:
        """The reflection ``theta -> -theta`` acting on ``(w_i, v_i)``."""
        node = (-np.arange(self.N)) % self.N
        signs = np.tile([1.0, -1.0], self.N)
        return signed_permutation((2 * node[:, None] + np.arange(2)).ravel(), signs)

    # ---- closed forms ----------------------------------------------------------------------------
    def trivial_radius(self, p: float) -> float:
        """Radius ``r(p) = R / (1 + p R cos(theta/2) / EA)`` of the uniformly compressed ring."""
        return self.R / (1.0 + p * self.R * math.cos(self.theta / 2) / self.EA)

    def trivial_state(self, p: float) -> np.ndarray:
        """The state on the trivial branch at ``p``: ``w = r(p) - R``, ``v = 0``."""
        polar = np.zeros(2 * self.N)
        polar[0::2] = self.trivial_radius(p) - self.R
        return self._origin + self._to_polar.T @ polar

    def symbol(self, n: int, p: float) -> np.ndarray:
        """The 2 x 2 Hermitian symbol ``S(n)`` of the Hessian on the trivial branch (module docstring)."""
        th = self.theta
        s, c = math.sin(th / 2), math.cos(th / 2)
        r = self.trivial_radius(p)
        length = 2 * r * s
        hoop = -p * r * c
        z = complex(math.cos(n * th), math.sin(n * th))
        a = np.array([s * (1 + z), c * (z - 1)])
        b = np.array([-c * (z - 1), s * (z + 1)])
        B = np.array([[math.sin(th), math.cos(th)], [-math.cos(th), math.sin(th)]])
        bend = 4 * self.EI * math.sin(n * th / 2) ** 2 / (self.l0 * length ** 2)
        S = (self.EA / self.l0 * np.outer(a.conj(), a) + (hoop / length + bend) * np.outer(b.conj(), b)
             + p * (B * z + B.T * z.conjugate()) / 2)
        k = n % self.N
        if k == 0:
            S = S + self.k_anchor * np.diag([0.0, 1.0])
        if k == 1:
            S = S + 0.5 * self.k_anchor * np.array([[1, -1j], [1j, 1]])
        if k == self.N - 1:
            S = S + 0.5 * self.k_anchor * np.array([[1, 1j], [-1j, 1]])
        return S

    def trivial_hessian_eigenvalues(self, p: float) -> np.ndarray:
        """All ``2 N`` eigenvalues of the Hessian on the trivial branch at ``p``, from the symbols, sorted."""
        return np.sort(np.concatenate([np.linalg.eigvalsh(self.symbol(n, p)) for n in range(self.N)]))

    def buckling_load(self, n: int) -> float:
        """``p_n^(N)`` of this ring (membrane penalty included): the root of ``det S(n)`` above 0."""
        if not 2 <= n < self.N / 2:
            raise ValueError(f"PressurisedRing.buckling_load: n must lie in 2 .. {(self.N - 1) // 2}, got {n}")
        lowest = lambda p: float(np.linalg.eigvalsh(self.symbol(n, p))[0])
        top = 2.0 * self.inextensible_buckling_load(n)
        while lowest(top) > 0:
            top *= 2.0
        return float(brentq(lowest, 0.0, top, xtol=1e-15 * top, rtol=4 * np.finfo(float).eps))

    def inextensible_buckling_load(self, n: int) -> float:
        """``p_n^(N)`` in the limit ``EA -> inf`` (closed form of the module docstring)."""
        th, phi = self.theta, n * self.theta
        s, c = math.sin(th / 2), math.cos(th / 2)
        X = math.sin((phi - th) / 2) ** 2 * math.sin((phi + th) / 2) ** 2
        g = math.tan(th / 2) / math.tan(phi / 2)
        num = 16 * self.EI * X / (self.l0 ** 3 * c ** 2)
        den = (4 * self.R * X / (self.l0 * c * math.sin(phi / 2) ** 2)
               - math.cos(phi) * math.sin(th) * (1 + g ** 2) + 2 * g * math.sin(phi) * math.cos(th))
        return num / den

    def classical_buckling_load(self, n: int) -> float:
        """``(n^2 - 1) EI / R^3`` (Timoshenko & Gere 1961, ch. 7)."""
        return (n * n - 1) * self.EI / self.R ** 3
