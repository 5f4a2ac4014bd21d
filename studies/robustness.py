"""Stiff and extreme scenes: every scene runs to the end of its branch, or stops and says why.

Run ``python -m studies.robustness`` (a few cheap scenes, well under a minute) or ``--full`` (the
whole matrix of issue 6, about ten minutes on two workers).  Each scene is the shell scene of
``contin trace`` with a few keys changed: thickness, mesh, cap depth, the contact barrier's
stiffness ``K_c`` and range ``dhat``, the indenter, the units (E, R) and the continuation's step
limits.  Every stored point of every branch is then checked, independently of the run's own
bookkeeping:

- **converged**: ``max|f| <= tol * residual_scale`` at every stored point (the worst ratio is
  reported; above 1 is a failure);
- **finite**: no NaN or inf in any state, parameter, observable or eigenvalue;
- **force from the energy**: the reported force equals the derivative of the total energy with
  respect to the load, ``F = dE/dw`` (displacement control; at equilibrium the total derivative is
  the partial one), by central differences of the energy alone at up to 12 points per branch;
  for an indenter, whose log barrier is too stiff to difference, the load is compared with the
  base ring's reaction, the derivative of the elastic energy in the ring's height (equal in
  equilibrium); the largest deviation relative to ``max|F|`` on the branch must stay below 1e-5;
- **no penetration** (sphere, plate): the smallest node–indenter distance over every stored point
  is positive;
- **mesh**: the class (point load) or the snap travel ``w_b^c`` (indenter) is the same on a mesh
  twice as fine (``w_b^c`` within 1 %);
- **units**: the scenes with other E and R must give the default scene's normalized results
  (``F R / (2 pi D)``, ``w / R``) to 1e-6.

The largest membrane strain of each run (and of its finer mesh) is reported beside the checks; it is
not a check of its own, but when the class of a point load changes with the mesh it names the cause
(the strain at the singular pole, :mod:`contin_models.shell.strain`).

A scene *completes* when the run succeeded and every check holds; it *stops* when the run ended
early with a stated reason and every stored point still passes the checks; anything else (an
unconverged or non-finite stored point, a force that is not the energy's derivative, penetration,
a class that changes with the mesh, an exception) is a *failure* and the study exits with status 1.
The matrix (scene, outcome, time, steps, worst residual, checks) goes to ``matrix.csv`` and
``summary.json`` in ``--out``; ``docs/robustness.md`` quotes the ``--full`` run.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import math  # noqa: E402
import time  # noqa: E402
from collections.abc import Sequence  # noqa: E402
from dataclasses import dataclass, field  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from contin.app.scene import TraceResult, load_scene  # noqa: E402
from contin.results.branch import Branch  # noqa: E402
from contin_models.shell.strain import STRAIN_LIMIT  # noqa: E402
from contin_models.shell_scene import contact_problem, point_problem  # noqa: E402
from studies._common import (executor_from_args, output_dir, print_table, say, study_parser,  # noqa: E402
                             write_csv, write_json, write_text)

#: Largest deviation of the reported force from the energy's derivative, relative to max|F| on the branch.
ENERGY_TOLERANCE = 1e-5
#: Largest relative change of the normalized results when only the units (E, R) change.
UNITS_TOLERANCE = 1e-6
#: Largest relative change of the snap travel w_b^c on a mesh twice as fine.
MESH_TOLERANCE = 1e-2
#: Points per branch at which the force is compared with the energy's derivative.
ENERGY_SAMPLES = 12


@dataclass(frozen=True)
class Case:
    """One scene of the matrix: a name, its group, the ``--set`` overrides and the checks to run."""

    name: str
    group: str
    overrides: tuple[str, ...]
    mesh_check: bool = True
    units_check: bool = False
    fast: bool = False
    note: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


def _sphere(*more: str) -> tuple[str, ...]:
    return ("load.kind=sphere", "load.radius=0.5", *more)


CASES: tuple[Case, ...] = (
    Case("default", "reference", (), fast=True),
    # thickness (lambda from 42 to 2.1 at phi_hat = 0.8)
    Case("h/R = 1e-3", "thickness", ("shell.h=0.001", "shell.N=400"),
         note="lambda = 42; N = 400 keeps ~8 nodes per bending length"),
    Case("h/R = 2e-3", "thickness", ("shell.h=0.002",)),
    Case("h/R = 0.1", "thickness", ("shell.h=0.1",), fast=True),
    Case("h/R = 0.2", "thickness", ("shell.h=0.2",)),
    # mesh
    Case("N = 22", "mesh", ("shell.N=22",), fast=True,
         note="the coarsest mesh the scene admits for this cap: 4 nodes over sqrt(R h)"),
    Case("N = 5000", "mesh", ("shell.N=5000",), mesh_check=False),
    Case("N = 20000", "mesh", ("shell.N=20000",), mesh_check=False),
    # cap depth
    Case("phi_hat = 0.3", "depth", ("shell.phi_hat=0.3",), note="a deep cap, lambda = 17"),
    Case("phi_hat = 1.5", "depth", ("shell.phi_hat=1.5",), fast=True),
    # barrier stiffness and range (sphere r/R = 0.5)
    Case("K_c = 1e4", "barrier", _sphere("contact.K_c=1e4")),
    Case("K_c = 1e8 (default)", "barrier", _sphere()),
    Case("K_c = 1e12", "barrier", _sphere("contact.K_c=1e12")),
    Case("dhat = 1e-5", "barrier", _sphere("contact.dhat=1e-5")),
    Case("dhat = 1e-2", "barrier", _sphere("contact.dhat=1e-2")),
    # indenters
    Case("sphere r/R = 1e-3", "indenter", ("load.kind=sphere", "load.radius=0.001")),
    Case("sphere r/R = 10", "indenter", ("load.kind=sphere", "load.radius=10")),
    Case("plate", "indenter", ("load.kind=plate",)),
    # units: normalized results must not move
    Case("E = 1e-3 Pa", "units", ("shell.E=1e-3",), mesh_check=False, units_check=True, fast=True),
    Case("E = 1e9 Pa", "units", ("shell.E=1e9",), mesh_check=False, units_check=True),
    Case("R = 1e-3 m", "units", ("shell.R=1e-3", "shell.h=2e-5"), mesh_check=False, units_check=True),
    Case("R = 1e3 m", "units", ("shell.R=1e3", "shell.h=20"), mesh_check=False, units_check=True),
    # continuation step limits
    Case("ds_max = 1e-3 (small)", "steps", ("continuation.ds=1e-4", "continuation.ds_max=1e-3",
                                            "continuation.max_steps=100000"), mesh_check=False),
    Case("ds_max = 1e-4, 3000 steps", "steps", ("continuation.ds=1e-5", "continuation.ds_max=1e-4"),
         mesh_check=False, note="the path stops at max_steps; the everted branch decides the class"),
    Case("ds = ds_max = 10 (large)", "steps", ("continuation.ds=10", "continuation.ds_max=10"),
         mesh_check=False, fast=True),
)


# ---------------------------------------------------------------------------------------------------
# checks on a finished run
# ---------------------------------------------------------------------------------------------------
def _problem_of(scene: dict[str, dict[str, Any]]) -> Any:
    """The problem the scene's displacement-controlled run traced (point load, or sphere/plate)."""
    if scene["load"]["kind"] == "point":
        return point_problem(scene, "displacement")
    return contact_problem(scene)


