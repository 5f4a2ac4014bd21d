"""Sweeps: classify every combination of values of some scene keys, in parallel and resumably.

A *sweep axis* is a scene key with a list of values, written ``section.key=SPEC`` (the argument of
``contin classify --sweep``):

- a comma list ``0.6,0.8,1.0`` (each value read like a ``--set`` value),
- a range ``start:stop:count``: ``count`` evenly spaced values, both ends included,
- a geometric range ``log:start:stop:count``.

:func:`parse_sweep` reads one axis, :func:`sweep_scenes` resolves and validates the scene of every
combination (the cartesian product, first axis slowest) exactly as ``contin classify --set`` would,
and :func:`run_sweep` classifies them with the model's ``classify`` through an executor
(:mod:`contin.app.executors`: local worker processes by default, this process, or a Dask cluster),
appending one CSV row per finished combination.  Rerun with the same CSV and the rows already there are
reused: an interrupted sweep loses only the combinations that were running.

The CSV has one row per combination.  Its columns are the swept keys (``section.key``), ``label``
(the class; empty when undecided), ``status`` (the classification's :attr:`~contin.app.scene.Classification.status`:
``ok``, ``incomplete`` when the path stopped before its end, whether or not it proved a class on the way,
or why it failed), the scalar values of the model's :class:`~contin.app.scene.Classification` (numbers,
booleans; empty when absent), ``wall_time_s``, ``failure`` (empty when the combination was classified
on its whole path; else why not) and ``scene`` (the resolved scene as compact JSON, so that every row
says exactly what it was computed for).  A CSV written before rows had a ``status`` is read and
resumed as it is.

Nothing here knows about any particular model: models are found through the registry
(:func:`contin.app.registry.load_model`) or passed as runner objects.
"""

from __future__ import annotations

import csv
import errno
import functools
import hashlib
import io
import itertools
import json
import math
import os
import pickle
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from contextlib import closing
from pathlib import Path
from typing import Any

from ..results.io import atomic_write, status_text
from . import registry
from .executors import Executor, ProcessExecutor, SerialExecutor, WorkerDied, default_workers, make_executor
from .scene import (Classification, Field, ModelRunner, SceneError, Schema, can_classify, check_classifiable,
                    engine_failures, format_toml_value, load_scene, parse_override)

__all__ = ["SweepError", "SWEEP_SYNTAX", "parse_sweep", "sweep_scenes", "run_sweep", "default_workers",
           "read_sweep_csv", "check_sweep_classifiable"]

#: How a sweep axis is written (quoted in error messages and in the help).
SWEEP_SYNTAX = ("SPEC is a comma list of values (0.6,0.8,1.0), a range start:stop:count (count evenly spaced "
                "values, both ends included, e.g. 0.6:1.2:4) or a geometric range log:start:stop:count "
                "(e.g. log:0.005:0.05:5)")
#: Largest number of combinations a sweep may have.
MAX_COMBINATIONS = 1_000_000
#: Columns of the CSV after the swept keys and the model's values (``label`` comes right after the keys).
TAIL_COLUMNS = ("wall_time_s", "failure", "scene")
#: Start of the ``failure`` of a combination whose worker process died; such rows are recomputed on resume.
WORKER_DIED = "the worker process died"
#: Columns every row has: the class and the run's status (``ok``, ``incomplete``, ``failed``, ...).
_STANDARD = ("label", "status") + TAIL_COLUMNS

Scene = dict[str, dict[str, Any]]
_FLOAT_MAX = sys.float_info.max
Combination = tuple[dict[str, Any], Scene]


class SweepError(SceneError):
    """Bad sweep input: a malformed axis, a combination out of range, or a CSV that belongs to another sweep.

    A :class:`~contin.app.scene.SceneError`, so the command line reports it as bad input (exit status 2).
    ``kind`` is ``"syntax"`` (the axis), ``"unknown"`` (the key), ``"type"``, ``"range"``,
    ``"constraint"`` (a combination's scene) or ``"file"`` (the CSV).
    """


# ---------------------------------------------------------------------------------------------------
# axes
# ---------------------------------------------------------------------------------------------------
def _show(value: Any) -> str:
    """A value as written on the command line (floats shortened to 10 significant digits)."""
    if isinstance(value, float):
        text = f"{value:.10g}"
        return text if any(c in text for c in ".ein") else text + ".0"
    try:
        return format_toml_value(value) if not isinstance(value, str) else value
    except TypeError:
        return repr(value)


def _canonical(value: Any) -> tuple[str, Any]:
    """What two values of a swept key must share to count as the same value (12 significant digits)."""
    import numpy as np  # here, not at the top: the command line's help and bad input need no numpy

    if isinstance(value, bool):
        return ("b", value)
    if isinstance(value, (int, float, np.integer, np.floating)):
        try:
            return ("n", float(f"{float(value):.12g}"))
        except OverflowError:  # an integer beyond the float range: only equal to itself
            return ("n", int(value))
    return ("s", str(value))


def _number(text: str, name: str, bad: Callable[[str], SweepError]) -> int | float:
    value = parse_override(f"{name}={text}")[2] if text.strip() else None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise bad(f"{text.strip()!r} is not a number")
    try:
        finite = math.isfinite(value)
    except OverflowError:  # an integer beyond the float range
        raise bad(f"{text.strip()!r} is beyond the range of floating-point numbers") from None
    if not finite:
        raise bad(f"{text.strip()!r} is not a number")
    return value


