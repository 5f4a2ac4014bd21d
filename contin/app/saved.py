"""Saved runs read back: the output directory of ``contin trace`` as branches that can be drawn again.

``contin plot OUT [OUT ...]`` re-draws or overlays saved runs without recomputing them (as AUTO's plotting
of saved runs does).  :func:`load_run` rebuilds, from a run's ``branch.csv`` and ``summary.json``, one
:class:`contin.Branch` per traced branch: the parameter, the observables and the stability flags per
stored point (no states: the CSV holds none), its special points and its snaps (the ends of each jump)
from the summary's records.  :func:`contin.plot_branches` draws them as the run drew its own diagram
(the axes, the control the diagram is styled by, the axis names and which special points are marked
come from the summary's ``diagram`` record).
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..results.branch import Branch, SpecialPoint

__all__ = ["SavedRun", "SavedRunError", "load_run", "overlay_labels"]

#: The keyword arguments of :func:`contin.plot_branches` that ``summary.json`` keeps under ``"diagram"``
#: (beside ``x``, ``y`` and ``stability``), so that ``contin plot`` draws a run again as it was drawn.
REPLOT_OPTIONS = ("axis_labels", "special_kinds", "zero_line", "scale", "title", "note", "control", "symbols", "same_as",
                  "faded")

#: Columns of ``branch.csv`` that are not observables.
_NOT_OBSERVABLES = ("branch", "p", "s", "residual", "newton_iterations")


class SavedRunError(ValueError):
    """A directory that is not a readable output of ``contin trace``; the message names the file."""


@dataclass
class SavedRun:
    """A run read back from its output directory.

    Attributes
    ----------
    path : Path
        The output directory.
    summary : dict
        ``summary.json``.
    branches : list of Branch
        One per traced branch (no states).
    x, y : str
        The quantities on the run's diagram (``"p"`` for the parameter).
    stability : str or None
        The stability label the diagram is styled by.
    plot_options : dict
        The diagram's options of :func:`contin.plot_branches` that were saved (:data:`REPLOT_OPTIONS`).
    jumps : list of (float, dict, dict)
        Each snap: the parameter it happens at and the observables where it leaves and where it lands
        (the ``jumps`` of :func:`contin.plot_branches`).
    labels : list of str
        The branches' names (``"loading"``, ``"loading after snap 1"``).
    """

    path: Path
    summary: dict[str, Any]
    branches: list[Branch]
    x: str = "p"
    y: str | None = None
    stability: str | None = None
    plot_options: dict[str, Any] = field(default_factory=dict)
    jumps: list[tuple[float, dict[str, float], dict[str, float]]] = field(default_factory=list)
    labels: list[str] = field(default_factory=list)

    @property
    def control(self) -> str | None:
        """What the diagram's stability refers to: its ``control`` option, else its stability label."""
        return self.plot_options.get("control") or self.stability


def _number(text: str) -> float:
    return float(text) if text != "" else math.nan


def _numeric(rows: list[dict[str, str]], name: str) -> bool:
    """Whether every entry of the column ``name`` is a number or empty."""
    try:
        for row in rows:
            _number(row.get(name) or "")
    except ValueError:
        return False
    return True


