"""studies/apex_load_waves.py: the clamped cap under an apex load (Fitch 1968) against the independent shallow-shell
model (models/benchmarks/shallow_cap.py), which shares nothing with the shell model but the engine."""

import numpy as np
import pytest

from studies import apex_load_waves as al
from studies import shallow_cap_waves

N_SHELL = 120    # meridian of the shell model at R/t = 10^4 (the shallow limit); at 60 the first bifurcation is 2 % late
N_SHALLOW = 40   # radial elements of the shallow-shell model
#: The two models differ by the discretisations (about 0.3 % at these meshes, docs/asymmetric.md) and the shell's
#: depth (H / R = 2e-3 at lambda = 14, R/t = 10^4): 1 % on deflections and loads.
TOL = 0.01


def shallow_path(lam: float, w_end: float):
    """The shallow model's axisymmetric path to ``w_end`` with its wave numbers watched, and its load in
    ``P R / (E t^3)``."""
    cap, path = shallow_cap_waves.axisymmetric_path(lam, N_SHALLOW, w_end)
    return path, np.asarray(path.observable("q")) * al.load_factor(lam, al.NU)


def test_load_maximum_is_the_vertex_of_a_parabola() -> None:
    w = np.linspace(0.0, 4.0, 9)
    P = 3.0 - 0.7 * (w - 1.9) ** 2
    assert al.load_maximum(w, P) == pytest.approx((1.9, 3.0), rel=1e-12)
    assert al.load_maximum(w, w ** 2) is None


@pytest.mark.parametrize("lam, n", [pytest.param(12.0, 4, marks=pytest.mark.slow), pytest.param(14.0, 3, marks=pytest.mark.slow)])
def test_the_first_bifurcation_in_the_shallow_limit_is_the_shallow_theory_s(lam: float, n: int) -> None:
    case = al.apex_case(lam, al.SHALLOW, N_SHELL, 2, branch=False)
    path, P = shallow_path(lam, 22.0)
    first = next(s for s in path.special_points if s.kind == "bifurcation" and s.located)
    assert case["n"] == int(first.info["key"]) == n
    assert case["w_bif"] == pytest.approx(float(first.p), rel=TOL)
    assert case["P_bif"] == pytest.approx(float(np.interp(first.p, path.p, P)), rel=TOL)
    # well before the axisymmetric limit load: the cap leaves the path at under half of it
    assert case["bifurcation_first"] and case["P_bif"] < 0.5 * case["P_limit"]


@pytest.mark.slow
def test_at_lambda_8_the_cap_snaps_axisymmetrically_before_any_bifurcation() -> None:
    """Fitch's (1968) narrow range of thick caps where the axisymmetric snap comes first; the limit load as the
    shallow theory's."""
    case = al.apex_case(8.0, al.SHALLOW, N_SHELL, 2, branch=False)
    path, P = shallow_path(8.0, 2.0 * al.rise_over_thickness(8.0))
    assert not any(s.kind == "bifurcation" for s in path.special_points)
    assert case["n"] is None and not case["bifurcation_first"]
    w_lim, P_lim = al.load_maximum(np.asarray(path.p), P)
    assert case["w_limit"] == pytest.approx(w_lim, rel=TOL)
    assert case["P_limit"] == pytest.approx(P_lim, rel=TOL)


@pytest.mark.slow
def test_the_lambda_10_branch_is_a_bubble_that_returns_where_the_shallow_path_gets_stable_again() -> None:
    """The four-wave branch at lambda = 10 leaves and rejoins the axisymmetric path where its block ``n = 4`` turns
    indefinite and definite again; the shallow model's path crosses there too."""
    case = al.apex_case(10.0, al.SHALLOW, N_SHELL, 2)
    path, _ = shallow_path(10.0, 22.0)
    crossings = [float(s.p) for s in path.special_points if s.kind == "bifurcation" and s.info.get("key") == 4]
    assert case["n"] == 4 and len(crossings) == 2
    assert case["w_bif"] == pytest.approx(crossings[0], rel=TOL)
    assert case["w_return"] == pytest.approx(crossings[1], rel=TOL)
    # the bubble carries the cap past its return up to a fold in w, stable where it leaves the path
    assert case["end"] == "fold in w" and case["w_end"] > case["w_return"]
    assert case["stable_to_w"] > case["w_bif"]