def _range_values(name: str, raw: str, bad: Callable[[str], SweepError]) -> list[Any]:
    import numpy as np

    parts = raw.split(":")
    geometric = parts[0].strip().lower() == "log"
    if geometric:
        parts = parts[1:]
    if len(parts) != 3:
        raise bad("a range has three parts, start:stop:count" + (" after log:" if geometric else ""))
    start, stop = (_number(p, name, bad) for p in parts[:2])
    count = parse_override(f"{name}={parts[2]}")[2] if parts[2].strip() else None
    if isinstance(count, bool) or not isinstance(count, int) or count < 2:
        raise bad(f"the count {parts[2].strip()!r} must be an integer >= 2 (for one value, give just the value)")
    if count > MAX_COMBINATIONS:
        raise bad(f"the count {count} is more than {MAX_COMBINATIONS}")
    if start == stop:
        raise bad(f"start and stop are both {start}: the range would repeat one value")
    if geometric:
        if start <= 0 or stop <= 0:
            raise bad("a geometric range needs start > 0 and stop > 0")
        points = np.geomspace(float(start), float(stop), count)
    else:
        if not math.isfinite(float(stop) - float(start)):  # numpy would fill the range with inf and nan
            raise bad("start and stop are too far apart: stop - start is beyond the range of floating-point numbers")
        points = np.linspace(float(start), float(stop), count)
    # 12 significant digits, so that 0.6:1.0:5 gives 0.7 and not 0.7000000000000001; the ends exactly as given
    values: list[Any] = [float(f"{x:.12g}") for x in points]
    values[0], values[-1] = float(start), float(stop)
    integral = all(abs(v - round(v)) <= 1e-9 * max(1.0, abs(v)) for v in values)
    if isinstance(start, int) and isinstance(stop, int) and integral:
        values = [int(round(v)) for v in values]
    return values


def _swept_field(schema: Schema, spec: str, name: str) -> Field:
    """The schema field of the swept key ``name`` (``section.key``) of the ``--sweep`` argument ``spec``.

    Raises
    ------
    SweepError
        Kind ``"unknown"``: the schema has no such section or key.
    """
    section, _, key = name.partition(".")
    if section not in schema.sections:
        raise SweepError(f"unknown scene section [{section}] in --sweep {spec}; allowed sections: "
                         f"{', '.join(f'[{s}]' for s in schema.sections)}", "unknown")
    if key not in schema.sections[section]:
        raise SweepError(f"unknown scene key {name} in --sweep {spec}; section [{section}] allows: "
                         f"{', '.join(schema.sections[section]) or '(none)'}", "unknown")
    return schema.field(section, key)


def parse_sweep(spec: str, schema: Schema | None = None) -> tuple[str, list[Any]]:
    """Read one sweep axis, ``section.key=SPEC``.

    Parameters
    ----------
    spec : str
        ``section.key=SPEC`` where SPEC is a comma list ``0.6,0.8,1.0`` (each value read as a
        ``--set`` value: TOML, else a bare string), a range ``start:stop:count`` (``count`` evenly
        spaced values, both ends included) or ``log:start:stop:count`` (geometric).  Inner points of
        a range are rounded to 12 significant digits.  A range whose ends are integers and whose
        points are all integers gives integers (``model.N=40:100:4`` is 40, 60, 80, 100).
    schema : Schema, optional
        The model's schema.  With it the key must exist, a range of an integer key must give
        integers, numbers for a float key become floats, and a boolean or string key cannot take a
        range.  The values themselves are checked by :func:`sweep_scenes`.

    Returns
    -------
    name : str
        ``"section.key"``.
    values : list
        The values, in the order given.

    Raises
    ------
    SweepError
        One paragraph naming the key and the allowed syntax, for a malformed SPEC, a repeated value,
        or (with ``schema``) an unknown key or a range that does not fit the key's type.
    """
    name, sep, raw = spec.partition("=")
    name, raw = name.strip(), raw.strip()
    section, dot, key = name.partition(".")
    if not sep or not dot or not section or not key or "." in key or not raw:
        raise SweepError(f"bad --sweep argument {spec!r}: expected section.key=SPEC, where {SWEEP_SYNTAX}", "syntax")

    def bad(why: str) -> SweepError:
        return SweepError(f"bad --sweep {name}={raw}: {why}; {SWEEP_SYNTAX}", "syntax")

    field = None if schema is None else _swept_field(schema, spec, name)

    if ":" in raw:
        if field is not None and field.type not in (int, float):
            raise bad(f"{name} takes {field.allowed}, and only a numeric key takes a range: list its values")
        values = _range_values(name, raw, bad)
        if field is not None and field.type is int and not all(isinstance(v, int) for v in values):
            odd = next(v for v in values if not (isinstance(v, float) and v.is_integer()) and not isinstance(v, int))
            raise bad(f"{name} takes integers, but this range gives {odd:g}; choose start, stop and count so that "
                      f"every value is an integer (e.g. 40:100:4), or list the values")
    else:
        values = []
        for item in raw.split(","):
            if not item.strip():
                raise bad("an empty value in the list")
            value = parse_override(f"{name}={item}")[2]
            if isinstance(value, (list, dict)) or not isinstance(value, (bool, int, float, str)):
                raise bad(f"{item.strip()!r} is not a single value")
            values.append(value)
    if field is not None and field.type is float:
        # an integer beyond the float range stays as it is: the scene check rejects it with the allowed range
        values = [float(v) if isinstance(v, int) and not isinstance(v, bool) and abs(v) <= _FLOAT_MAX else v
                  for v in values]
    seen: set[tuple[str, Any]] = set()
    for v in values:
        if _canonical(v) in seen:
            raise bad(f"the value {_show(v)} is given twice")
        seen.add(_canonical(v))
    return name, values


