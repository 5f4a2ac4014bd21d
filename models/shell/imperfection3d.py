"""Imperfections that need not be axisymmetric, as stress-free references of the 3-D view.

Each function returns a state of the view (:class:`contin_models.shell.fourier.FourierShell`, the Fourier
coefficients of every ring in one :class:`~contin_models.shell.fourier.AngularBasis`): the structure's
reference plus a normal displacement field.  Give it as ``reference=`` to
:class:`~contin_models.shell.fourier.FourierShell` or :class:`~contin_models.shell.problem3d.Shell3D`, which
measure the strains against it (``docs/model.md``, "The 3-D view").

* :func:`mode_imperfection`: an ``n``-wave mode (the null vector of the harmonic block of ``n`` at a
  branch point, :func:`branch_mode`) scaled so that its largest normal displacement is ``delta``;
* :func:`dimple_imperfection`: a smooth normal bump of depth ``delta`` away from the pole, centred at a
  node or arc length and an angle.

Both take the sign of :func:`contin_models.shell.meridian.with_dimple`: ``delta > 0`` moves the shell
inward (against its outward normal) where the displacement is largest.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .fourier import AngularBasis, FourierShell

__all__ = ["branch_mode", "mode_imperfection", "dimple_imperfection", "meridian_normals"]


def meridian_normals(structure: Any) -> tuple[np.ndarray, np.ndarray]:
    """Outward unit normals ``(n_r, n_z)`` of the reference meridian at its nodes (the smooth curve's where
    the meridian knows them, else from the nodes by central differences); along the axis on the axis."""
    m = structure.reference.meridian
    if hasattr(m, "normals"):
        nr, nz = (np.array(a, dtype=float) for a in m.normals())
    else:
        x = np.asarray(m.x, dtype=float)
        tr, tz = np.gradient(x[0::2]), np.gradient(x[1::2])
        length = np.hypot(tr, tz)
        nr, nz = tz / length, -tr / length   # the meridian turns counter-clockwise: outward is to its right
    for k in structure.poles:
        nr[k], nz[k] = 0.0, math.copysign(1.0, nz[k])
    return nr, nz


def _arc_length(structure: Any) -> np.ndarray:
    """Arc length of the reference meridian at its nodes, from node 0."""
    m = structure.reference.meridian
    s = getattr(m, "s", None)
    if s is not None:
        return np.asarray(s, dtype=float) - float(s[0])
    return np.concatenate([[0.0], np.cumsum(np.asarray(m.edge_length, dtype=float))])


def _finite(name: str, value: Any, where: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{where}: {name} must be a finite number, got {value!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{where}: {name} must be a finite number, got {value!r}")
    return v


def _base(structure: Any, basis: AngularBasis, base: np.ndarray | None, where: str) -> tuple[FourierShell, np.ndarray]:
    view = FourierShell(structure, basis)
    if base is None:
        return view, view.reference_state()
    c = np.array(base, dtype=float)
    if c.shape != (view.size,) or not np.isfinite(c).all():
        raise ValueError(f"{where}: base must be a finite state of the view, shape ({view.size},), got shape {c.shape}")
    return view, c


def branch_mode(structure: Any, x: np.ndarray, n: int) -> np.ndarray:
    """The mode of the harmonic block of wave number ``n`` at the axisymmetric state ``x`` (a branch point
    located on the traced path): the eigenvector of the block's eigenvalue nearest zero, as per-node
    amplitudes ``(N, 3)``: ``a``, ``b``, ``c`` of ``dR = a cos(n theta)``, ``dZ = b cos(n theta)``,
    ``dT = c sin(n theta)`` (:func:`contin_models.shell.harmonic.harmonic_mode`'s layout).

    Parameters
    ----------
    structure : ShellStructure
        The shell.
    x : ndarray, shape ``(2 N,)``
        The branch point's axisymmetric state ``[r_0, z_0, ...]``.
    n : int
        The wave number, ``>= 1``.
    """
    import scipy.sparse.linalg as spla

    from .harmonic import harmonic_block, harmonic_dofs

    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"branch_mode: n (the wave number) must be an integer >= 1, got {n!r}")
    x = np.asarray(x, dtype=float)
    if x.shape != (2 * structure.N,) or not np.isfinite(x).all():
        raise ValueError(f"branch_mode: x must be a finite axisymmetric state of shape ({2 * structure.N},), "
                         f"got shape {x.shape}")
    K = harmonic_block(structure, x, int(n)).tocsc()
    T = harmonic_dofs(structure, int(n)).T
    if K.shape[0] <= 200:
        w, v = np.linalg.eigh(K.toarray())
        vec = v[:, int(np.argmin(np.abs(w)))]
    else:
        _, v = spla.eigsh(K, k=1, sigma=0.0, which="LM")
        vec = v[:, 0]
    return (T @ vec).reshape(structure.N, 3)


def mode_imperfection(structure: Any, basis: AngularBasis, n: int, mode: np.ndarray, delta: float,
                      base: np.ndarray | None = None) -> np.ndarray:
    """A reference with an ``n``-wave mode as imperfection: ``base`` plus the mode scaled so that its largest
    normal displacement is ``|delta|``, inward (``delta > 0``) at the node where it is largest.

    Parameters
    ----------
    structure : ShellStructure
        The shell.
    basis : AngularBasis
        The view's angular series; it must carry ``cos(n theta)`` in ``R`` and ``Z`` and ``sin(n theta)``
        in ``T`` (a ``D_n`` basis, or ``D_m`` with ``n`` a multiple of ``m``, or one without the mirror).
    n : int
        The mode's wave number, ``>= 1``.
    mode : ndarray, shape ``(N, 3)``
        Per-node amplitudes ``a``, ``b``, ``c`` of ``dR = a cos(n theta)``, ``dZ = b cos(n theta)``,
        ``dT = c sin(n theta)`` (:func:`branch_mode`, :func:`contin_models.shell.harmonic.harmonic_mode`).
    delta : float
        The largest normal displacement (a length; any sign, ``0`` gives ``base``).
    base : ndarray, optional
        The state the mode is added to (default: the structure's reference in ``basis``).
    """
    where = "mode_imperfection"
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"{where}: n (the wave number) must be an integer >= 1, got {n!r}")
    delta = _finite("delta", delta, where)
    mode = np.array(mode, dtype=float)
    if mode.shape != (structure.N, 3) or not np.isfinite(mode).all():
        raise ValueError(f"{where}: mode must be finite amplitudes of shape (N, 3) = ({structure.N}, 3), "
                         f"got shape {mode.shape}")
    try:
        idx = [basis.index("R", "cos", n), basis.index("Z", "cos", n), basis.index("T", "sin", n)]
    except KeyError:
        raise ValueError(f"{where}: the basis does not carry the wave n = {n} as cos in R, Z and sin in T "
                         f"(its waves: {basis.wave_numbers.tolist()}, parity {basis.parity!r})") from None
    view, c = _base(structure, basis, base, where)
    nr, nz = meridian_normals(structure)
    normal = mode[:, 0] * nr + mode[:, 1] * nz
    k = int(np.argmax(np.abs(normal)))
    if normal[k] == 0.0:
        raise ValueError(f"{where}: the mode has no normal displacement")
    scale = -delta / normal[k]
    for j, i in enumerate(idx):
        c[i::view.m] += scale * mode[:, j]
    return c


def dimple_imperfection(structure: Any, basis: AngularBasis, delta: float, width: float, *, node: int | None = None,
                        s0: float | None = None, theta0: float = 0.0, base: np.ndarray | None = None,
                        tolerance: float = 1e-2) -> np.ndarray:
    """A reference with a dimple away from the pole: ``base`` moved along the meridian's outward normal by
    ``-delta exp(-(d / width)^2)``, ``d`` the distance of a material point from the centre
    ``(s0, theta0)``: ``d^2 = (s - s0)^2 + (2 r sin((theta - theta0) / 2))^2`` (the arc along the meridian
    and the chord across the ring of radius ``r``: smooth and periodic in the angle, and independent of the
    angle on the axis, where a pole stays one point).

    Parameters
    ----------
    structure : ShellStructure
        The shell.
    basis : AngularBasis
        The view's angular series: ``n = 1``, with the mirror (``D_1``, then ``theta0`` is ``0`` or ``pi``:
        the dimple symmetric about the meridional plane ``theta = 0``) or without (any ``theta0``).  Its
        harmonics must carry the dimple: the largest difference between the bump and its truncated series
        at least ``tolerance`` times ``|delta|`` is refused.
    delta : float
        Depth (a length; ``> 0`` inward; ``0`` gives ``base``).
    width : float
        The Gaussian's width (a length), ``> 0``.
    node, s0 : int or float
        The centre on the meridian: a node in ``[0, N-1]`` or an arc length from node 0 in ``[0, s_{N-1}]``
        (exactly one of them).
    theta0 : float
        The centre's angle (radians).
    base : ndarray, optional
        The state the dimple is added to (default: the structure's reference in ``basis``).
    tolerance : float
        The truncation the basis may leave, relative to ``|delta|`` (``> 0``).
    """
    where = "dimple_imperfection"
    delta = _finite("delta", delta, where)
    width = _finite("width", width, where)
    if width <= 0:
        raise ValueError(f"{where}: width must be a positive length, got {width!r}")
    theta0 = _finite("theta0", theta0, where)
    tolerance = _finite("tolerance", tolerance, where)
    if tolerance <= 0:
        raise ValueError(f"{where}: tolerance must be positive, got {tolerance!r}")
    s = _arc_length(structure)
    N = structure.N
    if (node is None) == (s0 is None):
        raise ValueError(f"{where}: give exactly one of node (in [0, {N - 1}]) and s0 (in [0, {s[-1]:.6g}])")
    if node is not None:
        if not isinstance(node, (int, np.integer)) or not 0 <= node < N:
            raise ValueError(f"{where}: node must be an integer in [0, {N - 1}], got {node!r}")
        s0 = float(s[int(node)])
    else:
        s0 = _finite("s0", s0, where)
        if not 0.0 <= s0 <= s[-1]:
            raise ValueError(f"{where}: s0 (arc length from node 0) must be in [0, {s[-1]:.6g}], got {s0!r}")
    if basis.n != 1:
        raise ValueError(f"{where}: a single dimple needs a basis with n = 1 (D_1 or no symmetry), got n = {basis.n}")
    if basis.mirror and abs(math.sin(theta0)) > 1e-12:
        raise ValueError(f"{where}: a basis with the mirror (D_1) carries a dimple centred on its mirror plane only: "
                         f"theta0 must be 0 or pi, got {theta0!r}")
    if basis.parity == "odd":
        raise ValueError(f"{where}: the basis must carry fields symmetric about theta = 0 (parity 'even' or 'both')")
    view, c = _base(structure, basis, base, where)
    # the bump per node on a fine circle of angles; its series by the trapezoidal rule (exact below the grid's
    # Nyquist wave), then its truncation to the basis's waves checked on the same grid
    r = np.asarray(structure.reference.meridian.x, dtype=float)[0::2]
    waves = basis.wave_numbers
    L = 8 * int(waves.max()) + 64
    theta = 2.0 * math.pi * np.arange(L) / L
    d2 = (s - s0)[:, None] ** 2 + (2.0 * r[:, None] * np.sin(0.5 * (theta[None, :] - theta0))) ** 2
    w = -delta * np.exp(-d2 / width ** 2)                              # (N, L): outward displacement
    trig = {"cos": np.cos, "sin": np.sin}
    series = np.zeros_like(w)
    coefficient = {}
    for comp, kind, k in basis.terms:
        if comp != "R" or (kind, k) in coefficient:
            continue
        f = trig[kind](k * theta)
        a = (w @ f) * ((1.0 if k == 0 else 2.0) / L)
        coefficient[kind, k] = a
        series += a[:, None] * f[None, :]
    error = float(np.max(np.abs(series - w)))
    if delta != 0.0 and error > tolerance * abs(delta):
        raise ValueError(f"{where}: the basis (K = {basis.K} harmonics) carries the dimple of width {width!r} only "
                         f"to {error / abs(delta):.3g} of delta (tolerance {tolerance!r}): raise K or widen the "
                         f"dimple")
    nr, nz = meridian_normals(structure)
    poles = list(structure.poles)
    for (kind, k), a in coefficient.items():
        if k > 0:  # on the axis the bump does not depend on the angle: only roundoff in its waves
            a[poles] = 0.0
        c[basis.index("R", kind, k)::view.m] += a * nr
        c[basis.index("Z", kind, k)::view.m] += a * nz
    return c
