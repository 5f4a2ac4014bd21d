"""Force control of the indenter (issue 4, acceptance point 6): :class:`ShellIndentationForce`.

"Force control on the indenter reproduces the displacement-controlled branch where both are
stable."  The reference is the displacement-controlled :class:`ShellIndentation` (indenter travel
``w_b`` prescribed), traced independently from the undeformed cap; the force-controlled trace
(``w_b`` an unknown under a dead load ``F``) starts from one of its converged contact states (at
``F = 0`` without contact the indenter floats and ``w_b`` is undetermined) and runs in ``F`` up to
its limit point.  Along the way: the same equilibria at the same loads, the limit point at the
maximum of ``F`` along the displacement path, the same stability labels; plus the new problem's
derivatives against finite differences and its linear algebra (the band is kept: block
elimination of ``w_b`` on the banded LU, checked against dense solves, with a safe fallback).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

import contin
from contin.numerics.linalg import SingularMatrixError
from contin_models.contact import Sphere
from contin_models.contact.indentation import BorderedBandedLU, ShellIndentation, ShellIndentationForce

N = 60
W_START = 0.05  # travel of the contact state the force-controlled trace starts from
F_LEVELS = (25.0, 30.0, 40.0, 45.0, 49.0)  # loads between the start (F ~ 21.6) and the limit (F ~ 49.6)
W_END = 0.33  # the displacement trace goes a little past the maximum of F (w_b ~ 0.282)


def _param_weight(P) -> float:
    # F measured in ten times the shell's force unit 2 pi D / R (the scenes weigh it by the cap's rest
    # stiffness instead; this test's short trace needs neither, and keeps its own weight)
    return 1.0 / (10.0 * 2.0 * math.pi * P.D / P.R)


def _newton(P, u, p, tol=1e-12):
    """Newton at fixed parameter with the model's step filter (independent of the engine)."""
    u = np.array(u, dtype=float)
    for _ in range(30):
        r = P.residual(u, p)
        if np.max(np.abs(r)) <= tol * P.residual_scale:
            return u
        du = -P.factorize(P.jacobian(u, p)).solve(r)
        u = u + min(1.0, P.max_step_fraction(u, p, du, 0.0)) * du
    raise AssertionError("Newton did not converge")


def _richardson(fun, h):
    # central differences with one Richardson step: the barrier's third derivative (~K/d) is large
    d1 = (fun(h) - fun(-h)) / (2 * h)
    d2 = (fun(h / 2) - fun(-h / 2)) / h
    return (4 * d2 - d1) / 3


@pytest.fixture(scope="module")
def traces():
    P = ShellIndentation(N=N, indenter=Sphere(0.5))
    Pf = ShellIndentationForce.from_displacement(P)
    bd = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=W_END, max_steps=1000,
                             stability=True, n_eigs=0, detect_branch_points=False,
                             events=[contin.extremum("F", "max"), contin.crossing("w_b", W_START)]
                             + [contin.crossing("F", v, direction=+1) for v in F_LEVELS])
    assert bd.status == "bound", bd.message
    (start,) = bd.events(f"w_b={W_START:g}")
    U0, F0 = Pf.from_displacement_state(start.u, start.p)
    assert 0 < F0 < F_LEVELS[0]
    stats0 = dict(Pf.linear_solver_stats)
    bf = contin.continuation(Pf, U0, F0, ds=0.005, ds_max=0.02, param_weight=_param_weight(Pf), max_steps=1000,
                             stop_at=("fold",), stability=True, n_eigs=0,
                             events=[contin.crossing("F", v) for v in F_LEVELS])
    stats = {k: Pf.linear_solver_stats[k] - stats0[k] for k in ("factorizations", "sparse", "refined")}
    return P, Pf, bd, bf, stats