def sweep_scenes(schema: Schema, axes: Sequence[tuple[str, Sequence[Any]]], path: str | Path | None = None,
                 overrides: Iterable[str] = ()) -> list[Combination]:
    """Resolve and validate the scene of every combination of the axes.

    Each scene is what ``load_scene(schema, path, [*overrides, "section.key=value", ...])`` gives,
    so it is resolved and checked exactly as ``contin classify --set`` would resolve it; every
    combination is checked before the function returns, so a bad value is reported before any work.

    Parameters
    ----------
    schema : Schema
        The model's scene schema.
    axes : sequence of (str, sequence)
        ``(section.key, values)`` per axis, as :func:`parse_sweep` returns them.
    path : str or Path, optional
        A TOML scene file (a swept key may also be set there; the sweep's values replace it).
    overrides : iterable of str
        ``section.key=value`` settings for every combination (``--set``); a swept key may not be among them.

    Returns
    -------
    list of (dict, dict)
        Per combination, in cartesian-product order (first axis slowest): the swept values by
        ``section.key`` (converted to the keys' types, as in the scene), and the resolved scene.

    Raises
    ------
    SweepError
        A key swept twice or also given by ``--set``, no axis, too many combinations, or a
        combination whose scene is invalid (the message names the field, the value and what is
        allowed, and the combination).
    SceneError
        When the scene without the sweep (file and overrides) is already invalid.
    """
    overrides = list(overrides)
    names = [name for name, _ in axes]
    if not names:
        raise SweepError("a sweep needs at least one axis (--sweep section.key=SPEC)", "syntax")
    for name in names:
        if names.count(name) > 1:
            raise SweepError(f"{name} is swept twice; give one --sweep per key ({SWEEP_SYNTAX})", "syntax")
    fixed = {".".join(parse_override(item)[:2]) for item in overrides}
    for name in names:
        if name in fixed:
            raise SweepError(f"{name} is given both by --set and by --sweep; drop one of them", "syntax")
    total = math.prod(len(values) for _, values in axes)
    if total == 0:
        empty = next(name for name, values in axes if not len(values))
        raise SweepError(f"the sweep of {empty} has no values; {SWEEP_SYNTAX}", "syntax")
    if total > MAX_COMBINATIONS:
        raise SweepError(f"the sweep has {total} combinations ({' x '.join(str(len(v)) for _, v in axes)}); at "
                         f"most {MAX_COMBINATIONS} are allowed", "syntax")
    load_scene(schema, path, overrides)  # the part every combination shares: its errors are plain scene errors
    out: list[Combination] = []
    for combo in itertools.product(*(values for _, values in axes)):
        try:
            items = [f"{name}={format_toml_value(value)}" for name, value in zip(names, combo)]
        except TypeError:
            raise SweepError(f"a swept value in {', '.join(map(repr, combo))} is not a scalar", "type") from None
        try:
            scene = load_scene(schema, path, [*overrides, *items])
        except SceneError as exc:
            message = str(exc)
            for name, item in zip(names, items):
                message = message.replace(f"(from --set {item})", f"(a value of --sweep {name})")
            where = ", ".join(f"{name}={_show(v)}" for name, v in zip(names, combo))
            raise SweepError(f"{message} (in the sweep combination {where})", exc.kind) from None
        values = {name: scene[name.split(".")[0]][name.split(".")[1]] for name in names}
        out.append((values, scene))
    return out


# ---------------------------------------------------------------------------------------------------
# CSV
# ---------------------------------------------------------------------------------------------------
def _cell_text(value: Any) -> str:
    import numpy as np

    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return repr(float(value)) if math.isfinite(value) else ""
    if isinstance(value, dict):
        return json.dumps(value, separators=(",", ":"), allow_nan=False)
    return str(value)


def _parse_cell(text: str) -> Any:
    if text == "":
        return None
    if text in ("true", "false"):
        return text == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def _parse_row(raw: dict[str, str], columns: Sequence[str], n_axes: int,
               axis_types: dict[str, type] | None = None) -> dict[str, Any]:
    """A CSV row as :func:`run_sweep` returns rows: typed values, ``label`` None when empty.

    ``axis_types`` gives the type of each swept key's values (a string key's ``"1"`` stays a string).

    Raises
    ------
    ValueError
        When a cell holds what the sweep never writes (the message names the column): a scene that is not
        a JSON object of sections, a value that is neither a number, true, false nor empty, a number that
        is not finite, a negative wall time, or neither a class nor a failure.
    """
    row: dict[str, Any] = {}
    for i, col in enumerate(columns):
        text = raw[col]
        if axis_types is not None and axis_types.get(col) is str:
            row[col] = text
        elif col == "label":
            row[col] = text or None
        elif col == "failure":
            row[col] = text
        elif col == "status":
            if not text or not all(c.islower() or c == "_" for c in text):
                raise _damaged(col, text, "is not a status (a word such as ok or incomplete)")
            row[col] = text
        elif col == "scene":
            try:
                scene = json.loads(text, parse_constant=_no_json_constant)
            except ValueError:
                raise _damaged(col, text, "is not a scene written as JSON") from None
            if not isinstance(scene, dict) or not all(isinstance(keys, dict) for keys in scene.values()):
                raise _damaged(col, text, "is not a scene (a JSON object of sections)")
            row[col] = scene
        else:
            value = _parse_cell(text)
            if isinstance(value, float) and not math.isfinite(value):
                raise _damaged(col, text, "is not a finite number (the sweep leaves a missing value empty)")
            if col == "wall_time_s":
                if isinstance(value, bool) or not isinstance(value, (int, float, type(None))) or (value or 0) < 0:
                    raise _damaged(col, text, "is not a time in seconds (a number >= 0)")
                value = None if value is None else float(value)
            elif i >= n_axes and isinstance(value, str):
                raise _damaged(col, text, "is not a number, true, false or empty")
            row[col] = value
    if "label" in row and "failure" in row and row["label"] is None and not row["failure"]:
        raise ValueError("it has neither a class (label) nor a failure")
    if "status" not in row and "failure" in row:  # a CSV written before rows had a status
        row["status"] = "failed" if row["failure"] else "ok"
    if "failure" in row and (row["status"] == "ok") != (not row["failure"]):
        raise ValueError(f"its status {row['status']!r} does not fit its failure (ok exactly when there is none)")
    return row


