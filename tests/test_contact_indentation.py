"""The shell indented through the log barrier (issue 4, first part): derivatives, limits, the snap.

References are independent of the code under test: finite differences of the energy, the bilateral
point load of :class:`contin_models.shell.ShellPointLoad` (a small sphere touches the pole alone, so the two
equilibria must coincide at equal pole displacement), and the physics of
``docs/model.md#snaps`` (the snap is a fold in the indenter travel where the force has fallen to zero).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.linalg as sl
import pytest

import contin
from contin_models.contact import Plate, Sphere
from contin_models.contact.indentation import ShellIndentation
from contin_models.shell import ShellPointLoad


def _contact_state(P: ShellIndentation, w_b: float) -> tuple[np.ndarray, float]:
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=w_b, max_steps=400)
    assert br.status == "bound"
    return br.u[-1], float(br.p[-1])


@pytest.mark.parametrize("indenter", [Sphere(0.5), Plate()], ids=["sphere", "plate"])
def test_derivatives_in_contact_match_finite_differences(indenter):
    P = ShellIndentation(N=30, indenter=indenter)
    u, p = _contact_state(P, 0.03)
    assert P.evaluate_observables(u, p)["n_contact"] >= 1
    rng = np.random.default_rng(3)
    u = u + 1e-6 * rng.standard_normal(u.size)  # off equilibrium (the gradient is not ~0), still in the domain
    assert P.max_step_fraction(u, p, np.zeros(u.size), 0.0) == 1.0
    v = rng.standard_normal(u.size)
    v *= 1e-3 / np.max(np.abs(v))
    # central differences with one Richardson step: the barrier's third derivative (~K/d) is large,
    # so the plain O(h^2) error would dominate; steps of 1e-7 R stay far inside dhat = 1e-3 R
    def richardson(fun, h):
        d1 = (fun(h) - fun(-h)) / (2 * h)
        d2 = (fun(h / 2) - fun(-h / 2)) / h
        return (4 * d2 - d1) / 3

    h = 1e-4
    g = P.residual(u, p)
    dE = richardson(lambda s: P.energy(u + s * v, p), h)
    assert g @ v == pytest.approx(dE, rel=1e-6)
    Jv = P.jacobian(u, p) @ v
    fd = richardson(lambda s: P.residual(u + s * v, p), h)
    np.testing.assert_allclose(Jv, fd, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd)))
    # the barrier is only C2 at d = dhat and one of the cells' sample points may sit within 1e-7 R of
    # it: a smaller step keeps the kink out of the difference quotient
    dp = 1e-9
    fd_p = richardson(lambda s: P.residual(u, p + s), dp)
    np.testing.assert_allclose(P.dresidual_dp(u, p), fd_p, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd_p)))
    # the indenter force is the derivative of the energy with respect to the travel
    F = P.evaluate_observables(u, p)["F"]
    assert F > 0
    assert F == pytest.approx(richardson(lambda s: P.energy(u, p + s), dp), rel=1e-6)
    # and its declared derivatives (the stored path's tangent in F) are those of the force itself
    dF_du, dF_dp = P.observable_derivatives["F"](u, p)
    force = P.observables["F"]
    assert dF_du @ v == pytest.approx(richardson(lambda s: force(u + s * v, p), h), rel=1e-5)
    assert dF_dp == pytest.approx(richardson(lambda s: force(u, p + s), dp), rel=1e-5)
    dN_du, dN_dp = P.observable_derivatives["F_norm"](u, p)
    unit = P.observables["F_norm"](u, p) / F
    np.testing.assert_allclose(dN_du, unit * dF_du, rtol=1e-14)
    assert dN_dp == pytest.approx(unit * dF_dp, rel=1e-14)


def test_small_sphere_is_the_point_load_at_equal_pole_displacement():
    N = 60
    point = ShellPointLoad(N=N)
    br = contin.continuation(point, point.reference_unknowns(), 0.0, ds=0.01, ds_max=0.02, p_max=0.1)
    F_point = br.observables["F"][-1]
    for r in (0.05, 0.005):
        P = ShellIndentation(N=N, indenter=Sphere(r))
        bs = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02,
                                 bounds={"w_s": (None, 0.1)}, max_steps=500)
        obs = P.evaluate_observables(bs.u[-1], bs.p[-1])
        # the pole's cell and its neighbour's half towards the pole (the cells overlap the pole's region)
        assert obs["w_s"] == pytest.approx(0.1, rel=1e-12) and obs["n_contact"] <= 2
        # the barrier's curve passes the axis at 3/4 of the pole node and 1/4 of its neighbour ring,
        # so the tiny sphere's load is shared by both: measured 3.6e-4 at N = 60
        assert obs["F"] == pytest.approx(F_point, rel=1e-3)
    # a larger sphere spreads the contact over a ring of nodes and pushes harder at equal w_s
    P = ShellIndentation(N=N, indenter=Sphere(0.5))
    bs = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02,
                             bounds={"w_s": (None, 0.1)}, max_steps=500)
    obs = P.evaluate_observables(bs.u[-1], bs.p[-1])
    assert obs["n_contact"] > 5 and obs["F"] > 1.01 * F_point


def test_sphere_snaps_at_a_fold_in_the_travel_where_the_force_vanishes():
    P = ShellIndentation(N=60, indenter=Sphere(0.5))
    w_end = 1.05 * 2 * (1 - math.sin(0.8))
    res = contin.quasistatic(P, P.reference_unknowns(), 0.0, w_end, ds=0.005, ds_max=0.02, n_eigs=0, max_steps=2000)
    assert res.status == "completed", res.message
    (fold,) = res.folds
    (jr,) = res.jumps
    F_max = max(float(np.max(br.observables["F"])) for br in res.branches)
    obs = fold.observables
    assert fold.located
    # a fold of the travel: the displacement-control Hessian is singular there (a dense eigensolver;
    # measured 3e-6 of the next eigenvalue, whose own scale is the barrier's 1e7)
    eig = sl.eigvalsh(P.jacobian(fold.u, fold.p).toarray())
    assert abs(eig[0]) < 1e-5 * eig[1]
    assert 0 <= obs["F"] < 1e-4 * F_max  # the snap comes as the force reaches zero
    assert obs["Delta_H"] == 0.0 and obs["n_contact"] >= 1  # the pole still touches
    assert obs["kappa_p_R"] < 0  # the pole region is already inverted
    land = P.evaluate_observables(jr.u_to, jr.p)
    assert jr.success and land["n_contact"] == 0 and land["Delta_H"] > 0.05  # detached, everted
    assert land["w_s"] > obs["w_s"] + 0.05
    # no stored point ever penetrates the indenter
    for br in res.branches:
        for u, p in zip(br.u, br.p):
            assert np.min(P.barrier.distances(P.full_state(u), P.position(p))) > 0


def test_overlapping_start_is_a_clear_error_not_a_nan():
    P = ShellIndentation(N=30, indenter=Sphere(0.5))
    br = contin.continuation(P, P.reference_unknowns(), 0.05, ds=0.005, p_max=0.1)
    assert br.status == "failed" and "not outside the sphere indenter" in br.message
    with pytest.raises(ValueError, match="radius must be > 0"):
        ShellIndentation(N=30, indenter=Sphere(0.0))


def test_small_sphere_snaps_where_the_bilateral_point_load_force_vanishes():
    # up to the force zero the unilateral contact is the bilateral point load; the snap of a small
    # sphere is therefore the first zero of F(w) on the point-load path (an independent trace)
    N = 60
    point = ShellPointLoad(N=N)
    bp = contin.continuation(point, point.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, p_max=0.45,
                             events=[contin.crossing("F", 0.0, direction=-1, terminal=True)])
    assert bp.status == "event"
    w_zero = float(bp.p[-1])
    P = ShellIndentation(N=N, indenter=Sphere(0.05))
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.005, ds_max=0.02, stop_at=("fold",), p_max=0.7,
                             max_steps=2000)
    (fold,) = [s for s in br.special_points if s.kind == "fold"]
    assert fold.observables["w_s"] == pytest.approx(w_zero, rel=1e-6)  # measured 6e-9 at N = 200