def load_run(path: str | Path) -> SavedRun:
    """Read the output directory ``path`` of ``contin trace`` back (module docstring).

    Raises
    ------
    SavedRunError
        When ``summary.json`` or ``branch.csv`` is missing or unreadable.
    """
    path = Path(path)
    summary_file, csv_file = path / "summary.json", path / "branch.csv"
    for f in (summary_file, csv_file):
        if not f.is_file():
            raise SavedRunError(f"{str(f)!r} not found: {str(path)!r} is not an output directory of 'contin trace'")
    try:
        summary = json.loads(summary_file.read_text())
        with open(csv_file, newline="") as fh:
            rows = list(csv.DictReader(fh))
    except (OSError, ValueError) as exc:
        raise SavedRunError(f"cannot read the saved run in {str(path)!r}: {exc}") from None
    if not isinstance(summary, dict) or not rows or "p" not in rows[0]:
        raise SavedRunError(f"{str(csv_file)!r} or {str(summary_file)!r} is not a saved run of 'contin trace'")
    parameter = str(summary.get("parameter", "p"))
    names = list(rows[0])
    stability_labels = [n[len("stable_"):] for n in names if n.startswith("stable_")]
    # a model may add columns of text (a branch's symmetry, a representation's name): not observables
    observable_names = [n for n in names if n not in _NOT_OBSERVABLES
                        and not n.startswith(("stable", "n_negative", "tangent_")) and _numeric(rows, n)]
    by_branch: dict[int, list[dict[str, str]]] = {}
    for row in rows:
        by_branch.setdefault(int(float(row.get("branch") or 0)), []).append(row)
    try:
        branches = [_branch(by_branch.get(b, []), b, parameter, observable_names, stability_labels, summary)
                    for b in range(max(by_branch) + 1)]
    except ValueError as exc:
        raise SavedRunError(f"{str(csv_file)!r}: {exc}") from None
    diagram = summary.get("diagram") or {}
    options = {k: diagram[k] for k in REPLOT_OPTIONS if k in diagram}
    if "special_kinds" in options:
        options["special_kinds"] = tuple(options["special_kinds"])
    labels = [str(b.get("label", "")) for b in summary.get("branches") or [] if isinstance(b, dict)]
    return SavedRun(path=path, summary=summary, branches=branches, x=str(diagram.get("x") or "p"),
                    y=diagram.get("y"), stability=diagram.get("stability"), plot_options=options,
                    jumps=_jumps(summary, observable_names), labels=labels)


def _observed(rec: dict[str, Any], names: Sequence[str]) -> dict[str, float]:
    """The quantities a special point's record gives: its ``observables`` and the fields of its own that are
    columns of ``branch.csv`` (a model may add columns, e.g. the indenter's travel ``w`` beside ``w_b``)."""
    own = {k: rec[k] for k in names if isinstance(rec.get(k), (int, float)) and not isinstance(rec.get(k), bool)}
    return {k: float(v) for k, v in {**own, **(rec.get("observables") or {})}.items()}


def _jumps(summary: dict[str, Any], names: Sequence[str]) -> list[tuple[float, dict[str, float], dict[str, float]]]:
    """The snaps of a saved run from its ``jump_from`` and ``jump_to`` records (those with a ``jump`` number);
    ``names``: the observables (:func:`_observed`)."""
    ends: dict[int, dict[str, dict[str, Any]]] = {}
    for rec in summary.get("special_points", []):
        if rec.get("kind") == "jump" and rec.get("jump") is not None and rec.get("label") in ("jump_from", "jump_to"):
            ends.setdefault(int(rec["jump"]), {})[rec["label"]] = rec
    out = []
    for _, pair in sorted(ends.items()):
        if len(pair) == 2:
            a, b = pair["jump_from"], pair["jump_to"]
            out.append((float(a.get("p", math.nan)), _observed(a, names), _observed(b, names)))
    return out


def _branch(rows: list[dict[str, str]], index: int, parameter: str, observable_names: list[str],
            stability_labels: list[str], summary: dict[str, Any]) -> Branch:
    n = len(rows)
    # a parameter with a column of its own is the path's parameter; "p" is then one of the model's
    # quantities (the pressure of a volume-controlled run, whose parameter is the volume dV)
    own = parameter if parameter != "p" and rows and parameter in rows[0] else "p"
    column = {name: np.array([_number(r.get(name, "")) for r in rows]) for name in (own, "s", "residual")}
    column["p"] = column.pop(own)
    observables = {name: np.array([_number(r.get(name, "")) for r in rows]) for name in observable_names}
    # the diagram styles by stable/unstable only: a stable point counts 0 negative eigenvalues, else 1
    stability_by = {label: ((np.array([_number(r.get(f"stable_{label}", "")) for r in rows]) != 1.0).astype(int),
                            np.zeros((n, 0))) for label in stability_labels}
    specials = []
    for rec in summary.get("special_points", []):
        if rec.get("branch", 0) != index or rec.get("kind") in ("jump_from", "jump_to"):
            continue
        info: dict[str, Any] = {}
        if rec.get("kind") == "fold":
            info["folds"] = rec.get("parameter", parameter)
        if rec.get("kind") == "bifurcation" and rec.get("family") is not None:
            info["family"], info["key"] = rec["family"], rec.get(str(rec["family"]))
        observed = _observed(rec, observable_names)
        specials.append(SpecialPoint(str(rec.get("kind")), observed.get(own, float(rec.get("p", math.nan))), np.zeros(0),
                                     observed,
                                     located=bool(rec.get("located", True)), label=str(rec.get("label") or ""),
                                     info=info))
    # the direction of the path at each point (runs saved before the tangent columns have none: drawn straight)
    tangent = {name: np.array([_number(r.get(f"tangent_{name}", "")) for r in rows])
               for name in (own, *observable_names) if f"tangent_{name}" in rows[0]}
    tangent["p"] = tangent.pop(own, np.full(n, np.nan))
    # the primary label (the traced control's) is the plain "stable" column where there is one
    n_negative = stability_by[stability_labels[0]][0] if stability_labels else None
    if rows and "stable" in rows[0]:
        n_negative = (np.array([_number(r.get("stable", "")) for r in rows]) != 1.0).astype(int)
    return Branch(p=column["p"], u=np.zeros((n, 0)), s=column["s"] if "s" in rows[0] else np.arange(n, dtype=float),
                  tangent_p=tangent.pop("p"), residual=column["residual"], newton_iterations=np.zeros(n, dtype=int),
                  observables=observables, n_negative=n_negative, stability_by=stability_by, special_points=specials,
                  meta={"parameter_name": parameter}, tangents=tangent)


