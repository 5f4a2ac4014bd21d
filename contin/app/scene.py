"""Declarative scenes: a typed schema, TOML loading with ``--set`` overrides, and the model-runner protocol.

A *scene* is the complete input of one command-line run, as a two-level TOML document::

    [model]
    n = 200

    [continuation]
    ds = 0.1

A :class:`Schema` names every section and key with a :class:`Field` (type, default, validity check and
a human description of the allowed range), plus cross-field :class:`Constraint` s.
:func:`load_scene` reads a file, applies ``section.key=value`` overrides, fills the defaults and
validates; any problem raises :class:`SceneError` whose message is one paragraph naming the field,
the offending value and what is allowed.

A model becomes runnable from the command line by exposing a :class:`SceneModel` (or any object
with the same attributes, see :class:`ModelRunner`) through the ``contin.models`` entry-point group.
Its ``run`` returns a :class:`TraceResult`; :meth:`TraceResult.from_branches` derives the special
point records, the CSV columns and the printed table from the branches, so a runner stays small.
A model may also classify a scene (``contin classify``): it then provides a ``classify`` callable
returning a :class:`Classification` (see :class:`Classifier`; a :class:`SceneModel` takes it as
``classifier``), and may restrict the scenes it classifies with ``classify_requires`` (checked by
:func:`check_classifiable` before anything runs).  Models without one are traced but not classified.
A model may also restart from a point saved by an earlier run (``contin trace --from OUT --label K``): it
then provides a ``resume`` callable (see :class:`Resumer`; a :class:`SceneModel` takes it as ``resumer``)
and lists in ``restart_fixed`` the scene keys a restart must keep (:mod:`contin.app.restart`).
A :class:`SceneModel` may also say that it is the default model and give the command line its
examples and help (``default``, ``examples``, ``help``; see :mod:`contin.app.registry`).

A run is complete when every branch reached the end its runner planned for it: a branch that stopped
because its step budget ran out (:data:`BUDGET_STATUSES`) makes :attr:`TraceResult.complete` false,
the status ``"incomplete"`` and the run unsuccessful.  A scene's ``[output] figure = false``
(:func:`wants_figure`) means no figure file.

Nothing here knows about any particular model.
"""

from __future__ import annotations

import datetime
import math
import tomllib
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

if TYPE_CHECKING:  # the engine's results, named in annotations only: reading a scene imports no numpy
    import numpy as np

    from ..results.branch import Branch, SpecialPoint
    from ..analyses.jump import JumpResult

__all__ = [
    "SceneError", "Field", "Constraint", "Schema", "load_scene", "parse_override", "defaults",
    "format_toml_value", "schema_as_toml",
    "integer", "real", "boolean", "choice", "text",
    "TraceResult", "Classification", "ModelRunner", "Classifier", "Resumer", "SceneModel", "can_classify",
    "special_point_records", "special_label", "special_point_table", "branch_columns", "check_classifiable", "wants_figure",
    "engine_failures",
    "BUDGET_STATUSES",
]


class SceneError(ValueError):
    """Invalid scene input.  The message is a single paragraph fit to show a user as is.

    Attributes
    ----------
    kind : str
        ``"file"`` (unreadable or invalid TOML), ``"syntax"`` (bad ``--set``), ``"unknown"`` (unknown
        section or key), ``"type"``, ``"range"`` or ``"constraint"``.
    """

    def __init__(self, message: str, kind: str = "") -> None:
        # a one-paragraph guarantee: parser messages and reprs may carry newlines
        super().__init__(" ".join(str(message).split()))
        self.kind = kind


# ---------------------------------------------------------------------------------------------------
# schema
# ---------------------------------------------------------------------------------------------------
_TYPE_NAMES = {bool: "a boolean (true or false)", int: "an integer", float: "a number", str: "a string"}
#: Integers a scene accepts are within [-2**63, 2**63) whatever the field's own range.
_INT64_LIMIT = 2 ** 63


@dataclass(frozen=True)
class Field:
    """One scene key.

    Attributes
    ----------
    type : {bool, int, float, str}
        Expected type.  An integer is accepted where a float is expected (and converted); a boolean
        is never accepted as a number.
    default : Any
        Value used when the scene does not set the key.
    check : callable, optional
        ``check(value) -> bool`` on the converted value; False means out of range.
    allowed : str
        Human description of the allowed values, e.g. ``"a float > 0"``.
    help : str
        What the key means (shown by ``contin models``).
    words : tuple of str
        Strings accepted besides the values of ``type`` (e.g. ``"auto"`` for an integer the tool
        chooses); the model reading the scene says what each means.
    """

    type: type
    default: Any
    check: Callable[[Any], bool] | None = None
    allowed: str = ""
    help: str = ""
    words: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.type not in _TYPE_NAMES:
            raise TypeError(f"Field.type must be one of bool, int, float, str; got {self.type!r}")
        if not self.allowed:
            object.__setattr__(self, "allowed", _TYPE_NAMES[self.type])

    def convert(self, value: Any) -> Any:
        """Return ``value`` as the field's type (or one of its :attr:`words`), or raise ``TypeError`` with the
        expected type."""
        if isinstance(value, str) and value in self.words:
            return value
        t = self.type
        if t is bool:
            ok = isinstance(value, bool)
        elif t is int:
            ok = isinstance(value, int) and not isinstance(value, bool)
        elif t is float:
            ok = isinstance(value, (int, float)) and not isinstance(value, bool)
            if ok:
                try:
                    value = float(value)
                except OverflowError:  # an integer beyond the float range (TOML integers are unbounded)
                    raise TypeError("a finite number") from None
                if not math.isfinite(value):
                    raise TypeError("a finite number")
        else:
            ok = isinstance(value, str)
        if not ok:
            raise TypeError(_TYPE_NAMES[t])
        return value

    def valid(self, value: Any) -> bool:
        """Whether the (converted) value passes the field's check (one of its :attr:`words` always does)."""
        if isinstance(value, str) and value in self.words:
            return True
        return self.check is None or bool(self.check(value))


