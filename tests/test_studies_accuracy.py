"""``python -m studies.accuracy`` (error against run time), fast mode, end to end; and its bookkeeping.

The bookkeeping (Richardson reference, Pareto fronts, equal-error ratios) is checked on synthetic
data with closed-form answers.  The study runs once (module fixture) into a temporary directory;
its outputs are checked for consistency with each other (every error recomputed from the CSV), for
what must hold (ours converges with N, the extrapolated value is closer than the N = 200 one), and
against an independent method: the natural-parameter baseline's bracket holds our N = 200 maximum.
"""

from __future__ import annotations

import csv
import json
import math
import statistics
from pathlib import Path
from typing import Any

import pytest

from studies import accuracy as study
from tests.figure_check import assert_figure


# ---- bookkeeping on synthetic data -----------------------------------------------------------------
def test_reference_of_a_known_expansion() -> None:
    ns = [25 * 2 ** k for k in range(6)]
    exact = 3.0
    values = [exact + 5.0 / n ** 2 + 40.0 / n ** 3 for n in ns]
    ref = study.reference(ns, values)
    err = abs(ref["value"] - exact)
    assert err < 0.05 * abs(values[-1] - exact)  # far closer than the finest mesh
    assert ref["order"] == pytest.approx(2.0, abs=0.05)
    assert ref["from_Ns"] == ns[-3:]
    # both estimates bound the actual error of the reference
    assert ref["estimate_previous"] >= err and ref["last_correction"] >= err
    assert ref["error_estimate"] == ref["estimate_previous"]
    with pytest.raises(ValueError):
        study.reference([25, 50, 200], values[:3])


def test_pareto_front_and_equal_error_ratio_of_power_laws() -> None:
    # ours: t = 1e-3 e^(-1/2); the baseline needs 40 times as long at every error; plus dominated points
    errs = [10.0 ** -k for k in range(1, 8)]
    ours = [(1e-3 * e ** -0.5, e) for e in errs] + [(1.0, 1e-2), (0.0, 1e-3)]
    base = [(40 * 1e-3 * e ** -0.5, e) for e in errs[:5]] + [(5.0, 0.5)]
    front = study.pareto_front(ours)
    assert [e for _, e in front] == errs and all(t2 > t1 for (t1, _), (t2, _) in zip(front, front[1:]))
    r = study.equal_error_ratios(base, ours)
    assert r["overlap"] == [pytest.approx(1e-5), pytest.approx(1e-1)]
    assert r["min"] == pytest.approx(40.0, rel=1e-12) and r["max"] == pytest.approx(40.0, rel=1e-12)
    assert set(r["at_decades"]) == {"1e-05", "1e-04", "1e-03", "1e-02", "1e-01"}
    # no common range: only the lower bound (ours at least as accurate) remains
    worse = [(2.0, 0.3), (1.0, 0.6)]
    r = study.equal_error_ratios(worse, ours)
    assert r["overlap"] is None and r["min"] is None
    fastest_good = min(t for t, e in study.pareto_front(ours) if e <= 0.3)
    assert r["lower_bound_max"] == pytest.approx(2.0 / fastest_good)
    assert study.equal_error_ratios([], ours)["lower_bounds"] == []


def test_short_runs_are_timed_by_the_median_of_repeats(monkeypatch: pytest.MonkeyPatch) -> None:
    # the study's run below uses --repeat 1; the repeats themselves are checked here
    calls: list[int] = []
    out, t, times = study._timed(lambda: calls.append(1) or len(calls), 3)
    assert out == 3 and len(times) == 3 and t == statistics.median(times)
    monkeypatch.setattr(study, "REPEAT_BELOW_S", 0.0)  # a run that counts as long runs once
    out, t, times = study._timed(lambda: calls.append(1) or len(calls), 3)
    assert out == 4 and times == [t]


