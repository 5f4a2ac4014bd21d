"""The shell's 2-D energy on a ring mesh of ``M`` sectors: an independent check of the harmonic blocks.

The same densities as every view (:mod:`contin_models.shell.density`), evaluated on a ring of ``M``
material points per node in Cartesian coordinates, with the ``theta``-derivatives replaced by central
differences over the sectors and the integral over ``theta`` by a sum.  It shares neither the
harmonic blocks' mode maps nor the 3-D view's Fourier series, so their agreement (to second order in
``1/M``, ``tests/test_harmonic.py``) checks both; its second-order differences are why the 3-D view uses
Fourier series instead (``docs/model.md``, "The 3-D view").  Differentiated by forward jets
(:class:`contin_models.shell.jets.Jet`): slow, a check only.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .density import (_addv, _norm, _scale, _sub, bend_density, free_edge_density, pole_curvature, skirt_density,
                      stretch_density, volume_density)
from .harmonic import HarmonicShell
from .jets import Jet

__all__ = ["ring_mesh_energy", "ring_mesh_block"]


def ring_mesh_energy(hs: HarmonicShell, X: tuple, M: int, pressure: float = 0.0, contact: tuple | None = None,
                     points: Any = None):
    """The 2-D energy of :class:`HarmonicShell` on a ring mesh of ``M`` sectors (``M`` even).

    ``X = (X, Y, Z)``: Cartesian node positions, each an array (or :class:`Jet`) of ``N M`` points,
    node ``j`` at sector ``k`` (reference angle ``theta_k = 2 pi k / M``) at index ``j M + k``.
    The densities are evaluated at every ``theta_k`` in the local frame there, with the
    ``theta``-derivatives replaced by central differences over the sectors
    (``P' = (P_{k+1} - P_{k-1}) / (2 dtheta)``, ``P'' = (P_{k+1} - 2 P_k + P_{k-1}) / dtheta^2``),
    and the integral over ``theta`` by the sum ``dtheta sum_k`` (the pole's averages by means over
    ``k``).  ``contact = (barrier, c)`` adds the barrier over the points ``points`` of its integral
    (:class:`contin_models.contact.barrier.IntegrationPoints`; default every fixed sample of the
    cells), each at every sector, ``W`` by its closed form (points beyond ``dhat`` must be left out
    of ``points``: their ``W`` is zero).  Its Hessian at an axisymmetric state is block-circulant; projected on the Fourier mode
    ``n`` it tends to the harmonic block as ``M -> infinity``, with an ``O(M^-2)`` difference.
    """
    N, nu = hs.N, hs.nu
    M = int(M)
    if M % 2 or M < 4:
        raise ValueError("ring_mesh_energy: M must be even and >= 4")
    dth = 2.0 * math.pi / M
    k = np.arange(M)
    th = dth * k
    cs, sn = np.cos(th), np.sin(th)

    def idx(j, shift=0):
        j = np.atleast_1d(j)
        return (j[:, None] * M + (k[None, :] + shift) % M).ravel()

    def frame(V, j):  # components (r, t, z) of a Cartesian vector at nodes j, all sectors, in frame k
        c = np.tile(cs, len(np.atleast_1d(j)))
        s = np.tile(sn, len(np.atleast_1d(j)))
        return (V[0] * c + V[1] * s, V[1] * c - V[0] * s, V[2])

    def at(j, shift=0):
        i = idx(j, shift)
        return tuple(X[c].take(i) if isinstance(X[c], Jet) else X[c][i] for c in range(3))

    def P(j):
        return frame(at(j), j)

    def Pp(j, shift=0):
        return frame(_scale(_sub(at(j, shift + 1), at(j, shift - 1)), 1.0 / (2.0 * dth)), j)

    def Ppp(j):
        return frame(_scale(_addv(_sub(at(j, 1), _scale(at(j), 2.0)), at(j, -1)), 1.0 / dth ** 2), j)

    def rep(a, j):  # per-element parameters, repeated over the sectors
        return np.repeat(np.asarray(a, dtype=float), M) if np.ndim(a) else a

    def tot(e):
        return e.total() if isinstance(e, Jet) else np.sum(e)

    E = 0.0
    i = np.arange(N - 1)
    D = _sub(frame(at(i + 1), i), P(i))
    Mp = _scale(_addv(Pp(i), frame(_scale(_sub(at(i + 1, 1), at(i + 1, -1)), 1.0 / (2.0 * dth)), i)), 0.5)
    E = E + tot(stretch_density(D, Mp, rep(hs.s_lbar, i), rep(hs.s_rbar, i), rep(hs.s_ks, i), nu)) * dth
    j = hs.b_nodes
    if j.size:
        e1 = frame(_sub(at(j), at(j - 1)), j)
        e2 = frame(_sub(at(j + 1), at(j)), j)
        Dp = frame(_scale(_sub(_sub(at(j + 1, 1), at(j + 1, -1)), _sub(at(j - 1, 1), at(j - 1, -1))),
                          1.0 / (2.0 * dth)), j)
        L = None if hs.current else rep(hs.b_lbar, j)
        E = E + tot(bend_density(e1, e2, Dp, Pp(j), Ppp(j), rep(hs.b_lbar, j), rep(hs.b_rbar, j),
                                 rep(hs.b_k11, j), rep(hs.b_k22, j), rep(hs.b_kb, j), nu, L)) * dth
    if hs.clamp is not None:
        cl = hs.clamp
        gr, gz = cl.ghost
        G = (np.full(M, gr), np.zeros(M), np.full(M, gz))           # ghost in frame k
        Gp = (np.zeros(M), np.full(M, gr * math.sin(dth) / dth), np.zeros(M))
        z0 = np.array([0])
        e1 = _sub(P(z0), G)
        e2 = frame(_sub(at(np.array([1])), at(z0)), z0)
        Dp = _sub(frame(_scale(_sub(at(np.array([1]), 1), at(np.array([1]), -1)), 1.0 / (2.0 * dth)), z0), Gp)
        E = E + tot(bend_density(e1, e2, Dp, Pp(z0), Ppp(z0), cl.lbar, cl.rbar, cl.kappa_bar[0],
                                 cl.kappa_bar[1], cl.kb, cl.nu, cl.lbar)) * dth
    if hs.free_edge is not None:
        fe = hs.free_edge
        z0, o1 = np.array([0]), np.array([1])
        e = frame(_sub(at(o1), at(z0)), z0)
        Dp = frame(_scale(_sub(_sub(at(o1, 1), at(o1, -1)), _sub(at(z0, 1), at(z0, -1))), 1.0 / (2.0 * dth)), z0)
        E = E + tot(free_edge_density(e, Dp, Pp(z0), Ppp(z0), fe.K, fe.kappa_bar, nu)) * dth
    for kk, nb, north, element in hs.poles:
        jn, jk = np.array([nb]), np.array([kk])
        Pm = P(jn)
        Pq = frame(at(jn, M // 2), jn)
        Pc = frame(at(jk), jn)
        Pmp = Pp(jn)
        Pqp = frame(_scale(_sub(at(jn, M // 2 + 1), at(jn, M // 2 - 1)), 1.0 / (2.0 * dth)), jn)
        L = None if element.current_length else element.lbar
        B = pole_curvature(Pm, Pmp, Pc, Pq, Pqp, north, L) - element.kappa_bar
        Akb = element.K / (1.0 + nu)
        mean = tot(B) * (1.0 / M)
        mean2 = tot(B * B) * (1.0 / M)
        E = E + (mean * mean * (3.0 * nu - 1.0) + mean2 * (2.0 * (1.0 - nu))) * Akb
    if contact is not None:
        barrier, cpos = contact
        cells = barrier.cells(N)
        cell_of, coef, weight = (cells.cell, cells.cz, cells.weight) if points is None else \
            (points.cell, points.cz, points.weight)
        st_nodes = cells.stencil[cell_of]  # (S, 3)
        mirror = cell_of == N - 1
        pts = None
        for j in range(3):
            nodes = st_nodes[:, j]
            shift = np.where(mirror & (j == 2), M // 2, 0)  # the pole cell's third node: the opposite point
            ii = (nodes[:, None] * M + (k[None, :] + shift[:, None]) % M).ravel()
            Pj = tuple(X[cc].take(ii) if isinstance(X[cc], Jet) else X[cc][ii] for cc in range(3))
            c_ = np.repeat(coef[:, j], M)
            term = _scale(Pj, c_)
            pts = term if pts is None else _addv(pts, term)
        if barrier.indenter.name == "sphere":
            rho = float(barrier.indenter.params[0])
            dvec = (pts[0], pts[1], pts[2] - cpos)
            d = _norm(dvec) - rho
        else:
            d = -pts[2] + cpos
        Kc, dh = barrier.K, barrier.dhat
        t = d * (1.0 / dh)
        lg = t.log() if isinstance(t, Jet) else np.log(t)
        W = (d - dh) * (d - dh) * lg * (-Kc)
        wts = np.repeat(weight, M)
        E = E + tot(W * wts) * (1.0 / M)
    if pressure != 0.0:
        Vol = tot(volume_density(P(i), frame(at(i + 1), i), Pp(i),
                                 frame(_scale(_sub(at(i + 1, 1), at(i + 1, -1)), 1.0 / (2.0 * dth)), i))) * dth
        if 0 not in [p[0] for p in hs.poles]:
            z0 = np.array([0])
            Vol = Vol + tot(skirt_density(P(z0), Pp(z0), hs.z_ref)) * dth
        E = E + Vol * pressure
    return E


def ring_mesh_block(hs: HarmonicShell, x: np.ndarray, n: int, M: int, pressure: float = 0.0,
                    contact: tuple | None = None) -> np.ndarray:
    """The Hessian of :func:`ring_mesh_energy` at the axisymmetric state ``x`` projected on mode ``n``.

    Exact (second-order forward differentiation with the mode amplitudes ``u`` as variables): the
    ``3N x 3N`` matrix ``Phi_n^T H_M Phi_n`` with ``Phi_n`` the Cartesian field of the mode
    ``(a cos n theta_k e_r + c sin n theta_k e_theta + b cos n theta_k e_z)`` (constants for
    ``n = 0``), i.e. the Fourier transform of the block-circulant ring-mesh Hessian.
    """
    N = hs.N
    x = np.asarray(x, dtype=float)
    r, z = x[0::2], x[1::2]
    th = 2.0 * math.pi * np.arange(M) / M
    cs, sn = np.cos(th), np.sin(th)
    if n == 0:
        fc, fs = np.ones(M), np.ones(M)
    else:
        fc, fs = np.cos(n * th), np.sin(n * th)
    k = 3 * N
    m = N * M
    X0 = [np.repeat(r, M) * np.tile(cs, N), np.repeat(r, M) * np.tile(sn, N), np.repeat(z, M)]
    G = [np.zeros((k, m)) for _ in range(3)]
    for j in range(N):
        sl = slice(j * M, (j + 1) * M)
        G[0][3 * j, sl] = fc * cs       # a: radial
        G[1][3 * j, sl] = fc * sn
        G[2][3 * j + 1, sl] = fc        # b: axial
        G[0][3 * j + 2, sl] = -fs * sn  # c: circumferential
        G[1][3 * j + 2, sl] = fs * cs
    X = tuple(Jet.linear(X0[c], G[c]) for c in range(3))
    points = None
    if contact is not None:
        barrier, cpos = contact
        points = barrier.integration_points(x, cpos)
    E = ring_mesh_energy(hs, X, M, pressure, contact, points)
    return E.h[:, :, 0]