@dataclass(frozen=True)
class Constraint:
    """A condition that involves several fields, checked after every field is valid on its own.

    Attributes
    ----------
    fields : tuple of str
        Dotted names (``"section.key"``) of the fields involved, reported in the error.
    check : callable
        ``check(scene) -> bool`` on the resolved scene.
    allowed : str
        The rule in words, e.g. ``"continuation.ds <= continuation.ds_max"``.
    reason : str
        Why the rule exists (optional; appended to the error).
    detail : callable, optional
        ``detail(scene) -> str``: what the rule asks of this scene in particular, called only when the
        check fails (e.g. the number a formula gives, or why a file could not be read); the error
        puts it before the rule in general.
    """

    fields: tuple[str, ...]
    check: Callable[[dict[str, dict[str, Any]]], bool]
    allowed: str
    reason: str = ""
    detail: Callable[[dict[str, dict[str, Any]]], str] | None = None


@dataclass(frozen=True)
class Schema:
    """Sections of named :class:`Field` s plus cross-field :class:`Constraint` s."""

    sections: Mapping[str, Mapping[str, Field]]
    constraints: Sequence[Constraint] = ()

    def field(self, section: str, key: str) -> Field:
        """The field ``section.key`` (``KeyError`` if unknown)."""
        return self.sections[section][key]


def integer(default: int | str, low: int | None = None, high: int | None = None, help: str = "",
            words: tuple[str, ...] = ()) -> Field:
    """An integer field, optionally bounded (inclusive), that also takes the strings ``words``."""
    if low is not None and high is not None:
        allowed = f"an integer in [{low}, {high}]"
    elif low is not None:
        allowed = f"an integer >= {low}"
    elif high is not None:
        allowed = f"an integer <= {high}"
    else:
        allowed = "an integer"
    allowed += "".join(f' or "{word}"' for word in words)
    return Field(int, default, lambda v: (low is None or v >= low) and (high is None or v <= high), allowed, help,
                 tuple(words))


def real(default: float, *, gt: float | None = None, ge: float | None = None, lt: float | None = None,
         le: float | None = None, help: str = "") -> Field:
    """A float field with optional strict (``gt``, ``lt``) or inclusive (``ge``, ``le``) bounds."""
    low = (gt, "(", ">") if gt is not None else (ge, "[", ">=") if ge is not None else None
    high = (lt, ")", "<") if lt is not None else (le, "]", "<=") if le is not None else None
    if low and high:
        allowed = f"a float in {low[1]}{low[0]:g}, {high[0]:g}{high[1]}"
    elif low or high:
        value, _, op = low or high
        allowed = f"a float {op} {value:g}"
    else:
        allowed = "a float"

    def check(v: float) -> bool:
        return ((gt is None or v > gt) and (ge is None or v >= ge) and (lt is None or v < lt)
                and (le is None or v <= le))

    return Field(float, float(default), check, allowed, help)


def boolean(default: bool, help: str = "") -> Field:
    """A boolean field."""
    return Field(bool, bool(default), None, "true or false", help)


def choice(default: str, options: Iterable[str], help: str = "") -> Field:
    """A string field restricted to a set of options."""
    opts = tuple(options)
    return Field(str, default, lambda v: v in opts, "one of " + ", ".join(f'"{o}"' for o in opts), help)


def text(default: str, help: str = "") -> Field:
    """A free string field."""
    return Field(str, default, None, "a string", help)


def defaults(schema: Schema) -> dict[str, dict[str, Any]]:
    """The scene with every field at its default."""
    return {sec: {key: f.default for key, f in keys.items()} for sec, keys in schema.sections.items()}


# ---------------------------------------------------------------------------------------------------
# loading
# ---------------------------------------------------------------------------------------------------
def _show(value: Any) -> str:
    if isinstance(value, (dict, list)):
        return repr(value)
    if isinstance(value, (datetime.date, datetime.time)):  # TOML dates and times, as written in TOML
        return value.isoformat()
    try:
        return format_toml_value(value)
    except TypeError:
        return repr(value)


def parse_override(text_: str) -> tuple[str, str, Any]:
    """Split ``"section.key=value"`` into ``(section, key, value)``.

    The value is parsed as a TOML value (``3``, ``1e-8``, ``true``, ``"s"``, ``[1, 2]``); if it is not
    valid TOML it is taken as a bare string, so ``--set model.kind=plate`` works without quotes.

    Raises
    ------
    SceneError
        If the text is not of the form ``section.key=value``.
    """
    name, sep, raw = text_.partition("=")
    name = name.strip()
    section, dot, key = name.partition(".")
    if not sep or not dot or not section or not key or "." in key or not raw.strip():
        example = f"--set {name}=VALUE" if dot and section and key and "." not in key else "--set continuation.ds=0.05"
        raise SceneError(f"bad --set argument {text_!r}: expected the form section.key=value in one argument, with "
                         f"no space around '=', e.g. {example}", "syntax")
    raw = raw.strip()
    try:
        doc = tomllib.loads(f"value = {raw}")
        value = doc["value"] if set(doc) == {"value"} else raw
    except tomllib.TOMLDecodeError:
        value = raw
    except RecursionError:  # tomllib recurses once per level of nested arrays or tables
        raise SceneError(f"bad value for {section}.{key}: arrays or tables nested too deeply; a scene value is a "
                         f"single number, boolean or string", "syntax") from None
    return section, key, value


def _read_toml(path: Path) -> dict[str, Any]:
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise SceneError(f"cannot read scene file {str(path)!r}: {exc.strerror or exc}", "file") from None
    try:
        text = data.decode("utf-8-sig")  # a byte-order mark, as some editors write, is not part of the TOML
    except UnicodeDecodeError as exc:
        raise SceneError(f"scene file {str(path)!r} is not UTF-8 text ({exc.reason} at byte {exc.start})", "file") from None
    if not text.strip():
        # a file cut to nothing (a full disk, an interrupted copy) would otherwise run the defaults silently
        raise SceneError(f"scene file {str(path)!r} is empty; give a scene ('contin models NAME --toml' prints "
                         f"one with every key), or leave the file out to use the model's defaults", "file")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene file {str(path)!r} is not valid TOML: {exc}", "file") from None
    except RecursionError:  # tomllib recurses once per level of nested arrays or tables
        raise SceneError(f"scene file {str(path)!r} is not a scene: its arrays or tables are nested too deeply "
                         f"(a scene is [section] tables of single values)", "file") from None


