"""The baselines of ``studies.accuracy`` (:mod:`studies.baselines`) against independent answers.

* natural-parameter stepping with bisection: the bracket holds the von Mises truss's closed-form
  limit load, and the shell's limit load located as a fold by PALC under force control;
* implicit dynamic relaxation: the masses against the cap's closed-form area, the lowest frequency
  against a dense generalized eigensolve and the truss's closed-form eigenvalues, the relaxed
  static state against the truss's closed-form equilibrium, the snap load of a slow force ramp
  against the delayed-bifurcation lag of the fold's normal form (Airy), and the reaction maximum
  of a displacement ramp on the shell against PALC, with the lag proportional to the ramp rate.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.optimize import brentq

from contin_models.benchmarks.truss import VonMisesTruss
from contin_models.shell import ShellPointLoad
from studies.baselines import (NewtonFailure, critical_damping, dr_reaction_maximum, dr_relax, dr_snap_load,
                               lowest_frequency, lumped_masses, natural_parameter_limit, newton)
from studies.shell_mesh_convergence import first_force_maximum, force_limit_load

#: first zero of Ai(-s): the blow-up time of z' = t + z^2 from its stable branch
AIRY_A1 = 2.338107410459767


def _truss() -> tuple[VonMisesTruss, float, float]:
    truss = VonMisesTruss(a=1.0, b=0.5, k=1.0)
    (y_star, p_max), _ = truss.limit_points()
    return truss, y_star, p_max


# ---- natural-parameter stepping ---------------------------------------------------------------------
def test_natural_parameter_brackets_the_truss_limit_load() -> None:
    truss, y_star, p_max = _truss()
    tol = 1e-8
    res = natural_parameter_limit(truss, np.array([0.0, 0.5]), 0.0, 0.01, tol, max_jump=("y", 0.1))
    assert res.status == "bracketed" and res.failures >= 1
    assert res.hi - res.lo <= tol
    # the closed-form limit load lies in the bracket (Newton fails beyond it, converges below)
    assert res.lo <= p_max <= res.hi
    assert res.p_limit == pytest.approx(p_max, abs=tol)
    # the last converged state is on the symmetric path just above the fold, where y - y* ~ sqrt(P_max - P)
    assert res.u_lo[0] == pytest.approx(0.0, abs=1e-12)
    assert y_star < res.u_lo[1] < y_star + 1e-3


def test_natural_parameter_agrees_with_the_palc_fold_of_the_shell() -> None:
    N = 40
    shell = ShellPointLoad(N=N, control="force")
    unit = 2.0 * math.pi * shell.D / shell.R
    res = natural_parameter_limit(shell, shell.reference_unknowns(), 0.0, 1.0 * unit, 1e-4 * unit,
                                  max_jump=("w", 0.05 * shell.R))
    assert res.status == "bracketed"
    fold = force_limit_load(N)  # PALC under force control, the fold located by its extended system
    width = res.hi - res.lo
    assert width <= 1e-4 * unit
    assert res.lo - 1e-9 * unit <= fold <= res.hi + 1e-9 * unit
    assert abs(res.p_limit - fold) <= 0.5 * width + 1e-9 * unit
    # the converged state is an equilibrium of the dead load (not a point left unconverged)
    r = shell.residual(res.u_lo, res.lo)
    assert np.max(np.abs(r)) <= 1e-10 * shell.residual_scale
    assert np.isfinite(res.observables["w"]) and 0.2 < res.observables["w"] / shell.R < 0.4


def test_newton_past_the_fold_fails_or_lands_on_the_far_branch_which_the_jump_guard_rejects() -> None:
    truss, y_star, p_max = _truss()
    # just past the limit load there is no equilibrium near the upper branch: Newton fails (and says so)
    with pytest.raises(NewtonFailure):
        newton(truss, np.array([0.0, 0.3]), 1.05 * p_max, max_iter=25)
    # further past it, Newton may converge -- on the inverted branch, y < -b (closed form P(y))
    u, _, _ = newton(truss, np.array([0.0, 0.3]), 1.5 * p_max, max_iter=25)
    assert u[1] < -truss.b
    assert truss.load_on_symmetric_path(u[1]) == pytest.approx(1.5 * p_max, rel=1e-9)
    # so without the jump guard the stepping follows the far branch and never brackets the limit load
    unguarded = natural_parameter_limit(truss, np.array([0.0, 0.5]), 0.0, 0.01, 1e-8, max_steps=200)
    assert unguarded.status != "bracketed" and unguarded.lo > p_max
    with pytest.raises(ValueError):
        natural_parameter_limit(truss, np.array([0.0, 0.5]), 0.0, 0.0, 1e-6)


# ---- dynamic relaxation: ingredients ----------------------------------------------------------------
def test_lumped_masses_add_up_to_the_cap() -> None:
    rho = 1000.0
    shell = ShellPointLoad(N=200, control="force")  # the pole's z is an unknown: every node counted once
    m = lumped_masses(shell, rho)
    assert m.shape == (shell.n,) and np.all(m > 0)
    idx = np.asarray(shell.idx)
    node_mass = np.concatenate([[m[0]], m[idx % 2 == 1]])  # r_0 (the base) and every free z
    assert node_mass.size == shell.N
    exact = rho * shell.h * 2.0 * math.pi * shell.R ** 2 * (1.0 - math.sin(shell.phi_hat))
    assert node_mass.sum() == pytest.approx(exact, rel=1e-3)
    # the r and z unknowns of a node carry the same mass
    r_of = {i // 2: k for k, i in enumerate(idx) if i % 2 == 0}
    z_of = {i // 2: k for k, i in enumerate(idx) if i % 2 == 1}
    for node in set(r_of) & set(z_of):
        assert m[r_of[node]] == m[z_of[node]]


def test_lowest_frequency_matches_closed_form_and_dense_eigensolve() -> None:
    truss, _, _ = _truss()
    lam = truss.eigenvalues_on_symmetric_path(0.5)
    assert lowest_frequency(truss, np.array([0.0, 0.5]), 0.0, np.ones(2)) == pytest.approx(math.sqrt(lam[0]), rel=1e-12)
    assert lowest_frequency(truss, np.array([0.0, 0.5]), 0.0, np.array([4.0, 4.0])) == pytest.approx(
        math.sqrt(lam[0] / 4.0), rel=1e-12)
    shell = ShellPointLoad(N=20)
    m = lumped_masses(shell, 1000.0)
    u = shell.reference_unknowns()
    K = shell.jacobian(u, 0.0).toarray()
    dense = sla.eigh(K, np.diag(m), eigvals_only=True)[0]
    assert lowest_frequency(shell, u, 0.0, m) == pytest.approx(math.sqrt(dense), rel=1e-9)
    with pytest.raises(ValueError):
        lowest_frequency(truss, np.array([0.0, 0.0]), 0.0, np.ones(2))  # flat truss: not positive definite


def test_relaxed_state_is_the_static_equilibrium() -> None:
    truss, y_star, p_max = _truss()
    m = np.ones(2)
    alpha = critical_damping(lowest_frequency(truss, np.array([0.0, 0.5]), 0.0, m))
    p = 0.9 * p_max
    y_exact = brentq(lambda y: truss.load_on_symmetric_path(y) - p, y_star, 0.5, xtol=1e-15)
    # from rest at the unloaded shape, and from a swayed, moving start: both settle on the same state
    for u0, v0 in ((np.array([0.0, 0.5]), None), (np.array([0.05, 0.45]), np.array([0.01, -0.02]))):
        r = dr_relax(truss, u0, p, m, alpha, 0.5, vtol=1e-12, v0=v0)
        assert r.status == "stopped"
        assert r.u[0] == pytest.approx(0.0, abs=1e-9)
        assert r.u[1] == pytest.approx(y_exact, abs=1e-9)
        assert np.all(np.isfinite(r.u))


# ---- dynamic relaxation: the snap of a force ramp ----------------------------------------------------
def _normal_form_lag(truss: VonMisesTruss, y_star: float, c: float, rate: float) -> float:
    """Overdamped fold normal form ``c z' = rate t + kappa z^2 / 2``: the load passes the limit load by
    ``a1 (2 c^2 rate^2 / kappa)^(1/3)`` when ``z`` blows up, ``kappa = -P''(y*)`` of the closed-form path."""
    L = math.hypot(truss.a, y_star)
    kappa = 6.0 * truss.k * y_star * truss.L0 * truss.a ** 2 / L ** 5
    return AIRY_A1 * (2.0 * c * c * rate * rate / kappa) ** (1.0 / 3.0)


def test_force_ramp_snaps_after_the_limit_load_by_the_normal_form_lag() -> None:
    truss, y_star, p_max = _truss()
    m = np.ones(2)
    alpha = critical_damping(lowest_frequency(truss, np.array([0.0, 0.5]), 0.0, m))
    p0 = 0.9 * p_max
    start = dr_relax(truss, np.array([0.0, 0.5]), p0, m, alpha, 0.5, vtol=1e-12).u
    lags = []
    for rate, tol in ((1e-5, 0.05), (1e-6, 0.02)):
        res = dr_snap_load(truss, start, m, alpha, 1.0, rate, p0=p0, monitor="y", jump_rate=0.03, p_end=2 * p_max)
        lag = res["p_snap"] - p_max
        predicted = _normal_form_lag(truss, y_star, alpha * 1.0, rate)
        assert lag > 0  # no snap below the limit load
        assert lag == pytest.approx(predicted, rel=tol)
        assert res["monitor_before"] < y_star  # it has crept past the fold before leaving
        lags.append(lag)
    # the lag falls like rate^(2/3)
    assert lags[0] / lags[1] == pytest.approx(10 ** (2 / 3), rel=0.05)


def test_displacement_ramp_on_the_shell_lags_in_proportion_to_the_rate() -> None:
    N = 40
    shell = ShellPointLoad(N=N)
    F_palc, w_over_R = first_force_maximum(ShellPointLoad(N=N))
    m = lumped_masses(shell, 1000.0)
    u0 = shell.reference_unknowns()
    w1 = lowest_frequency(shell, u0, 0.0, m)
    alpha = critical_damping(w1)
    errs = []
    for dt_omega, eps in ((1e2, 1e-5), (1e3, 1e-6)):  # the same 1e-3 R per step: the same samples of w
        res = dr_reaction_maximum(shell, u0, m, alpha, dt_omega / w1, eps * shell.R * w1, p_end=0.5 * shell.R)
        assert res["status"] == "stopped"
        assert res["p_at_max"] == pytest.approx(w_over_R * shell.R, abs=2e-3 * shell.R)
        errs.append(res["F_max"] - F_palc)
    # the reaction runs ahead of the static one (damping resists the motion), by an amount proportional
    # to the rate: ten times slower, ten times closer (up to the sampling of the maximum, < 1e-5 F)
    assert errs[0] > errs[1] > 0
    assert errs[0] / errs[1] == pytest.approx(10.0, rel=0.2)
    assert errs[1] / F_palc < 1e-3


def test_a_force_maximum_only_bracketed_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    # with tol = xtol = 1e-3 the corrector jumps across the maximum at N = 200 and the event cannot be
    # located (docs/accuracy.md); the stored point next to it must not come back as F_max
    import studies.shell_mesh_convergence as smc

    loose = smc.continuation

    def sloppy(*args, **kwargs):
        return loose(*args, **{**kwargs, "tol": 1e-3, "xtol": 1e-3})

    monkeypatch.setattr(smc, "continuation", sloppy)
    with pytest.raises(RuntimeError, match="bracketed but not located|no maximum"):
        first_force_maximum(ShellPointLoad(N=200))
