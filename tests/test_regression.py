"""Regression: the special points of six scenes stay where they were before the redesign of issue 14.

The reference files in ``tests/regression/`` were written by ``python -m tests.regression.capture``
on commit 57912bb.  Every located special point must come back in the same order with the same kind,
label and stability, and at the same place to 1e-8 (displacements in units of R, forces in units of
``2 pi D / R``).
"""

from __future__ import annotations

import json
import math

import pytest

from tests.regression.capture import HERE, SCENES, extract, trace_summary

TOL = 1e-8
#: numeric fields and the unit they are compared in (F is compared through F_norm)
NUMERIC = ("p", "w", "w_b", "F_norm", "w_over_R", "w_b_over_R")


def _close(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=0.0, abs_tol=TOL)


@pytest.mark.parametrize("name", list(SCENES))
def test_special_points_unchanged(name: str) -> None:
    reference = json.loads((HERE / f"{name}.json").read_text())
    now = extract(trace_summary(reference["overrides"]))
    ref_points, new_points = reference["special_points"], now["special_points"]
    assert [(p["kind"], p["label"]) for p in new_points] == [(p["kind"], p["label"]) for p in ref_points]
    for i, (ref, new) in enumerate(zip(ref_points, new_points)):
        for key in ("parameter", "stable_before", "stable_after"):
            assert new.get(key) == ref.get(key), f"{name}: point {i} ({ref['kind']}) {key}"
        for key in NUMERIC:
            if key in ref:
                assert _close(new[key], ref[key]), f"{name}: point {i} ({ref['kind']}) {key} {new[key]!r} != {ref[key]!r}"
    for key, value in reference["summary"].items():
        if isinstance(value, float):
            scale = 1.0 if key != "F_at_snap" else abs(reference["summary"][key]) or 1.0
            assert _close(now["summary"][key] / scale, value / scale), f"{name}: {key}"
        else:
            assert now["summary"][key] == value, f"{name}: {key}"