def load_scene(schema: Schema, path: str | Path | None = None, overrides: Iterable[str] = ()) -> dict[str, dict[str, Any]]:
    """Read, override, complete and validate a scene.

    Parameters
    ----------
    schema : Schema
        The model's scene schema.
    path : str or Path, optional
        A TOML scene file; without it the scene starts from the defaults.
    overrides : iterable of str
        ``"section.key=value"`` strings applied after the file, in order.

    Returns
    -------
    dict
        ``{section: {key: value}}`` with every field of the schema, values converted to the field
        types (an integer given for a float becomes a float).

    Raises
    ------
    SceneError
        One paragraph naming the field as ``section.key``, the offending value and the allowed range;
        for unknown sections or keys, the allowed ones; for an unreadable or invalid file, the file and
        the parser's message.
    """
    overrides = list(overrides)
    # a malformed --set is reported before the file is read: `--set section.key 1` makes '1' the file
    parsed = [_parsed_override(item, path) for item in overrides]
    # value and where it came from, for error messages
    given: dict[str, dict[str, tuple[Any, str]]] = {}
    if path is not None:
        if not str(path):  # Path("") would be the current directory
            raise SceneError("the scene file name is empty; give a TOML file, or leave it out to use the model's "
                             "defaults", "file")
        path = Path(path)
        where = f"in {str(path)!r}"
        for section, content in _read_toml(path).items():
            if not isinstance(content, dict) and section not in schema.sections:
                raise SceneError(f"scene key {section} = {_show(content)} {where} is not inside a section; "
                                 f"keys belong in the sections {', '.join(f'[{s}]' for s in schema.sections)}",
                                 "unknown")
            _known_section(schema, section, where)
            if not isinstance(content, dict):
                raise SceneError(f"scene entry {section!r} {where} must be a table [{section}] of keys, "
                                 f"got the value {_show(content)}; allowed keys of [{section}]: "
                                 f"{_key_list(schema, section)}", "type")
            for key, value in content.items():
                _known_key(schema, section, key, where)
                given.setdefault(section, {})[key] = (value, where)
    for item, (section, key, value) in zip(overrides, parsed, strict=True):
        where = f"(from --set {item})"
        _known_section(schema, section, where)
        _known_key(schema, section, key, where)
        given.setdefault(section, {})[key] = (value, where)

    scene = defaults(schema)
    for section, keys in given.items():
        for key, (value, where) in keys.items():
            fld = schema.field(section, key)
            name = f"{section}.{key}"
            try:
                converted = fld.convert(value)
            except TypeError as exc:
                raise SceneError(f"scene field {name} = {_show(value)} {where} has the wrong type: expected "
                                 f"{exc.args[0]}, got {_type_name(value)}; allowed: {fld.allowed}", "type") from None
            # TOML integers are unbounded; numpy, array sizes and the models take 64-bit ones
            fits = fld.type is not int or not isinstance(converted, int) or -_INT64_LIMIT <= converted < _INT64_LIMIT
            if not fits or not fld.valid(converted):
                limit = "" if fits else f" (and within 64-bit integers, at most {_INT64_LIMIT - 1} in size)"
                raise SceneError(f"scene field {name} = {_show(value)} {where} is out of range; allowed: "
                                 f"{fld.allowed}{limit}", "range")
            scene[section][key] = converted
    _check_constraints(schema.constraints, scene, "are not allowed together")
    return scene


def _parsed_override(item: str, path: str | Path | None) -> tuple[str, str, Any]:
    """:func:`parse_override`; when ``item`` lacks its value and the scene file named ``path`` does not exist,
    the error suggests the ``--set`` that puts them together (``--set section.key 1`` makes two arguments)."""
    try:
        return parse_override(item)
    except SceneError as exc:
        name, _, raw = item.partition("=")
        stray = str(path).lstrip("=").strip() if path is not None else ""
        if raw.strip() or not stray or Path(str(path)).exists() or "." not in name:
            raise
        raise SceneError(f"{exc}; did you mean --set {name.strip()}={stray}? ({str(path)!r} was read as the scene "
                         f"file)", exc.kind) from None


def _check_constraints(constraints: Iterable[Constraint], scene: dict[str, dict[str, Any]], verdict: str) -> None:
    """Raise :class:`SceneError` (``"constraint"``) naming the fields and values of the first constraint that fails."""
    for con in constraints:
        if not con.check(scene):
            values = ", ".join(f"{n} = {_show(scene[n.split('.')[0]][n.split('.')[1]])}" for n in con.fields)
            reason = f" ({con.reason})" if con.reason else ""
            noun = "field" if len(con.fields) == 1 else "fields"
            detail = f": {con.detail(scene)}" if con.detail is not None else ""
            raise SceneError(f"scene {noun} {values} {verdict}{detail}; allowed: {con.allowed}{reason}", "constraint")


def check_classifiable(model: Any, scene: dict[str, dict[str, Any]]) -> None:
    """Refuse a scene that the model can trace but not classify.

    A runner lists what a scene must satisfy to be classified in ``classify_requires`` (a sequence of
    :class:`Constraint`; none when absent).

    Raises
    ------
    SceneError
        Kind ``"constraint"``: one paragraph naming the fields, their values, what classification
        needs and why (the constraint's reason, which says what to run instead).
    """
    _check_constraints(getattr(model, "classify_requires", ()), scene, "cannot be classified")


def engine_failures() -> tuple[type[BaseException], ...]:
    """The engine's exceptions for a numerical failure that a runner let through instead of reporting it.

    The command line and the sweeps turn these into a failed run (exit status 1, a ``failure`` row),
    not an internal error.  Imported when called: the continuation core is not needed to read a scene.
    """
    import numpy as np

    from ..analyses.jump import JumpError
    from ..numerics.linalg import SingularMatrixError
    from ..palc import CorrectorFailure
    from ..problem import NonFiniteError

    return (CorrectorFailure, NonFiniteError, JumpError, SingularMatrixError, np.linalg.LinAlgError)


def wants_figure(scene: Mapping[str, Mapping[str, Any]]) -> bool:
    """Whether a run of ``scene`` should draw its diagram: the standard key ``output.figure``.

    A schema may declare ``[output] figure`` (a boolean); false means no figure file is written.
    Without that key the figure is always drawn.
    """
    return bool(scene.get("output", {}).get("figure", True))


def _type_name(value: Any) -> str:
    names = {bool: "a boolean", int: "an integer", float: "a float", str: "a string", list: "an array",
             dict: "a table"}
    return names.get(type(value), f"a {type(value).__name__}")


def _key_list(schema: Schema, section: str) -> str:
    return ", ".join(schema.sections[section]) or "(none)"


def _known_section(schema: Schema, section: str, where: str) -> None:
    if section not in schema.sections:
        raise SceneError(f"unknown scene section [{section}] {where}; allowed sections: "
                         f"{', '.join(f'[{s}]' for s in schema.sections)}", "unknown")


