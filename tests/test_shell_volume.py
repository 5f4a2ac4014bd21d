"""Enclosed volume of the discrete shell (contin_models.shell.volume): closed forms, derivatives, invariances.

The closed forms (cone, cylinder, spherical cap) and the invariances (homogeneity of degree 3,
translation of the shell together with its base plane, the projected area as the response to a
rigid lift) do not depend on the implementation, so they cannot be tuned to it; the derivatives
are checked against central differences, which are exact up to round-off here because ``V`` is a
cubic polynomial in the state.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

from contin_models.shell.energy import HALF_BANDWIDTH, ShellEnergy
from contin_models.shell.geometry import interleave, spherical_cap, split
from contin_models.shell.volume import (VOLUME_HALF_BANDWIDTH, PressureTerm, enclosed_volume, volume_gradient,
                                        volume_hessian)

R, PHI_HAT = 1.0, 0.6


def cap_volume(R: float, phi_hat: float) -> float:
    """``pi H^2 (3 R - H) / 3`` with ``H = R (1 - sin phi_hat)``."""
    H = R * (1.0 - math.sin(phi_hat))
    return math.pi * H**2 * (3.0 * R - H) / 3.0


def perturbed_cap(N: int, seed: int, lift: float = 0.0) -> tuple[np.ndarray, float]:
    """A randomly perturbed cap state (pole kept on the axis) and the reference base height.

    ``lift`` moves the base node off the plane, so that the skirt term is exercised too.
    """
    cap = spherical_cap(R, PHI_HAT, N)
    rng = np.random.default_rng(seed)
    x = cap.x + 0.05 * rng.standard_normal(2 * N)
    x[-2] = 0.0
    x[1] = cap.z[0] + lift
    return x, float(cap.z[0])


# ---- closed forms ------------------------------------------------------------------------------------

@pytest.mark.parametrize("N", [2, 3, 7])
def test_cone(N: int) -> None:
    a, H, z0 = 0.7, 1.3, 0.4
    t = np.linspace(0.0, 1.0, N)
    x = interleave(a * (1.0 - t), z0 + H * t)  # collinear nodes: any N gives the same cone
    assert enclosed_volume(x, z0) == pytest.approx(math.pi * a**2 * H / 3.0, rel=1e-14)


def test_cylinder_with_lid_and_skirt() -> None:
    a, H = 0.8, 1.7
    # wall up at r = a, then a flat lid in to the axis; the lid contributes nothing (dz = 0)
    x = interleave([a, a, a, 0.5 * a, 0.0], [0.0, 0.5 * H, H, H, H])
    assert enclosed_volume(x, 0.0) == pytest.approx(math.pi * a**2 * H, rel=1e-14)
    # a plane below the base node adds the cylinder between them
    assert enclosed_volume(x, -0.3) == pytest.approx(math.pi * a**2 * (H + 0.3), rel=1e-14)
    # a truncated cone (frustum) from r = a down to r = b < a, closed by a lid
    b = 0.3
    y = interleave([a, b, 0.0], [0.0, H, H])
    assert enclosed_volume(y, 0.0) == pytest.approx(math.pi * H * (a * a + a * b + b * b) / 3.0, rel=1e-14)


@pytest.mark.parametrize("pole_ratio", [1.0, 0.5])
def test_cap_volume_converges_at_second_order(pole_ratio: float) -> None:
    exact = cap_volume(R, PHI_HAT)
    Ns = [20, 40, 80, 160, 320]
    err = []
    for N in Ns:
        cap = spherical_cap(R, PHI_HAT, N, pole_ratio=pole_ratio)
        err.append(exact - enclosed_volume(cap.x, float(cap.z[0])))
    err = np.array(err)
    # chords lie inside the sphere: the polyline's volume is short of the cap's
    assert np.all(err > 0)
    # observed order in the number of edges N - 1 (the spacing is proportional to 1 / (N - 1))
    edges = np.array(Ns) - 1.0
    order = np.log(err[:-1] / err[1:]) / np.log(edges[1:] / edges[:-1])
    # measured: 1.9998 .. 2.0000 (uniform), 1.9993 .. 2.0000 (graded)
    assert np.all(np.abs(order - 2.0) < 0.005), order
    assert err[-1] / exact < 1e-4


# ---- derivatives -------------------------------------------------------------------------------------

@pytest.mark.parametrize("lift", [0.0, 0.07])
def test_gradient_matches_central_differences(lift: float) -> None:
    x, z_ref = perturbed_cap(9, seed=1, lift=lift)
    g = volume_gradient(x, z_ref)
    eps = 1e-5
    fd = np.empty_like(g)
    for k in range(x.size):
        e = np.zeros_like(x)
        e[k] = eps
        fd[k] = (enclosed_volume(x + e, z_ref) - enclosed_volume(x - e, z_ref)) / (2 * eps)
    # central differences of a cubic are off by eps^2/6 V''' only
    np.testing.assert_allclose(g, fd, rtol=0, atol=1e-9)


@pytest.mark.parametrize("lift", [0.0, 0.07])
def test_hessian_matches_central_differences_and_is_symmetric(lift: float) -> None:
    x, z_ref = perturbed_cap(9, seed=2, lift=lift)
    H = volume_hessian(x, z_ref)
    assert isinstance(H, sp.csr_matrix) and H.shape == (x.size, x.size)
    D = H.toarray()
    assert np.array_equal(D, D.T)
    eps = 1e-5
    fd = np.empty_like(D)
    for k in range(x.size):
        e = np.zeros_like(x)
        e[k] = eps
        fd[:, k] = (volume_gradient(x + e, z_ref) - volume_gradient(x - e, z_ref)) / (2 * eps)
    np.testing.assert_allclose(D, fd, rtol=0, atol=1e-9)


def test_hessian_fits_inside_the_shell_band() -> None:
    N = 12
    x, z_ref = perturbed_cap(N, seed=3, lift=0.05)
    H = volume_hessian(x, z_ref).tocoo()
    width = int(np.max(np.abs(H.row - H.col)))
    assert width == VOLUME_HALF_BANDWIDTH <= HALF_BANDWIDTH
    # the pattern is a subset of the shell Hessian's, so adding the two keeps the shell's pattern
    shell = ShellEnergy(spherical_cap(R, PHI_HAT, N), E=1.0, h=0.01, nu=0.3).hessian(x)
    S = shell.copy()
    S.data[:] = 1.0
    P = volume_hessian(x, z_ref)
    P.data[:] = 1.0
    assert (P - P.multiply(S)).nnz == 0
    # the pattern does not depend on the state
    Q = volume_hessian(np.zeros_like(x), 0.0)
    assert np.array_equal(Q.indptr, P.indptr) and np.array_equal(Q.indices, P.indices)


# ---- invariances and physics -------------------------------------------------------------------------

@pytest.mark.parametrize("z_ref", [0.0, 0.4])
def test_dilation_gives_three_times_the_volume(z_ref: float) -> None:
    """Euler: ``V`` is homogeneous of degree 3 in ``(x, z_ref)``, and ``dV/dz_ref = -pi r_0^2``."""
    x, _ = perturbed_cap(15, seed=4, lift=0.1)
    V = enclosed_volume(x, z_ref)
    r0 = x[0]
    assert x @ volume_gradient(x, z_ref) - math.pi * r0**2 * z_ref == pytest.approx(3.0 * V, rel=1e-13)
    # the same through the dilated volume itself, V((1+e) x, (1+e) z_ref) = (1+e)^3 V
    e = 0.01
    assert enclosed_volume((1 + e) * x, (1 + e) * z_ref) == pytest.approx((1 + e) ** 3 * V, rel=1e-13)


def test_translation_with_the_plane_and_rigid_lift() -> None:
    x, z_ref = perturbed_cap(15, seed=5, lift=0.03)
    V = enclosed_volume(x, z_ref)
    t = 0.37
    shifted = x.copy()
    shifted[1::2] += t
    # every node and the plane together: the same body
    assert enclosed_volume(shifted, z_ref + t) == pytest.approx(V, rel=1e-13)
    # the shell alone over the fixed plane: the volume grows by the base disc times the lift,
    # i.e. the pressure's resultant on the shell is p times its projected area pi r_0^2
    assert enclosed_volume(shifted, z_ref) - V == pytest.approx(math.pi * x[0] ** 2 * t, rel=1e-12)
    assert volume_gradient(x, z_ref)[1::2].sum() == pytest.approx(math.pi * x[0] ** 2, rel=1e-13)


def _shell_flux(x: np.ndarray, dx: np.ndarray) -> float:
    """Flux of the displacement ``dx`` through the shell's surface, ``2 pi int r (dr z' - dz r') dt``.

    Linear interpolation on every edge; the integrand is quadratic in the edge parameter, so the
    2-point Gauss rule is exact.  Independent of the volume formula: this is the pressure's virtual
    work per unit pressure on the shell alone.
    """
    r, z = split(x)
    dr, dz = split(dx)
    total = 0.0
    for s in (0.5 - 0.5 / math.sqrt(3.0), 0.5 + 0.5 / math.sqrt(3.0)):
        rs = (1 - s) * r[:-1] + s * r[1:]
        drs = (1 - s) * dr[:-1] + s * dr[1:]
        dzs = (1 - s) * dz[:-1] + s * dz[1:]
        total += 0.5 * np.sum(2 * math.pi * rs * (drs * np.diff(z) - dzs * np.diff(r)))
    return float(total)


def test_gradient_is_the_pressure_work_on_the_shell() -> None:
    """``dV . dx`` equals the shell's swept volume whenever the skirt carries no flux.

    That is: the base node on the plane (any ``dx``, the sliding base's case), or the base node
    off the plane with ``dr_0 = 0`` (a base lifting off vertically).  The plane through the
    current base node would miss ``pi r_0^2 dz_0`` (module docstring).
    """
    rng = np.random.default_rng(6)
    x, z_ref = perturbed_cap(11, seed=6)
    dx = rng.standard_normal(x.size)
    dx[-2] = 0.0  # the pole stays on the axis
    assert volume_gradient(x, z_ref) @ dx == pytest.approx(_shell_flux(x, dx), rel=1e-12)
    y, z_ref = perturbed_cap(11, seed=7, lift=0.1)
    # in general the skirt adds its own flux, 2 pi r_0 (z_0 - z_ref) dr_0 ...
    skirt = 2 * math.pi * y[0] * (y[1] - z_ref) * dx[0]
    assert abs(skirt) > 1e-2
    assert volume_gradient(y, z_ref) @ dx == pytest.approx(_shell_flux(y, dx) + skirt, rel=1e-12)
    # ... which vanishes when the base ring only moves vertically
    dx[0] = 0.0
    assert volume_gradient(y, z_ref) @ dx == pytest.approx(_shell_flux(y, dx), rel=1e-12)
    # the plane through the current base node: its gradient is dV - pi r_0^2 e_{z_0}
    current = volume_gradient(x, float(x[1]))
    current[1] -= math.pi * x[0] ** 2
    e_z0 = np.zeros_like(x)
    e_z0[1] = 1.0
    assert abs(current @ e_z0 - _shell_flux(x, e_z0)) == pytest.approx(math.pi * x[0] ** 2, rel=1e-12)


# ---- the pressure term -------------------------------------------------------------------------------

def test_pressure_term_pieces() -> None:
    cap = spherical_cap(R, PHI_HAT, 10)
    term = PressureTerm.from_reference(cap.x)
    assert term.z_ref == cap.z[0]
    assert term.V0 == pytest.approx(cap_volume(R, PHI_HAT), rel=1e-2)
    assert term.energy(cap.x, 2.5) == 0.0
    x, _ = perturbed_cap(10, seed=8)
    p = -1.7
    assert term.energy(x, p) == pytest.approx(p * (enclosed_volume(x, term.z_ref) - term.V0), rel=1e-14)
    np.testing.assert_array_equal(term.gradient(x, p), p * volume_gradient(x, term.z_ref))
    np.testing.assert_array_equal(term.hessian(x, p).toarray(), p * volume_hessian(x, term.z_ref).toarray())
    np.testing.assert_array_equal(term.gradient_dp(x), volume_gradient(x, term.z_ref))
    dp = 1e-3
    assert term.energy_dp(x) == pytest.approx((term.energy(x, p + dp) - term.energy(x, p - dp)) / (2 * dp),
                                              rel=1e-10)
    np.testing.assert_allclose(term.gradient_dp(x), (term.gradient(x, p + dp) - term.gradient(x, p - dp)) / (2 * dp),
                               rtol=0, atol=1e-12)


def test_bad_input() -> None:
    with pytest.raises(ValueError):
        enclosed_volume(np.zeros(5), 0.0)
    with pytest.raises(ValueError):
        enclosed_volume(np.zeros(2), 0.0)
    with pytest.raises(ValueError):
        PressureTerm(float("nan"))


def test_derivatives_equal_sympy_in_high_precision() -> None:
    """Gradient and Hessian against sympy's exact derivatives of the volume formula, evaluated at 40 digits."""
    import sympy

    N = 5
    rs, zs = sympy.symbols(f"r0:{N}"), sympy.symbols(f"z0:{N}")
    z_ref = sympy.Rational(-1, 7)
    V = sympy.pi / 3 * sum((rs[i] ** 2 + rs[i] * rs[i + 1] + rs[i + 1] ** 2) * (zs[i + 1] - zs[i]) for i in range(N - 1))
    V += sympy.pi * rs[0] ** 2 * (zs[0] - z_ref)
    dofs = [v for pair in zip(rs, zs) for v in pair]
    rng = np.random.default_rng(7)
    x = rng.uniform(0.1, 1.0, 2 * N)
    subs = {s: sympy.Float(float(v), 40) for s, v in zip(dofs, x)}
    grad = np.array([float(sympy.diff(V, d).evalf(40, subs=subs)) for d in dofs])
    hess = np.array([[float(sympy.diff(V, a, b).evalf(40, subs=subs)) for b in dofs] for a in dofs])
    assert enclosed_volume(x, -1 / 7) == pytest.approx(float(V.evalf(40, subs=subs)), rel=1e-14)
    assert np.allclose(volume_gradient(x, -1 / 7), grad, rtol=1e-14, atol=1e-14 * np.abs(grad).max())
    assert np.allclose(volume_hessian(x, -1 / 7).toarray(), hess, rtol=1e-14, atol=1e-14 * np.abs(hess).max())


def test_pressure_work_equals_the_stored_energy_along_a_traced_path() -> None:
    """Along an equilibrium path from the unloaded cap, ``E_el(end) = -int p dV`` (energy balance of a
    conservative load), with ``int p dV`` by the trapezoidal rule on the stored points (error ~ step^2).
    """
    import contin
    from contin_models.shell.pressure import ShellPressure

    # units h = 1 and p_c = 1 (E from p_c = 2 E (h/R)^2 / sqrt(3 (1 - nu^2))), a cap with lambda = 6
    R = 100.0
    E = math.sqrt(3.0 * (1.0 - 0.3**2)) / (2.0 * (1.0 / R) ** 2)
    pr = ShellPressure(R=R, E=E, nu=0.3, h=1.0, phi_hat=math.asin(1.0 - 5.45 / R), N=60, boundary="clamped")
    br = contin.continuation(pr, pr.reference_unknowns(), 0.0, contin.Settings(ds=0.01, ds_max=0.01, max_steps=400),
                             p_max=0.8, stability=False)
    assert br.message.startswith("stopped at p_max")
    p = np.asarray(br.p)
    V = np.array([pr.pressure.volume(pr.full_state(u)) for u in br.u])
    work = float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(V)))
    stored = pr.structure.energy(pr.full_state(br.u[-1]))
    assert stored > 0 and work < 0
    assert stored == pytest.approx(-work, rel=2e-4)
