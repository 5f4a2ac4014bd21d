"""What the engine does today at the degenerate points of four symmetric models with closed forms.

Run ``python -m studies.degenerate_points [--out DIR] [--full]``.

The models (``contin_models.benchmarks``; each module's docstring derives its closed forms):

* :class:`~contin_models.benchmarks.square.D4Square`: the square membrane, ``n = 30``; branch points of
  the trivial branch at the eigenvalues of the discrete Laplacian, double for ``(j, k) != (k, j)``;
* :class:`~contin_models.benchmarks.ring.PressurisedRing`: the ring under hydrostatic pressure,
  ``N = 64`` and ``128``, in displacements and in positions; double points at ``p_n^(N)``, ``n = 2 .. 5``;
* :class:`~contin_models.benchmarks.spring_chain.BistableChain`: ``k = 2, 3, 6`` springs under a
  prescribed total elongation, in node positions and in zero-sum modes; two branch points of
  multiplicity ``k - 1`` on the homogeneous branch, and the quasi-static sawtooth;
* :class:`~contin_models.benchmarks.augusti.AugustiStrut`: the O(2)-symmetric and the two-mode
  (``a/L = 2``) strut, perfect (a double point at ``lambda = 1``) and with an initial tilt ``1e-5``
  and ``1e-6`` (its limit load, along an axis and a diagonal).

Every run uses the engine's default settings, with ``stability=True`` (without it the engine counts
no Morse index) and the bound the case needs: :func:`contin.continuation` from the unloaded state
(the imperfect strut from its tilted state at ``lambda = 0``), :func:`contin.switch_branch` where a
user would (at the first located branch point beside a closed-form one), :func:`contin.quasistatic`
for the chain.  The imperfect strut's bound is a tilt of 0.5 besides ``lambda = 1.5``: past its
limit load the path tilts the strut towards 1, where its residual is not defined.  For each
closed-form special point the table gives what the engine reported near it
(within ``1e-3`` relative): its kind, its location and error, whether it was located, and the change
of the Morse index across it between stored points; then every change of the Morse index between
two stored points that the special points the engine reported there do not account for (each
reported fold or branch point accounts for a change by one).  The ring's automatic scales (the
inverse arclength weights) and the first step are listed, with the first step of a run without a
bound, and the discretisation error of the ring's ``p_2`` (closed form, :meth:`PressurisedRing.buckling_load`)
against ``3 EI / R^3`` for ``N = 32, 64, 128``, split into the mesh's and the membrane penalty's share.

Verdicts: ``ok`` (located, of the right kind, simple, within ``1e-8``), ``silent`` (nothing reported
although the Morse index changed), ``as simple`` (a multiple point reported as a simple one),
``misread`` (the engine's kind or its recorded error says something else), ``bracketed``
(reported but not located), ``imprecise`` (located, off by more than ``1e-8``), ``not reached``
(the run ended first).

``--full``: the square up to ``p = 105`` (two double points instead of one) and the ring also at
``N = 32``.  Writes ``points.csv`` (one row per closed-form point), ``index_changes.csv``,
``runs.csv``, ``ring_scales.csv``, ``ring_discretisation.csv`` and ``summary.json``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from dataclasses import dataclass  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import contin  # noqa: E402
from contin_models.benchmarks.augusti import AugustiStrut  # noqa: E402
from contin_models.benchmarks.ring import PressurisedRing  # noqa: E402
from contin_models.benchmarks.spring_chain import BistableChain  # noqa: E402
from contin_models.benchmarks.square import D4Square  # noqa: E402
from studies._common import output_dir, print_table, run_study, say, study_parser, write_csv, write_json  # noqa: E402

#: A reported special point within this relative distance of a closed-form one is taken for it.
MATCH_WINDOW = 1e-3
#: The acceptance's precision: a located point within this (relative) of its closed form is ``ok``.
LOCATE_TOL = 1e-8
#: The bound of every ring run (four double points for N = 64: n = 2 .. 5).
RING_P_MAX = 30.0


@dataclass(frozen=True)
class Expected:
    """A closed-form special point: ``kind`` (``"branch_point"`` or ``"fold"``), where, its multiplicity."""

    kind: str
    p: float
    multiplicity: int
    label: str


# ---- reading a branch -------------------------------------------------------------------------------
def _reported(branch: contin.Branch) -> list[contin.SpecialPoint]:
    return [s for s in branch.special_points if s.kind in ("fold", "branch_point") and s.label != "origin"]


def index_change_across(branch: contin.Branch, p: float) -> tuple[int, int] | None:
    """The Morse indices of the stored points on either side of the first crossing of ``p`` (None: not crossed)."""
    if branch.n_negative is None or len(branch) < 2:
        return None
    side = np.sign(branch.p - p)
    for i in range(len(branch) - 1):
        if side[i] != 0 and side[i] != side[i + 1]:
            return int(branch.n_negative[i]), int(branch.n_negative[i + 1])
    return None


def unexplained_index_changes(branch: contin.Branch) -> list[dict[str, Any]]:
    """Every step between stored points whose change of the Morse index the reported points do not account for."""
    if branch.n_negative is None:
        return []
    counts: dict[int, int] = {}
    for s in _reported(branch):
        # a point that ends the branch is stored as its last point and lies between the two before it
        at = s.index - 1 if s.index == len(branch) - 1 and s.p == branch.p[-1] else s.index
        counts[at] = counts.get(at, 0) + _multiplicity(s)
    rows = []
    for i, change in enumerate(np.diff(branch.n_negative)):
        reported = counts.get(i, 0)
        if abs(int(change)) > reported:
            rows.append({"p_from": float(branch.p[i]), "p_to": float(branch.p[i + 1]), "index_from": int(branch.n_negative[i]),
                         "index_to": int(branch.n_negative[i + 1]), "reported_points": reported})
    return rows


def _multiplicity(s: contin.SpecialPoint) -> int:
    """The multiplicity a reported point claims (1 without a bifurcation record).

    A bracketed point that breaks a fixed-space branch's symmetry claims the index change it brackets.
    """
    if s.info.get("breaks_symmetry"):
        return abs(int(s.info["n_negative_after"]) - int(s.info["n_negative_before"]))
    return 1 if s.bifurcation is None else int(s.bifurcation.multiplicity)


def judge(branch: contin.Branch, expected: Expected) -> dict[str, Any]:
    """One row of the table: the closed-form point against what ``branch`` reports near it."""
    row: dict[str, Any] = {"closed_form": expected.label, "kind": expected.kind, "p_closed": expected.p,
                           "multiplicity": expected.multiplicity}
    across = index_change_across(branch, expected.p)
    row["index_across"] = None if across is None else f"{across[0]}->{across[1]}"
    near = [s for s in _reported(branch) if abs(s.p - expected.p) <= MATCH_WINDOW * max(1.0, abs(expected.p))]
    if not near:
        reached = len(branch) and min(branch.p) <= expected.p <= max(branch.p)
        row["verdict"] = "silent" if reached else "not reached"
        return row
    s = min(near, key=lambda x: abs(x.p - expected.p))
    err = abs(s.p - expected.p) / max(1.0, abs(expected.p))
    record = s.bifurcation
    kind = "" if record is None else f" ({record.kind}, multiplicity {record.multiplicity})"
    row.update({"engine": s.kind + kind, "p_engine": float(s.p), "rel_error": err, "located": bool(s.located),
                "engine_error": s.info.get("error", "")})
    if s.kind != expected.kind or s.info.get("error"):
        row["verdict"] = "misread"
    elif not s.located:
        row["verdict"] = "bracketed"
    elif expected.multiplicity > 1 and _multiplicity(s) == 1:
        row["verdict"] = "as simple"
    elif _multiplicity(s) != expected.multiplicity:
        row["verdict"] = f"multiplicity {_multiplicity(s)}"
    else:
        row["verdict"] = "ok" if err <= LOCATE_TOL else "imprecise"
    return row


def run_row(case: str, run: str, branch: contin.Branch, seconds: float) -> dict[str, Any]:
    """What a run says about itself."""
    rejected = branch.meta.get("rejected_steps") or {}
    return {"case": case, "run": run, "status": branch.status, "success": branch.success, "points": len(branch),
            "p_end": float(branch.p[-1]) if len(branch) else None, "rejections": int(sum(rejected.values())),
            "index_rejections": int(rejected.get("Morse index changed from # to # in one step", 0)),
            "seconds": seconds, "message": branch.message}


class Study:
    """Collects the table's rows while the cases run."""

    def __init__(self, quiet: bool) -> None:
        self.quiet = quiet
        self.points: list[dict[str, Any]] = []
        self.changes: list[dict[str, Any]] = []
        self.runs: list[dict[str, Any]] = []

    def record(self, case: str, run: str, branch: contin.Branch, seconds: float,
               expected: Sequence[Expected] = ()) -> None:
        """Judge ``branch`` against ``expected`` and keep its unexplained index changes and its summary."""
        self.runs.append(run_row(case, run, branch, seconds))
        self.points += [{"case": case, "run": run, **judge(branch, e), "success": branch.success} for e in expected]
        self.changes += [{"case": case, "run": run, **c} for c in unexplained_index_changes(branch)]

    def timed(self, label: str, call: Callable[[], Any]) -> tuple[Any, float]:
        say(self.quiet, label)
        t0 = time.perf_counter()
        result = call()
        return result, time.perf_counter() - t0


