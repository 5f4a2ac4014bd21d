"""The bar-hinge shallow arch against Marguerre's shallow-arch theory (issue 15).

The reference is :class:`contin_models.benchmarks.marguerre.MarguerreArch`, the pinned shallow arch in
sine modes; its derivatives are checked by finite differences and its two-mode truncation against the
closed form of the half-sine arch.  The bar-hinge arch's first branch-point load must then agree with
it at a shallow case, within a tolerance measured with ``python -m studies.arch_marguerre``.
"""

from __future__ import annotations


import numpy as np
import pytest

from contin import continuation


from contin_models.benchmarks import arch, marguerre  # noqa: E402


def first_loads(problem, n_unknowns: int, unit: float, rise: float) -> dict[str, float]:
    """``Q`` at the first branch point and the first fold, default continuation settings."""
    br = continuation(problem, np.zeros(n_unknowns), 0.0, bounds={"deflection": (None, 0.9 * rise)})
    out = {}
    for kind in ("branch_point", "fold"):
        pts = [s for s in br.special_points if s.kind == kind and s.located]
        assert pts, f"no located {kind}: {br.message}"
        out[kind] = pts[0].p / unit
    return out


@pytest.mark.parametrize("shape", ["sine", "parabola", "circle"])
def test_marguerre_derivatives_match_finite_differences(shape: str) -> None:
    m = marguerre.MarguerreArch(K=7, rise=0.05, shape=shape)
    rng = np.random.default_rng(1)
    a, P, h = 0.02 * rng.standard_normal(m.K), 3.0, 1e-7
    E = np.eye(m.K)
    grad = np.array([(m.energy(a + h * e, P) - m.energy(a - h * e, P)) / (2 * h) for e in E])
    hess = np.array([(m.residual(a + h * e, P) - m.residual(a - h * e, P)) / (2 * h) for e in E]).T
    f = m.residual(a, P)
    np.testing.assert_allclose(f, grad, rtol=0, atol=1e-7 * np.max(np.abs(f)))
    H = m.jacobian(a, P)
    np.testing.assert_allclose(H, hess, rtol=0, atol=1e-7 * np.max(np.abs(H)))
    np.testing.assert_array_equal(H, H.T)
    dp = (m.residual(a, P + 1e-3) - m.residual(a, P - 1e-3)) / 2e-3
    np.testing.assert_allclose(m.dresidual_dp(a, P), dp, atol=1e-9)
    # the same sign convention as ShallowArch: a positive load pushes the crown down
    assert m.observables["deflection"](np.linalg.solve(m.jacobian(0 * a, P), -m.dresidual_dp(a, P)), P) > 0


def test_half_sine_arch_derivatives_match_finite_differences() -> None:
    a = arch.ShallowArch(n=12, rise=0.05, shape="sine")
    rng = np.random.default_rng(2)
    u, P, h = 1e-3 * rng.standard_normal(2 * (a.n - 1)), 3.0, 1e-7
    E = np.eye(u.size)
    grad = np.array([(a.energy(u + h * e, P) - a.energy(u - h * e, P)) / (2 * h) for e in E])
    hess = np.array([(a.residual(u + h * e, P) - a.residual(u - h * e, P)) / (2 * h) for e in E]).T
    f, H = a.residual(u, P), a.jacobian(u, P).toarray()
    np.testing.assert_allclose(f, grad, rtol=0, atol=1e-7 * np.max(np.abs(f)))
    np.testing.assert_allclose(H, hess, rtol=0, atol=1e-7 * np.max(np.abs(H)))


@pytest.mark.parametrize("eps", [5.0, 10.0])
def test_two_modes_reproduce_the_half_sine_closed_form(eps: float) -> None:
    m = marguerre.MarguerreArch(K=2, rise=0.05, rise_over_gyration=eps, shape="sine")
    q = first_loads(m, 2, m.load_unit(), m.rise)
    closed = marguerre.two_mode_half_sine(eps)
    assert q["branch_point"] == pytest.approx(closed["branch_point"], rel=1e-9)
    assert q["fold"] == pytest.approx(closed["fold"], rel=1e-9)
    # above sqrt(22) the branch point comes first, below it the limit point
    assert (q["branch_point"] < q["fold"]) == (eps > closed["criterion"])