def _all_finite(br: Branch) -> bool:
    arrays = [br.p, br.u, br.s, br.residual, *br.observables.values()]
    arrays += [np.asarray(nneg, dtype=float) for nneg, _ in br.stability_by.values()]
    arrays += [np.asarray(eig, dtype=float) for _, eig in br.stability_by.values() if eig is not None]
    return all(bool(np.all(np.isfinite(np.asarray(a, dtype=float)))) for a in arrays if np.size(a))


def _energy_derivative(problem: Any, u: np.ndarray, p: float, step: float) -> float:
    """``dE/dp`` at fixed ``u`` by a fourth-order central difference of the energy."""
    e = [problem.energy(u, p + k * step) for k in (-2, -1, 1, 2)]
    return (e[0] - 8.0 * e[1] + 8.0 * e[2] - e[3]) / (12.0 * step)


def _support_reaction(problem: Any, u: np.ndarray, scene: dict[str, dict[str, Any]]) -> float:
    """The indenter's load as ``dE_elastic / dz_0``: what the held base ring must carry.

    Differentiating the total energy in the indenter's travel would go through the log barrier,
    whose energy is huge next to its derivative when the barrier is stiff or short (``K_c = 1e12``
    leaves gaps of 5e-13 R): no difference step fits between round-off and the gap.  In equilibrium
    the indenter's load equals the base's reaction, the derivative of the smooth elastic energy
    alone with respect to the base ring's height, with the other nodes held.
    """
    x = np.array(problem.full_state(u), dtype=float)
    step = _energy_step(problem, u, 0.0, scene, barrier=False)
    energies = []
    for k in (-2, -1, 1, 2):
        y = x.copy()
        y[1] += k * step
        energies.append(problem.elastic.elastic_energy(y))
    return (energies[0] - 8.0 * energies[1] + 8.0 * energies[2] - energies[3]) / (12.0 * step)


