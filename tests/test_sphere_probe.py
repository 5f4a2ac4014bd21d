"""A pressurised complete sphere probed at its poles (``studies.sphere_probe``, ``docs/three_d.md`` section 6).

Checked against what the study does not compute: the closed form of the pressurised point-load stiffness against a
quadrature of its defining integral; the model's stiffness against that closed form; the volume-held probe's
derivatives against finite differences; and, marked slow, the study's key numbers: the force maximum under external
pressure is where the symmetry about the equator breaks (two equal dimples in series: an argument, not a number of
the code), and the unpressurised sphere's first bifurcation into waves (regression pins, labelled as such, beside the
mesh check of ``docs/three_d.md``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

import contin
from contin_models.shell.meridian import complete_sphere_meridian
from contin_models.shell.probe import ProbeAtFixedVolume
from contin_models.shell.structure import ShellOfRevolution, ShellStructure
from studies.sphere_probe import (initial_stiffness, pressurised_state, pressurised_stiffness, probe_case,
                                  probe_problem, probed_sphere)


@pytest.mark.parametrize("tau", [-0.9, -0.5, 0.0, 0.5, 0.999, 1.0, 1.5, 3.0])
def test_the_pressurised_stiffness_is_the_integral_it_comes_from(tau: float) -> None:
    """``k / k_R = (pi / 2) / int_0^inf ds / (s^2 + 2 tau s + 1)`` (the Hankel transform's integral in units where
    ``D = E h / R^2 = 1``), by quadrature."""
    integral = quad(lambda s: 1.0 / (s * s + 2.0 * tau * s + 1.0), 0.0, np.inf, epsabs=0.0, epsrel=1e-12)[0]
    assert pressurised_stiffness(tau) == pytest.approx(math.pi / 2.0 / integral, rel=1e-9)


@pytest.mark.parametrize("p", [-0.5, 0.5])
def test_the_probed_spheres_stiffness_follows_the_pressurised_closed_form(p: float) -> None:
    """The pole stiffness at ``p`` over the unpressurised one (the mesh's and the thickness's share of the offset
    from Reissner cancels) against ``k(tau) / k_R`` with ``tau = -p / p_c``: within 2 % at ``N = 201`` (measured
    0.6 % and 0.8 % off; 0.5 % and 0.9 % at ``N = 401``, ``python -m studies.sphere_probe --full``)."""
    st = probed_sphere(201)
    k = {}
    for q in (0.0, p):
        problem, U, w = probe_problem(st, q, "pressure", pressurised_state(st, q), harmonics=0)
        k[q] = initial_stiffness(problem, U, w)
    assert k[p] / k[0.0] == pytest.approx(pressurised_stiffness(-p), rel=0.02)


def test_the_volume_held_probe_has_the_derivatives_of_its_residual() -> None:
    st = ShellStructure(complete_sphere_meridian(1.0, 41), 1e6, 0.3, 0.01, boundary="pinned")
    probe = ShellOfRevolution(st, "point", "displacement", pressure=300.0)
    volume = ProbeAtFixedVolume(probe, 0.99 * probe.pressure.V0, 1e3)
    rng = np.random.default_rng(3)
    U = volume.join(probe.reference_unknowns() + 1e-3 * rng.standard_normal(probe.n), 250.0)
    report = contin.check_problem(volume, U, 0.01)
    assert report.ok, report
    # the observables' exact derivatives (the force's share of the multiplier among them) by central differences
    v, eps, w = rng.standard_normal(U.size), 1e-6, 0.01
    for name in ("F", "F_norm", "V", "p", "w"):
        fun, (dU, dw) = volume.observables[name], volume.observable_derivatives[name](U, w)
        along = (fun(U + eps * v, w) - fun(U - eps * v, w)) / (2.0 * eps)
        in_w = (fun(U, w + eps) - fun(U, w - eps)) / (2.0 * eps)
        size = abs(np.dot(dU, v)) + abs(dw) + 1e-300
        assert np.dot(dU, v) == pytest.approx(along, rel=1e-5, abs=1e-7 * size), name
        assert dw == pytest.approx(in_w, rel=1e-5, abs=1e-7 * size), name


def test_the_volume_held_probe_refuses_what_it_cannot_hold() -> None:
    st = ShellStructure(complete_sphere_meridian(1.0, 21), 1e6, 0.3, 0.01, boundary="pinned")
    with pytest.raises(ValueError, match="nonzero pressure"):
        ProbeAtFixedVolume(ShellOfRevolution(st, "point", "displacement"), 1.0, 1.0)
    with pytest.raises(ValueError, match="control='displacement'"):
        ProbeAtFixedVolume(ShellOfRevolution(st, "point", "force", pressure=1.0), 1.0, 1.0)
    with pytest.raises(ValueError, match="volume must be positive"):
        ProbeAtFixedVolume(ShellOfRevolution(st, "point", "displacement", pressure=1.0), -1.0, 1.0)


@pytest.mark.slow
def test_under_external_pressure_the_largest_force_is_where_the_equator_symmetry_breaks() -> None:
    """``p = 0.5 p_c``, pressure control, ``N = 201``: the force maximum and the first branch point coincide (two
    equal dimples in series lose their symmetry where each one's stiffness vanishes), no bifurcation into waves
    before it, and the probe's force there (regression pin 0.490 E h^3 / R, 1.2 % below the N = 401 value of
    ``docs/three_d.md``)."""
    case = probe_case(0.5, "pressure", 201)
    assert case["w_branch_point"] == pytest.approx(case["w_Fmax"], rel=1e-3)
    assert case["n"] is None or case["w_bif"] > case["w_Fmax"]
    assert case["F_max"] == pytest.approx(0.490, rel=0.01)


@pytest.mark.slow
def test_the_unpressurised_dimple_breaks_into_two_and_three_waves_together() -> None:
    """``p = 0``, pressure control, ``N = 201``: no force maximum to the travel's end; the first bifurcation into
    waves at ``w = 30.4 h`` (regression pin; 29.97 h at ``N = 801``, ``python -m studies.sphere_probe --full``),
    ``n = 2`` with ``n = 3`` in the same step."""
    case = probe_case(0.0, "pressure", 201)
    assert case["F_max"] is None
    assert case["n"] == 2 and "3" in case["n_also"].split()
    assert case["w_bif"] == pytest.approx(30.4, abs=0.2)