def _switch_where_located(study: Study, case: str, problem: contin.Problem, branch: contin.Branch,
                          expected: Expected, **bounds: Any) -> None:
    """Switch at the reported branch point nearest ``expected`` (if one is located) and record the new branch."""
    near = [s for s in branch.branch_points() if s.located and s.bifurcation is not None
            and len(s.bifurcation.directions) and abs(s.p - expected.p) <= MATCH_WINDOW * max(1.0, abs(expected.p))]
    if not near:
        study.runs.append({"case": case, "run": f"switch_branch at {expected.label}", "status": "not run",
                           "success": None, "message": "no located branch point to switch at"})
        return
    bp = min(near, key=lambda s: abs(s.p - expected.p))
    # one run per resolved direction: at a multiple point one per class of branches (copies left out)
    for k in range(len(bp.bifurcation.directions)):
        run = f"switch_branch at {expected.label}" + (f", direction {k}" if len(bp.bifurcation.directions) > 1 else "")
        try:
            switched, seconds = study.timed(f"{case}: {run}", lambda: contin.switch_branch(
                problem, bp, branch=k, stability=True, known=branch.branch_points(), **bounds))
        except contin.CorrectorFailure as exc:
            study.runs.append({"case": case, "run": run, "status": "raised", "success": False, "message": str(exc)})
            continue
        study.record(case, run, switched, seconds)


