"""The automatic arclength scales see the buckling load and the state a path grows to.

With default settings the weights are ``1 / U`` and ``1 / P``, the start's own scales
(:mod:`contin.path.scales`).  Three starts where the sizes alone mislead:

* a ring under pressure in nodal positions: nearly rigid before it buckles (membrane penalty
  ``EA R^2 / EI = 1e6``), so the load that would move the state by its own size is about ``1e6``
  while the buckling loads are 3, 8, 15 and 24 (``PressurisedRing.buckling_load``);
* Augusti's struts tilted by ``1e-5`` or ``1e-6``: the state at the start is that small, and the path
  grows it by three orders of magnitude before its limit load (``AugustiStrut.limit_load``);
* the pitchfork's branch point, located at a roundoff-small load, switched from on a model that has
  measured no scales yet: the load scale is not that roundoff, but the load change of the new branch
  over the state's scale (in any units of the load).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import contin
from contin_models.benchmarks.augusti import AugustiStrut
from contin_models.benchmarks.pitchfork import Pitchfork
from contin_models.benchmarks.ring import PressurisedRing

#: The closed-form points are located to this relative precision.
LOCATE_TOL = 1e-8
#: The ring's bound: four double points (modes n = 2 .. 5) below it.
RING_P_MAX = 30.0


@pytest.mark.parametrize("N, coordinates, stability", [
    (64, "positions", False), (64, "displacements", True),
    pytest.param(128, "positions", True, marks=pytest.mark.slow),
    pytest.param(128, "displacements", True, marks=pytest.mark.slow)])
def test_the_ring_steps_through_each_buckling_load_and_locates_it_as_double(N: int, coordinates: str,
                                                                          stability: bool) -> None:
    # with stability on, a step guard rejected every step across a double point (its index jumps by
    # two) until the steps fell into the corrector's singular zone there: the runs stopped at n = 5
    # (N = 64, displacements) or at n = 2 and n = 4 (N = 128)
    m = PressurisedRing(N, coordinates=coordinates)
    loads = [m.buckling_load(n) for n in (2, 3, 4, 5)]
    assert loads[-1] < RING_P_MAX < m.buckling_load(6)
    br = contin.continuation(m, m.trivial_state(0.0), 0.0, p_max=RING_P_MAX, stability=stability)
    assert br.status == "bound", br.message
    p = np.asarray(br.p)
    crossed = [sum(min(a, b) < load <= max(a, b) for load in loads) for a, b in zip(p[:-1], p[1:])]
    assert max(crossed) <= 1, f"a step from p = 0 crossed {max(crossed)} buckling loads (first step to {p[1]:.4g})"
    for load in loads:
        near = [bp for bp in br.branch_points() if abs(bp.p - load) <= 1e-3 * load]
        assert len(near) == 1, f"p_n = {load}: {[bp.p for bp in br.branch_points()]}"
        (bp,) = near
        assert bp.located
        assert abs(bp.p - load) <= LOCATE_TOL * load
        assert bp.bifurcation.multiplicity == 2


STRUTS = [(None, 1e-5, 0.0), (None, 1e-6, 0.0),
          (2.0, 1e-5, 0.0), (2.0, 1e-5, math.pi / 4), (2.0, 1e-6, 0.0), (2.0, 1e-6, math.pi / 4)]


@pytest.mark.parametrize("spring_length, imperfection, direction", STRUTS)
def test_the_imperfect_strut_reaches_its_limit_load_with_default_settings(spring_length, imperfection, direction) -> None:
    m = AugustiStrut(spring_length, imperfection, direction)
    _, limit = m.limit_load()
    # the strut lies flat at tilt 1, where its residual is not defined: stop well before
    br = contin.continuation(m, m.path_state(imperfection), 0.0, p_max=1.5, bounds={"tilt": (None, 0.5)})
    assert br.status == "bound", br.message
    folds = [s for s in br.special_points if s.kind == "fold"]
    assert folds, f"no fold: {br.message}"
    assert folds[0].located
    assert abs(folds[0].p - limit) <= LOCATE_TOL * limit
    assert max(br.p) <= limit * (1 + LOCATE_TOL)


def test_a_switch_at_a_pitchfork_located_at_a_roundoff_load_follows_the_new_branch() -> None:
    br = contin.continuation(Pitchfork(), np.zeros(2), -1.0, p_max=1.0, ds=0.1)
    (bp,) = br.branch_points()
    assert abs(bp.p) <= 1e-12  # located at a roundoff-small load, not at 0
    # a model that has measured no scales yet (built anew, or the branch read back from a file)
    new = contin.switch_branch(Pitchfork(), bp, p_max=0.25)
    assert new.status == "bound", new.message
    assert new.p[-1] == pytest.approx(0.25, abs=1e-12)
    # the supercritical branch u1^2 = p
    np.testing.assert_allclose(np.asarray(new.u)[1:, 0] ** 2, np.asarray(new.p)[1:], atol=1e-8)


def pitchfork_in_load_units(unit: float, symmetric: bool) -> contin.Problem:
    """The pitchfork's normal form with the load in units of ``1 / unit``: ``u1^2 = p / unit`` past ``p = 0``."""
    return contin.Problem(residual=lambda u, p: np.array([-(p / unit) * u[0] + u[0] ** 3, u[1]]),
                          jacobian=lambda u, p: np.array([[-(p / unit) + 3 * u[0] ** 2, 0.0], [0.0, 1.0]]),
                          dresidual_dp=lambda u, p: np.array([-u[0] / unit, 0.0]), symmetric=symmetric,
                          name=f"pitchfork(unit={unit:g})")


@pytest.mark.parametrize("unit, symmetric", [(1e6, True), (1.0, False)],
                         ids=["loads a million times larger", "not declared symmetric"])
def test_the_switch_at_a_roundoff_pitchfork_takes_the_steps_of_its_branch(unit: float, symmetric: bool) -> None:
    # symmetric: the branch's Koiter coefficient gives the load scale (p - p_c = unit xi^2);
    # otherwise only the step that found the point says its load is zero
    br = contin.continuation(pitchfork_in_load_units(unit, symmetric), np.zeros(2), -unit, p_max=unit, ds=0.1)
    (bp,) = br.branch_points()
    assert abs(bp.p) <= 1e-12 * unit
    new = contin.switch_branch(pitchfork_in_load_units(unit, symmetric), bp, p_max=0.25 * unit)
    assert new.status == "bound", new.message
    assert len(new.p) <= 20
    np.testing.assert_allclose(np.asarray(new.u)[1:, 0] ** 2, np.asarray(new.p)[1:] / unit, atol=1e-8)
