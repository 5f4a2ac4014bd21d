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
    """Sliding cap with a pole force: same unknowns, residual and Jacobian as ShellPointLoad
    (displacement control), same linear stiffness under both controls."""
    old = ShellPointLoad(1.0, 1e6, 0.5, 0.02, 0.8, 120, control)
    new = ShellOfRevolution(ShellStructure(spherical_cap(1.0, 0.8, 120), 1e6, 0.5, 0.02, "sliding"), "point", control)
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