def test_force_control_reproduces_the_displacement_branch(traces):
    P, Pf, bd, bf, _ = traces
    assert bf.status == "event" and "fold" in bf.message
    assert np.all(np.diff(bf.p) > 0)  # the load rises monotonically up to its limit point
    # the same equilibria at the same loads: both traces locate F = F_k on their own branch
    for F in F_LEVELS:
        (a,) = bd.events(f"F={F:g}")
        (b,) = bf.events(f"F={F:g}")
        assert b.p == pytest.approx(F, rel=1e-12)
        for name in ("w_b", "w_s"):
            assert b.observables[name] == pytest.approx(a.observables[name], rel=1e-8)  # measured <= 6e-11
    # every few stored points of the force trace: Newton on displacement control at the same w_b,
    # started from the displacement trace interpolated there (not from the force-control state)
    for k in range(1, len(bf), 8):
        U, F = bf.u[k], bf.p[k]
        u_f, w_b = Pf.split(U)
        i = int(np.searchsorted(bd.p, w_b))
        t = (w_b - bd.p[i - 1]) / (bd.p[i] - bd.p[i - 1])
        u = _newton(P, (1 - t) * bd.u[i - 1] + t * bd.u[i], w_b)
        obs = P.evaluate_observables(u, w_b)
        assert obs["F"] == pytest.approx(F, rel=1e-8)  # measured <= 5e-11
        assert obs["w_s"] == pytest.approx(bf.observables["w_s"][k], rel=1e-8)
        assert np.max(np.abs(u - u_f)) <= 1e-8 * P.R


def test_force_limit_point_is_the_maximum_of_the_force_under_displacement_control(traces):
    _, _, bd, bf, _ = traces
    (peak,) = bd.events("max(F)")
    (fold,) = bf.folds()
    assert fold.located and fold.info["ends_branch"] and fold.info["stable_before"]
    assert fold.p == pytest.approx(peak.observables["F"], rel=1e-6)  # measured 8e-11
    # the travel at the peak: the extremum event differentiates F along the path numerically
    assert fold.observables["w_b"] == pytest.approx(peak.observables["w_b"], rel=1e-6)  # measured 7e-8
    assert fold.observables["w_s"] == pytest.approx(peak.observables["w_s"], rel=1e-6)
    assert bf.p[-1] == fold.p and bd.p[-1] > fold.observables["w_b"]  # the reference runs past the peak