# ---- the cases --------------------------------------------------------------------------------------
def square_case(study: Study, p_max: float) -> dict[str, Any]:
    """The trivial branch of the D4 square, a switch at (1,1) with its amplitude, and at (1,2)/(2,1)."""
    m = D4Square(30)
    case = "square n=30"
    expected = [Expected("branch_point", p, mult, f"({j},{k})" + ("" if j == k else f"/({k},{j})"))
                for p, mult, (j, k) in m.branch_points(p_max)]
    br, seconds = study.timed(f"{case}: continuation to p = {p_max:g}",
                              lambda: contin.continuation(m, np.zeros(m.n * m.n), 0.0, p_max=p_max, stability=True))
    study.record(case, "continuation", br, seconds, expected)
    simple = expected[0]
    bound = simple.p + 1.0
    near = [s for s in br.branch_points() if s.located and abs(s.p - simple.p) <= MATCH_WINDOW * simple.p]
    amplitude = None
    if near:
        sw, seconds = study.timed(f"{case}: switch_branch at (1,1)",
                                  lambda: contin.switch_branch(m, near[0], stability=True, p_max=bound))
        study.record(case, "switch_branch at (1,1)", sw, seconds)
        if sw.status == "bound":
            amplitude = {"p": float(sw.p[-1]), "norm": float(sw.observables["norm"][-1]),
                         "closed_form_leading_order": m.branch_amplitude(float(sw.p[-1]), "pure", 1, 1)}
    double = next(e for e in expected if e.multiplicity == 2)
    _switch_where_located(study, case, m, br, double, p_max=double.p + 1.0)
    return {"switch_at_11_amplitude": amplitude}