def _no_json_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a value of a scene")


def _damaged(column: str, text: str, why: str) -> ValueError:
    shown = text if len(text) <= 60 else text[:57] + "..."
    return ValueError(f"its {column} cell {shown!r} {why}")


def _csv_line(columns: Sequence[str], row: dict[str, Any]) -> str:
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([_cell_text(row.get(c)) for c in columns])
    return buf.getvalue()


def _fixed_part(scene: Scene, axes: Sequence[str]) -> Scene:
    swept = {tuple(a.split(".", 1)) for a in axes}
    return {sec: {k: v for k, v in keys.items() if (sec, k) not in swept} for sec, keys in scene.items()}


def _first_difference(a: Scene, b: Scene) -> str:
    for sec in sorted(set(a) | set(b)):
        for key in sorted(set(a.get(sec, {})) | set(b.get(sec, {}))):
            va, vb = a.get(sec, {}).get(key, "(absent)"), b.get(sec, {}).get(key, "(absent)")
            if va != vb:
                shown = [format_toml_value(v) if isinstance(v, str) and v != "(absent)" else _show(v) for v in (va, vb)]
                return f"{sec}.{key} = {shown[0]} there, {shown[1]} in this sweep"
    return "the scenes differ"


def _starts_afresh() -> str:
    return "write to another file (--csv PATH), delete it, or start afresh with --no-resume, which overwrites it"


def read_sweep_csv(path: str | Path) -> tuple[list[str], list[dict[str, Any]]]:
    """Read a sweep CSV written by :func:`run_sweep`.

    Returns
    -------
    columns : list of str
        The header.
    rows : list of dict
        Typed rows (numbers, booleans, None for empty cells; ``scene`` as a dict), in file order.
        A last line cut short by an interrupted write is left out.

    Raises
    ------
    SweepError
        If the file cannot be read or is not a sweep CSV (the message names the file).
    """
    path = Path(path)
    columns, rows, _ = _read_csv(path)
    if columns is None:
        return [], []
    n_axes = columns.index("label")
    out = []
    for lineno, raw in enumerate(rows, start=2):
        try:
            out.append(_parse_row(raw, columns, n_axes))
        except ValueError as exc:
            raise SweepError(f"line {lineno} of the sweep CSV {str(path)!r} is damaged: {exc}", "file") from None
    return columns, out


def _read_csv(path: Path, axes: Sequence[str] | None = None) -> tuple[list[str] | None, list[dict[str, str]], bool]:
    """Header, raw rows, and whether an unfinished last line was dropped.

    With ``axes`` (the swept keys of the sweep about to write the file), a file without a complete line
    counts as a header cut short only if it is the start of this sweep's header: any other such file is
    not a sweep CSV (and is not overwritten).
    """
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise SweepError(f"{str(path)!r} is not a sweep CSV written by contin classify: it is not UTF-8 text "
                         f"({exc.reason} at byte {exc.start}); {_starts_afresh()}", "file") from None
    except OSError as exc:
        raise SweepError(f"cannot read the sweep CSV {str(path)!r}: {exc.strerror or exc}", "file") from None
    cut = bool(text) and not text.endswith("\n")
    if cut:  # a row whose write was interrupted: it is recomputed
        fragment = text[text.rfind("\n") + 1:]
        text = text[: text.rfind("\n") + 1]
        start = ",".join([*axes, "label"]) if axes else ""
        if axes and not text and not (start.startswith(fragment) or fragment.startswith(start + ",")):
            raise SweepError(f"{str(path)!r} is not a sweep CSV written by contin classify (it starts "
                             f"{fragment[:40]!r} and has no complete line); {_starts_afresh()}", "file")
    try:
        records = list(csv.reader(io.StringIO(text)))
    except csv.Error as exc:  # e.g. a field over the csv module's size limit
        raise SweepError(f"{str(path)!r} is not a sweep CSV written by contin classify ({exc}); "
                         f"{_starts_afresh()}", "file") from None
    if not records:
        return None, [], cut
    header = records[0]
    tail = list(TAIL_COLUMNS)
    if ("label" not in header or header[-len(tail):] != tail or len(set(header)) != len(header)
            or header.index("label") == 0):
        raise SweepError(f"{str(path)!r} is not a sweep CSV written by contin classify (its columns are "
                         f"{', '.join(header[:8])}{', ...' if len(header) > 8 else ''}); {_starts_afresh()}", "file")
    rows = []
    for lineno, rec in enumerate(records[1:], start=2):
        if len(rec) != len(header):
            raise SweepError(f"line {lineno} of the sweep CSV {str(path)!r} has {len(rec)} fields, the header "
                             f"{len(header)}; delete that line (it is recomputed) or {_starts_afresh()}", "file")
        rows.append(dict(zip(header, rec)))
    return header, rows, cut