def test_marguerre_branch_point_is_the_second_euler_load() -> None:
    # on the symmetric path the antisymmetric mode 2 is unloaded: it bifurcates when the axial force
    # (constant along the span of the pinned arch) reaches the Euler load of mode 2, -4 pi^2 EI / L^2
    m = marguerre.MarguerreArch(K=17, rise=0.01, shape="circle")
    br = continuation(m, np.zeros(m.K), 0.0, bounds={"deflection": (None, 0.9 * m.rise)})
    bp = br.branch_points()[0]
    N = m.EA / m.span * m._T(bp.u)
    assert N == pytest.approx(-4 * np.pi ** 2 * m.EI / m.span ** 2, rel=1e-9)


#: |Q(bars) / Q(Marguerre) - 1| allowed at n = 80, h / L = 0.01, h / r = 10.  Measured: -0.127 % for
#: the branch point, -0.164 % for the fold (studies/arch_marguerre.py), of which the n^-2 mesh error
#: is 0.076 % / 0.11 % (Richardson, successive differences shrinking by 4.00) and the shallow-arch
#: error 0.050 % (about 5 (h/L)^2).  A hinge stiffness off by 10 % moves the branch point by 9 %, an
#: axial stiffness off by 10 % by +0.5 % or -0.9 %: both far outside.
TOL = 3e-3


def test_bar_hinge_branch_point_agrees_with_marguerre_at_a_shallow_arch() -> None:
    n, rise, rg = 80, 0.01, 10.0
    m = marguerre.MarguerreArch(K=33, rise=rise, rise_over_gyration=rg, shape="parabola")
    ref = first_loads(m, m.K, m.load_unit(), rise)
    assert ref["branch_point"] == pytest.approx(71.588037, rel=1e-6)  # the study's value, K converged
    a = arch.ShallowArch(n=n, rise=rise, rise_over_gyration=rg)
    q = first_loads(a, 2 * (n - 1), m.load_unit(), rise)
    assert abs(q["branch_point"] / ref["branch_point"] - 1) < TOL
    assert abs(q["fold"] / ref["fold"] - 1) < TOL
    # a wrong hinge spring is caught
    stiff = arch.ShallowArch(n=n, rise=rise, rise_over_gyration=rg)
    stiff.k_hinge *= 1.1
    wrong = first_loads(stiff, 2 * (n - 1), m.load_unit(), rise)["branch_point"]
    assert abs(wrong / ref["branch_point"] - 1) > 10 * TOL


def test_limit_point_comes_first_at_a_low_rise() -> None:
    m = marguerre.MarguerreArch(K=17, rise=0.01, rise_over_gyration=5.0, shape="parabola")
    br = continuation(m, np.zeros(m.K), 0.0, bounds={"deflection": (None, 0.9 * m.rise)})
    # along the symmetric path: the snap first, then (past it, at a slightly lower load) the bifurcation
    assert [s.kind for s in br.special_points][:2] == ["fold", "branch_point"]
    assert all(s.located for s in br.special_points[:2])


@pytest.mark.slow
def test_differences_shrink_with_n_and_with_the_rise() -> None:
    from studies.arch_marguerre import compare, shrinking

    rows = compare(True, (20, 40, 80))
    assert shrinking(rows)
    extrapolated = [r for r in rows if r["n"] == "inf" and r["shape"] == "circle"]
    for r in extrapolated:
        assert r["ratio"] == pytest.approx(4.0, rel=0.02)  # an n^-2 mesh error
    for rg in (10.0, 5.0):
        # what is left after the mesh error goes like (h / L)^2: the shallow-arch approximation
        c = [abs(r["err_bp"]) / r["h/L"] ** 2 for r in extrapolated if r["h/r"] == rg]
        assert max(c) / min(c) < 1.4