def test_stability_labels_agree_between_the_controls(traces):
    P, Pf, bd, bf, _ = traces
    assert list(bf.stability_by) == ["force", "displacement"]  # the control's own label is primary
    assert list(bd.stability_by) == ["displacement", "force"]
    # up to its limit point (the last point, where the count is decided by roundoff) the
    # force-controlled branch is stable under both controls
    assert np.all(bf.stability_by["force"][0][:-1] == 0) and np.all(bf.stability_by["displacement"][0] == 0)
    # the displacement branch: force-stable before the peak of F, one unstable mode after it
    (peak,) = bd.events("max(F)")
    w_peak = peak.observables["w_b"]
    force_label = bd.stability_by["force"][0]
    assert np.all(force_label[bd.p < w_peak] == 0) and np.all(force_label[bd.p > w_peak] == 1)
    assert np.all(bd.stability_by["displacement"][0] == 0)
    # the same states counted by each problem (both labels), on both sides of the peak
    picks = np.flatnonzero(bd.p >= W_START)
    picks = np.append(picks[:: max(1, picks.size // 12)], len(bd.p) - 1)  # the last point is past the peak
    assert np.any(bd.p[picks] > w_peak)
    def counts(problem: contin.Problem, u: np.ndarray, p: float) -> dict[str, int]:
        return {label: info.n_negative for label, info in problem.stability(u, p).items()}

    for k in picks:
        U, F = Pf.from_displacement_state(bd.u[k], bd.p[k])
        assert counts(Pf, U, F) == counts(P, bd.u[k], bd.p[k])
    for k in range(0, len(bf), 10):
        u, w_b = Pf.split(bf.u[k])
        assert counts(P, u, w_b) == {"displacement": 0, "force": 0}


def test_the_band_is_kept_by_block_elimination(traces):
    P, Pf, bd, bf, stats = traces
    # every factorization of the trace took the block path (banded LU + 1x1 Schur complement)
    assert stats["factorizations"] > 0 and stats["sparse"] == 0
    k = len(bf) // 2
    U, F = bf.u[k], bf.p[k]
    J = Pf.jacobian(U, F)
    fac = Pf.factorize(J)
    assert type(fac) is BorderedBandedLU and fac.path == "block"
    # the leading block is the displacement-control Jacobian; the border lives on the contact nodes
    u, w_b = Pf.split(U)
    assert abs(J[:-1, :-1] - P.jacobian(u, w_b)).max() == 0
    # (at most the r and z of the three nodes of each contact cell)
    assert 0 < np.count_nonzero(J[:-1, -1].toarray()) <= 6 * P.evaluate_one("n_contact", u, w_b)
    Jd = J.toarray()
    assert np.array_equal(Jd, Jd.T)
    rng = np.random.default_rng(5)
    norm = np.max(np.abs(Jd).sum(axis=1))
    cond = np.linalg.cond(Jd)
    for trans in (False, True):
        for b in (rng.standard_normal(Pf.n), rng.standard_normal((Pf.n, 3))):
            x = fac.solve(b, trans=trans)
            M = Jd.T if trans else Jd
            x_ref = np.linalg.solve(M, b)
            assert x.shape == b.shape
            assert np.max(np.abs(M @ x - b)) <= 1e-14 * norm * np.max(np.abs(x))  # backward stable
            assert np.max(np.abs(x - x_ref)) <= 10 * cond * 2.2e-16 * np.max(np.abs(x_ref))
    sign, logdet = fac.det_sign_log()
    ref = np.linalg.slogdet(Jd)
    assert sign == ref[0] and logdet == pytest.approx(ref[1], rel=1e-12)
    assert fac.path == "block" and not fac.exactly_singular


def _laplacian_bordered(m, shift, neumann=False, seed=0):
    """``[[A, b], [c^T, 1]]``: ``A = tridiag(-1, 2, -1) - (lambda_min - shift) I`` (or the Neumann
    Laplacian, exactly singular), ``b`` and ``c`` random but not orthogonal to its null vector."""
    rng = np.random.default_rng(seed)
    if neumann:
        diag = 2.0 * np.ones(m)
        diag[[0, -1]] = 1.0
        null = np.ones(m) / math.sqrt(m)
    else:
        lam = 2 - 2 * math.cos(math.pi / (m + 1))
        diag = (2 - lam + shift) * np.ones(m)
        null = np.sin(math.pi * np.arange(1, m + 1) / (m + 1))
        null /= np.linalg.norm(null)
    A = sp.diags([-np.ones(m - 1), diag, -np.ones(m - 1)], [-1, 0, 1])
    b = null + 0.3 * rng.standard_normal(m)
    c = null + 0.3 * rng.standard_normal(m)
    return sp.bmat([[A, sp.csr_matrix(b[:, None])], [sp.csr_matrix(c[None, :]), np.array([[1.0]])]], format="csr")


@pytest.mark.parametrize("shift", [0.0, 1e-12, 1e-8])
def test_an_ill_conditioned_leading_block_is_refined(shift):
    # the leading block is nearly singular (condition 2e16, 4e12, 4e8), the bordered matrix is not
    # (condition ~1e4): plain block elimination cancels (measured forward errors 5, 6e-6, 5e-10);
    # the solve notices it on its backward error and one refinement step restores round-off
    m = 200
    J = _laplacian_bordered(m, shift)
    stats = {}
    fac = BorderedBandedLU(J, 1, 1, stats=stats)
    Jd = J.toarray()
    rng = np.random.default_rng(2)
    for trans in (False, True):
        b = rng.standard_normal(m + 1)
        x = fac.solve(b, trans=trans)
        x_ref = np.linalg.solve(Jd.T if trans else Jd, b)
        assert np.max(np.abs(x - x_ref)) <= 1e-11 * np.max(np.abs(x_ref))  # measured <= 4e-13
    assert stats["refined"] >= 1
    # at condition 1e12 and better one refinement step is enough; at 2e16 (singular to working
    # precision) it may not be, and the factorization switched to a sparse LU of the whole matrix
    assert fac.path == "block" or shift == 0.0
    assert fac.det_sign_log()[0] == np.linalg.slogdet(Jd)[0]


def test_an_exactly_singular_leading_block_falls_back_to_a_sparse_lu():
    m = 200
    J = _laplacian_bordered(m, 0.0, neumann=True)
    stats = {}
    fac = BorderedBandedLU(J, 1, 1, stats=stats)
    assert fac.path == "sparse" and stats["sparse"] == 1 and "exactly singular" in fac.fallback_reason
    Jd = J.toarray()
    b = np.random.default_rng(4).standard_normal(m + 1)
    assert np.max(np.abs(fac.solve(b) - np.linalg.solve(Jd, b))) <= 1e-11 * np.max(np.abs(np.linalg.solve(Jd, b)))
    sign, logdet = fac.det_sign_log()
    assert sign == np.linalg.slogdet(Jd)[0] and logdet == pytest.approx(np.linalg.slogdet(Jd)[1], rel=1e-10)
    # the deflation of the engine's bordered solver finds the singular index among the pivots
    assert np.all(np.isfinite(fac.pivots()))


def test_a_singular_bordered_matrix_is_reported_not_solved():
    # the floating indenter: no contact, so the border row and column vanish
    Pf = ShellIndentationForce(N=30, indenter=Sphere(0.5))
    U = np.append(Pf.displacement.reference_unknowns(), -0.01)
    J = Pf.jacobian(U, 0.0)
    fac = Pf.factorize(J)
    assert fac.exactly_singular and fac.det_sign_log()[0] == 0.0
    with pytest.raises(SingularMatrixError):
        fac.solve(np.ones(Pf.n))
    with pytest.raises(ValueError, match="no contact force"):
        Pf.from_displacement_state(Pf.displacement.reference_unknowns(), -0.01)


def test_derivatives_match_finite_differences():
    Pf = ShellIndentationForce(N=30, indenter=Sphere(0.5))
    U, F = Pf.contact_start(0.03)
    rng = np.random.default_rng(3)
    U = U + 1e-6 * rng.standard_normal(U.size)  # off equilibrium, still in the domain
    F = 0.9 * F
    assert Pf.max_step_fraction(U, F, np.zeros(U.size), 0.0) == 1.0
    v = rng.standard_normal(U.size)
    v *= 1e-3 / np.max(np.abs(v))
    h = 1e-4  # steps of 1e-7 R stay far inside dhat = 1e-3 R
    g = Pf.residual(U, F)
    assert g @ v == pytest.approx(_richardson(lambda s: Pf.energy(U + s * v, F), h), rel=1e-6)
    J = Pf.jacobian(U, F)
    fd = _richardson(lambda s: Pf.residual(U + s * v, F), h)
    np.testing.assert_allclose(J @ v, fd, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd)))
    # the border alone: the derivative along the indenter travel
    e = np.zeros(U.size)
    e[-1] = 1.0
    fd_w = _richardson(lambda s: Pf.residual(U + s * e, F), 1e-7)
    np.testing.assert_allclose(J @ e, fd_w, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd_w)))
    assert np.any(fd_w[:-1] != 0)
    fd_p = _richardson(lambda s: Pf.residual(U, F + s), 1e-3)
    np.testing.assert_allclose(Pf.dresidual_dp(U, F), fd_p, rtol=1e-9, atol=1e-9)
    assert abs(Pf.jacobian_dp(U, F)).max() == 0
    # the last residual row is the contact force minus the load, and the observables follow U
    u, w_b = Pf.split(U)
    assert g[-1] == pytest.approx(Pf.displacement.evaluate_one("F", u, w_b) - F, rel=1e-12)
    obs = Pf.evaluate_observables(U, F)
    ref = Pf.displacement.evaluate_observables(u, w_b)
    assert list(obs) == list(ref)  # the same observables as under displacement control
    assert obs["F"] == F and obs["w_b"] == w_b and obs["F_norm"] == pytest.approx(ref["F_norm"] * F / ref["F"])
    for name in set(ref) - {"F", "F_norm"}:
        assert obs[name] == ref[name]