def _energy_step(problem: Any, u: np.ndarray, p: float, scene: dict[str, dict[str, Any]], barrier: bool = True) -> float:
    # moving the load at fixed u strains the elements next to it: the step is a small part of a mean
    # element length (the pole's element is shorter still on the graded mesh)
    s = scene["shell"]
    step = 1e-3 * s["R"] * (0.5 * math.pi - s["phi_hat"]) / s["N"]
    if barrier and hasattr(problem, "contact"):
        # the indenter may move by a small part of the smallest gap only (the barrier is singular at 0)
        gap = float(np.min(problem.contact(u, p, hessian=False).distances))
        step = min(step, 0.05 * gap)
    return step


def check_branches(problem: Any, branches: Sequence[Branch], scene: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """Independent checks of every stored point (see the module docstring)."""
    tol = scene["continuation"]["tol"]
    scale = tol * float(getattr(problem, "residual_scale", 1.0))
    worst, finite, energy_dev, min_gap, n_points = 0.0, True, 0.0, math.inf, 0
    for br in branches:
        if not len(br):
            continue
        n_points += len(br)
        worst = max(worst, float(np.max(br.residual)) / scale)
        finite = finite and _all_finite(br)
        if hasattr(problem, "contact"):
            for u, p in zip(br.u, br.p):
                min_gap = min(min_gap, float(np.min(problem.contact(u, float(p), hessian=False).distances)))
        F = np.asarray(br.observables["F"], dtype=float)
        F_scale = float(np.max(np.abs(F), initial=0.0)) or 1.0
        for i in np.unique(np.linspace(0, len(br) - 1, ENERGY_SAMPLES).round().astype(int)):
            u, p = br.u[i], float(br.p[i])
            if hasattr(problem, "contact"):
                dE = _support_reaction(problem, u, scene)
            else:
                dE = _energy_derivative(problem, u, p, _energy_step(problem, u, p, scene))
            energy_dev = max(energy_dev, abs(dE - F[i]) / F_scale)
    return {"points": n_points, "worst_residual": worst, "finite": finite, "energy_deviation": energy_dev,
            "min_gap": None if min_gap == math.inf else min_gap}


def _key_result(result: TraceResult, scene: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """What the mesh and units checks compare: the class and normalized folds, or the snap travel."""
    s = result.summary
    if scene["load"]["kind"] == "point":
        return {"class": s.get("classification"), "F_max_norm": s.get("F_max_norm"),
                "w_at_F_max_over_R": s.get("w_at_F_max_over_R"), "F_min_norm": s.get("F_min_norm"),
                "w_at_F_min_over_R": s.get("w_at_F_min_over_R")}
    w_c = s.get("w_b_c")
    return {"class": None, "w_b_c_over_R": None if w_c is None else w_c / scene["shell"]["R"]}


def _trace(overrides: Sequence[str]) -> tuple[dict[str, dict[str, Any]], TraceResult, float]:
    from contin.app.registry import load_model

    model = load_model("shell")
    scene = load_scene(model.schema, None, [*overrides, "output.figure=false", "load.control=displacement"])
    t0 = time.perf_counter()
    result = model.run(scene, False)
    return scene, result, time.perf_counter() - t0


def run_case(case: Case) -> dict[str, Any]:
    """Run one scene and its checks; never raises (an exception is reported as the outcome)."""
    row: dict[str, Any] = {"scene": case.name, "group": case.group, "settings": " ".join(case.overrides) or "(defaults)"}
    try:
        scene, result, wall = _trace(case.overrides)
        checks = check_branches(_problem_of(scene), result.branches, scene)
        row.update(time_s=wall, steps=int(sum(br.meta.get("n_steps", max(len(br) - 1, 0)) for br in result.branches)),
                   status=result.status, message=result.message, **checks, **_key_result(result, scene),
                   max_strain=result.summary.get("max_strain"), max_strain_at=result.summary.get("max_strain_at"))
        if case.mesh_check:
            fine = [*case.overrides, f"shell.N={2 * scene['shell']['N']}"]
            _, fine_result, fine_wall = _trace(fine)
            fine_key = _key_result(fine_result, scene)
            row["fine_time_s"] = fine_wall
            row["fine_status"] = fine_result.status
            row["fine_max_strain"] = fine_result.summary.get("max_strain")
            if scene["load"]["kind"] == "point":
                row["fine_class"] = fine_key["class"]
            else:
                a, b = row.get("w_b_c_over_R"), fine_key.get("w_b_c_over_R")
                row["fine_w_b_c_over_R"] = b
                row["mesh_change"] = None if a is None or b is None else abs(a - b) / abs(b)
    except Exception as exc:  # the outcome of the scene, reported in the matrix
        row.update(status="exception", message=f"{type(exc).__name__}: {exc}")
    return row


# ---------------------------------------------------------------------------------------------------
# verdicts
# ---------------------------------------------------------------------------------------------------
def verdict(row: dict[str, Any], case: Case, reference: dict[str, Any] | None) -> tuple[str, str]:
    """``(outcome, why)``: ``completed``, ``stopped`` (a stated reason) or ``FAILED``."""
    if row.get("status") == "exception":
        return "FAILED", row["message"]
    problems = []
    if row["worst_residual"] > 1.0:
        problems.append(f"a stored point is not converged (residual {row['worst_residual']:.2g} x tol)")
    if not row["finite"]:
        problems.append("a stored value is NaN or inf")
    if row["energy_deviation"] > ENERGY_TOLERANCE:
        problems.append(f"F differs from dE/dw by {row['energy_deviation']:.2g} of max|F|")
    if row.get("min_gap") is not None and not row["min_gap"] > 0.0:
        problems.append("a node penetrates the indenter")
    if "fine_class" in row and row.get("fine_status") == "ok" and row["status"] == "ok" and row["fine_class"] != row["class"]:
        why = f"the class changes on the finer mesh ({row['class']} -> {row['fine_class']})"
        a, b = row.get("max_strain"), row.get("fine_max_strain")
        if row.get("max_strain_at") == "pole" and a is not None and b is not None and max(a, b) > STRAIN_LIMIT:
            why += (f": the point load's strain at the pole is {a:.3g} on the mesh and {b:.3g} on the finer one, "
                    f"beyond the material law's range ({STRAIN_LIMIT:g}); the singular pole is resolved ever more "
                    f"finely (models/shell/strain.py)")
        problems.append(why)
    if row.get("mesh_change") is not None and row["mesh_change"] > MESH_TOLERANCE:
        problems.append(f"w_b^c changes by {row['mesh_change']:.2g} on the finer mesh")
    if case.units_check and reference is not None:
        change = max((abs(row[k] - reference[k]) / abs(reference[k]) for k in reference
                      if isinstance(reference.get(k), float) and isinstance(row.get(k), float)), default=math.inf)
        row["units_change"] = change
        if row.get("class") != reference.get("class") or change > UNITS_TOLERANCE:
            problems.append(f"normalized results move by {change:.2g} when only the units change")
    if problems:
        return "FAILED", "; ".join(problems)
    if row["status"] == "ok":
        return "completed", ""
    return "stopped", row["message"]


def main(argv: Sequence[str] | None = None) -> int:
    parser = study_parser("robustness", "stiff and extreme scenes: complete, or stop with a reason",
                          executor_options=True)
    args = parser.parse_args(argv)
    out = output_dir(args.out)
    cases = [c for c in CASES if args.full or c.fast]
    say(args.quiet, f"robustness: {len(cases)} scenes{'' if args.full else ' (fast mode; --full for the whole matrix)'}")
    rows: list[dict[str, Any] | None] = [None] * len(cases)
    t0 = time.perf_counter()
    with executor_from_args(args) as executor:
        for done, (i, row) in enumerate(executor.map_unordered(run_case, cases), start=1):
            rows[i] = row
            say(args.quiet, f"  [{done}/{len(cases)}] {cases[i].name}: {row.get('status')} "
                      f"({row.get('time_s', float('nan')):.1f} s, {row.get('steps', 0)} steps)")
    reference = next((r for r, c in zip(rows, cases) if c.name == "default"), None)
    ref_key = None if reference is None or reference.get("status") != "ok" else {
        k: reference.get(k) for k in ("class", "F_max_norm", "w_at_F_max_over_R", "F_min_norm", "w_at_F_min_over_R")}
    table = []
    for case, row in zip(cases, rows):
        assert row is not None
        outcome, why = verdict(row, case, ref_key)
        row["outcome"], row["why"] = outcome, why
        table.append({"scene": case.name, "outcome": outcome, "time_s": row.get("time_s"), "steps": row.get("steps"),
                      "worst_res/tol": row.get("worst_residual"), "dE/dw dev": row.get("energy_deviation"),
                      "result": row.get("class") or _fmt_w(row), "why": why[:90]})
    print_table(table, list(table[0]))
    write_csv(out / "matrix.csv", rows)
    write_text(out / "matrix.md", markdown_table(rows))
    n_failed = sum(r["outcome"] == "FAILED" for r in rows)
    write_json(out / "summary.json", {"scenes": rows, "failed": n_failed, "wall_time_s": time.perf_counter() - t0,
                                      "command": "python -m studies.robustness" + (" --full" if args.full else "")})
    say(args.quiet, f"{len(rows)} scenes: {sum(r['outcome'] == 'completed' for r in rows)} completed, "
              f"{sum(r['outcome'] == 'stopped' for r in rows)} stopped with a reason, {n_failed} failed; "
              f"outputs in {out}")
    return 1 if n_failed else 0


def markdown_table(rows: Sequence[dict[str, Any]]) -> str:
    """The matrix as a Markdown table (scene, settings, outcome, time, steps, checks, result, reason)."""
    def num(v: Any, fmt: str) -> str:
        return "–" if v is None or (isinstance(v, float) and not math.isfinite(v)) else format(v, fmt)

    lines = ["| scene | settings | outcome | time (s) | steps | worst residual / tol | max \\|F − dE/dw\\| / max\\|F\\| "
             "| min gap | max strain (finer mesh) | finer mesh | result | reason |",
             "|---|---|---|---:|---:|---:|---:|---:|---|---|---|---|"]
    for r in rows:
        fine = r.get("fine_class") or ("" if r.get("mesh_change") is None else f"w_b^c Δ {r['mesh_change']:.1e}")
        if r.get("units_change") is not None:
            fine = f"units Δ {r['units_change']:.1e}"
        lines.append("| " + " | ".join([
            r["scene"], f"`{r['settings']}`", f"**{r['outcome']}**", num(r.get("time_s"), ".1f"), str(r.get("steps", "–")),
            num(r.get("worst_residual"), ".2g"), num(r.get("energy_deviation"), ".1e"), num(r.get("min_gap"), ".1e"),
            _fmt_strain(r), fine or "–", r.get("class") or _fmt_w(r) or "–", (r.get("why") or "").replace("|", "/")]) + " |")
    return "\n".join(lines) + "\n"


def _fmt_strain(row: dict[str, Any]) -> str:
    a, b = row.get("max_strain"), row.get("fine_max_strain")
    if a is None:
        return "–"
    text = f"{a:.2g} {row.get('max_strain_at') or ''}".rstrip()
    return text + (f" ({b:.2g})" if b is not None else "")


def _fmt_w(row: dict[str, Any]) -> str:
    w = row.get("w_b_c_over_R")
    return "" if w is None else f"w_b^c/R = {w:.6g}"


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