# ---- the study, fast mode -----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def result(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int, dict[str, Any], list[dict[str, str]]]:
    out = tmp_path_factory.mktemp("accuracy")
    # one timing per run (not the default median of 3): the checks here are on values, and on the
    # timings only for their bookkeeping, which --repeat 1 passes through as well
    rc = study.main(["--out", str(out), "--quiet", "--repeat", "1"])
    with open(out / "runs.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    return out, rc, json.loads((out / "summary.json").read_text()), rows


def _f(row: dict[str, str], key: str) -> float:
    return float(row[key])


def _select(rows: list[dict[str, str]], method: str, quantity: str, setting: str | None = None) -> list[dict[str, str]]:
    return [r for r in rows if r["method"] == method and r["quantity"] == quantity
            and (setting is None or r["setting"] == setting)]


def _ours_at(rows: list[dict[str, str]], N: int) -> dict[str, str]:
    return [r for r in _select(rows, "ours", "F_max", "default") if int(r["N"]) == N][0]


@pytest.mark.slow
def test_writes_every_file(result) -> None:
    out, rc, summary, rows = result
    assert rc == 0
    assert_figure(out, "error_vs_time", min_png_bytes=10_000)
    assert summary["mode"] == "fast" and summary["repeat"] == 1
    assert summary["command"].startswith("python -m studies.accuracy")
    assert {"F_max", "w_at_F_max", "w_b_c_over_R"} <= set(summary["references"])
    assert {r["method"] for r in rows} == {"ours", "ours+Richardson", "natural_parameter", "dynamic_relaxation"}
    assert not [r for r in rows if r["failure"]]
    assert summary["wall_time_s"] < 120


@pytest.mark.slow
def test_every_error_is_recomputed_from_its_value(result) -> None:
    _, _, summary, rows = result
    for r in rows:
        ref = summary["references"][r["quantity"]]["value"]
        assert _f(r, "reference") == ref
        assert _f(r, "abs_error") == pytest.approx(abs(_f(r, "value") - ref), rel=1e-12, abs=1e-300)
        assert _f(r, "rel_error") == pytest.approx(abs(_f(r, "value") - ref) / abs(ref), rel=1e-12, abs=1e-300)
        assert math.isfinite(_f(r, "wall_time_s")) and _f(r, "wall_time_s") > 0


@pytest.mark.slow
def test_ours_converges_and_the_reference_is_its_richardson_limit(result) -> None:
    _, _, summary, rows = result
    for q in ("F_max", "w_at_F_max", "w_b_c_over_R"):
        dflt = sorted(_select(rows, "ours", q, "default"), key=lambda r: int(r["N"]))
        ns = [int(r["N"]) for r in dflt]
        vals = [_f(r, "value") for r in dflt]
        errs = [_f(r, "rel_error") for r in dflt]
        ref = summary["references"][q]
        # errors fall with N on every mesh not used for the reference
        assert all(b < a for a, b in zip(errs[:-3], errs[1:-2])), (q, errs)
        # the reference is Richardson from the three finest meshes, and its error estimate is the
        # change from the three before; both are below the N = 200 error
        f0, f1, f2 = vals[-3:]
        p = math.log2(abs((f1 - f0) / (f2 - f1)))
        assert ref["value"] == pytest.approx(f2 + (f2 - f1) / (2 ** p - 1), rel=1e-14)
        assert ref["from_Ns"] == ns[-3:]
        e200 = errs[ns.index(200)] * abs(ref["value"])
        assert ref["error_estimate"] < e200
        assert ref["estimate_previous"] < e200
    orders = summary["orders"]["F_max"]["successive"]
    assert all(1.8 < p < 2.2 for p in orders)  # second order, as shell_mesh_convergence measures


@pytest.mark.slow
def test_natural_parameter_bracket_holds_our_maximum(result) -> None:
    _, _, summary, rows = result
    ours200 = _f(_ours_at(rows, 200), "value")
    finest = min((r for r in _select(rows, "natural_parameter", "F_max") if int(r["N"]) == 200),
                 key=lambda r: _f(r, "bracket_hi") - _f(r, "bracket_lo"))
    lo, hi = _f(finest, "bracket_lo"), _f(finest, "bracket_hi")
    assert hi - lo < 1e-3
    assert lo - 1e-9 <= ours200 <= hi + 1e-9
    # so the two agree to the bracket, far below the discretization error at N = 200
    assert _f(finest, "solver_rel_error") < 0.1 * _f(finest, "discretization_rel_error")


@pytest.mark.slow
def test_slower_ramps_and_tighter_brackets_are_more_accurate(result) -> None:
    _, _, _, rows = result
    dr = {(r["N"], r["dt_omega"], r["rate_eps"]): _f(r, "solver_rel_error")
          for r in _select(rows, "dynamic_relaxation", "F_max")}
    assert dr[("50", "1000000.0", "1e-09")] < dr[("50", "10000.0", "1e-07")] < dr[("50", "1.0", "0.001")]
    np200 = sorted((r for r in _select(rows, "natural_parameter", "F_max") if r["N"] == "200"),
                   key=lambda r: -(_f(r, "bracket_hi") - _f(r, "bracket_lo")))
    errs = [_f(r, "solver_rel_error") for r in np200]
    assert errs[-1] < errs[0]
    # dynamic relaxation's reaction runs ahead of the static maximum (damping resists the motion) by
    # ~140 eps F: above ours wherever that lag exceeds the sampling error of the maximum (< 1e-5 F)
    ours50 = _f(_ours_at(rows, 50), "value")
    ahead = [r for r in _select(rows, "dynamic_relaxation", "F_max") if r["N"] == "50" and float(r["rate_eps"]) >= 1e-7]
    assert len(ahead) == 2 and all(_f(r, "value") > ours50 for r in ahead)


@pytest.mark.slow
def test_targets_follow_from_the_numbers(result) -> None:
    _, _, summary, rows = result
    t = summary["targets"]["N200_within_1e-3_under_0.5s"]
    row = _ours_at(rows, 200)
    assert t["rel_error"] == pytest.approx(_f(row, "rel_error"), rel=1e-12)
    assert t["time_s"] == pytest.approx(_f(row, "wall_time_s"), rel=1e-12)
    assert t["met"] is (t["rel_error"] <= 1e-3 and t["time_s"] < 0.5)
    assert t["rel_error"] < 1e-3  # the accuracy half holds on any machine
    rt = summary["targets"]["richardson_200_400_800_within_1e-6_under_5s"]
    rich = [r for r in _select(rows, "ours+Richardson", "F_max") if r["N"] == "200"][0]
    assert rt["rel_error"] == pytest.approx(_f(rich, "rel_error"), rel=1e-12)
    assert rt["met"] is (rt["rel_error"] <= 1e-6 and rt["time_s"] < 5.0)
    # Richardson beats every single mesh of ours up to 800 (its finest input)
    assert rt["rel_error"] < min(_f(r, "rel_error") for r in _select(rows, "ours", "F_max", "default")
                                 if int(r["N"]) <= 800)
    ratios = summary["ratios"]["F_max"]["natural_parameter/ours"]
    assert ratios["min"] is not None and ratios["min"] > 0
    for p in ratios["points"]:
        assert p["ratio"] == pytest.approx(p["t_baseline"] / p["t_ours"])
    cost = summary["newton_step_cost"]
    assert 0.0 < cost["exponent_N_ge_400"] < 2.0 and len(cost["seconds"]) == len(cost["N"])
