"""The pressurised cap probed at its pole: the limit load's fold curve in (p, F) (``studies/pressure_probe.py``).

The check is independent of the fold-curve machinery: where the limit load of the point force falls to
``F = 0`` the cap carries the pressure alone at a singular point, which must be a fold of the
pressure-controlled path traced on its own (measured at N = 200: equal to 1e-12).
"""

from __future__ import annotations

import pytest

from studies.pressure_probe import fold_curve, pressure_folds


@pytest.mark.slow
def test_limit_load_vanishes_at_a_fold_of_the_pressure_alone() -> None:
    curve = fold_curve(100)
    assert curve["F_max_at_p0_norm"] > 0 and curve["p_at_F_zero_over_p_c"] is not None
    folds = pressure_folds(100)
    nearest = min(folds, key=lambda f: abs(f - curve["p_at_F_zero_over_p_c"]))
    assert curve["p_at_F_zero_over_p_c"] == pytest.approx(nearest, abs=1e-8)
    F = [r["F"] for r in curve["rows"]]
    assert F[0] == pytest.approx(curve["F_max_at_p0"], rel=1e-9)  # the curve starts at the cap's own limit load