class _CsvStore:
    """The sweep's CSV: reads what a previous run left, then appends one flushed row per combination.

    A new file (or the replacement of an old one) is created with its first row, not before: a sweep
    interrupted before any combination finished leaves no empty file, and an old file as it was.
    """

    def __init__(self, path: str | Path, axes: list[str], combos: Sequence[Combination], resume: bool) -> None:
        self.path = Path(path)
        self.axes = axes
        self.columns: list[str] | None = None
        self.resumed: dict[int, dict[str, Any]] = {}
        self.extra: list[dict[str, Any]] = []  # rows for other values of the same axes: kept in the file
        self.written: list[dict[str, Any]] = []  # every row now in the file, in file order
        self._fh: io.TextIOWrapper | None = None
        if self.path.is_dir():
            raise SweepError(f"the sweep CSV {str(self.path)!r} is a directory; give a file name", "file")
        rewrite = False
        if resume and self.path.exists():
            rewrite = self._load(combos)
        self._mode = "a" if resume and self.columns else "w"  # of the first open, at the first row
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            if rewrite:
                self._rewrite(self.written)
            _check_writable(self.path)
        except OSError as exc:
            raise SweepError(f"cannot write the sweep CSV {str(self.path)!r}: {exc.strerror or exc}", "file") from None

    def _load(self, combos: Sequence[Combination]) -> bool:
        header, raw_rows, rewrite = _read_csv(self.path, self.axes)
        if header is None:
            return rewrite
        n = header.index("label")
        if header[:n] != self.axes:
            raise SweepError(f"the sweep CSV {str(self.path)!r} holds a sweep over {', '.join(header[:n])}, and this "
                             f"sweep is over {', '.join(self.axes)}; {_starts_afresh()}", "file")
        fixed = _fixed_part(combos[0][1], self.axes)
        index = {tuple(_canonical(v) for v in values.values()): i for i, (values, _) in enumerate(combos)}
        for lineno, raw in enumerate(raw_rows, start=2):
            try:
                row = _parse_row(raw, header, n, {a: type(v) for a, v in combos[0][0].items()})
                for a in self.axes:  # the swept values are also in the row's scene: they must agree
                    sec, key = a.split(".", 1)
                    if not isinstance(row["scene"].get(sec), dict) or key not in row["scene"][sec]:
                        raise ValueError(f"its scene has no {a}")
                    if _canonical(row[a]) != _canonical(row["scene"][sec][key]):
                        raise _damaged(a, raw[a], f"is not the value of {a} in its scene "
                                                  f"({_show(row['scene'][sec][key])})")
            except ValueError as exc:
                raise SweepError(f"line {lineno} of the sweep CSV {str(self.path)!r} is damaged: {exc}; delete that "
                                 f"line (it is recomputed) or {_starts_afresh()}", "file") from None
            if not isinstance(row["scene"], dict) or _fixed_part(row["scene"], self.axes) != fixed:
                theirs = row["scene"] if isinstance(row["scene"], dict) else {}
                raise SweepError(f"the sweep CSV {str(self.path)!r} holds results for another scene "
                                 f"({_first_difference(_fixed_part(theirs, self.axes), fixed)}, line {lineno}); "
                                 f"{_starts_afresh()}", "file")
            i = index.get(tuple(_canonical(row[a]) for a in self.axes))
            if i is None:
                self.extra.append(row)
            elif str(row["failure"]).startswith(WORKER_DIED):
                rewrite = True  # not a result of the combination: computed again
            else:
                rewrite = rewrite or i in self.resumed
                self.resumed[i] = row  # the last row of a combination counts
        self.columns = list(header)
        self.written = [*self.extra, *self.resumed.values()]
        return rewrite or len(self.written) != len(raw_rows)

    def _rewrite(self, rows: Sequence[dict[str, Any]]) -> None:
        """Replace the file by ``rows`` under ``self.columns``, atomically (it keeps its permissions)."""
        if self.columns is None:
            return
        if self._fh is not None:
            self._fh.close()
            self._fh = None
        columns = self.columns

        def write(fh: Any) -> None:
            fh.write(_csv_line(columns, {c: c for c in columns}))
            for row in rows:
                fh.write(_csv_line(columns, row))
        atomic_write([(self.path, write)], keep_mode=True)
        self._mode = "a"  # the rows that follow go after these

    def append(self, row: dict[str, Any]) -> None:
        """Write one row and flush it; extend the header (rewriting the file) if the row has new columns."""
        new = [k for k in row if k not in (self.columns or ()) and k not in self.axes and k not in _STANDARD]
        self.written.append(row)
        if self.columns is None:
            self.columns = [*self.axes, "label", "status", *new, *TAIL_COLUMNS]
            self._open().write(_csv_line(self.columns, {c: c for c in self.columns}))
        elif new:
            self.columns = [*self.columns[:-len(TAIL_COLUMNS)], *new, *TAIL_COLUMNS]
            self._rewrite(self.written)
            return
        fh = self._open()
        fh.write(_csv_line(self.columns, row))
        fh.flush()

    def _open(self) -> io.TextIOWrapper:
        """The file, opened for the rows (created or truncated the first time when it is not resumed)."""
        if self._fh is None:
            self._fh = open(self.path, self._mode, encoding="utf-8", newline="")
            self._mode = "a"
        return self._fh

    def finish(self, rows: Sequence[dict[str, Any]], columns: list[str]) -> None:
        """Rewrite the file in combination order with the final columns (the rows are all there already)."""
        self.columns = columns
        self._rewrite([*rows, *self.extra])

    def close(self) -> None:
        if self._fh is not None:
            self._fh.close()
            self._fh = None


def _check_writable(path: Path) -> None:
    """Raise ``OSError`` when ``path`` could not be written (created in its directory, or replaced).

    The sweep creates its CSV with the first row; this tells before any work that it could.
    """
    target = path if path.exists() else path.parent
    if not os.access(target, os.W_OK):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), str(target))


