"""The shell of revolution with its supports and one load (:mod:`contin_models.shell.structure`), issue 16.

On the spherical cap the general problem must be the paper's (:class:`ShellPointLoad`) and the
pressure problem of the first step exactly; its new pieces (ring loads, the south pole's mirror
element, supports on any meridian) are checked against finite differences and closed forms.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import contin
from contin_models.shell import ShellPointLoad
from contin_models.shell.geometry import spherical_cap
from contin_models.shell.structure import SUPPORTS, ShellOfRevolution, ShellStructure, edge_tangent

NU = 0.3


def _random_state(pr: ShellOfRevolution, size: float, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return pr.reference_unknowns() + size * rng.standard_normal(pr.n)


@pytest.mark.parametrize("control", ["displacement", "force"])
def test_point_load_on_the_cap_is_the_papers_problem(control: str) -> None:
    """Sliding cap without an edge element (the paper's base) with a pole force: same unknowns, residual and Jacobian as ShellPointLoad
    (displacement control), same linear stiffness under both controls."""
    old = ShellPointLoad(1.0, 1e6, 0.5, 0.02, 0.8, 120, control)
    new = ShellOfRevolution(ShellStructure(spherical_cap(1.0, 0.8, 120), 1e6, 0.5, 0.02, "sliding", edge_bending="none"),
                            "point", control)
    assert new.linear_stiffness() == pytest.approx(old.linear_stiffness(), rel=1e-12)
    if control == "displacement":
        u = _random_state(new, 1e-3)
        assert np.array_equal(new.idx, old.idx)
        assert np.allclose(new.residual(u, 0.01), old.residual(u, 0.01), rtol=0, atol=1e-12 * old.residual_scale)
        assert abs(new.jacobian(u, 0.01) - old.jacobian(u, 0.01)).max() <= 1e-12 * abs(old.jacobian(u, 0.01)).max()
        obs_old, obs_new = old.evaluate_observables(u, 0.01), new.evaluate_observables(u, 0.01)
        assert obs_new["F"] == pytest.approx(obs_old["F"], rel=1e-12)
        assert obs_new["F_norm"] == pytest.approx(obs_old["F_norm"], rel=1e-12)


@pytest.mark.parametrize("boundary", ["sliding", "pinned", "clamped"])
@pytest.mark.parametrize("load, control", [("point", "force"), ("point", "displacement"), ("ring", "force"),
                                           ("ring", "displacement"), ("pressure", "force")])
def test_derivatives_against_finite_differences(boundary: str, load: str, control: str) -> None:
    cap = spherical_cap(1.0, 0.6, 40, 0.5)
    pr = ShellOfRevolution(ShellStructure(cap, 1e6, NU, 0.01, boundary), load, control, node=20, p_c=1.0)
    u = _random_state(pr, 1e-3)
    p = {"force": 50.0, "displacement": 0.01}[control] if load != "pressure" else 300.0
    report = contin.check_problem(pr, u, p)
    assert report.ok, report


@pytest.mark.parametrize("load, control", [("point", "force"), ("ring", "force"), ("ring", "displacement")])
def test_stability_labels_count_the_right_operators(load: str, control: str) -> None:
    """The other control's operator is the Hessian with or without the loaded node's height, whatever
    the node's place among the unknowns (the ring's is in the middle, the pole's last)."""
    cap = spherical_cap(1.0, 0.6, 30, 1.0)
    st = ShellStructure(cap, 1e6, NU, 0.01, "clamped")
    pr = ShellOfRevolution(st, load, control, node=12)
    u, p = _random_state(pr, 1e-2), 0.02 if control == "displacement" else 40.0
    x = pr.full_state(u, p)
    H = st.hessian(x).toarray()
    with_node = np.sort(np.append(st.free[st.free != pr.z_node], pr.z_node))
    without = st.free[st.free != pr.z_node]
    expected = {"force": int(np.sum(np.linalg.eigvalsh(H[np.ix_(with_node, with_node)]) < 0)),
                "displacement": int(np.sum(np.linalg.eigvalsh(H[np.ix_(without, without)]) < 0))}
    counts = {label: info.n_negative for label, info in pr.stability(u, p).items()}
    assert counts == expected
    assert list(counts)[0] == control  # the control's own label is the primary one
    assert expected["force"] != expected["displacement"] or expected["force"] > 0  # the state is not trivial


def test_supports_fix_the_right_dofs() -> None:
    cap = spherical_cap(1.0, 0.6, 20, 1.0)
    fixed = {b: list(ShellStructure(cap, 1e6, NU, 0.01, b).fixed) for b in SUPPORTS}
    n = 40
    assert fixed["sliding"] == [1, n - 2]
    assert fixed["pinned"] == fixed["clamped"] == [0, 1, n - 2]
    free = ShellStructure(cap, 1e6, NU, 0.01, "free")
    assert free.rigid_fix == 2 * 10 + 1 and list(free.fixed) == [21, n - 2]  # the rigid translation, removed


def test_loads_the_structure_cannot_carry_are_refused() -> None:
    cap = spherical_cap(1.0, 0.6, 20, 1.0)
    free = ShellStructure(cap, 1e6, NU, 0.01, "free")
    with pytest.raises(ValueError, match="support in z"):
        ShellOfRevolution(free, "point", "force")
    with pytest.raises(ValueError, match="free edge cannot carry pressure"):
        ShellOfRevolution(free, "pressure")
    sliding = ShellStructure(cap, 1e6, NU, 0.01, "sliding")
    with pytest.raises(ValueError, match="ring load needs node"):
        ShellOfRevolution(sliding, "ring", "force", node=19)
    with pytest.raises(ValueError, match="boundary must be one of"):
        ShellStructure(cap, 1e6, NU, 0.01, "glued")


def test_edge_tangent_is_exact_on_circles_and_lines() -> None:
    th = np.array([0.3, 0.35, 0.42])
    r, z = 2.0 * np.cos(th), 2.0 * np.sin(th) - 1.0
    assert edge_tangent(r, z) == pytest.approx((-math.sin(0.3), math.cos(0.3)), abs=1e-13)
    assert edge_tangent(np.array([1.0, 0.7, 0.2]), np.array([0.0, 0.4, 16.0 / 15.0])) == pytest.approx((-0.6, 0.8))


@pytest.mark.parametrize("control", ["force", "displacement"])
def test_point_load_under_a_fixed_pressure(control: str) -> None:
    """A pressurised cap probed at the pole: exact derivatives, and the fixed pressure's work in the energy."""
    cap = spherical_cap(1.0, 0.6, 40, 0.5)
    st = ShellStructure(cap, 1e6, NU, 0.01, "clamped")
    pr = ShellOfRevolution(st, "point", control, pressure=200.0)
    u = _random_state(pr, 1e-3)
    p = 50.0 if control == "force" else 0.01
    assert contin.check_problem(pr, u, p).ok
    bare = ShellOfRevolution(st, "point", control)
    x = pr.full_state(u, p)
    assert pr.energy(u, p) - bare.energy(u, p) == pytest.approx(200.0 * pr.pressure.energy_dp(x), rel=1e-12)
    other = pr.with_pressure(0.0)
    assert np.allclose(other.residual(u, p), bare.residual(u, p), rtol=0, atol=1e-12 * bare.residual_scale)
    assert pr.residual(u, p) is not None and pr.fixed_pressure == 200.0  # the copy did not touch the original


@pytest.mark.parametrize("control", ["force", "displacement"])
def test_with_pressure_is_the_problem_built_at_that_pressure(control: str) -> None:
    """The copy of :meth:`ShellOfRevolution.with_pressure` reads its own pressure everywhere: its observables (the
    reaction under displacement control carries the pressure's share) and their derivatives, its stability
    operators and its harmonic blocks are those of the problem built at that pressure."""
    st = ShellStructure(spherical_cap(1.0, 0.6, 40, 0.5), 1e6, NU, 0.01, "clamped")
    copy = ShellOfRevolution(st, "point", control, pressure=100.0, harmonics=3).with_pressure(300.0)
    built = ShellOfRevolution(st, "point", control, pressure=300.0, harmonics=3)
    u = _random_state(built, 1e-3)
    p = 50.0 if control == "force" else 0.01
    for name, fun in built.observables.items():
        assert copy.observables[name](u, p) == pytest.approx(fun(u, p), rel=1e-12, abs=1e-12), name
    for name, fun in built.observable_derivatives.items():
        for a, b in zip(copy.observable_derivatives[name](u, p), fun(u, p)):
            assert np.allclose(a, b, rtol=1e-12, atol=0.0), name
    ops, reference = copy.stability_operators(u, p), built.stability_operators(u, p)
    assert list(ops) == list(reference)
    for label in reference:
        assert abs(ops[label] - reference[label]).max() == 0.0, label
    blocks = (f.operator(2, u, p).toarray() for f in (copy.operator_families[0], built.operator_families[0]))
    assert np.array_equal(*blocks)


@pytest.mark.parametrize("boundary, factor", [("clamped", 1.0), ("pinned", (3.0 + NU) / (1.0 + NU))])
def test_plate_under_a_central_point_load_matches_the_linear_plate_solution(boundary: str, factor: float) -> None:
    """``w = factor F a^2 / (16 pi D)`` (Timoshenko & Woinowsky-Krieger, circular plates with a central load):
    factor 1 clamped, ``(3 + nu) / (1 + nu)`` simply supported.  Measured on the graded plate mesh
    (``python -m pytest tests/test_shell_structure.py -k plate``): clamped 3.1e-4, 8.2e-5, 2.2e-5 at
    N = 100, 200, 400 (order 1.92); pinned 1.2e-4, 3.3e-5, 8.6e-6 (order 1.92; without the moment-free
    edge element first order, 1.2e-3 at N = 200)."""
    from contin_models.shell.meridian import plate_meridian

    E, h, a = 1e6, 0.01, 1.0
    D = E * h**3 / (12.0 * (1.0 - NU**2))
    exact = factor * a * a / (16.0 * math.pi * D)
    errors = []
    for N in (100, 200, 400):
        pr = ShellOfRevolution(ShellStructure(plate_meridian(a, N), E, NU, h, boundary), "point", "force")
        errors.append(1.0 / pr.linear_stiffness() / exact - 1.0)
    assert abs(errors[-1]) < 5e-5
    assert errors[1] / errors[2] > 3.5 and errors[0] / errors[1] > 3.5  # second order


def test_complete_sphere_shrinks_uniformly_under_pressure() -> None:
    """Linear response of a complete sphere at the equator against ``-p R^2 (1 - nu) / (2 E h)`` divided by
    ``1 + (h/R)^2 / 12`` (the bending energy of the uniform curvature change): second order in 1/N,
    the Richardson extrapolation within 1e-8 (measured 3.5e-10, ``python -m studies.complete_sphere``)."""
    from contin_models.shell.meridian import complete_sphere_meridian

    R, E, h = 1.0, 1e6, 0.01
    exact = -R * R * (1.0 - NU) / (2.0 * E * h) / (1.0 + (h / R) ** 2 / 12.0)
    errors = []
    for N in (201, 401, 801):
        st = ShellStructure(complete_sphere_meridian(R, N), E, NU, h)
        assert st.poles == [0, N - 1] and st.rigid_fix == 2 * (N // 2) + 1  # the equator's height holds it
        dx = ShellOfRevolution(st, "pressure").linear_response()
        k = N // 2
        errors.append((dx[2 * k] / R) / exact - 1.0)  # the equator's radial displacement
    order = math.log2((errors[0] - errors[1]) / (errors[1] - errors[2]))
    extrapolated = errors[2] - (errors[1] - errors[2]) / (2.0**order - 1.0)
    assert order == pytest.approx(2.0, abs=0.05)
    assert abs(errors[2]) < 1e-5 and abs(extrapolated) < 1e-8


@pytest.mark.slow
def test_complete_sphere_bifurcates_near_the_classical_pressure() -> None:
    """R/h = 100: the first singular point of the pressure path within 2 % of p_c, mode degree 17 or 18."""
    from studies.complete_sphere import bifurcation_nodes, bifurcation_row

    row = bifurcation_row(100.0, bifurcation_nodes(100.0))
    assert row["p_over_p_c"] == pytest.approx(1.0, abs=0.02)
    assert row["l"] in (17, 18)


def test_moment_free_edge_derivatives_equal_sympy_in_high_precision() -> None:
    """The hand-derived gradient and Hessian of MomentFreeEdge against sympy's, evaluated at 40 digits."""
    import sympy

    from contin_models.shell.structure import MomentFreeEdge

    r, z = np.array([0.7, 0.55, 0.3]), np.array([0.6, 0.78, 0.9])
    edge = MomentFreeEdge(r, z, kb=2.5, nu=NU)
    r0, z0, r1, z1 = sympy.symbols("r0 z0 r1 z1")
    kappa = (z1 - z0) / (sympy.sqrt((r1 - r0) ** 2 + (z1 - z0) ** 2) * r0)
    energy = sympy.Float(edge.K, 40) * (kappa - sympy.Float(edge.kappa_bar, 40)) ** 2
    dofs = (r0, z0, r1, z1)
    x = np.array([0.71, 0.58, 0.56, 0.8])
    subs = {d: sympy.Float(float(v), 40) for d, v in zip(dofs, x)}
    grad = np.array([float(sympy.diff(energy, d).evalf(40, subs=subs)) for d in dofs])
    hess = np.array([[float(sympy.diff(energy, a, b).evalf(40, subs=subs)) for b in dofs] for a in dofs])
    state = np.concatenate([x, np.zeros(2)])
    assert edge.energy(state) == pytest.approx(float(energy.evalf(40, subs=subs)), rel=1e-13)
    assert np.allclose(edge.gradient(state), grad, rtol=1e-12, atol=1e-13 * np.abs(grad).max())
    assert np.allclose(edge.hessian(state), hess, rtol=1e-12, atol=1e-13 * np.abs(hess).max())


# ---- a point support of a closed shell's pole ---------------------------------------------------------
def test_a_point_support_of_the_south_pole_reacts_a_force_at_the_north_pole_with_reissners_stiffness() -> None:
    """A complete sphere pinned at its south pole (``boundary="pinned"``) under a point force at its north pole:
    by the symmetry about the equator each pole's dimple takes half the approach, so a pole's stiffness is twice
    the measured ``dF/dw``; Reissner (1946): ``4 E h^2 / (R sqrt(3 (1 - nu^2)))`` for a thin shell.  At ``R/h =
    1000`` the meshes N = 801 / 1601 / 3201 give 0.9886 / 0.9952 / 0.9971 of it (``R/h = 100``, N = 1601: 0.985, a
    thickness effect), so 1 % at N = 1601."""
    from contin_models.shell.meridian import complete_sphere_meridian

    R, h, E, N = 1000.0, 1.0, 1.0, 1601
    st = ShellStructure(complete_sphere_meridian(R, N), E, NU, h, boundary="pinned")
    assert st.boundary == "pinned" and st.rigid_fix is None and list(st.fixed) == [0, 1, 2 * N - 2]
    k_pole = 2.0 * ShellOfRevolution(st, "point", "displacement").linear_stiffness()
    assert k_pole / (4.0 * E * h * h / (R * math.sqrt(3.0 * (1.0 - NU * NU)))) == pytest.approx(1.0, abs=0.01)


@pytest.mark.parametrize("control", ["force", "displacement"])
def test_derivatives_of_a_probed_sphere_on_its_point_support(control: str) -> None:
    from contin_models.shell.meridian import complete_sphere_meridian

    st = ShellStructure(complete_sphere_meridian(1.0, 41), 1e6, NU, 0.01, boundary="pinned")
    pr = ShellOfRevolution(st, "point", control, pressure=300.0)
    report = contin.check_problem(pr, _random_state(pr, 1e-3), {"force": 50.0, "displacement": 0.01}[control])
    assert report.ok, report


def test_a_pole_takes_only_a_point_support() -> None:
    """On a pole: "pinned" (a point support) or "free" (the default "sliding" is read as it); "clamped" is refused
    with a message naming the allowed supports; a free sphere still refuses a point force."""
    from contin_models.shell.meridian import complete_sphere_meridian

    sphere = complete_sphere_meridian(1.0, 21)
    with pytest.raises(ValueError, match="pole on the axis: its support is 'pinned'.*or 'free'"):
        ShellStructure(sphere, 1e6, NU, 0.01, "clamped")
    assert ShellStructure(sphere, 1e6, NU, 0.01).boundary == "free"
    with pytest.raises(ValueError, match="support in z"):
        ShellOfRevolution(ShellStructure(sphere, 1e6, NU, 0.01, "free"), "point", "displacement")