def _known_key(schema: Schema, section: str, key: str, where: str) -> None:
    if key not in schema.sections[section]:
        raise SceneError(f"unknown scene key {section}.{key} {where}; section [{section}] allows: "
                         f"{_key_list(schema, section)}", "unknown")


def format_toml_value(value: Any) -> str:
    """A scalar as TOML source text (``TypeError`` for anything else)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    raise TypeError(f"not a TOML scalar: {value!r}")


def schema_as_toml(schema: Schema, indent: str = "") -> str:
    """The default scene as commented TOML (each key with its meaning and allowed range)."""
    lines = []
    for section, keys in schema.sections.items():
        lines.append(f"{indent}[{section}]")
        width = max((len(k) + 3 + len(format_toml_value(f.default)) for k, f in keys.items()), default=0)
        for key, fld in keys.items():
            assignment = f"{key} = {format_toml_value(fld.default)}"
            note = f"{fld.help}; {fld.allowed}" if fld.help else fld.allowed
            lines.append(f"{indent}{assignment:<{width}}  # {note}")
    for con in schema.constraints:
        reason = f" ({con.reason})" if con.reason else ""
        lines.append(f"{indent}# requires {con.allowed}{reason}")
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------------
# what a model runner returns
# ---------------------------------------------------------------------------------------------------
#: Statuses of a branch that stopped because its step budget (``max_steps``) ran out: the engine calls it
#: ``"completed"`` (all the steps it was given are done); ``"max_steps"`` is accepted as the same.
BUDGET_STATUSES = ("completed", "max_steps")


@dataclass
class TraceResult:
    """Result of a scene run, in the form the command line writes out.

    Attributes
    ----------
    branches : list of Branch
        Traced branches, in the order they were traced.
    jumps : list of JumpResult
        Snaps between branches (may be empty).
    summary : dict
        Extra JSON fields for ``summary.json`` (e.g. a classification, closed-form references).  Strings listed
        under ``"warnings"`` (questionable but not failed, e.g. a strain beyond the material law) are
        repeated in :attr:`message`.
    special_points : list of dict
        JSON records of the special points: ``kind``, ``label``, ``branch``, ``parameter``, ``p``,
        ``observables``, ``residual``, ``located`` and, when known, ``stable_before``/``stable_after``.
    table : list of dict
        Rows of the special-point table printed after the run (keys are the column headers).
    csv_columns : dict of name -> 1-D array
        ``branch.csv``, one row per stored point, columns in insertion order.
    x, y : str
        Observables on the diagram's axes (``"p"`` for the parameter).
    parameter_name : str
        Label of the parameter (axis labels, JSON).
    labels : list of str
        Per-branch names (legend, messages).
    jump_observables : list of (dict, dict)
        Observables at the start and landing of each jump (for the arrows of the diagram).
    failure : str
        Non-empty when the runner itself gave up (e.g. a jump could not start); the run then counts
        as failed even if every branch succeeded.
    plot : callable, optional
        ``plot(ax)`` drawing the diagram in place of :meth:`draw`.
    stability : str, optional
        The stability label the diagram is styled by (stable solid, unstable dashed), e.g. the
        scene's control; default each branch's primary label.
    plot_options : dict
        Further keyword arguments of :func:`contin.plot_branches` for the diagram: ``axis_labels``
        (what the quantities on the axes are), ``note`` (a line in the corner), ``zero_line``,
        ``special_kinds``.
    shapes : dict of name -> array
        Arrays the model saves beside the run, written by the command line as ``shapes.npz`` (e.g.
        the deformed shape at every special point and the located modes); empty: no such file.
    draw_shapes : callable, optional
        ``draw_shapes(figure)`` draws :attr:`shapes` on an empty matplotlib Figure; the command line
        writes it as ``shapes.png`` (with the diagram, unless the scene turns figures off).
    jump_branches : list of (int, int or None)
        Per jump, the branch it leaves and the branch that starts at its landing (None: none), when the
        branches are not a quasi-static sweep's (jump ``j`` from branch ``j`` to branch ``j + 1``, the
        default when empty): what a restart from a jump's records reads.
    """

    branches: list[Branch]
    jumps: list[JumpResult] = field(default_factory=list)
    summary: dict[str, Any] = field(default_factory=dict)
    special_points: list[dict[str, Any]] = field(default_factory=list)
    table: list[dict[str, Any]] = field(default_factory=list)
    csv_columns: dict[str, np.ndarray] = field(default_factory=dict)
    x: str = "p"
    y: str | None = None
    parameter_name: str = "p"
    labels: list[str] = field(default_factory=list)
    jump_observables: list[tuple[dict[str, float], dict[str, float]]] = field(default_factory=list)
    failure: str = ""
    plot: Callable[[Any], Any] | None = None
    stability: str | None = None
    plot_options: dict[str, Any] = field(default_factory=dict)
    shapes: dict[str, np.ndarray] = field(default_factory=dict)
    draw_shapes: Callable[[Any], Any] | None = None
    jump_branches: list[tuple[int, int | None]] = field(default_factory=list)

    @classmethod
    def from_branches(cls, branches: Sequence[Branch], jumps: Sequence[JumpResult] = (), *, problem: Any = None,
                      x: str = "p", y: str | None = None, labels: Sequence[str] = (),
                      summary: Mapping[str, Any] | None = None, failure: str = "",
                      table_observables: Sequence[str] | None = None) -> "TraceResult":
        """Build a result whose records, table and CSV columns are derived from the branches.

        Parameters
        ----------
        branches, jumps : the traced branches and the snaps between them.
        problem : Problem, optional
            Used to evaluate the observables at the ends of the jumps.
        x, y : str
            Diagram axes.
        labels : sequence of str
            Branch names.
        summary : mapping, optional
            Extra JSON fields.
        failure : str
            Reason the runner stopped early, if it did.
        table_observables : sequence of str, optional
            Observables shown in the printed table (default: all).
        """
        branches = list(branches)
        jumps = list(jumps)
        pname = next((br.meta.get("parameter_name") for br in branches if br.meta.get("parameter_name")),
                     getattr(problem, "parameter_name", "p"))
        jump_obs = [(problem.evaluate_observables(j.u_from, j.p), problem.evaluate_observables(j.u_to, j.p))
                    if problem is not None else ({}, {}) for j in jumps]
        records = special_point_records(branches, jumps, jump_obs, pname)
        return cls(branches=branches, jumps=jumps, summary=dict(summary or {}), special_points=records,
                   table=special_point_table(records, pname, table_observables,
                                             branch_labels=list(labels) if len(branches) > 1 else None),
                   csv_columns=branch_columns(branches), x=x, y=y, parameter_name=pname,
                   labels=list(labels), jump_observables=jump_obs, failure=failure)

    def draw(self, ax: Any) -> Any:
        """The default diagram on the matplotlib Axes ``ax``: :func:`contin.plot_branches` of ``y`` against
        ``x`` styled by :attr:`stability`, folds marked by the quantity that folds, jumps as arrows,
        with :attr:`plot_options`.

        Returns
        -------
        matplotlib Axes
        """
        from ..plot.branches import plot_branches

        if not any(len(br) for br in self.branches):
            ax.text(0.5, 0.5, "no branch traced", ha="center", va="center", transform=ax.transAxes)
            return ax
        # plot_branches reads the parameter as "p": a branch stores it apart from its observables
        x = "p" if self.x == self.parameter_name else self.x
        y = "p" if self.y == self.parameter_name else self.y
        jumps = [(j, a, b) for j, (a, b) in zip(self.jumps, self.jump_observables)]
        return plot_branches(self.branches, x=x, y=y, ax=ax, jumps=jumps,
                             labels=self.labels if len(self.labels) == len(self.branches) else None,
                             stability=self.stability, **self.plot_options)

    # ---- overall outcome ---------------------------------------------------------------------------
    @property
    def complete(self) -> bool:
        """True when no branch stopped because its step budget ran out (:data:`BUDGET_STATUSES`).

        Every other planned end (a bound, a terminal event, a closed loop) is where the runner meant
        the branch to end; a spent budget is not, so the run did not reach the end of its path.
        """
        return not any(br.status in BUDGET_STATUSES for br in self.branches)

    @property
    def success(self) -> bool:
        """True when every branch reached its planned end, every jump landed, and the runner finished."""
        return (not self.failure and self.complete and all(br.success for br in self.branches)
                and all(j.success for j in self.jumps))

    @property
    def status(self) -> str:
        """``"ok"``, or the status of the first failure (``"min_step"``, ``"failed"``, ``"incomplete"``, ...)."""
        for br in self.branches:
            if not br.success and br.status not in BUDGET_STATUSES:
                return br.status
        if not self.complete:
            return "incomplete"
        if any(not j.success for j in self.jumps):
            return "jump_failed"
        return "failed" if self.failure else "ok"

    def _name(self, i: int) -> str:
        return self.labels[i] if i < len(self.labels) else (f"branch {i}" if len(self.branches) > 1 else "")

    @property
    def message(self) -> str:
        """One line per branch and jump, joined: why each ended (and which stopped short of its end)."""
        parts = []
        for i, br in enumerate(self.branches):
            name = self._name(i)
            parts.append(f"{name}: {br.message}" if name else br.message)
        for i, j in enumerate(self.jumps):
            parts.append(f"jump {i} at {self.parameter_name} = {j.p:.10g}: {j.message}")
        short = [self._name(i) or "the branch" for i, br in enumerate(self.branches) if br.status in BUDGET_STATUSES]
        if short:
            parts.append(f"incomplete: {', '.join(short)} stopped when the step limit (max_steps) was reached, before "
                         f"the end of the path")
        if self.failure:
            parts.append(self.failure)
        parts += [f"warning: {w}" for w in self.summary.get("warnings", [])]
        parts += [f"advice: {a}" for a in self.summary.get("advice", [])]
        return "; ".join(parts) if parts else "nothing traced"


@dataclass
class Classification:
    """Result of classifying one scene (``contin classify``).

    Attributes
    ----------
    label : str or None
        The class, e.g. ``"bistable"``; None when the run ended before the class could be decided.
    values : dict
        Machine-readable facts behind the label (JSON scalars or None), e.g. the extrema of the response
        and where they occur.  Printed by ``contin classify --json`` beside the standard fields.
    lines : list of str
        Human-readable lines printed under the label by ``contin classify``.
    trace : TraceResult, optional
        The run the classification was derived from (its branches give ``n_steps``, its status the
        reported status).
    failure : str
        Why the class could not be decided; non-empty means the command exits with status 1.
    """

    label: str | None
    values: dict[str, Any] = field(default_factory=dict)
    lines: list[str] = field(default_factory=list)
    trace: TraceResult | None = None
    failure: str = ""

    @property
    def complete(self) -> bool:
        """True when the run behind the class reached the end of its path (or there is no run to judge)."""
        return self.trace is None or self.trace.complete

    @property
    def success(self) -> bool:
        """True when a class was decided, nothing failed on the way and the run reached the end of its path.

        A class proved on part of a path (a cap seen bistable before its step limit) is still reported
        as :attr:`label`, but the run is not a success: the quantities read off the path (its snap loads,
        its folds) are those of the part traced, and the status says ``"incomplete"``.
        """
        return self.label is not None and not self.failure and self.complete

    @property
    def status(self) -> str:
        """``"ok"``, the failing run's status (``"incomplete"`` for a path cut short), or ``"failed"``."""
        if self.success:
            return "ok"
        if self.trace is not None and not self.trace.success:
            return self.trace.status
        return "failed"

    @property
    def message(self) -> str:
        """Why the classification failed (empty on success); includes the run's message when it failed."""
        if self.success:
            return ""
        parts = [self.failure] if self.failure else []
        if self.trace is not None and not self.trace.success:
            parts.append(self.trace.message)
        return "; ".join(parts) or "the class could not be decided"

    @property
    def n_steps(self) -> int:
        """Continuation steps of the underlying run (0 without one)."""
        if self.trace is None:
            return 0
        return int(sum(br.meta.get("n_steps", max(len(br) - 1, 0)) for br in self.trace.branches))


