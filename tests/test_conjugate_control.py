"""contin.ConjugateControl: the load's conjugate displacement prescribed, the load a Lagrange multiplier.

Small problems with answers derived by hand, then the pressure-loaded cap against its own pressure control.

The two-dof model: ``E(x, y, p) = x^4/4 - x^2/2 + 3 y^2/2 - p (x + y)``, a double well in ``x`` beside a
spring ``y``, both loaded by a dead load ``p`` on ``q = x + y``.  Under the load (force control) the
equilibria are ``p = x^3 - x = 3 y``, with limit loads at ``x = +-1/sqrt(3)`` and ``J = diag(3 x^2 - 1, 3)``
unstable between them.  Prescribing ``q = x + y`` instead: ``q = x + (x^3 - x)/3 = (x^3 + 2 x)/3``, monotonic in
``x``, so the displacement-controlled path has no fold at all, and the Hessian restricted to the constraint's
tangent ``(1, -1)/sqrt(2)`` is ``(3 x^2 - 1 + 3)/2 > 0``: stable everywhere, also where ``J`` is not.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

import contin
from contin import Problem, continuation
from contin.analyses.conjugate import ConjugateControl, LoadConjugate
from contin.analyses.deadload import DeadLoad
from contin.problem import Constrained, LeadingBlock
from tests.test_deadload import TiedTruss


# ---- the two-dof model -------------------------------------------------------------------------------
class Well(Problem):
    """``E = x^4/4 - x^2/2 + 3 y^2/2 - p (x + y)`` (module docstring); the load ``p`` is the parameter."""

    def __init__(self) -> None:
        super().__init__(symmetric=True, name="well", parameter_name="p",
                         observables={"x": lambda u, p: float(u[0]), "y": lambda u, p: float(u[1])},
                         observable_derivatives={"x": lambda u, p: (np.array([1.0, 0.0]), 0.0)})

    def energy(self, u: np.ndarray, p: float) -> float:
        x, y = u
        return x ** 4 / 4 - x ** 2 / 2 + 1.5 * y ** 2 - p * (x + y)

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        x, y = u
        return np.array([x ** 3 - x - p, 3 * y - p])

    def jacobian(self, u: np.ndarray, p: float) -> np.ndarray:
        return np.array([[3 * u[0] ** 2 - 1, 0.0], [0.0, 3.0]])

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        return np.array([-1.0, -1.0])

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        return -float(u[0] + u[1])


class CurvedLoad(Well):
    """The well with a load that enters concavely: ``E - k p^2 / 2`` (a spring in series with the load)."""

    def __init__(self, k: float) -> None:
        super().__init__()
        self.k = k

    def energy(self, u: np.ndarray, p: float) -> float:
        return super().energy(u, p) - 0.5 * self.k * p * p

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        return -float(u[0] + u[1]) - self.k * p

    def conjugate_stiffness(self, u: np.ndarray, p: float) -> float:
        return -self.k


def fd_jacobian(P: Problem, U: np.ndarray, q: float, h: float = 1e-6) -> np.ndarray:
    cols = []
    for j in range(U.size):
        e = np.zeros(U.size)
        e[j] = h
        cols.append((P.residual(U + e, q) - P.residual(U - e, q)) / (2 * h))
    return np.array(cols).T


def restricted_count(H: np.ndarray, a: np.ndarray) -> int:
    """Negative eigenvalues of ``H`` on the tangent space ``a . v = 0`` (dense null space of the border)."""
    Z = sla.null_space(a[None, :])
    return int(np.count_nonzero(np.linalg.eigvalsh(Z.T @ H @ Z) < 0))


# ---- residual, Jacobian, observables ---------------------------------------------------------------------
@pytest.mark.parametrize("unit", [1.0, 0.25])
def test_residual_and_jacobian_are_the_lagrangian_derivatives(unit: float) -> None:
    P = ConjugateControl(Well(), displacement="q", linear=True, multiplier_unit=unit, scaled={"q2": ("q", 2.0)})
    U, q, h = np.array([0.3, -0.2, 0.7]), 0.4, 1e-6
    assert P.residual(U, q) == pytest.approx(
        [(P.energy(U + h * e, q) - P.energy(U - h * e, q)) / (2 * h) for e in np.eye(3)], abs=1e-8)
    J = P.jacobian(U, q).toarray()
    assert J == pytest.approx(fd_jacobian(P, U, q), abs=1e-7)
    assert J == pytest.approx(J.T)
    assert J[-1, -1] == 0.0  # a linear load: a KKT matrix
    assert P.dresidual_dp(U, q) == pytest.approx((P.residual(U, q + h) - P.residual(U, q - h)) / (2 * h), abs=1e-8)
    report = contin.check_problem(P, U, q)
    assert report.ok, report
    # observables: the base's at (u, p), the multiplier in the load's units, the displacement
    x, y, p = U[0], U[1], unit * U[2]
    obs = P.evaluate_observables(U, q)
    assert obs == pytest.approx({"x": x, "y": y, "p": p, "q": q, "q2": 2 * q})
    for name in ("x", "p", "q", "q2"):
        dU, dq = P.observable_derivatives[name](U, q)
        num = [(P.observables[name](U + h * e, q) - P.observables[name](U - h * e, q)) / (2 * h) for e in np.eye(3)]
        assert dU == pytest.approx(num, abs=1e-8)
        assert dq == pytest.approx((P.observables[name](U, q + h) - P.observables[name](U, q - h)) / (2 * h), abs=1e-8)


def test_a_nonlinear_load_borders_with_its_stiffness() -> None:
    P = ConjugateControl(CurvedLoad(0.5), displacement="q", multiplier_unit=2.0)
    U, q = np.array([0.3, -0.2, 0.7]), 0.4
    J = P.jacobian(U, q).toarray()
    assert J == pytest.approx(fd_jacobian(P, U, q), abs=1e-7)
    assert J[-1, -1] == pytest.approx(-0.5 * 4.0)


def test_equilibria_map_to_the_base() -> None:
    base = Well()
    P = ConjugateControl(base, displacement="q", linear=True, multiplier_unit=0.5)
    x = 0.4
    u, p = np.array([x, (x ** 3 - x) / 3]), x ** 3 - x
    assert np.max(np.abs(base.residual(u, p))) < 1e-15
    U, q = P.from_load_state(u, p)
    assert q == pytest.approx(u.sum()) and P.split(U)[1] == pytest.approx(p)
    assert np.max(np.abs(P.residual(U, q))) < 1e-15
    assert P.energy(U, q) == pytest.approx(x ** 4 / 4 - x ** 2 / 2 + 1.5 * u[1] ** 2)  # the Lagrangian: E_el


def test_refusals() -> None:
    with pytest.raises(TypeError, match="conjugate_force"):
        ConjugateControl(Problem(residual=lambda u, p: u - p, symmetric=True))
    with pytest.raises(TypeError, match="conjugate_stiffness"):
        ConjugateControl(Well())  # neither linear=True nor a declared load stiffness
    with pytest.raises(ValueError, match="multiplier_unit"):
        ConjugateControl(Well(), linear=True, multiplier_unit=0.0)
    with pytest.raises(ValueError, match="other than the load"):
        ConjugateControl(Well(), displacement="p", linear=True)
    assert isinstance(Well(), LoadConjugate) and not isinstance(Problem(), LoadConjugate)


# ---- stability under both controls ---------------------------------------------------------------------
@pytest.mark.parametrize("x", [-1.2, -0.5, 0.0, 0.3, 0.57, 0.6, 1.5])
def test_stability_of_the_well_under_both_controls(x: float) -> None:
    P = ConjugateControl(Well(), displacement="q", linear=True, labels=("displacement", "force"))
    u, p = np.array([x, (x ** 3 - x) / 3]), x ** 3 - x
    U, q = P.from_load_state(u, p)
    info = P.stability(U, q)
    assert list(info) == ["displacement", "force"]
    # by hand: the restricted Hessian (3 x^2 + 2) / 2 > 0; J = diag(3 x^2 - 1, 3)
    assert info["displacement"].n_negative == 0
    assert info["force"].n_negative == (1 if 3 * x * x < 1 else 0)
    # independently: the dense null space of the border
    H = P.jacobian(U, q).toarray()
    assert info["displacement"].n_negative == restricted_count(H[:2, :2], H[:2, 2])


@pytest.mark.parametrize("seed", range(8))
def test_constrained_count_is_the_hessian_on_the_tangent_space(seed: int) -> None:
    # a quadratic energy E = u.H.u/2 - p a.u with a random indefinite H: the counts of J = H and of H on
    # a.v = 0 differ (Cauchy interlacing: by 0 or 1), and the bordered count minus one is the latter
    rng = np.random.default_rng(seed)
    n = 7
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    H = Q @ np.diag(rng.choice([-1.0, 1.0], n) * rng.uniform(0.2, 2.0, n)) @ Q.T
    a = rng.standard_normal(n)

    class Quadratic(Problem):
        def residual(self, u: np.ndarray, p: float) -> np.ndarray:
            return H @ u - p * a

        def jacobian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
            return sp.csr_matrix(H)

        def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
            return -a

        def conjugate_force(self, u: np.ndarray, p: float) -> float:
            return -float(a @ u)

    P = ConjugateControl(Quadratic(symmetric=True), displacement="q", linear=True)
    U = rng.standard_normal(n + 1)
    counts = {label: s.n_negative for label, s in P.stability(U, 0.3).items()}
    assert counts["force"] == int(np.count_nonzero(np.linalg.eigvalsh(H) < 0))
    assert counts["displacement"] == restricted_count(H, a)
    # with eigenvalues asked for: the same counts; none reported for the constrained label
    info = P.stability(U, 0.3, n_eigs=2)
    assert {label: s.n_negative for label, s in info.items()} == counts
    assert info["displacement"].eigenvalues.size == 0 and info["force"].eigenvalues.size == 2


def test_seeds_include_a_case_where_the_controls_disagree() -> None:
    # the parametrized test above is only meaningful if some seed has differing counts
    differ = 0
    for seed in range(8):
        rng = np.random.default_rng(seed)
        Q, _ = np.linalg.qr(rng.standard_normal((7, 7)))
        H = Q @ np.diag(rng.choice([-1.0, 1.0], 7) * rng.uniform(0.2, 2.0, 7)) @ Q.T
        a = rng.standard_normal(7)
        differ += restricted_count(H, a) != int(np.count_nonzero(np.linalg.eigvalsh(H) < 0))
    assert differ >= 2


def test_a_concave_load_counts_the_legendre_transform() -> None:
    # E - k p^2/2: eliminating the multiplier (stationary in p) leaves the displacement-controlled energy, whose
    # Hessian in u is E_uu - E_up E_pp^-1 E_pu = J + a a^T / k (a = df/dp); its count is the constrained label's
    k = 0.05
    P = ConjugateControl(CurvedLoad(k), displacement="q")
    for x in (-0.3, 0.0, 0.2):
        U, q = np.array([x, 0.1, 0.2]), 0.0
        H = P.jacobian(U, q).toarray()
        J, a = H[:2, :2], H[:2, 2]
        expected = int(np.count_nonzero(np.linalg.eigvalsh(J + np.outer(a, a) / k) < 0))
        assert P.stability(U, q)["displacement"].n_negative == expected
        assert P.stability(U, q)["force"].n_negative == 1  # 3 x^2 - 1 < 0


def test_a_convex_load_is_refused_when_counted() -> None:
    P = ConjugateControl(CurvedLoad(-0.5), displacement="q")
    with pytest.raises(ValueError, match="positive eigenvalue"):
        P.stability(np.array([0.1, 0.1, 0.1]), 0.0)


# ---- the engine feature: Constrained -------------------------------------------------------------------
def test_constrained_operator_declared_on_a_plain_problem() -> None:
    # K = [[H, a], [a, 0]] with H = diag(-1, 2), a = (1, 0): on a.v = 0 the Hessian is 2 (stable), H has one
    # negative eigenvalue, K has one (the constraint's) beside two positive ones
    K = np.array([[-1.0, 0.0, 1.0], [0.0, 2.0, 0.0], [1.0, 0.0, 0.0]])
    P = Problem(residual=lambda u, p: u, symmetric=True,
                stability_operators={"constrained": Constrained(lambda u, p: K), "free": LeadingBlock("constrained", -1)})
    assert {k: v.n_negative for k, v in P.stability(np.zeros(3), 0.0).items()} == {"constrained": 0, "free": 1}
    assert {k: v.n_negative for k, v in P.stability(np.zeros(3), 0.0, n_eigs=1).items()} == {"constrained": 0,
                                                                                             "free": 1}
    # alone (no block): counted on its own
    Q = Problem(residual=lambda u, p: u, symmetric=True, stability_operators={"c": Constrained(lambda u, p: K)})
    assert Q.stability(np.zeros(3), 0.0)["c"].n_negative == 0
    assert Constrained(lambda u, p: K).count(0) == 0  # never below zero (an exactly singular H)
    with pytest.raises(ValueError, match="positive integer"):
        Constrained(lambda u, p: K, 0)
    with pytest.raises(TypeError, match="callable"):
        Constrained(K)  # type: ignore[arg-type]


def test_constrained_count_survives_a_singular_leading_block() -> None:
    # at a limit load of the force control J is singular: the pivot-free LDL^T breaks down (a zero pivot) and
    # the nested count falls back to the block's own count (0) plus its Schur complement, which an exactly
    # singular block cannot give (0 again); the bordered count minus one would be -1, and is kept at 0, which
    # is right: on sum(v) = 0, v.Hv = sum d_i v_i^2 > 0
    n = 80
    d = np.linspace(0.0, 3.0, n)  # one exactly zero eigenvalue
    H = sp.diags(d).tocsr()
    a = np.ones(n)
    K = contin.analyses.deadload.bordered_matrix(H, a, 0.0)
    P = Problem(residual=lambda u, p: u, symmetric=True,
                stability_operators={"c": Constrained(lambda u, p: K), "f": LeadingBlock("c", -1)})
    counts = {k: v.n_negative for k, v in P.stability(np.zeros(n + 1), 0.0).items()}
    assert counts == {"c": 0, "f": 0}


# ---- continuation: through the limit loads without a fold ----------------------------------------------
def test_displacement_control_passes_the_limit_loads_of_the_well() -> None:
    P = ConjugateControl(Well(), displacement="q", linear=True)
    U0, q0 = P.from_load_state(np.array([-1.3, ((-1.3) ** 3 + 1.3) / 3]), (-1.3) ** 3 + 1.3)
    st = contin.Settings(ds=0.05, ds_max=0.1, stability=True, n_eigs=0, max_steps=500)
    br = continuation(P, U0, q0, st, p_max=-q0, events=[contin.extremum("p", folds="p", stability_label="force")])
    assert br.status == "bound"
    assert not [s for s in br.special_points if s.kind == "fold"]  # no fold in q
    limits = [s for s in br.special_points if s.info.get("folds") == "p"]
    assert [round(s.observables["x"], 6) for s in limits] == pytest.approx([-1 / math.sqrt(3), 1 / math.sqrt(3)],
                                                                           abs=1e-6)
    nd, nf = br.stability_by["displacement"][0], br.stability_by["force"][0]
    assert np.all(nd == 0) and nf.max() == 1 and nf[0] == 0 and nf[-1] == 0
    x = br.observables["x"]
    assert np.all(nf[3 * x ** 2 < 1 - 1e-6] == 1)
    # p along the path is the force-controlled equilibrium's load
    assert br.observables["p"] == pytest.approx(x ** 3 - x, abs=1e-9)


class Conjugated(DeadLoad):
    """A dead load that also declares its conjugate: ``dE_F/dF = -p`` (the base's displacement, unknown)."""

    def conjugate_force(self, U: np.ndarray, F: float) -> float:
        return -float(U[-1])


def test_conjugate_control_undoes_a_dead_load() -> None:
    # displacement control -> DeadLoad (force control) -> ConjugateControl: the displacement control again
    base = TiedTruss()
    P = ConjugateControl(Conjugated(base), displacement="p", linear=True, labels=("displacement", "force"))
    for y, p in ((0.1, 0.3), (-0.2, 0.05), (0.45, 0.2)):
        Ub = np.array([y])
        F = float(base.conjugate_force(Ub, p))
        U = np.array([y, p, F])
        assert P.residual(U, p)[:1] == pytest.approx(base.residual(Ub, p))
        assert np.max(np.abs(P.residual(U, p)[1:])) < 1e-15
        counts = {k: v.n_negative for k, v in P.stability(U, p).items()}
        # the prescribed p fixes the truss's own count; the dead load's is the bordered truss Hessian's
        assert counts["displacement"] == int(base.jacobian(Ub, p)[0, 0] < 0)
        dead = DeadLoad(base).stability(np.array([y, p]), F)
        assert counts["force"] == dead["force"].n_negative


# ---- the pressure-loaded cap: volume control against pressure control ----------------------------------
@pytest.fixture(scope="module")
def cap_traces() -> dict:
    """The clamped lambda = 7 cap (R/h = 400, nu = 0.3, N = 60; h = 1 and p_c = 1) under both controls."""
    from contin_models.shell.pressure import ShellPressure, phi_hat_for_lambda
    from contin_models.shell_scene.pressure import volume_problem

    R, h, nu = 400.0, 1.0, 0.3
    E = math.sqrt(3.0 * (1.0 - nu * nu)) / (2.0 * (h / R) ** 2)
    cap = ShellPressure(R=R, E=E, nu=nu, h=h, phi_hat=phi_hat_for_lambda(7.0, R, h, nu), N=60, boundary="clamped")
    u0 = cap.reference_unknowns()
    st = contin.Settings(ds=0.02, ds_max=0.1, max_steps=500, stability=True, n_eigs=0)
    pressure = continuation(cap, u0, 0.0, st, stop_at=("fold",), p_max=3.0)
    vol = volume_problem(cap)
    V0, depth = cap.pressure.V0, 2 * R * (1 - math.sin(cap.phi_hat))
    dV_p = V0 - pressure.observables["V"]  # the volume change along the pressure-controlled branch
    # crossings of the pressure branch's volumes, located on the volume-controlled branch (not interpolated)
    events = [contin.crossing("dV", float(v), name=f"at{i}") for i, v in enumerate(dV_p[1:-1], start=1)]
    events.append(contin.extremum("p", "max", folds="p", stability_label="pressure"))
    stv = contin.Settings(ds=0.02 * depth, ds_max=0.05 * depth, max_steps=500, stability=True, n_eigs=0,
                          state_weight=1.0 / h, param_weight=depth / (2 * V0))
    U0, q0 = vol.from_load_state(u0, 0.0)
    volume = continuation(vol, U0, q0, stv, stop_at=("fold",), p_max=V0, events=events)
    return {"cap": cap, "pressure": pressure, "volume": volume, "dV_p": dV_p}


def test_volume_control_passes_the_pressure_limit_point_without_a_fold(cap_traces: dict) -> None:
    pressure, volume = cap_traces["pressure"], cap_traces["volume"]
    assert pressure.status == "event" and pressure.special_points[-1].kind == "fold"
    p_fold = pressure.special_points[-1].p
    assert p_fold / cap_traces["cap"].p_c == pytest.approx(1.0515, abs=1e-3)  # studies.classical, N = 60
    # along the volume path: the pressure maximum first (no fold in dV there), then the first fold in dV
    specials = [s for s in volume.special_points if s.kind == "fold" or s.info.get("folds") == "p"]
    assert [s.info.get("folds", "dV") for s in specials] == ["p", "dV"]
    p_max, dV_fold = specials
    assert p_max.located and p_max.observables["p"] == pytest.approx(p_fold, rel=1e-7)
    assert dV_fold.p > p_max.p
    # stability: under the prescribed volume stable up to the fold in dV; under the pressure unstable past its
    # maximum
    nv, npr = volume.stability_by["volume"][0], volume.stability_by["pressure"][0]
    # (the branch ends at the located fold, stored last, where the count is decided by roundoff)
    assert dV_fold.index >= len(volume) - 2
    assert np.all(nv[:dV_fold.index] == 0)
    assert np.all(npr[:p_max.index + 1] == 0) and np.all(npr[p_max.index + 1:dV_fold.index] == 1)
    assert p_max.info["stable_before"] is True and p_max.info["stable_after"] is False
    assert dV_fold.index > p_max.index + 1  # stored points between them: stable in volume, unstable in pressure


def test_the_multiplier_is_the_pressure_controlled_branchs_pressure(cap_traces: dict) -> None:
    pressure, volume = cap_traces["pressure"], cap_traces["volume"]
    crossings = {s.label: s for s in volume.special_points if s.kind == "event" and s.label.startswith("at")}
    assert len(crossings) == len(pressure) - 2
    for label, s in crossings.items():
        i = int(label[2:])
        assert s.located and s.p == pytest.approx(cap_traces["dV_p"][i], rel=1e-9)
        assert s.observables["p"] == pytest.approx(pressure.p[i], rel=1e-6)
        assert s.observables["w"] == pytest.approx(pressure.observables["w"][i], rel=1e-5)



def test_the_cap_under_volume_control_keeps_exact_derivatives_and_its_band(cap_traces: dict) -> None:
    from contin_models.contact.indentation import BorderedBandedLU
    from contin_models.shell_scene.pressure import volume_problem

    cap = cap_traces["cap"]
    vol = volume_problem(cap)
    rng = np.random.default_rng(1)
    u0 = cap.reference_unknowns()
    U, q = vol.join(u0 + 0.3 * rng.standard_normal(u0.size), 0.8 * cap.p_c), 0.1 * cap.pressure.V0
    report = contin.check_problem(vol, U, q)
    assert report.ok, report
    # the bordered Jacobian is factorized on the cap's band (block elimination), and solves right
    J = vol.jacobian(U, q)
    F = vol.factorize(J)
    assert isinstance(F, BorderedBandedLU) and F.path == "block"
    b = rng.standard_normal(J.shape[0])
    assert F.solve(b) == pytest.approx(np.linalg.solve(J.toarray(), b), rel=1e-8, abs=1e-12)
    # observables: the cap's, the multiplier as the pressure, the prescribed volume change and its ratio
    obs = vol.evaluate_observables(U, q)
    assert obs["p"] == pytest.approx(0.8 * cap.p_c) and obs["p_over_p_c"] == pytest.approx(0.8)
    assert obs["dV"] == q and obs["dV_over_V0"] == pytest.approx(0.1)


# ---- study (e), end to end --------------------------------------------------------------------------------
@pytest.mark.slow
def test_the_volume_control_study_runs(tmp_path) -> None:
    import json

    from studies import volume_control
    from tests.figure_check import assert_figure

    assert volume_control.main(["--out", str(tmp_path), "--quiet"]) == 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    lam7, lam5 = summary["caps"]
    assert lam7["pressure_control"]["p_max_over_p_c"] == pytest.approx(1.0527, abs=1e-3)
    assert lam7["pressure_control"]["landing_success"] and lam5["pressure_control"]["landing_success"]
    # lambda = 7: the volume passes the pressure maximum and folds a little later; lambda = 5: no fold at all
    first = lam7["volume_control"]["first_fold_in_dV"]
    assert first["dV_over_V0"] > lam7["pressure_control"]["dV_at_p_max_over_V0"]
    assert lam5["volume_control"]["n_folds_in_dV"] == 0 and lam5["volume_control"]["max_n_negative_volume"] == 0
    for cap in (lam7, lam5):
        assert cap["agreement"]["n_compared"] == cap["agreement"]["n_wanted"] > 10
        assert cap["agreement"]["max_rel_diff_p"] < 1e-6
    assert_figure(tmp_path, "volume_control")


def test_a_prescribed_volume_traces_with_default_settings() -> None:
    """Without ``stability`` the engine watches the Morse index from the corrector's factorization of
    the bordered Jacobian, which has one negative eigenvalue more than the constrained Hessian (the
    multiplier's saddle): counted as the primary index it made every volume-controlled trace
    'unexplained' at its first step.  The primary operator's own count (Constrained) is what is watched."""
    from contin_models.shell.geometry import spherical_cap
    from contin_models.shell.structure import ShellOfRevolution, ShellStructure

    st = ShellStructure(spherical_cap(1.0, 0.8, 20), 1e6, 0.3, 0.02, boundary="clamped")
    pressure = ShellOfRevolution(st, "pressure")
    volume = ConjugateControl(pressure, "dV", linear=True, multiplier_unit=1e3)
    U0, q0 = volume.from_load_state(pressure.reference_unknowns(), 0.0)
    br = continuation(volume, U0, q0, p_max=0.005, ds=0.001, ds_max=0.0025)
    assert br.status == "bound", br.message
    assert volume.index_from_jacobian(3) == 2 and pressure.index_from_jacobian(3) == 3
