"""Steps that jump over part of the curve are rejected (issue 15, item 3).

``f = u^3 - u + p`` is an S-curve with folds at ``u = -+1/sqrt 3``, ``p = +-2 / (3 sqrt 3)``.  From
``u = 2`` with a first step of 12 (unit weights: the model gives its residual scale) the corrector
lands on the far arm, ``u = -1.97``: both folds are stepped over, the determinant sign changes twice
(i.e. not at all) and the tangents at both ends are parallel, so neither the fold test nor the
tangent guard sees it; without stability there is no Morse index either.  The observable's change
(-3.97) is far beyond what its slopes at the step's ends allow.
"""

import math

import numpy as np
import pytest

import contin
import contin.palc as palc


def s_curve() -> contin.Problem:
    return contin.Problem(residual=lambda u, p: np.array([u[0] ** 3 - u[0] + p]),
                          jacobian=lambda u, p: np.array([[3 * u[0] ** 2 - 1]]),
                          dresidual_dp=lambda u, p: np.array([1.0]),
                          observables={"u": lambda u, p: float(u[0])},
                          observable_derivatives={"u": lambda u, p: (np.array([1.0]), 0.0)},
                          residual_scale=1.0, symmetric=True, name="s_curve")


def trace() -> contin.Branch:
    return contin.continuation(s_curve(), [2.0], -6.0, p_max=8.0, ds=12.0, ds_max=12.0, max_steps=100)


def test_a_step_over_both_folds_is_rejected_and_both_folds_are_found():
    br = trace()
    assert br.status == "bound", br.message
    assert any("changed by" in reason for reason in br.meta["rejected_steps"])
    folds = br.folds()
    assert len(folds) == 2 and all(f.located for f in folds)
    p_fold = 2 / (3 * math.sqrt(3))
    np.testing.assert_allclose(sorted(f.p for f in folds), [-p_fold, p_fold], rtol=1e-10)
    np.testing.assert_allclose(sorted(f.u[0] for f in folds), [-1 / math.sqrt(3), 1 / math.sqrt(3)], rtol=1e-8)


def test_without_the_observable_guard_the_same_run_skips_both_folds(monkeypatch: pytest.MonkeyPatch):
    # the guard is what finds them: switched off, the first step lands on the far arm unnoticed
    monkeypatch.setattr(palc, "OBSERVABLE_JUMP", math.inf)
    br = trace()
    assert br.status == "bound" and not br.folds()
    assert br.u[1, 0] < -1.0