def _stability_fields(spt: SpecialPoint) -> dict[str, bool]:
    """``stable_before`` / ``stable_after`` of a special point, where known.

    Under the point's own stability label (:meth:`SpecialPoint.stability_under`), else as a model
    stated them in ``info`` (a point it located itself, without the engine's stability table).
    """
    known = spt.stability_under() or spt.info
    return {key: bool(known[key]) for key in ("stable_before", "stable_after") if known.get(key) is not None}


def special_label(spt: SpecialPoint) -> str:
    """The label a special point's record and table row carry: its own, but for a bifurcation into another
    mode the mode it goes into (``n = 3``: the family's name and the key, :mod:`contin.watch.modes`)."""
    if spt.kind == "bifurcation" and spt.info.get("key") is not None:
        return f"{spt.info.get('family', 'key')} = {spt.info['key']}"
    return spt.label


def special_point_records(branches: Sequence[Branch], jumps: Sequence[JumpResult] = (),
                          jump_observables: Sequence[tuple[dict, dict]] = (), parameter_name: str = "p", *,
                          fields: Callable[[SpecialPoint], Mapping[str, Any]] | None = None) -> list[dict[str, Any]]:
    """JSON records of the branches' special points, then two per jump (``jump_from``, ``jump_to``).

    Parameters
    ----------
    branches, jumps : the traced branches and the snaps between them.
    jump_observables : sequence of (dict, dict)
        Observables at the start and the landing of each jump.
    parameter_name : str
        The continuation parameter's name (``"parameter"`` of every record but declared limit points).
    fields : callable, optional
        ``fields(special_point) -> mapping`` of a model's own fields, added to each branch record.

    Returns
    -------
    list of dict
        A branch record has ``kind``, ``label``, ``branch``, ``parameter``, ``p``, ``observables``,
        ``residual``, ``located``, ``index`` (it lies between stored points ``index`` and ``index + 1``),
        ``s`` (its arclength along the branch), ``bracket_p`` and ``error`` where known, and ``stable_before`` /
        ``stable_after`` under the point's stability label.  An extremum event that declares a limit
        point (``contin.extremum(..., folds=...)``) is recorded as ``kind = "fold"`` with the quantity
        that folds as ``parameter``.  A bifurcation into another mode (:mod:`contin.watch.modes`) carries
        its key under its family's name (e.g. ``"n": 3``), ``also``, ``eigenvalue`` and
        ``next_eigenvalue``.
    """
    out: list[dict[str, Any]] = []
    for bi, br in enumerate(branches):
        for spt in br.special_points:
            declared = spt.kind == "event" and spt.info.get("folds") is not None
            rec: dict[str, Any] = {
                "kind": "fold" if declared else spt.kind, "label": special_label(spt), "branch": bi,
                "parameter": spt.info["folds"] if declared else parameter_name,
                "p": float(spt.p), "observables": {k: float(v) for k, v in spt.observables.items()},
                "residual": float(spt.residual), "located": bool(spt.located), "index": int(spt.index),
                "s": float(spt.s),
            }
            rec.update(_stability_fields(spt))
            if "bracket_p" in spt.info and spt.info["bracket_p"] is not None:
                rec["bracket_p"] = [float(v) for v in spt.info["bracket_p"]]
            if "error" in spt.info:
                rec["error"] = str(spt.info["error"])
            if spt.kind == "bifurcation":  # the mode it bifurcates into, under its family's name
                rec["family"] = str(spt.info.get("family", "key"))
                rec[rec["family"]] = spt.info.get("key")
                for name in ("also", "eigenvalue", "next_eigenvalue"):
                    if spt.info.get(name) is not None:
                        rec[name] = spt.info[name]
            if fields is not None:
                rec.update(fields(spt))
            out.append(rec)
    for ji, j in enumerate(jumps):
        obs_from, obs_to = jump_observables[ji] if ji < len(jump_observables) else ({}, {})
        base = {"kind": "jump", "jump": ji, "parameter": parameter_name, "p": float(j.p)}
        out.append({**base, "label": "jump_from", "observables": dict(obs_from), "residual": None,
                    "located": True, "energy": float(j.energy_from)})
        out.append({**base, "label": "jump_to", "observables": dict(obs_to), "residual": float(j.residual),
                    "located": bool(j.success), "energy": float(j.energy_to), "stable": bool(j.n_negative == 0),
                    "message": j.message})
    return out