def ring_case(study: Study, N: int, coordinates: str) -> dict[str, Any]:
    """The trivial branch of the ring to ``RING_P_MAX``, the automatic scales and first step, a switch at n = 2."""
    m = PressurisedRing(N, coordinates=coordinates)
    case = f"ring N={N} {coordinates}"
    expected = [Expected("branch_point", m.buckling_load(n), 2, f"n={n}") for n in range(2, N // 2)
                if m.buckling_load(n) < RING_P_MAX]
    u0 = m.trivial_state(0.0)
    br, seconds = study.timed(f"{case}: continuation to p = {RING_P_MAX:g}",
                              lambda: contin.continuation(m, u0, 0.0, p_max=RING_P_MAX, stability=True))
    study.record(case, "continuation", br, seconds, expected)
    free = contin.continuation(PressurisedRing(N, coordinates=coordinates), u0, 0.0, stability=True, max_steps=1)
    scales = {"case": case, "U": 1.0 / br.meta["state_weight"], "P": 1.0 / br.meta["param_weight"],
              "first_step_p": float(br.p[1]) if len(br) > 1 else None,
              "first_step_p_unbounded": float(free.p[1]) if len(free) > 1 else None,
              "p_2_closed": expected[0].p, "p_2_classical": m.classical_buckling_load(2)}
    _switch_where_located(study, case, m, br, expected[0], p_max=2 * expected[0].p, p_min=0.0)
    return scales


def ring_discretisation(sizes: Sequence[int], ratios: Sequence[float]) -> list[dict[str, Any]]:
    """``p_2`` of the discrete ring (closed form) against ``3 EI / R^3``: the mesh's and the membrane penalty's share."""
    rows = []
    for N in sizes:
        for ratio in ratios:
            m = PressurisedRing(N, membrane_ratio=ratio)
            p2, limit = m.buckling_load(2), m.inextensible_buckling_load(2)
            rows.append({"N": N, "EA_R2_over_EI": ratio, "p_2": p2, "p_2_inextensible": limit,
                         "mesh_error": limit / m.classical_buckling_load(2) - 1.0, "penalty_effect": p2 / limit - 1.0})
    return rows


def chain_case(study: Study, k: int, coordinates: str) -> list[dict[str, Any]]:
    """The homogeneous branch of the chain and its quasi-static sawtooth; returns the teeth's rows."""
    m = BistableChain(k, coordinates=coordinates)
    case = f"chain k={k} {coordinates}"
    expected = [Expected("branch_point", D, mult, f"Delta=k e_{side}") for (D, _, mult), side
                in zip(m.homogeneous_branch_points(), "ab")]
    u0 = m.state(np.zeros(k))
    br, seconds = study.timed(f"{case}: continuation",
                              lambda: contin.continuation(m, u0, 0.0, p_max=1.5 * k, stability=True))
    study.record(case, "continuation", br, seconds, expected)
    _switch_where_located(study, case, m, br, expected[0], p_min=0.0, p_max=1.5 * k)
    sweep, seconds = study.timed(f"{case}: quasistatic", lambda: contin.quasistatic(m, u0, 0.0, 1.5 * k))
    force = m.observables["force"]
    teeth = []
    for j, tooth in enumerate(m.sawtooth()):
        row: dict[str, Any] = {"case": case, "tooth": j + 1, "snap_at": tooth.at, "multiplicity": tooth.multiplicity,
                               "Delta_closed": tooth.delta, "F_before_closed": tooth.force_before,
                               "F_after_closed": tooth.force_after}
        if j < len(sweep.jumps):
            jump = sweep.jumps[j]
            row.update({"Delta_engine": float(jump.p), "F_before_engine": force(jump.u_from, jump.p),
                        "F_after_engine": force(jump.u_to, jump.p),
                        "Delta_rel_error": abs(jump.p - tooth.delta) / tooth.delta,
                        "F_after_error": abs(force(jump.u_to, jump.p) - tooth.force_after)})
        teeth.append(row)
    study.runs.append({"case": case, "run": "quasistatic", "status": sweep.status, "success": sweep.success,
                       "points": sum(len(b) for b in sweep.branches), "p_end": sweep.p_final,
                       "seconds": seconds, "message": f"{len(sweep.jumps)} snap(s); {sweep.message}"})
    for b in sweep.branches:
        study.changes += [{"case": case, "run": "quasistatic", **c} for c in unexplained_index_changes(b)]
    return teeth


def augusti_case(study: Study, spring_length: float | None, epsilon: float, omega: float) -> None:
    """The strut from ``lambda = 0``: perfect (the double point, then a switch) or imperfect (its limit load)."""
    m = AugustiStrut(spring_length, epsilon, omega)
    kind = "O(2)" if spring_length is None else f"two-mode a/L={spring_length:g}"
    line = "axis" if omega == 0.0 else "diagonal"
    case = f"Augusti {kind}" + ("" if epsilon == 0 else f" eps={epsilon:g} {line}")
    if epsilon == 0.0:
        expected = [Expected("branch_point", 1.0, 2, "lambda_c = 1")]
    else:
        xi_s, lam_s = m.limit_load()
        expected = [Expected("fold", lam_s, 1, f"lambda_s (Koiter {m.koiter_limit_load():.9f})")]
        secondary = m.secondary_branch_point()
        if secondary is not None:
            expected.insert(0, Expected("branch_point", secondary[1], 1, "secondary"))
    u0 = m.path_state(epsilon) if epsilon else np.zeros(2)
    bounds = {"tilt": (None, 0.5)} if epsilon else {}
    br, seconds = study.timed(f"{case}: continuation",
                              lambda: contin.continuation(m, u0, 0.0, p_max=1.5, stability=True, bounds=bounds))
    study.record(case, "continuation", br, seconds, expected)
    if epsilon == 0.0:
        _switch_where_located(study, case, m, br, expected[0], p_min=0.0, p_max=1.5)


# ---- the command line -------------------------------------------------------------------------------
POINT_COLUMNS = ["case", "run", "closed_form", "kind", "multiplicity", "p_closed", "engine", "p_engine", "rel_error",
                 "located", "index_across", "verdict", "success"]


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: see the module docstring."""
    parser = study_parser("degenerate_points", "the engine at the degenerate points of symmetric models with closed forms")
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    study = Study(args.quiet)
    square = square_case(study, 105.0 if args.full else 60.0)
    scales = [ring_case(study, N, coordinates) for N in ((32, 64, 128) if args.full else (64, 128))
              for coordinates in ("displacements", "positions")]
    discretisation = ring_discretisation((32, 64, 128), (1e4, 1e5, 1e6))
    teeth = [row for k in (2, 3, 6) for coordinates in ("nodes", "modes") for row in chain_case(study, k, coordinates)]
    for spring_length in (None, 2.0):
        augusti_case(study, spring_length, 0.0, 0.0)
        for epsilon in (1e-5, 1e-6):
            for omega in ((0.0,) if spring_length is None else (0.0, math.pi / 4)):
                augusti_case(study, spring_length, epsilon, omega)

    print("Closed-form special points against the engine (default settings, stability=True):")
    print_table(study.points, POINT_COLUMNS, digits=10)
    print("\nWhat the engine recorded where it misread a point:")
    print_table([r for r in study.points if r.get("engine_error")], ["case", "closed_form", "engine_error"])
    print("\nChanges of the Morse index between stored points that the reported points do not account for:")
    print_table(study.changes, ["case", "run", "p_from", "p_to", "index_from", "index_to", "reported_points"], digits=10)
    print("\nThe quasi-static sawtooth of the chain (closed form against contin.quasistatic):")
    print_table(teeth, ["case", "tooth", "snap_at", "multiplicity", "Delta_closed", "Delta_engine", "Delta_rel_error",
                        "F_before_closed", "F_before_engine", "F_after_closed", "F_after_engine"], digits=8)
    print("\nThe ring's automatic scales and first step (p_max = 30, and without a bound):")
    print_table(scales, ["case", "U", "P", "first_step_p", "first_step_p_unbounded", "p_2_closed", "p_2_classical"])
    print("\nThe ring's n = 2 load: the mesh (inextensible p_2^(N) / 3 - 1) and the membrane penalty (p_2 / p_2^inext - 1):")
    print_table(discretisation, ["N", "EA_R2_over_EI", "p_2", "p_2_inextensible", "mesh_error", "penalty_effect"], digits=10)
    print("\nRuns:")
    print_table(study.runs, ["case", "run", "status", "success", "points", "p_end", "rejections", "index_rejections",
                             "seconds", "message"], digits=6)
    if square["switch_at_11_amplitude"]:
        a = square["switch_at_11_amplitude"]
        print(f"\nsquare, branch from (1,1) at p = {a['p']:.6g}: ||u||_h = {a['norm']:.6g}, leading order "
              f"{a['closed_form_leading_order']:.6g}")
    write_csv(out / "points.csv", study.points, POINT_COLUMNS + ["engine_error"])
    write_csv(out / "index_changes.csv", study.changes)
    write_csv(out / "runs.csv", study.runs)
    write_csv(out / "ring_scales.csv", scales)
    write_csv(out / "ring_discretisation.csv", discretisation)
    write_json(out / "summary.json", {"points": study.points, "index_changes": study.changes, "runs": study.runs,
                                      "ring_scales": scales, "ring_discretisation": discretisation,
                                      "chain_teeth": teeth, "square": square,
                                      "match_window": MATCH_WINDOW, "locate_tol": LOCATE_TOL})
    return 0


if __name__ == "__main__":
    raise SystemExit(run_study(main))