# ---------------------------------------------------------------------------------------------------
# classifying one combination (in this process or in a worker)
# ---------------------------------------------------------------------------------------------------
def _one_line(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {' '.join(str(exc).split())}"


def _scalar_values(values: dict[str, Any]) -> dict[str, Any]:
    """The values fit for a CSV column: numbers, booleans and None (strings, lists and tables are left out)."""
    import numpy as np

    out: dict[str, Any] = {}
    for key, v in values.items():
        if v is None or isinstance(v, (bool, np.bool_)):
            out[str(key)] = None if v is None else bool(v)
        elif isinstance(v, (int, np.integer)):
            out[str(key)] = int(v)
        elif isinstance(v, (float, np.floating)):
            out[str(key)] = float(v) if math.isfinite(v) else None
    return out


_Outcome = tuple[str | None, dict[str, Any], str, str, float]  # label, scalar values, status, failure, wall time


def _classify_safely(runner: Any, scene: Scene) -> _Outcome:
    """Classify one scene; every failure becomes the ``failure`` text, never an exception (but an interrupt)."""
    t0 = time.perf_counter()
    label: str | None = None
    values: dict[str, Any] = {}
    status = "failed"
    try:
        result = runner.classify(scene, False)
        if not isinstance(result, Classification):
            failure = (f"internal error: classify() of {getattr(runner, 'name', 'the model')!r} returned "
                       f"{type(result).__name__}, expected Classification")
        else:
            label, values, status = result.label, _scalar_values(result.values), result.status
            failure = "" if result.success else " ".join(result.message.split())
    except SceneError as exc:
        failure = f"the model rejected this scene: {' '.join(str(exc).split())}"
    except engine_failures() as exc:
        failure = f"run failed: {_one_line(exc)}"
    except Exception as exc:  # a bug in the model or in contin: reported in the row, the sweep goes on
        failure = f"internal error: {_one_line(exc)}"
    return label, values, status, failure, time.perf_counter() - t0


def _load_runner(name: str) -> ModelRunner:
    try:
        return registry.load_model(name)
    except registry.ModelNotFound as exc:
        raise SweepError(str(exc), "unknown") from None


def check_sweep_classifiable(runner: Any, scenes: Sequence[Combination]) -> None:
    """Refuse a sweep with a combination the model can trace but not classify, before anything runs.

    Raises
    ------
    SweepError
        Kind ``"constraint"``: the refusal of :func:`contin.app.scene.check_classifiable`, naming the
        combination (when a key is swept).
    """
    for values, scene in scenes:
        try:
            check_classifiable(runner, scene)
        except SceneError as exc:
            where = ", ".join(f"{name}={_show(v)}" for name, v in values.items())
            raise SweepError(f"{exc}{f' (in the sweep combination {where})' if where else ''}", exc.kind) from None


# in a worker process (of the pool or of a Dask cluster): the runners of its sweeps by model, or why
# loading one failed
_WORKER: dict[str, tuple[Any, str]] = {}


def _model_key(model: str | bytes) -> str:
    """The key of a model reference (a registered name, or a pickled runner) in a worker's cache."""
    return model if isinstance(model, str) else "pickle:" + hashlib.sha1(model).hexdigest()


def _init_worker(model: str | bytes) -> None:
    """Initializer of a worker: load the model (a registered name or a pickled runner) once.

    An exception is kept and reported in the row of every combination, never as a traceback.
    """
    try:
        _WORKER[_model_key(model)] = (_load_runner(model) if isinstance(model, str) else pickle.loads(model), "")
    except BaseException as exc:
        _WORKER[_model_key(model)] = (None, _one_line(exc))


def _classify_in_worker(key: str, scene: Scene) -> _Outcome:
    """Classify one scene with the model the worker loaded under ``key`` (:func:`_init_worker`)."""
    runner, error = _WORKER.get(key, (None, "the worker was not initialized"))
    if runner is None:
        return None, {}, "failed", f"the model could not be loaded in the worker process: {error}", 0.0
    return _classify_safely(runner, scene)


# ---------------------------------------------------------------------------------------------------
# the sweep
# ---------------------------------------------------------------------------------------------------
def _duration(seconds: float) -> str:
    if seconds < 60:
        return f"{seconds:.0f} s" if seconds >= 10 else f"{seconds:.1f} s"
    if seconds < 3600:
        return f"{int(seconds // 60)} min {int(seconds % 60):02d} s"
    return f"{int(seconds // 3600)} h {int(seconds % 3600 // 60):02d} min"


def _make_row(values: dict[str, Any], scene: Scene, outcome: _Outcome) -> dict[str, Any]:
    label, model_values, status, failure, wall = outcome
    row: dict[str, Any] = dict(values)
    row["label"] = label
    row["status"] = status
    for key, v in model_values.items():
        if key not in row and key not in _STANDARD:
            row[key] = v
    row["wall_time_s"] = wall
    row["failure"] = failure
    row["scene"] = scene
    return row


Row = dict[str, Any]


def _checked_runner(model: str | ModelRunner, scenes: Sequence[Combination], workers: int | None,
                    scheduler: str | None, executor: Executor | None,
                    runner: ModelRunner | None) -> tuple[ModelRunner, str, int | None]:
    """Check the arguments of :func:`run_sweep` and load the runner, before any executor or CSV exists.

    Parameters
    ----------
    model, scenes, workers, scheduler, executor, runner
        As for :func:`run_sweep` (``scenes`` not empty).

    Returns
    -------
    runner : ModelRunner
        The runner that classifies in this process.
    name : str
        The model's name, for messages.
    workers : int or None
        ``workers`` as an int.

    Raises
    ------
    ValueError
        An executor together with workers or a scheduler, or fewer than one worker.
    SweepError
        An unknown model, one that cannot classify, or a combination it cannot classify.
    """
    if executor is not None and (workers is not None or scheduler is not None):
        raise ValueError("give an executor, or workers and scheduler to make one, not both")
    workers = None if workers is None else int(workers)
    if workers is not None and workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if runner is None:
        runner = _load_runner(model) if isinstance(model, str) else model
    name = model if isinstance(model, str) else getattr(runner, "name", type(runner).__name__)
    if not can_classify(runner):
        raise SweepError(f"model {name!r} cannot classify: it provides no classification", "unknown")
    check_sweep_classifiable(runner, scenes)
    return runner, name, workers


def _printer(progress: bool) -> Callable[[str], None]:
    """The progress printer of :func:`run_sweep`: ``contin: MSG`` on stderr (:func:`contin.results.io.status_text`),
    or nothing."""
    if not progress:
        return lambda msg: None
    return lambda msg: print(status_text(f"contin: {msg}"), file=sys.stderr, flush=True)


def _rows_to_compute(store: _CsvStore | None, total: int) -> tuple[list[Row | None], list[int]]:
    """The rows resumed from the CSV (None where a combination is still to compute) and the indices to compute.

    Parameters
    ----------
    store : _CsvStore or None
        The results file, if any.
    total : int
        The number of combinations.

    Returns
    -------
    rows : list of dict or None
        One entry per combination.
    todo : list of int
        The indices of the combinations without a row, in combination order.
    """
    rows: list[Row | None] = [None] * total
    if store is not None:
        for i, row in store.resumed.items():
            rows[i] = row
    return rows, [i for i in range(total) if rows[i] is None]


class _Recorder:
    """Takes each finished combination: its row goes into ``rows`` and the CSV, and one progress line is said.

    Parameters
    ----------
    scenes : sequence of (dict, dict)
        The combinations of the sweep.
    rows : list of dict or None
        The rows by combination, filled in place.
    todo : list of int
        The indices being computed (for the count and the estimate of the time left).
    store : _CsvStore or None
        The results file, if any.
    say : callable
        The progress printer.
    """

    def __init__(self, scenes: Sequence[Combination], rows: list[Row | None], todo: Sequence[int],
                 store: _CsvStore | None, say: Callable[[str], None]) -> None:
        self.scenes, self.rows, self.todo, self.store, self.say = scenes, rows, todo, store, say
        self.t_start = time.perf_counter()
        self.computed = 0

    def __call__(self, i: int, outcome: _Outcome) -> None:
        """Record the outcome of combination ``i``."""
        values, scene = self.scenes[i]
        row = _make_row(values, scene, outcome)
        self.rows[i] = row
        if self.store is not None:
            self.store.append(row)
        self.computed += 1
        total = len(self.rows)
        done = total - len(self.todo) + self.computed
        left = len(self.todo) - self.computed
        eta = (time.perf_counter() - self.t_start) / self.computed * left
        what = row["label"] if not row["failure"] else f"no class: {row['failure']}"
        if len(what) > 160:
            what = what[:157] + "..."
        combo = " ".join(f"{k}={_show(v)}" for k, v in values.items())
        self.say(f"[{done}/{total}] {combo} -> {what} ({row['wall_time_s']:.2f} s"
                 f"{'; ETA ' + _duration(eta) if left else ''})")


def _task(model: str | ModelRunner, runner: ModelRunner, name: str,
          in_process: bool) -> tuple[Callable[[Scene], _Outcome], Callable[..., None] | None, tuple]:
    """What the executor runs per combination, with its worker initializer and the initializer's arguments.

    Parameters
    ----------
    model : str or ModelRunner
        As for :func:`run_sweep`: a registered name is sent to workers as is, a runner pickled.
    runner : ModelRunner
        The runner for this process.
    name : str
        The model's name, for the error.
    in_process : bool
        Whether the executor runs the tasks in this process (then ``runner`` classifies directly).

    Returns
    -------
    task : callable
        Scene -> outcome.
    initializer : callable or None
        Loads the model in a worker.
    initargs : tuple
        The arguments of ``initializer``.

    Raises
    ------
    TypeError
        The runner cannot be pickled for worker processes.
    """
    if in_process:
        return functools.partial(_classify_safely, runner), None, ()
    if isinstance(model, str):
        ref: str | bytes = model
    else:
        try:
            ref = pickle.dumps(runner)
        except Exception as exc:
            raise TypeError(f"the model {name!r} cannot be sent to worker processes ({_one_line(exc)}); "
                            f"pass its registered name, or workers=1") from None
    return functools.partial(_classify_in_worker, _model_key(ref)), _init_worker, (ref,)


def _classify_all(run_on: Executor, task: tuple[Callable[[Scene], _Outcome], Callable[..., None] | None, tuple],
                  scenes: Sequence[Combination], todo: Sequence[int], record: _Recorder) -> None:
    """Run the combinations ``todo`` on ``run_on`` and record each outcome as it finishes.

    Parameters
    ----------
    run_on : Executor
        Where to run.
    task : tuple
        The task, initializer and initializer arguments of :func:`_task`.
    scenes : sequence of (dict, dict)
        The combinations of the sweep.
    todo : sequence of int
        The indices to compute.
    record : _Recorder
        Takes ``(index, outcome)``; a dead worker's outcome is a failure that resume computes again.
    """
    fn, initializer, initargs = task
    items = [scenes[i][1] for i in todo]
    with closing(run_on.map_unordered(fn, items, initializer=initializer, initargs=initargs)) as results:
        for k, outcome in results:
            if isinstance(outcome, WorkerDied):
                outcome = (None, {}, "failed", f"{WORKER_DIED} while classifying this combination (killed, out of "
                                     f"memory, or a crash in compiled code); it is computed again on resume", 0.0)
            record(todo[k], outcome)


def _final_rows(axes: Sequence[str], rows: Sequence[Row | None]) -> tuple[list[Row], list[str]]:
    """Every row with the same columns: the swept keys, ``label``, the union of the model's values, the tail.

    Parameters
    ----------
    axes : sequence of str
        The swept keys.
    rows : sequence of dict
        One row per combination (all computed by now).

    Returns
    -------
    out : list of dict
        The rows, None where a row lacks a column.
    columns : list of str
        The columns, in order.
    """
    columns = [*axes, "label", "status"]
    for row in rows:
        assert row is not None
        columns += [k for k in row if k not in columns and k not in TAIL_COLUMNS]
    columns += list(TAIL_COLUMNS)
    return [{c: row.get(c) for c in columns} for row in rows if row is not None], columns


def _reorder_csv(store: _CsvStore, out: Sequence[Row], columns: list[str], say: Callable[[str], None]) -> None:
    """Rewrite the complete CSV in combination order; a failure is only a warning (the rows are all there)."""
    try:
        store.finish(out, columns)
    except OSError as exc:  # every row is in the file already, in completion order
        say(f"warning: could not put {str(store.path)!r} in combination order: {exc.strerror or exc}")


def run_sweep(model: str | ModelRunner, scenes: Sequence[Combination], csv_path: str | Path | None = None,
              workers: int | None = None, progress: bool = True, resume: bool = True, *,
              scheduler: str | None = None, executor: Executor | None = None,
              runner: ModelRunner | None = None) -> list[dict[str, Any]]:
    """Classify every combination of a sweep, in parallel, writing each row to a CSV as it finishes.

    Parameters
    ----------
    model : str or ModelRunner
        A registered model's name (worker processes load it through the registry) or a runner that
        can classify (sent to the workers by pickling: its functions must be importable).
    scenes : sequence of (dict, dict)
        The combinations, as :func:`sweep_scenes` returns them: the swept values by ``section.key``
        and the resolved scene.
    csv_path : str or Path, optional
        The results file.  Each finished row is appended and flushed at once (the header is written
        with the first row).  When the file exists and ``resume`` is true, the rows it holds for
        combinations of this sweep are reused, not recomputed (matched on the swept values to 12
        significant digits); rows of other values of the same keys are kept.  Rows whose worker
        died are computed again.  When the sweep is complete, the file is rewritten in combination
        order (atomically).  Without ``csv_path`` nothing is written.
    workers : int, optional
        Local worker processes (default: the CPUs available, :func:`default_workers`).  With 1, or
        with one combination to compute, the combinations are classified in this process.  Workers
        run with one BLAS/OpenMP thread each.  Not with ``scheduler`` or ``executor``.
    progress : bool
        Print one line per finished combination to stderr (with the class, the time and an estimate
        of the time left), and how many rows were resumed.
    resume : bool
        Reuse the rows of an existing ``csv_path``; False overwrites the file.
    scheduler : str, optional
        Run on the Dask cluster of this scheduler (``tcp://HOST:8786``; needs the ``dask`` extra).
    executor : Executor, optional
        Run on this executor (:mod:`contin.app.executors`; it is not closed here) instead of one made
        from ``workers`` and ``scheduler``.  A :class:`~contin.app.executors.ProcessExecutor` with one
        combination to compute classifies it in this process.
    runner : ModelRunner, optional
        With ``model`` a registered name: its runner, already loaded by the caller.  It classifies
        what runs in this process; worker processes still load the model by name.

    Returns
    -------
    list of dict
        One row per combination, in the order of ``scenes``: the swept keys, ``label`` (None when
        undecided or failed), every scalar value of the model's classification (the union over the
        rows; None where a row has none), ``wall_time_s``, ``failure`` (empty when classified) and
        ``scene``.  The rows do not depend on the executor (but for ``wall_time_s``).

    Raises
    ------
    SweepError
        When ``csv_path`` belongs to another sweep (other keys, or another scene for the keys not
        swept), cannot be read or written, or when the model cannot classify.
    contin.app.executors.ExecutorError
        Bad ``workers``, or a Dask scheduler that cannot be used (not installed, not reached); raised
        before the CSV is touched.
    KeyboardInterrupt
        On Ctrl-C: the workers are stopped; the rows written so far stay in the CSV.

    Notes
    -----
    A combination that fails (no class decided, a numerical failure, an exception in the model)
    is a row with ``failure`` set; a worker that dies costs only the combination it was running.
    The environment variables of the BLAS thread counts are set to 1 in this process while it
    starts local workers, and restored afterwards.
    """
    scenes = list(scenes)
    if not scenes:
        return []
    runner, name, workers = _checked_runner(model, scenes, workers, scheduler, executor, runner)
    axes = list(scenes[0][0])
    total = len(scenes)
    say = _printer(progress)

    own = executor is None
    if executor is None:
        if scheduler is None and workers is None:
            workers = min(default_workers(), total)
        executor = make_executor(workers, scheduler)
    store: _CsvStore | None = None
    try:
        store = _CsvStore(csv_path, axes, scenes, resume) if csv_path is not None else None
        rows, todo = _rows_to_compute(store, total)
        # one combination: starting a worker process would only cost time
        run_on = SerialExecutor() if len(todo) == 1 and isinstance(executor, ProcessExecutor) else executor
        if store is not None and store.resumed:
            say(f"resumed {len(store.resumed)} of {total} combinations from {str(store.path)!r}")
        if todo:
            say(f"classifying {len(todo)} of {total} combinations {run_on.where(len(todo))}")
        record = _Recorder(scenes, rows, todo, store, say)
        _classify_all(run_on, _task(model, runner, name, run_on.in_process), scenes, todo, record)
        out, columns = _final_rows(axes, rows)
        if store is not None:
            _reorder_csv(store, out, columns, say)
        return out
    finally:
        if store is not None:
            store.close()
        if own:
            executor.close()