def _flat_scene(summary: dict[str, Any]) -> dict[str, Any]:
    """``section.key -> value`` of a run's scene, without the output section (it changes no result)."""
    scene = summary.get("scene")
    if not isinstance(scene, dict):
        return {}
    return {f"{section}.{key}": value for section, keys in scene.items() if isinstance(keys, dict)
            and section != "output" for key, value in keys.items()}


def _labels_from_titles(runs: Sequence[SavedRun]) -> tuple[str, list[str]] | None:
    """Title and labels from the diagrams' titles (the scene in a few symbols, comma-separated parts): the
    parts all share make the title, the others tell the runs apart; None when that does not tell them apart."""
    from ..plot.branches import comma_parts

    titles = [run.plot_options.get("title") for run in runs]
    if not all(titles):
        return None
    parts = [[p.strip().rstrip(",").strip() for p in comma_parts(t)] for t in titles]
    common = [p for p in parts[0] if all(p in other for other in parts[1:])]
    labels = [", ".join(p for p in own if p not in common) for own in parts]
    controls = [run.control for run in runs]
    if len(set(controls)) > 1:  # the titles may not say it: a dead load and a prescribed displacement
        labels = [label if f"{c} control" in label else ", ".join(t for t in (label, f"{c} control") if t)
                  for label, c in zip(labels, controls)]
    if not all(labels) or len(set(labels)) < len(labels):
        return None
    head = " / ".join(sorted({str(run.summary.get("model", "?")) for run in runs}))
    return (f"{head}: {', '.join(common)}" if common else head), labels


def overlay_labels(runs: Sequence[SavedRun]) -> tuple[str, list[str]]:
    """The title of an overlay of saved runs and a legend label for each run.

    Runs whose diagrams carry titles (``plot_options["title"]``, the scene in a few symbols) are told
    apart by the parts of their titles that differ (``rigid sphere, $r_s/R = 0.5$`` against ``point
    load``) and titled by the parts they share, with each run's control when the controls differ.
    Otherwise runs of one model whose scenes differ are told apart by the scene keys that differ
    (``model.n = 20`` against ``model.n = 40``, the title naming the model); otherwise (another model,
    no saved scene, the same scene) by their directory names.
    """
    from_titles = _labels_from_titles(runs)
    if from_titles is not None:
        return from_titles
    names = [str(run.path.name or run.path) for run in runs]
    models = {run.summary.get("model") for run in runs}
    scenes = [_flat_scene(run.summary) for run in runs]
    keys = sorted({key for scene in scenes for key in scene})
    differing = [key for key in keys if len({repr(scene.get(key)) for scene in scenes}) > 1]
    if len(models) != 1 or not all(scenes) or not differing:
        return " / ".join(names), names
    from .scene import _show  # the scene's own way of writing a value (TOML)

    labels = [", ".join(f"{key} = {_show(scene.get(key))}" for key in differing) for scene in scenes]
    if len(set(labels)) < len(labels):  # two runs of one scene among others: their directories tell them apart
        labels = [f"{label} ({name})" for label, name in zip(labels, names)]
    return f"{models.pop()}: runs that differ in {', '.join(differing)}", labels