def first_instability(records: Sequence[Mapping[str, Any]], parameter: str, fields: Sequence[str] = (),
                      branch: int = 0) -> dict[str, Any] | None:
    """Where a path first loses stability under its control: its first fold in ``parameter`` or its first
    bifurcation into another mode (:mod:`contin.watch.modes`), whichever comes first along the branch.

    Parameters
    ----------
    records : special-point records of :func:`special_point_records` (in path order per branch).
    parameter : str
        The control's parameter: a fold in it is where the controlled path turns back.
    fields : sequence of str
        Observables (or record fields) to copy into the result.
    branch : int
        The branch (0: the path from the start).

    Returns
    -------
    dict or None
        ``kind`` (``"fold"`` or ``"bifurcation"``), the family's key for a bifurcation (e.g. ``"n"``;
        None for a fold), ``p`` and the requested fields; None when the branch has neither.
    """
    for rec in records:
        if rec.get("branch", 0) != branch or not rec.get("located", True):
            continue
        fold = rec["kind"] == "fold" and rec.get("parameter") == parameter
        if not (fold or rec["kind"] == "bifurcation"):
            continue
        out: dict[str, Any] = {"kind": rec["kind"], "p": rec["p"], "label": rec.get("label")}
        if rec["kind"] == "bifurcation":
            out["family"] = rec.get("family")
            out[str(rec.get("family"))] = rec.get(str(rec.get("family")))
        for name in fields:
            value = rec.get(name, rec.get("observables", {}).get(name))
            out[name] = value
        return out
    return None


