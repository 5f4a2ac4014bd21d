"""Restarts: a run saved with its states, and a new run started from one of its points.

``contin trace`` writes, beside ``summary.json``, the file :data:`STATES_FILE` (``states.npz``): the
whole traced run (every branch with its states, every jump, as :meth:`contin.Branch.to_bundle` and
:meth:`contin.JumpResult.to_bundle` store them) and, for every numbered special point of
``summary.json`` and the last point of every branch, the state ``u``, the parameter ``p`` and the
direction the path went through it (the secant between the stored points on either side, ``du``,
``dp``; for a branch end the last secant), plus the last step's arclength.  ``contin trace --from OUT
--label K`` reads one of them back as a :class:`Start` and hands it, with the saved scene
(``summary.json``'s ``scene``, updated by each ``--set``), to the model's ``resume``
(:class:`Resumer`).  The model continues from there with its own settings: the same path (a branch
cut short by its step limit, or on from a special point), or, where it allows, the same state under
another continuation parameter.

**The same path, joined** (:func:`attach_saved_path`, :func:`continue_saved`): when the restart's scene
differs from the saved one only in :data:`PATH_FREE_SECTIONS` (the step control and the outputs) and the
point lies on the path the saved run followed from its start (its first branch, or a branch the run
reached from there by jumps), the saved path up to the point is joined to the new run: the result is
the run the saved one would have been with the new settings, so its summary, classification, table and
figures describe the whole path.  Otherwise (another control, another structure, a point on a branch that
does not start where the run started) the result describes only the part traced from the point, and
the command line says so.

Labels ``K`` (:func:`find_point`):

* a number: the special point of that number, the ``#`` column of the printed table (1 is the first
  record of ``summary.json``'s ``special_points``; its ``number`` field);
* ``end`` or ``end:B``: the last point of the first branch, or of branch ``B`` (0 is the first);
* any other text: the special point with that label, when exactly one has it.

Every numbered point can be restarted from or is refused with the reason: a jump's ``jump_to`` (the
stable landing) restarts like any point; its ``jump_from`` is the limit point's state at a load just
past the limit, where no equilibrium is near, and is refused in favour of the limit point itself.

A model says which scene keys fix the structure of its unknowns (``restart_fixed``, e.g. a number of
nodes): a ``--set`` that changes one of them is refused (:func:`restart_scene`), since the saved
state no longer fits the problem.  A point at or past the end of the new scene's path in the
direction the path went (:func:`beyond_end`) is refused too: there is nothing to trace.

:func:`resume` is the engine's side of a runner's ``resume``: it continues a problem from a
:class:`Start` along its direction (:func:`contin.continuation` with the saved direction as the
first tangent's orientation), and, at a branch point saved with its bifurcating direction, can
follow the other branch instead (:func:`contin.switch_branch`).  A special point that the new
run finds again at its own start (the point it started from) is left out.

Nothing here knows about any particular model.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["STATES_FILE", "PATH_FREE_SECTIONS", "Start", "SavedTrace", "SavedPrefix", "RestartError", "can_resume",
           "restart_states", "number_points", "read_start", "find_point", "restart_scene", "attach_saved_path",
           "continue_saved", "join_branches", "beyond_end", "resume", "drop_start_duplicates", "restart_record"]

#: The file of a run's saved states, beside ``summary.json``.
STATES_FILE = "states.npz"
#: Format of :data:`STATES_FILE` (its ``index`` names it); the first format saved the points alone.
_FORMAT = "contin-states-2"
_READABLE = ("contin-states-1", _FORMAT)
#: Scene sections a restart may change and still continue the saved run's path: how the path is
#: stepped and what is written, not which equilibria it passes through.
PATH_FREE_SECTIONS = ("continuation", "output")


class RestartError(ValueError):
    """A restart that cannot be made: a missing or unreadable saved run, an unknown label, a structural change;
    the message is one line fit to show a user."""


@dataclass
class SavedTrace:
    """The whole run saved in :data:`STATES_FILE`: its branches (with states) and jumps, in the order traced.

    Attributes
    ----------
    branches : list of Branch
    jumps : list of JumpResult
    reached_by_jump : list of bool
        Per branch: whether it starts where jump ``b - 1`` landed (a quasi-static sweep's branch after a snap).
    """

    branches: list[Any]
    jumps: list[Any]
    reached_by_jump: list[bool]


@dataclass
class SavedPrefix:
    """The saved path leading to a restart's point: what a restart on the same path is joined to.

    Attributes
    ----------
    branches : list of Branch
        Whole branches of the saved path before the point's branch.
    jumps : list of JumpResult
        The jumps between them (and the one into the point's branch, when it was reached by a jump).
    cut : Branch or None
        The point's branch up to the point: its stored points before it (and the point itself when it is
        one, ``at_stored_point``) and its special points up to and including it; None for a jump's
        landing after which the saved run traced nothing.
    at_stored_point : bool
        Whether the point is ``cut``'s last stored point (a branch end, a jump's landing) rather than a
        special point located between two stored points.
    s : float
        The point's arclength along its branch.
    """

    branches: list[Any]
    jumps: list[Any]
    cut: Any | None
    at_stored_point: bool = False
    s: float = 0.0


@dataclass
class Start:
    """A saved point to restart from.

    Attributes
    ----------
    u : ndarray
        State (the unknowns of the problem that traced it).
    p : float
        Parameter.
    du, dp : ndarray, float
        Direction the saved path went through the point (not normalised); it orients the first tangent.
    ds : float or None
        Arclength of the step that reached (or left) the point in the saved run's metric.
    name : str
        The label given (``"3"``, ``"end"``, ...).
    kind : str
        ``"end"`` for a branch end, else the special point's kind (``"fold"``, ``"event"``, ``"branch_point"``,
        ``"jump"``, ...).
    label : str
        The special point's own label (``"max(F)"``, ``"jump_to"``, ...; ``"end"`` for a branch end).
    branch : int
        The branch of the saved run it lies on (for a jump's landing: the branch that starts there, or
        the number of branches when the saved run traced none after it).
    number : int or None
        Its number in ``summary.json``'s ``special_points`` (1-based; None for a branch end).
    record : dict
        Its record of ``summary.json`` (empty for a branch end).
    complete : bool
        For a branch end: whether the saved branch reached its planned end (else its step limit cut it).
    extra : dict of str to ndarray
        Further saved arrays of the point, e.g. ``bifurcation_direction`` and ``branch_tangent`` of a
        located branch point.
    saved_scene : dict
        The scene of the run that saved the point (``summary.json``'s ``scene``): what ``u`` and ``p`` are
        the unknowns and parameter of (e.g. which quantity was the continuation parameter).
    special : int or None
        Its position in its branch's ``special_points`` (None for a branch end).
    jump : int or None
        For a jump's landing: the jump's number.
    saved : SavedTrace or None
        The whole saved run (None for a file of the first format, which saved the points alone).
    prefix : SavedPrefix or None
        Set by :func:`attach_saved_path` when the restart continues the saved path: the part of it
        before the point, which :func:`continue_saved` joins to the new run.
    """

    u: np.ndarray
    p: float
    du: np.ndarray
    dp: float
    ds: float | None = None
    name: str = ""
    kind: str = "end"
    label: str = ""
    branch: int = 0
    number: int | None = None
    record: dict[str, Any] = field(default_factory=dict)
    complete: bool = True
    extra: dict[str, np.ndarray] = field(default_factory=dict)
    saved_scene: dict[str, Any] = field(default_factory=dict)
    special: int | None = None
    jump: int | None = None
    saved: SavedTrace | None = None
    prefix: SavedPrefix | None = None

    @property
    def direction(self) -> int:
        """+1 when the saved path went towards larger parameter through the point, -1 towards smaller (0: neither)."""
        return int(np.sign(self.dp))

    @property
    def continues_saved_path(self) -> bool:
        """True when the new run is joined to the saved path before the point (:func:`attach_saved_path`)."""
        return self.prefix is not None

    def describe(self) -> str:
        """A short phrase naming the point, e.g. ``point 3 (fold max(F)) at p = 0.289`` or ``the end of branch 0``."""
        if self.kind == "end":
            return f"the end of branch {self.branch} at p = {self.p:.10g}"
        what = f"{self.record.get('kind', self.kind)} {self.label}".strip()
        return f"special point {self.number} ({what}) at p = {self.p:.10g}"


def can_resume(model: Any) -> bool:
    """Whether a runner can restart from a saved point: a callable ``resume``, unless a false ``can_resume`` says
    otherwise (as a :class:`contin.app.scene.SceneModel` without a ``resumer`` does)."""
    flag = getattr(model, "can_resume", None)
    if flag is not None and not callable(flag):
        return bool(flag)
    return callable(getattr(model, "resume", None))


# ---------------------------------------------------------------------------------------------------
# saving
# ---------------------------------------------------------------------------------------------------
def _matched_points(branches: Sequence[Any], records: Sequence[Mapping[str, Any]]) -> dict[int, tuple[int, int]]:
    """Record position -> (branch, position in its ``special_points``) of the special point it was made from.

    A runner makes its records from the branches' special points in path order and may leave some out,
    rename a kind or restate ``p`` in another quantity (a pressure record under volume control); a record
    is matched to the next special point of its branch with its label and arclength ``s`` (which every
    record of :func:`contin.app.scene.special_point_records` carries), else its parameter.  Jump records are
    not matched here.
    """
    from .scene import special_label

    out: dict[int, tuple[int, int]] = {}
    cursor: dict[int, int] = {}
    for k, rec in enumerate(records):
        b = rec.get("branch")
        if not isinstance(b, int) or "jump" in rec or not 0 <= b < len(branches):
            continue
        points = branches[b].special_points
        for j in range(cursor.get(b, 0), len(points)):
            spt = points[j]
            if special_label(spt) != str(rec.get("label", "")):
                continue
            where = ("s", float(spt.s)) if "s" in rec else ("p", float(spt.p))
            if _same(where[1], float(rec.get(where[0], math.nan))):
                out[k] = (b, j)
                cursor[b] = j + 1
                break
    return out


def _same(a: float, b: float) -> bool:
    return a == b or (math.isfinite(a) and math.isfinite(b) and abs(a - b) <= 1e-12 * max(abs(a), abs(b), 1e-300))


def _secant(br: Any, i: int) -> tuple[np.ndarray, float, float | None]:
    """Direction of the branch through stored point ``i`` to ``i + 1`` (the last secant for the last point)."""
    n = len(br)
    states = np.asarray(br.u)
    if n >= 2 and states.shape[0] == n:
        a = min(max(i, 0), n - 2)
        return states[a + 1] - states[a], float(br.p[a + 1] - br.p[a]), float(br.s[a + 1] - br.s[a])
    # without the stored states (store_states off): the parameter's direction alone
    tp = float(br.tangent_p[min(max(i, 0), n - 1)]) if n else 1.0
    return np.zeros(states.shape[1] if states.ndim == 2 else 0), tp if tp != 0.0 else 1.0, None


def number_points(records: Sequence[dict[str, Any]], table: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Give each special-point record its ``number`` (1-based, the label of ``--from OUT --label K``) and return the
    table with a first column ``#`` (when the table has one row per record; else the table as it is)."""
    for k, rec in enumerate(records):
        rec["number"] = k + 1
    if len(table) != len(records):
        return list(table)
    return [{"#": k + 1, **row} for k, row in enumerate(table)]


def _reached_by_jump(branches: Sequence[Any], n_jumps: int) -> list[bool]:
    """Per branch: whether it starts with the landing of jump ``b - 1`` (how :func:`contin.quasistatic` and
    :func:`contin.continuation` with ``origin`` mark a branch traced on after a snap)."""
    out = []
    for b, br in enumerate(branches):
        first = br.special_points[0] if br.special_points else None
        out.append(bool(0 < b <= n_jumps and first is not None and first.kind == "jump" and first.label == "jump_to"
                        and first.index == 0))
    return out


def _run_arrays(branches: Sequence[Any], jumps: Sequence[Any]) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The whole run as bundles (:meth:`Branch.to_bundle`, :meth:`JumpResult.to_bundle`): headers and arrays."""
    arrays: dict[str, np.ndarray] = {}
    headers: dict[str, Any] = {"branches": [], "jumps": [], "reached_by_jump": _reached_by_jump(branches, len(jumps))}
    for b, br in enumerate(branches):
        header, data = br.to_bundle(prefix=f"run_branch{b}_")
        headers["branches"].append(header)
        arrays.update(data)
    for j, jr in enumerate(jumps):
        header, data = jr.to_bundle(prefix=f"run_jump{j}_")
        headers["jumps"].append(header)
        arrays.update(data)
    return headers, arrays


def restart_states(result: Any) -> dict[str, np.ndarray]:
    """The arrays of :data:`STATES_FILE` for a :class:`contin.app.scene.TraceResult` (empty when nothing can be saved).

    Arrays: ``index`` (a JSON text: the format, one entry per saved point: ``key``, ``kind``, ``label``,
    ``branch``, ``number``, ``p``, ``complete``, and ``run``: the headers of the saved branches and jumps),
    per point ``u_<key>``, ``du_<key>``, ``pd_<key>`` (``[p, dp, ds]``, ``ds`` NaN when unknown) and, for a
    located branch point, ``bifurcation_direction_<key>`` and ``branch_tangent_<key>``; and the run's
    branches and jumps under ``run_branch<B>_*`` and ``run_jump<J>_*``.  Keys are the special point's
    number or ``end<B>``.  A jump's ``jump_from`` record is saved as an entry that names why it cannot be
    restarted from (``refused``).
    """
    from .scene import BUDGET_STATUSES

    branches = list(getattr(result, "branches", []))
    jumps = list(getattr(result, "jumps", []))
    records = list(getattr(result, "special_points", []))
    arrays: dict[str, np.ndarray] = {}
    entries: list[dict[str, Any]] = []

    def put(key: str, u: np.ndarray, p: float, du: np.ndarray, dp: float, ds: float | None, entry: dict[str, Any],
            extra: Mapping[str, Any] = {}) -> None:
        u = np.asarray(u, dtype=float).ravel()
        if u.size == 0:
            return
        arrays[f"u_{key}"] = u
        arrays[f"du_{key}"] = np.asarray(du, dtype=float).ravel() if np.size(du) == u.size else np.zeros(u.size)
        arrays[f"pd_{key}"] = np.array([float(p), float(dp), math.nan if ds is None else float(ds)])
        for name, value in extra.items():
            arrays[f"{name}_{key}"] = np.asarray(value, dtype=float).ravel()
        entries.append({"key": key, **entry, "p": float(p)})

    for k, (b, j) in sorted(_matched_points(branches, records).items()):
        rec, spt = records[k], branches[b].special_points[j]
        du, dp, ds = _secant(branches[b], int(spt.index))
        bif = spt.bifurcation if spt.kind == "branch_point" else None
        extra = {} if bif is None or not len(bif.directions) else {"bifurcation_direction": bif.directions[0]}
        if bif is not None and bif.traced is not None:
            extra["branch_tangent"] = bif.traced
        put(str(k + 1), spt.u, spt.p, du, dp, ds,
            {"kind": str(rec.get("kind", spt.kind)), "engine_kind": spt.kind, "label": str(rec.get("label", "")),
             "branch": b, "special": j, "number": k + 1}, extra)
    reached = _reached_by_jump(branches, len(jumps))
    ends = list(getattr(result, "jump_branches", None) or [])
    for k, rec in enumerate(records):
        ji = rec.get("jump")
        if rec.get("kind") != "jump" or not isinstance(ji, int) or not 0 <= ji < len(jumps):
            continue
        jr = jumps[ji]
        if rec.get("label") == "jump_from":
            left, kinds = (ends[ji][0], _LOST_STABILITY) if ends else (ji, ("fold",))
            fold = next((r["number"] for r in records[:k][::-1] if r.get("branch") == left and r.get("kind") in kinds
                         and "number" in r), None)
            entries.append({"key": str(k + 1), "kind": "jump", "label": "jump_from", "number": k + 1, "jump": ji,
                            "p": float(jr.p), "refused": _jump_from_refusal(k + 1, fold)})
            continue
        if ends:
            landing = ends[ji][1] if ends[ji][1] is not None and ends[ji][1] < len(branches) else None
        else:
            landing = ji + 1 if ji + 1 < len(branches) and reached[ji + 1] else None
        if landing is not None and len(branches[landing]) >= 2:
            du, dp, ds = _secant(branches[landing], 0)
        else:  # the sweep goes on in the parameter's direction; the state's direction is unknown
            before = branches[ji] if ji < len(branches) else None
            dp = float(np.sign(before.p[-1] - before.p[0])) if before is not None and len(before) >= 2 else 1.0
            du, ds = np.zeros(np.size(jr.u_to)), None
        put(str(k + 1), jr.u_to, jr.p, du, dp or 1.0, ds,
            {"kind": "jump", "engine_kind": "jump", "label": "jump_to", "number": k + 1, "jump": ji,
             "branch": landing if landing is not None else len(branches), "special": 0 if landing is not None else None})
    for b, br in enumerate(branches):
        if not len(br) or np.asarray(br.u).ndim != 2 or not np.asarray(br.u).shape[0]:
            continue
        du, dp, ds = _secant(br, len(br) - 1)
        put(f"end{b}", np.asarray(br.u)[-1], float(br.p[-1]), du, dp, ds,
            {"kind": "end", "label": "end", "branch": b, "number": None,
             "complete": br.status not in BUDGET_STATUSES, "status": br.status})
    if not entries:
        return {}
    index: dict[str, Any] = {"format": _FORMAT, "points": entries}
    if all(np.asarray(br.u).ndim == 2 and np.asarray(br.u).shape[0] == len(br) for br in branches):
        index["run"], run = _run_arrays(branches, jumps)
        arrays.update(run)
    arrays["index"] = np.array(json.dumps(index, default=_json_default))
    return arrays


def _json_default(obj: Any) -> Any:
    """What a saved special point's ``info`` may hold beyond JSON: numpy scalars, arrays, other objects by name."""
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    return repr(obj)


#: Kinds of the located points a path loses stability at, which a jump leaves from.
_LOST_STABILITY = ("fold", "bifurcation", "branch_point")


def _jump_from_refusal(number: int, fold: int | None) -> str:
    instead = f"the limit point itself (point {fold})" if fold is not None else "the limit point itself"
    return (f"point {number} is where a jump leaves its limit point (where the path lost stability): the state at a "
            f"load just past it, where no equilibrium is near, so no path goes on from it; restart from {instead} or "
            f"from the landing (point {number + 1})")


# ---------------------------------------------------------------------------------------------------
# reading
# ---------------------------------------------------------------------------------------------------
def _read_saved(path: Path) -> tuple[dict[str, Any], Any, dict[str, Any]]:
    if not path.is_dir():
        raise RestartError(f"--from {str(path)!r}: no such directory (give the output directory of a 'contin trace' run)")
    summary_file, states_file = path / "summary.json", path / STATES_FILE
    if not summary_file.is_file():
        raise RestartError(f"--from {str(path)!r}: no summary.json there; it is not an output directory of 'contin trace'")
    if not states_file.is_file():
        raise RestartError(f"--from {str(path)!r}: no {STATES_FILE} there (a run saves its states since the restart was "
                           f"added; trace it again to restart from it)")
    try:
        summary = json.loads(summary_file.read_text())
        data = np.load(states_file, allow_pickle=False)
        index = json.loads(str(data["index"][()]))
    except (OSError, ValueError, KeyError) as exc:
        raise RestartError(f"--from {str(path)!r}: cannot read the saved run ({type(exc).__name__}: {exc})") from None
    if not isinstance(summary, dict) or not isinstance(summary.get("scene"), dict) or index.get("format") not in _READABLE:
        raise RestartError(f"--from {str(path)!r}: summary.json or {STATES_FILE} is not a saved run of 'contin trace'")
    return summary, data, index


def read_summary(path: str | Path) -> dict[str, Any]:
    """``summary.json`` of the saved run ``path`` (checked to be a restartable run); :class:`RestartError` if not."""
    return _read_saved(Path(path))[0]


def _available(points: Sequence[Mapping[str, Any]]) -> str:
    numbers = [p["number"] for p in points if p.get("number") is not None and not p.get("refused")]
    ends = [f"end:{p['branch']}" if p["branch"] else "end" for p in points if p.get("kind") == "end"]
    shown = ", ".join(str(n) for n in numbers[:30]) + (", ..." if len(numbers) > 30 else "")
    return f"saved: special points {shown or '(none)'}; branch ends {', '.join(ends) or '(none)'}"


def find_point(points: Sequence[Mapping[str, Any]], label: str) -> Mapping[str, Any]:
    """The entry of the saved ``points`` that ``label`` names (module docstring); :class:`RestartError` if none, or
    if the point it names cannot be restarted from (the reason)."""
    text = str(label).strip()
    if text.lower() == "end" or text.lower().startswith("end:"):
        branch_text = text[4:] if ":" in text else "0"
        try:
            b = int(branch_text)
        except ValueError:
            raise RestartError(f"--label {label!r}: expected end or end:B with B a branch number; "
                               f"{_available(points)}") from None
        found = [p for p in points if p.get("kind") == "end" and p.get("branch") == b]
    elif text.lstrip("+-").isdigit():
        found = [p for p in points if p.get("number") == int(text)]
    else:
        found = [p for p in points if p.get("label") == text and p.get("kind") != "end"]
        if len(found) > 1:
            raise RestartError(f"--label {label!r} names {len(found)} special points (numbers "
                               f"{', '.join(str(p['number']) for p in found)}); give the number of one")
    if not found:
        raise RestartError(f"--label {label!r}: no such saved point; {_available(points)} (the # column of the "
                           f"special-point table)")
    if found[0].get("refused"):
        raise RestartError(f"--label {label!r}: {found[0]['refused']}")
    return found[0]


def _saved_trace(data: Any, index: Mapping[str, Any], where: str) -> SavedTrace | None:
    """The saved run's branches and jumps, or None for a file that holds the points alone."""
    from ..results.branch import Branch
    from ..analyses.jump import JumpResult

    run = index.get("run")
    if not run:
        return None
    arrays = {name: data[name] for name in data.files if name.startswith("run_")}
    try:
        branches = [Branch.from_bundle(h, arrays, prefix=f"run_branch{b}_", where=where)
                    for b, h in enumerate(run["branches"])]
        jumps = [JumpResult.from_bundle(h, arrays, prefix=f"run_jump{j}_", where=where)
                 for j, h in enumerate(run["jumps"])]
    except (KeyError, TypeError, ValueError) as exc:
        raise RestartError(f"{where}: the saved run is incomplete ({type(exc).__name__}: {exc})") from None
    return SavedTrace(branches, jumps, [bool(v) for v in run.get("reached_by_jump", [False] * len(branches))])


def read_start(path: str | Path, label: str) -> tuple[dict[str, Any], Start]:
    """``summary.json`` of the saved run ``path`` and the :class:`Start` that ``label`` names.

    Raises
    ------
    RestartError
        The directory, ``summary.json`` or :data:`STATES_FILE` is missing or unreadable, no saved point has the
        label, or the point it names cannot be restarted from.
    """
    path = Path(path)
    summary, data, index = _read_saved(path)
    entry = find_point(list(index.get("points", [])), label)
    key = entry["key"]
    try:
        p, dp, ds = (float(v) for v in data[f"pd_{key}"])
        u, du = np.array(data[f"u_{key}"], dtype=float), np.array(data[f"du_{key}"], dtype=float)
        extra = {name: np.array(data[f"{name}_{key}"], dtype=float) for name in ("bifurcation_direction", "branch_tangent")
                 if f"{name}_{key}" in data.files}
    except (KeyError, ValueError) as exc:
        raise RestartError(f"--from {str(path)!r}: {STATES_FILE} is incomplete ({exc})") from None
    records = summary.get("special_points") or []
    number = entry.get("number")
    record = dict(records[number - 1]) if number is not None and 0 < number <= len(records) else {}
    saved = _saved_trace(data, index, f"{str(path)!r}: {STATES_FILE}")
    return summary, Start(u=u, p=p, du=du, dp=dp, ds=ds if math.isfinite(ds) else None, name=str(label),
                          kind=str(entry.get("engine_kind", entry.get("kind", "end"))), label=str(entry.get("label", "")),
                          branch=int(entry.get("branch", 0)), number=number, record=record,
                          complete=bool(entry.get("complete", True)), extra=extra,
                          saved_scene=dict(summary.get("scene") or {}), special=entry.get("special"),
                          jump=entry.get("jump"), saved=saved)


# ---------------------------------------------------------------------------------------------------
# the scene of a restart
# ---------------------------------------------------------------------------------------------------
def _as_overrides(scene: Mapping[str, Mapping[str, Any]]) -> list[str]:
    from .scene import format_toml_value

    out = []
    for section, keys in scene.items():
        if not isinstance(keys, Mapping):
            continue
        for key, value in keys.items():
            try:
                out.append(f"{section}.{key}={format_toml_value(value)}")
            except TypeError:
                raise RestartError(f"the saved scene's {section}.{key} = {value!r} is not a scene value") from None
    return out


def saved_scene(model: Any, summary: Mapping[str, Any]) -> dict[str, dict[str, Any]]:
    """The saved run's scene, resolved against ``model``'s schema (:class:`contin.app.scene.SceneError` if it
    no longer fits)."""
    from .scene import load_scene

    return load_scene(model.schema, None, _as_overrides(summary["scene"]))


def restart_scene(model: Any, summary: Mapping[str, Any], overrides: Iterable[str]) -> dict[str, dict[str, Any]]:
    """The scene of a restart: the saved scene, then each ``--set``, validated against ``model``'s schema.

    Raises
    ------
    RestartError
        A ``--set`` changes a key the model lists in ``restart_fixed`` (the structure of its unknowns).
    contin.app.scene.SceneError
        The saved scene no longer fits the schema, or a ``--set`` is invalid.
    """
    from .scene import load_scene, parse_override

    overrides = list(overrides)
    saved = saved_scene(model, summary)
    scene = load_scene(model.schema, None, _as_overrides(summary["scene"]) + overrides)
    for name in getattr(model, "restart_fixed", ()):
        section, key = name.split(".")
        if scene[section][key] != saved[section][key]:
            given = next((o for o in reversed(overrides) if parse_override(o)[:2] == (section, key)), name)
            raise RestartError(
                f"--set {given}: {name} fixes the structure of the problem (the saved state was traced with "
                f"{name} = {_show(saved[section][key])} and does not fit another value); a restart keeps {name}, "
                f"trace a new run for another one")
    return scene


def _show(value: Any) -> str:
    from .scene import format_toml_value

    try:
        return format_toml_value(value)
    except TypeError:
        return repr(value)


def path_changes(saved: Mapping[str, Mapping[str, Any]], scene: Mapping[str, Mapping[str, Any]]) -> list[str]:
    """The keys outside :data:`PATH_FREE_SECTIONS` whose values differ between two resolved scenes (``section.key``)."""
    keys = {(section, key) for sc in (saved, scene) for section, fields in sc.items()
            if section not in PATH_FREE_SECTIONS for key in fields}
    return sorted(f"{s}.{k}" for s, k in keys if saved.get(s, {}).get(k) != scene.get(s, {}).get(k))


def _on_path_from_start(saved: SavedTrace, b: int) -> bool:
    """Whether branch ``b`` of the saved run (for ``b`` = the number of branches: the landing of jump ``b - 1``,
    after which nothing was traced) lies on the path the run followed from its start, through its jumps."""
    while b > 0:
        if b < len(saved.branches) and not saved.reached_by_jump[b]:
            return False
        if b - 1 >= len(saved.jumps):
            return False
        b -= 1
    return True


def _prefix(start: Start) -> SavedPrefix | None:
    """The saved path before ``start``, when the point lies on the path the saved run followed from its start."""
    saved = start.saved
    b = start.branch
    if saved is None or not 0 <= b <= len(saved.branches) or not _on_path_from_start(saved, b):
        return None  # e.g. a branch traced back from the other end of the path
    if b == len(saved.branches):
        return SavedPrefix(list(saved.branches), list(saved.jumps[:b]), None)
    br = saved.branches[b]
    if start.kind == "end":
        return SavedPrefix(list(saved.branches[:b]), list(saved.jumps[:b]), br.head(len(br), list(br.special_points)),
                           at_stored_point=True, s=float(br.s[-1]))
    if start.special is None or not 0 <= start.special < len(br.special_points):
        return None
    spt = br.special_points[start.special]
    stored = spt.kind == "jump" and spt.index == 0  # a landing is the branch's first stored point
    keep = int(spt.index) + 1
    s = float(spt.s) if math.isfinite(float(spt.s)) else float(br.s[keep - 1])
    return SavedPrefix(list(saved.branches[:b]), list(saved.jumps[:b]),
                       br.head(keep, list(br.special_points[:start.special + 1])), at_stored_point=stored, s=s)


def attach_saved_path(model: Any, start: Start, summary: Mapping[str, Any],
                      scene: Mapping[str, Mapping[str, Any]]) -> list[str]:
    """Give ``start`` the saved path before it (:attr:`Start.prefix`) when the restart continues that path.

    It does when the saved file holds the whole run, the point lies on the path the run followed from its
    start, and the scene changes nothing outside :data:`PATH_FREE_SECTIONS`.

    Returns
    -------
    list of str
        Why the restart does not continue the saved path (empty when it does): the changed keys, or the
        point's place.
    """
    changed = path_changes(saved_scene(model, summary), scene)
    if start.saved is None:
        return ["the saved run holds its special points alone (it was traced before whole runs were saved)"]
    if changed:
        return [f"{', '.join(changed)} changed"]
    prefix = _prefix(start)
    if prefix is None:
        return [f"branch {start.branch} of the saved run does not start where the run started"]
    start.prefix = prefix
    return []


def join_branches(head: Any, tail: Any, *, repeated: bool = True, s0: float | None = None) -> Any:
    """One branch: ``head`` (a saved path up to a point) followed by ``tail`` (the run continued from that point).

    Parameters
    ----------
    head, tail : Branch
        ``tail``'s first stored point is the restart's starting state (corrected at its parameter).
    repeated : bool
        Whether that state is ``head``'s last stored point again (a branch end, a jump's landing): it is
        then stored once.  Otherwise it lies beyond ``head``'s last stored point (a special point
        located between two stored points) and is kept.
    s0 : float, optional
        The arclength of the starting state along ``head`` (default: ``head``'s last stored point's).

    Returns
    -------
    Branch
        Ending as ``tail`` ends (its status and message), its arclength running on from ``head``'s, its
        step count the sum of both.  Arrays a branch holds on one side only (an eigenvalue table of
        another width, a tangent the other lacks) are dropped.
    """
    if not len(tail):
        return replace(head, status=tail.status, message=tail.message)
    if not len(head):
        return tail
    skip = 1 if repeated else 0
    shift = len(head) - skip
    start_s = float(head.s[-1]) if s0 is None else float(s0)

    def cat(a: Any, b: Any) -> Any:
        if a is None or b is None:
            return None
        a, b = np.asarray(a), np.asarray(b)
        if a.shape[1:] != b.shape[1:]:
            return None
        return np.concatenate([a, b[skip:]])

    moved = [replace(spt, index=int(spt.index) + shift, s=float(spt.s) + start_s) for spt in tail.special_points]
    stability = {}
    for label, (nneg_head, eigs_head) in head.stability_by.items():
        if label in tail.stability_by:
            nneg = cat(nneg_head, tail.stability_by[label][0])
            eigs = cat(eigs_head, tail.stability_by[label][1])
            if nneg is not None:
                stability[label] = (nneg, eigs if eigs is not None else np.zeros((len(nneg), 0)))
    observables = {k: cat(v, tail.observables[k]) for k, v in head.observables.items() if k in tail.observables}
    tangents = {k: cat(v, tail.tangents[k]) for k, v in head.tangents.items() if k in tail.tangents}
    steps = int(head.meta.get("n_steps", max(len(head) - 1, 0))) + int(tail.meta.get("n_steps", max(len(tail) - 1, 0)))
    meta = dict(tail.meta, n_steps=steps)
    if "modes" in tail.meta or "modes" in head.meta:
        meta["modes"] = _joined_modes(head.meta.get("modes", {}), tail.meta.get("modes", {}), skip)
    return replace(tail, p=cat(head.p, tail.p), u=cat(head.u, tail.u),
                   s=np.concatenate([head.s, np.asarray(tail.s)[skip:] + start_s]),
                   tangent_p=cat(head.tangent_p, tail.tangent_p), residual=cat(head.residual, tail.residual),
                   newton_iterations=cat(head.newton_iterations, tail.newton_iterations),
                   observables={k: v for k, v in observables.items() if v is not None},
                   n_negative=cat(head.n_negative, tail.n_negative), eigenvalues=cat(head.eigenvalues, tail.eigenvalues),
                   stability_by=stability, special_points=list(head.special_points) + moved,
                   tangents={k: v for k, v in tangents.items() if v is not None}, meta=meta)


def _joined_modes(head: Mapping[str, Any], tail: Mapping[str, Any], skip: int) -> dict[str, Any]:
    """The per-point counts of the watched operator families (:mod:`contin.watch.modes`, ``Branch.meta["modes"]``) of
    two joined branches: a family both watched with the same keys has its rows joined; any other is left out."""
    out = {}
    for name, fam in tail.items():
        other = head.get(name)
        if other is None or list(other.get("keys", [])) != list(fam.get("keys", [])):
            continue
        width = len(fam["keys"])
        joined = dict(fam)
        for field in ("n_negative", "lowest"):
            if field in fam and field in other:
                a = np.asarray(other[field], dtype=float).reshape(-1, width)
                b = np.asarray(fam[field], dtype=float).reshape(-1, width)[skip:]
                joined[field] = np.concatenate([a, b]).tolist()
        out[name] = joined
    return out


def continue_saved(start: Start, branches: Sequence[Any], jumps: Sequence[Any] = ()) -> tuple[list[Any], list[Any]]:
    """The branches and jumps of a restarted run joined to the saved path before its point (:attr:`Start.prefix`).

    Without a prefix (the restart does not continue the saved path) they are returned as they are.  With
    one: the saved branches before the point's branch, that branch up to the point joined to the first
    new branch (:func:`join_branches`), the other new branches; the saved jumps before the point, then
    the new ones.
    """
    branches, jumps = list(branches), list(jumps)
    prefix = start.prefix
    if prefix is None:
        return branches, jumps
    if prefix.cut is not None and branches:
        joined = join_branches(prefix.cut, branches[0], repeated=prefix.at_stored_point, s0=prefix.s)
        branches = [joined] + branches[1:]
    elif prefix.cut is not None:
        branches = [prefix.cut]
    return list(prefix.branches) + branches, list(prefix.jumps) + jumps


def restart_record(path: str | Path, start: Start, overrides: Sequence[str], not_joined: Sequence[str] = ()) -> dict[str, Any]:
    """``summary.json``'s ``restart``: where the run started (the saved run, the label, the point), the ``--set``
    given, and whether the results describe the whole path (``joined``) or the part traced from the point."""
    record = {"from": str(path), "label": start.name, "kind": start.kind, "special_label": start.label,
              "number": start.number, "branch": start.branch, "p": start.p, "set": list(overrides),
              "joined": start.continues_saved_path}
    record["describes"] = ("the whole path: the saved run's path up to the point, joined to the part traced from it"
                           if start.continues_saved_path else
                           f"only the part traced from the point ({'; '.join(not_joined)})")
    return record


# ---------------------------------------------------------------------------------------------------
# the engine's side of a runner's resume
# ---------------------------------------------------------------------------------------------------
def beyond_end(problem: Any, start: Start, p_min: float = -math.inf, p_max: float = math.inf,
               bounds: Mapping[str, tuple[float | None, float | None]] | None = None, rtol: float = 1e-7) -> str | None:
    """Why a path continued from ``start`` along its saved direction would have nothing to trace, or None.

    That is when the point lies at or past one of the run's ends (a parameter bound or an observable
    bound) and the direction leads further out: a continuation started there never crosses the bound,
    so it would run on past the end of the path.  "At" is within ``rtol`` of the bound's size.
    """
    def out_of(value: float, rate: float, low: float | None, high: float | None) -> str | None:
        for bound, sign, word in ((high, 1.0, "at or above its end"), (low, -1.0, "at or below its end")):
            if bound is None or not math.isfinite(bound):
                continue
            tol = rtol * max(abs(bound), abs(value), 1e-300)
            if sign * (value - bound) > tol or (sign * (value - bound) >= -tol and sign * rate >= 0.0):
                return f"{word} {bound:.10g} ({value:.10g})"
        return None

    scale = max(float(np.max(np.abs(start.du), initial=0.0)), abs(start.dp), 1e-300)
    eps = 1e-7 / scale
    found = out_of(float(start.p), float(start.dp), p_min, p_max)
    if found:
        return f"the parameter is {found}"
    if bounds:
        here = problem.evaluate_observables(start.u, start.p)
        there = problem.evaluate_observables(start.u + eps * start.du, start.p + eps * start.dp)
        for name, (low, high) in bounds.items():
            if name not in here:
                continue
            found = out_of(float(here[name]), float(there[name]) - float(here[name]), low, high)
            if found:
                return f"{name} is {found}"
    return None


def drop_start_duplicates(branch: Any, u0: np.ndarray, p0: float, rtol: float = 1e-7) -> Any:
    """Leave out of ``branch`` the special points that are its own starting point found again (in place; returns it).

    A run started exactly on a fold or an event may see its test function change sign on the first
    step and locate the point it started from once more; that is no new special point.
    """
    u0 = np.asarray(u0, dtype=float)
    scale = max(float(np.max(np.abs(u0), initial=0.0)), 1e-300)

    def at_start(spt: Any) -> bool:
        if spt.index > 0 or np.asarray(spt.u).shape != u0.shape:
            return False
        near_p = abs(float(spt.p) - p0) <= rtol * max(abs(p0), abs(float(spt.p)), 1e-12)
        return near_p and float(np.max(np.abs(np.asarray(spt.u) - u0), initial=0.0)) <= rtol * scale

    branch.special_points = [spt for spt in branch.special_points if spt.kind == "jump" or not at_start(spt)]
    return branch


def resume(problem: Any, start: Start, settings: Any = None, *, switch: bool = False, events: Sequence[Any] = (),
           keep_step: bool = True, **overrides: Any) -> Any:
    """Continue ``problem`` from a saved point: the same branch along the saved direction, or the other branch.

    Parameters
    ----------
    problem : Problem
        The problem the state belongs to (the same unknowns as the run that saved it).
    start : Start
    settings : Settings, optional
        The model's settings for the run (keyword ``overrides`` as for :func:`contin.continuation`).
    switch : bool
        At a located branch point saved with its bifurcating direction: follow the other branch
        (:func:`contin.switch_branch`, the half given by the saved direction's orientation, else +1).
    events : sequence of Event
    keep_step : bool
        Start with the saved run's step at the point (within the settings' ``ds_min`` and ``ds_max``)
        instead of the settings' first step.

    Returns
    -------
    Branch
        Without the starting point found again as a special point (:func:`drop_start_duplicates`).

    Raises
    ------
    RestartError
        The point lies at or past an end of the path in the direction it went (:func:`beyond_end`).

    Notes
    -----
    The model check at the first point (``Settings.check_model``) is left out: the model was checked where
    the saved run started, and at a saved fold or branch point the Jacobian is nearly singular along the
    tangent, where the check's finite differences measure curvature rather than slope.
    """
    from ..palc import continuation, switch_branch
    from ..results.branch import Bifurcation, SpecialPoint
    from ..settings import resolve_settings

    st = resolve_settings(settings, {**overrides, "check_model": False})
    if keep_step and start.ds is not None and start.ds > 0 and "ds" not in overrides:
        st = replace(st, ds=min(max(start.ds, st.ds_min), st.ds_max))
    if switch:
        direction = start.extra.get("bifurcation_direction")
        if start.kind != "branch_point" or direction is None:
            raise RestartError(f"{start.describe()} is not a located branch point with a bifurcating direction: "
                               f"there is no other branch to follow from it")
        d = np.asarray(direction, dtype=float)
        record = Bifurcation(multiplicity=1, kernel=d[None, :-1] / max(float(np.linalg.norm(d[:-1])), 1e-300),
                             directions=d[None, :], traced=start.extra.get("branch_tangent"))
        bp = SpecialPoint("branch_point", start.p, start.u, dict(start.record.get("observables") or {}), located=True,
                          label=start.label, bifurcation=record)
        return switch_branch(problem, bp, st, events=events)
    past = beyond_end(problem, start, st.p_min, st.p_max, st.bounds)
    if past:
        raise RestartError(f"{start.describe()} lies at the end of this scene's path or beyond it ({past}) and the path "
                           f"went on outwards there: there is nothing to trace; move the end with --set, or restart "
                           f"from an earlier point")
    u0 = np.asarray(start.u, dtype=float)
    du = np.asarray(start.du, dtype=float)
    if du.shape != u0.shape:
        du = np.zeros_like(u0)
    branch = continuation(problem, u0, start.p, st, events=events, tangent=(du, float(start.dp)))
    return drop_start_duplicates(branch, u0, start.p)