def test_step_filter_includes_the_indenter_travel():
    Pf = ShellIndentationForce(N=30, indenter=Sphere(0.5))
    U, F = Pf.contact_start(0.03)
    e = np.zeros(U.size)
    e[-1] = 1.0
    # pushing the indenter 1e-2 R deeper with the shell held would penetrate (dc = -dw_b)
    frac = Pf.max_step_fraction(U, F, 1e-2 * e, 0.0)
    assert 0 < frac < 0.1
    assert Pf.max_step_fraction(U, F, -1e-2 * e, 0.0) == 1.0  # retracting is always safe
    # the shell moving down with the indenter is safe too: only relative motion counts
    down = np.zeros(2 * Pf.N)
    down[1::2] = -1e-2
    dU = np.append(down[Pf.displacement.idx], 1e-2)
    assert Pf.max_step_fraction(U, F, dU, 0.0) == 1.0


@pytest.mark.slow
def test_a_thin_shallow_cap_under_a_forced_sphere_ends_where_the_sphere_lands_on_the_base_ring():
    """The fuzz study's scene 11 (docs/robustness.md): with the load weighed by the cap's depth, the
    loading of the everted shell pressed on the sphere ran out of the scene's 3000 steps; that loading
    went on with the sphere already on the base ring, where the trace now ends."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCENE

    scene = load_scene(SHELL_SCENE.schema, None, [
        "shell.R=3.44359741000081", "shell.E=244162575.4191826", "shell.h=0.00387197843511877",
        "shell.phi_hat=1.402906343560587", "shell.nu=0.41341266477836053", "shell.N=48",
        "load.kind=sphere", "load.radius=4.117945163675228", "load.control=force", "output.figure=false"])
    result = SHELL_SCENE.run(scene, progress=False)
    assert result.status == "ok", result.message
    # the sphere (r/R = 1.2) snaps down onto the base ring: the trace ends at that landing
    assert [b.status for b in result.branches] == ["event"] and len(result.jumps) == 1
    assert "landed on or beyond the bound base_gap" in result.message and "base ring" in result.message
    assert result.jump_observables[0][1]["base_gap"] < 2.0 * result.summary["dhat"]
    assert sum(len(b.p) for b in result.branches) < 3000  # the scene's fixed step limit when this was measured


@pytest.mark.slow
def test_a_plate_that_snaps_onto_the_base_ring_ends_the_trace_there():
    """Seed 39's scene 144 of the fuzz study: the plate snaps the shallow cap flat and lands within
    2 dhat of the base ring.  The trace went on loading from there, the plate pressing the flattened
    cap onto the support, until its steps collapsed at F R / (2 pi D) = 39 ("min_step")."""
    from contin.app.scene import load_scene
    from contin_models.shell_scene import SHELL_SCENE

    scene = load_scene(SHELL_SCENE.schema, None, [
        "shell.R=289.96304748747053", "shell.E=117762993.80406687", "shell.h=0.8108587098785374",
        "shell.phi_hat=1.4093575258470221", "shell.nu=-0.2086544014968531", "shell.N=98",
        "load.kind=plate", "load.control=force", "output.figure=false"])
    result = SHELL_SCENE.run(scene, progress=False)
    assert result.status == "ok", result.message
    assert [b.status for b in result.branches] == ["event"] and len(result.jumps) == 1
    assert "base ring" in result.message
    fold, landing = result.jump_observables[0]
    assert landing["base_gap"] < 2.0 * result.summary["dhat"] < fold["base_gap"]
    assert landing["F"] == fold["F"] == pytest.approx(result.summary["F_snap"])