def special_point_table(records: Sequence[Mapping[str, Any]], parameter_name: str = "p",
                        observables: Sequence[str] | None = None,
                        branch_labels: Sequence[str] | None = None, *,
                        columns: Mapping[str, str] | None = None) -> list[dict[str, Any]]:
    """Printable rows (column header -> value) for special-point records.

    Parameters
    ----------
    records : sequence of mapping
        Records as :func:`special_point_records` makes them (a model may have added fields).
    parameter_name : str
        Header of the parameter column (``rec["p"]``).
    observables : sequence of str, optional
        Observables shown after the parameter (default: every observable of the record).
    branch_labels : sequence of str, optional
        Branch names: a first column ``on`` names the branch (or jump) of each point.
    columns : mapping of str to str, optional
        Header -> record field, in this order, in place of the parameter and observable columns.  A
        field is looked up among the record's own fields, then among its ``observables``; e.g.
        ``{"folds_in": "parameter", "w/R": "w_over_R"}`` shows which quantity folds and a normalized
        observable.  Missing fields show as None.

    Returns
    -------
    list of dict
        ``[on,] kind, label``, the parameter and observables (or ``columns``), ``residual``, ``located``
        and ``stability``: for a jump's record its own ``stable`` (the landing), for any other point
        ``stable_before -> stable_after`` followed by the control it is labelled under, in
        parentheses, when the record names one (``stability_control``).
    """
    word = {True: "stable", False: "unstable", None: "?"}
    rows = []
    for rec in records:
        obs = rec.get("observables", {})
        if rec["kind"] == "jump":
            # a jump is one state at one load: its landing's stability, not a change along a branch
            stab = word[rec["stable"]] if "stable" in rec else ""
        else:
            before, after = rec.get("stable_before"), rec.get("stable_after")
            stab = "" if before is None and after is None else f"{word[before]} -> {word[after]}"
            if stab and rec.get("stability_control"):
                stab += f" ({rec['stability_control']})"
        row: dict[str, Any] = {}
        if branch_labels is not None:
            if "jump" in rec:
                row["on"] = f"jump {rec['jump']}"
            else:
                bi = rec.get("branch", 0)
                row["on"] = branch_labels[bi] if bi < len(branch_labels) else f"branch {bi}"
        row.update({"kind": rec["kind"], "label": rec.get("label", "")})
        if columns is not None:
            row.update({head: rec[name] if name in rec else obs.get(name) for head, name in columns.items()})
        else:
            names = list(obs) if observables is None else [n for n in observables if n in obs]
            row[parameter_name] = rec["p"]
            row.update({n: obs[n] for n in names})
        row["residual"] = rec.get("residual")
        row["located"] = "yes" if rec.get("located") else "no"
        row["stability"] = stab
        rows.append(row)
    return rows


def _or_nan(values: np.ndarray | None, n: int) -> np.ndarray:
    import numpy as np

    return values if values is not None else np.full(n, np.nan)


def branch_columns(branches: Sequence[Branch],
                   stability_columns: Mapping[str, str] | None = None) -> dict[str, np.ndarray]:
    """CSV columns: one row per stored point of every branch.

    Parameters
    ----------
    branches : sequence of Branch
    stability_columns : mapping of str to str, optional
        Stability columns by name, each taken from :meth:`Branch.columns` (``stable_<label>`` or
        ``n_negative_<label>``), in this order, in place of the primary label's ``stable`` and
        ``n_negative``; e.g. ``{"stable_force": "stable_force", "n_negative": "n_negative_displacement"}``.
        Left out when some branch has no such column.

    Returns
    -------
    dict of str to ndarray
        ``branch``, ``p``, every observable, ``s``, ``residual``, ``tangent_p`` and ``tangent_<name>``
        (``d/ds`` of the parameter and of the observables that have it, :attr:`Branch.tangents`; empty
        where unknown) and, when any branch has stability
        data (and ``stability_columns`` is not given), ``stable`` (1/0) and ``n_negative`` (integers;
        floats with NaN where some branch has no stability data).
    """
    import numpy as np

    cols: dict[str, np.ndarray] = {}
    if not branches:
        return {"branch": np.zeros(0, dtype=int), "p": np.zeros(0)}
    cols["branch"] = np.concatenate([np.full(len(br), i, dtype=int) for i, br in enumerate(branches)])
    cols["p"] = np.concatenate([br.p for br in branches])
    names: list[str] = []
    for br in branches:
        names += [n for n in br.observables if n not in names and n != "p"]
    for name in names:
        cols[name] = np.concatenate([br.observables.get(name, np.full(len(br), np.nan)) for br in branches])
    cols["s"] = np.concatenate([br.s for br in branches])
    cols["residual"] = np.concatenate([br.residual for br in branches])
    # the path's direction at every point (d/ds of the parameter and of the observables that have it):
    # 'contin plot' draws the saved branches smooth from them
    cols["tangent_p"] = np.concatenate([br.tangent_p if br.tangent_p.shape == br.p.shape else np.full(len(br), np.nan)
                                        for br in branches])
    for name in names:
        if any(br.tangent(name) is not None for br in branches):
            cols[f"tangent_{name}"] = np.concatenate([_or_nan(br.tangent(name), len(br)) for br in branches])
    if stability_columns is not None:
        per_branch = [br.columns() for br in branches]
        for name, column in stability_columns.items():
            if all(column in c for c in per_branch):
                cols[name] = np.concatenate([c[column] for c in per_branch])
    elif all(br.n_negative is not None for br in branches):
        nneg_int = np.concatenate([br.n_negative for br in branches]).astype(int)
        cols["stable"] = (nneg_int == 0).astype(int)
        cols["n_negative"] = nneg_int
    elif any(br.n_negative is not None for br in branches):
        nneg = np.concatenate([br.n_negative.astype(float) if br.n_negative is not None else np.full(len(br), np.nan)
                               for br in branches])
        cols["stable"] = np.where(np.isnan(nneg), np.nan, (nneg == 0).astype(float))
        cols["n_negative"] = nneg
    cols.update(_mode_columns(branches))
    return cols


def _mode_columns(branches: Sequence[Branch]) -> dict[str, np.ndarray]:
    """Per watched operator family (:mod:`contin.watch.modes`): ``n_negative_<name>``, the Morse index of all its
    operators (each counted with its multiplicity); ``critical_<name>``, the smallest key with a negative
    eigenvalue, or where there is none the key whose eigenvalue nearest zero is smallest (a key that is not a
    number as its text, a tuple's parts separated by blanks); and
    ``lowest_<name>``, that key's eigenvalue nearest zero (NaN on a branch that did not watch the family)."""
    import numpy as np

    names: list[str] = []
    for br in branches:
        names += [n for n in br.meta.get("modes", {}) if n not in names]
    out: dict[str, np.ndarray] = {}
    for name in names:
        total, critical, lowest = [], [], []
        for br in branches:
            fam = br.meta.get("modes", {}).get(name)
            if fam is None or len(fam["n_negative"]) != len(br):
                for col in (total, critical, lowest):
                    col.append(np.full(len(br), np.nan))
                continue
            counts = np.asarray(fam["n_negative"], dtype=float).reshape(len(br), len(fam["keys"]))
            lows = np.asarray(fam.get("lowest", np.full(counts.shape, np.nan)), dtype=float).reshape(counts.shape)
            mult = np.asarray(fam.get("multiplicity", [1] * len(fam["keys"])), dtype=float)
            keys = _key_column(fam["keys"])
            total.append(counts @ mult)
            unstable = np.argmax(counts > 0, axis=1)  # the first key with a negative eigenvalue
            any_negative = (counts > 0).any(axis=1)
            finite = np.where(np.isfinite(lows), lows, np.inf)
            stable_pick = np.argmin(finite, axis=1)
            pick = np.where(any_negative, unstable, stable_pick)
            rows = np.arange(len(br))
            picked = lows[rows, pick]
            ok = any_negative | np.isfinite(finite[rows, stable_pick])
            critical.append(np.where(ok, keys[pick], np.nan if keys.dtype != object else ""))
            lowest.append(np.where(ok, picked, np.nan))
        out[f"n_negative_{name}"] = np.concatenate(total)
        out[f"critical_{name}"] = np.concatenate(critical)
        out[f"lowest_{name}"] = np.concatenate(lowest)
    return out


def _key_column(keys: Sequence[Any]) -> Any:
    """A family's keys as a column's values: numbers as floats, any other key (a tuple, a name) as its text."""
    import numpy as np

    try:
        return np.asarray(keys, dtype=float).reshape(len(keys))
    except (TypeError, ValueError):
        # a tuple's parts separated by blanks: the text goes into a CSV cell
        return np.array([" ".join(map(str, k)) if isinstance(k, (list, tuple)) else str(k) for k in keys], dtype=object)


# ---------------------------------------------------------------------------------------------------
# the runner protocol
# ---------------------------------------------------------------------------------------------------
@runtime_checkable
class ModelRunner(Protocol):
    """What a ``contin.models`` entry point resolves to (or what a zero-argument factory returns)."""

    name: str
    description: str
    schema: Schema

    def run(self, scene: dict[str, dict[str, Any]], progress: bool) -> TraceResult:
        """Trace the resolved ``scene``; print progress to stderr only when ``progress``."""
        ...


@runtime_checkable
class Resumer(Protocol):
    """The optional restart capability of a runner (``contin trace --from OUT --label K``, :mod:`contin.app.restart`).

    A runner that has it may also list, as ``restart_fixed``, the ``section.key`` names of the scene keys
    that fix the structure of its unknowns (a restart refuses a ``--set`` that changes one).
    """

    def resume(self, scene: dict[str, dict[str, Any]], start: Any, progress: bool) -> TraceResult:
        """Continue from ``start`` (a :class:`contin.app.restart.Start`: the saved state, parameter and direction) with
        the resolved ``scene`` (the saved one updated by ``--set``); progress to stderr only when ``progress``."""
        ...


@runtime_checkable
class Classifier(Protocol):
    """The optional classification capability of a runner (``contin classify``)."""

    def classify(self, scene: dict[str, dict[str, Any]], progress: bool) -> Classification:
        """Run what the resolved ``scene`` needs to be classified; progress to stderr only when ``progress``."""
        ...


def can_classify(model: Any) -> bool:
    """Whether a runner offers classification.

    A runner can classify when it has a callable ``classify``, unless it says otherwise through a
    false ``can_classify`` attribute (as a :class:`SceneModel` without a ``classifier`` does).
    """
    flag = getattr(model, "can_classify", None)
    if flag is not None and not callable(flag):
        return bool(flag)
    return callable(getattr(model, "classify", None))


@dataclass(frozen=True)
class SceneModel:
    """A ready-made :class:`ModelRunner`: name, description, schema, a run function and, optionally, a classifier.

    Attributes
    ----------
    name : str
    description : str
        One line shown by ``contin models``.
    schema : Schema
    runner : callable ``(scene, progress) -> TraceResult``
    classifier : callable ``(scene, progress) -> Classification``, optional
        What ``contin classify`` calls; without it the model cannot classify.
    classify_requires : sequence of Constraint
        What a scene must satisfy to be classified (:func:`check_classifiable`); each constraint's
        ``reason`` says why and what to run instead.  :meth:`classify` refuses other scenes.
    default : bool
        This is the model the command line uses when none is named (:func:`contin.app.registry.default_model`;
        exactly one registered model should say so).
    examples : mapping
        Command (``"trace"``, ``"classify"``, ``"models"``) to pairs of (arguments after the command,
        comment), shown in the command line's help.
    help : mapping
        Command to a paragraph on what the command does for this model, shown in its help.
    resumer : callable ``(scene, start, progress) -> TraceResult``, optional
        What ``contin trace --from OUT --label K`` calls (:class:`Resumer`); without it the model cannot restart.
    restart_fixed : sequence of str
        Scene keys (``section.key``) that a restart keeps: they fix the structure of the saved state.
    forecast : callable ``(scene) -> str or None``, optional
        A warning about what running a resolved scene will cost (e.g. roughly how long a very fine mesh
        takes, and why), said by the command line before it traces or classifies the scene; None when
        there is nothing to say.
    """

    name: str
    description: str
    schema: Schema
    runner: Callable[[dict[str, dict[str, Any]], bool], TraceResult]
    classifier: Callable[[dict[str, dict[str, Any]], bool], Classification] | None = None
    classify_requires: Sequence[Constraint] = ()
    default: bool = False
    examples: Mapping[str, Sequence[tuple[str, str]]] = field(default_factory=dict)
    help: Mapping[str, str] = field(default_factory=dict)
    resumer: Callable[[dict[str, dict[str, Any]], Any, bool], TraceResult] | None = None
    restart_fixed: Sequence[str] = ()
    forecast: Callable[[dict[str, dict[str, Any]]], str | None] | None = None

    @property
    def can_resume(self) -> bool:
        """Whether :meth:`resume` is available."""
        return self.resumer is not None

    def resume(self, scene: dict[str, dict[str, Any]], start: Any, progress: bool) -> TraceResult:
        """Continue from a saved point (:class:`Resumer`); ``NotImplementedError`` without a ``resumer``."""
        if self.resumer is None:
            raise NotImplementedError(f"model {self.name!r} cannot restart from a saved point")
        return self.resumer(scene, start, progress)

    @property
    def can_classify(self) -> bool:
        """Whether :meth:`classify` is available."""
        return self.classifier is not None

    def run(self, scene: dict[str, dict[str, Any]], progress: bool) -> TraceResult:
        """Trace the resolved scene."""
        return self.runner(scene, progress)

    def classify(self, scene: dict[str, dict[str, Any]], progress: bool) -> Classification:
        """Classify the resolved scene.

        Raises
        ------
        NotImplementedError
            If the model has no classifier (check :attr:`can_classify` first).
        SceneError
            If the scene fails one of :attr:`classify_requires`.
        """
        if self.classifier is None:
            raise NotImplementedError(f"model {self.name!r} cannot classify a scene")
        check_classifiable(self, scene)
        return self.classifier(scene, progress)
