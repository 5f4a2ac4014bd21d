"""The ``contin`` command: trace or classify a model's scene, list the models and their scene keys.

Commands
--------
``contin trace [SCENE.toml] [--model NAME] [--set section.key=value ...] [--out DIR] [--quiet]``
    Trace the scene and write ``summary.json``, ``branch.csv``, ``diagram.png`` and ``states.npz`` into DIR.
``contin trace --from OUT --label K [--set section.key=value ...] [--out DIR]``
    Restart from a point saved by an earlier run (:mod:`contin.app.restart`).
``contin classify [SCENE.toml] [--model NAME] [--set section.key=value ...] [--json] [--quiet]``
    Run what the model needs to classify the scene and print the class (``--json``: a JSON object).
``contin classify ... --sweep section.key=SPEC [--sweep ...] [--csv PATH] [--workers N | --scheduler ADDR] [--no-resume]``
    Classify every combination of the swept values (SPEC: ``0.6,0.8,1.0``, ``start:stop:count`` or
    ``log:start:stop:count``) in parallel worker processes (``--workers 1``: in this process;
    ``--scheduler``: on a Dask cluster, see :mod:`contin.app.executors`), appending one row per finished
    combination to PATH (default ``classify_sweep.csv``); a rerun reuses the rows already there (see
    :mod:`contin.app.sweep`).  Prints a table of the combinations (``--json``: a JSON list).
``contin models [NAME ...] [--toml]``
    List the registered models with every scene key, its default and its allowed range.

Models are found only through :mod:`contin.app.registry` (the ``contin.models`` entry-point group; the
engine never imports a model), and this module names none: the default model (the one whose runner
says ``default = True``), the examples and the model-specific help come from the registered runners.
An entry point resolves to a :class:`contin.app.scene.ModelRunner` (or a zero-argument factory returning
one); a runner that also has the classification capability (:func:`contin.app.scene.can_classify`) can
be used by ``contin classify``, for the scenes its ``classify_requires`` admit.

Exit status: 0 success, 1 the run failed (numerically, or it stopped at its step limit before the end
of its path, or the class could not be decided, for a sweep: of any combination; the outputs of
``trace`` are still written), 2 bad input (scene, ``--set``, ``--sweep``, unknown model, a model or
scene that cannot be classified, unwritable output directory, a sweep CSV that belongs to another
sweep, a Dask scheduler that cannot be used), 130 interrupted (a sweep's CSV keeps the finished rows;
an output directory the run made and wrote nothing into is removed).  No command prints a traceback
(set ``CONTIN_TRACEBACK=1`` to see one for an internal error).
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import os
import sys
import textwrap
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

# Only light modules here: 'contin --help', 'contin trace --help' and a refused scene import no numpy, scipy
# or matplotlib (tests/test_startup.py).  The engine, the sweeps and the executors are imported by the
# commands that use them.
from .. import __version__
from ..results.io import LINE_WIDTH, FileWriter, OutputDirectory, OutputError, atomic_write, json_ready, status_text
from . import registry
from .registry import ENTRY_POINT_GROUP, ModelNotFound, registered_models
from .scene import (Classification, ModelRunner, SceneError, TraceResult, can_classify, engine_failures,
                    format_toml_value, load_scene, schema_as_toml, wants_figure)

if TYPE_CHECKING:
    import numpy as np

__all__ = ["main", "DEFAULT_SWEEP_CSV", "ENTRY_POINT_GROUP", "CliError", "registered_models", "load_model",
           "summary_document", "classification_document", "write_outputs", "format_table"]

OUTPUT_FILES = ("summary.json", "branch.csv", "diagram.png", "diagram.pdf", "shapes.npz", "shapes.png", "shapes.pdf",
                "states.npz")
#: Results file of ``contin classify --sweep`` when ``--csv`` is not given (in the current directory).
DEFAULT_SWEEP_CSV = "classify_sweep.csv"
#: Where the help texts name the default model and list the models' examples (filled in only when a
#: help text is printed: that loads the models).
_DEFAULT = "{default_model}"


class CliError(Exception):
    """A user error: printed as one paragraph after ``contin: error:``, exit status 2."""


class _ArgumentParser(argparse.ArgumentParser):
    # argparse would print usage and call sys.exit; the contract is one paragraph and main() returning 2
    def error(self, message: str) -> None:  # type: ignore[override]
        raise CliError(f"{message} (see '{self.prog} --help')")


# ---------------------------------------------------------------------------------------------------
# models (through contin.app.registry)
# ---------------------------------------------------------------------------------------------------
def load_model(name: str) -> ModelRunner:
    """Load the runner registered as ``name`` (:func:`contin.app.registry.load_model`).

    Raises
    ------
    CliError
        If no such model is registered or its entry point does not load a runner.
    """
    try:
        return registry.load_model(name)
    except ModelNotFound as exc:
        raise CliError(str(exc)) from None


def _model_name(args: argparse.Namespace) -> str:
    """The model a command runs: ``--model``, else the registered default."""
    if args.model is not None:
        return args.model
    name = registry.default_model()
    if name is None:
        raise CliError(f"no default model is registered; choose one with --model NAME (registered: "
                       f"{', '.join(registered_models()) or 'none'}; see 'contin models')")
    return name


# ---------------------------------------------------------------------------------------------------
# help texts: what names a model comes from the registered models, when a help text is printed
# ---------------------------------------------------------------------------------------------------
def _exit_status(failed: str, bad: str) -> str:
    return textwrap.fill(f"exit status: 0 success, 1 {failed}, 2 bad input ({bad}), 130 interrupted. Errors are one "
                         f"paragraph on stderr, never a traceback.", width=95)


def _example(command: str, args: str, comment: str) -> str:
    line = f"  contin {command}{' ' + args if args else ''}"
    return f"{line:<47}  # {comment}" if comment else line


def _loaded_models() -> dict[str, Any]:
    """Every registered model that loads, by name (one that does not is left out of the help)."""
    found = {}
    for name in registered_models():
        try:
            found[name] = registry.load_model(name)
        except ModelNotFound:
            continue
    return found


def _examples(command: str) -> str:
    """The examples of ``contin COMMAND``: the default scene, then each model's own (``--model`` where needed)."""
    default = registry.default_model()
    lines = ["examples:"]
    if default is not None:
        lines.append(_example(command, "", f"the default model ({default}) at its default scene"))
    models = _loaded_models()
    # the default model's examples first: they need no --model
    for name in sorted(models, key=lambda n: n != default):
        for args, comment in registry.model_examples(models[name], command):
            lines.append(_example(command, args if name == default else f"--model {name} {args}".rstrip(), comment))
    lines.append(_example("models", "", "the models and all their scene keys"))
    return "\n".join(lines)


def _models_examples() -> str:
    name = registry.default_model() or "NAME"
    return "\n".join(["examples:", _example("models", "", "every model"),
                      _example("models", name, "one model's keys"),
                      _example("models", f"{name} --toml > scene.toml", "a scene file to edit, for SCENE.toml")])


def _model_help(command: str) -> str:
    """What ``command`` does for each model that says so (its ``help``), one paragraph per model."""
    parts = []
    for name, model in _loaded_models().items():
        text = (getattr(model, "help", None) or {}).get(command)  # a runner's help; a SceneModel's is a mapping
        if text:
            parts.append(textwrap.fill(f"{name}: {text}", width=95, subsequent_indent="  "))
    return "\n" + "\n".join(parts) if parts else ""


def _default_keys_help() -> str:
    """The default model's scene keys with their defaults, for the help texts (never raises)."""
    name = registry.default_model()
    try:
        model = registry.load_model(name) if name is not None else None
    except ModelNotFound:
        model = None
    if model is None:
        return "scene keys: 'contin models' lists every model's keys with defaults and allowed ranges."
    lines = [f"scene keys of the default model ({name}), with their defaults; "
             f"'contin models {name}' shows their allowed ranges:"]
    width = max(len(sec) for sec in model.schema.sections) + 2
    for section, keys in model.schema.sections.items():
        body = ", ".join(f"{k} = {format_toml_value(f.default)}" for k, f in keys.items())
        lines.append(textwrap.fill(body, width=100, initial_indent=f"  {'[' + section + ']':<{width}}  ",
                                   subsequent_indent=" " * (width + 4)))
    return "\n".join(lines)


def _default_line() -> str:
    name = registry.default_model()
    if name is None:
        return "No default model is registered: give --model NAME ('contin models' lists them)."
    try:
        description = registry.load_model(name).description
    except ModelNotFound:
        description = "it does not load; see 'contin models'"
    return textwrap.fill(f"Without --model, trace and classify use the default model '{name}': {description}.",
                         width=95)


def _sweep_syntax() -> str:
    from .sweep import SWEEP_SYNTAX

    return SWEEP_SYNTAX


#: Placeholders of the help texts and what fills them (each called only when its text is printed).
_PLACEHOLDERS: dict[str, Callable[[], str]] = {
    "{keys}": _default_keys_help,
    "{default_line}": _default_line,
    "{trace_examples}": lambda: _examples("trace"),
    "{classify_examples}": lambda: _examples("classify"),
    "{models_examples}": _models_examples,
    "{sweep_syntax}": lambda: textwrap.fill(_sweep_syntax() + ".", width=95, initial_indent="  ",
                                            subsequent_indent="  "),
    "{trace_models}": lambda: _model_help("trace"),
    "{classify_models}": lambda: _model_help("classify"),
    _DEFAULT: lambda: registry.default_model() or "none registered",
}


class _LazyHelpFormatter(argparse.RawDescriptionHelpFormatter):
    # the help names models: load them only when a help text is actually printed
    def add_text(self, text: str | None) -> None:
        super().add_text(_fill_placeholders(text))

    def _get_help_string(self, action: argparse.Action) -> str | None:
        return _fill_placeholders(action.help)


def _fill_placeholders(text: str | None) -> str | None:
    if text:
        for mark, fill in _PLACEHOLDERS.items():
            if mark in text:
                text = text.replace(mark, fill())
    return text


_TRACE_EPILOG = f"""\
outputs (in DIR):
  summary.json   the resolved scene, the classification (where the model has one), the special
                 points (kind, parameter, position, stability on both sides, residual), status,
                 whether the path was completed, wall time, number of steps
  branch.csv     one row per converged point: parameter, observables, residual, stability
  diagram.png    the bifurcation diagram (stable solid, unstable dashed, special points marked);
                 not written when the scene sets output.figure = false; with --pdf (or the scene
                 key output.pdf = true) also diagram.pdf, and shapes.pdf beside shapes.png
  shapes.npz     where the model saves them: the shape at every special point and the located
                 modes (read with numpy.load; the model's help names the arrays), drawn in
                 shapes.png (a model may save more on request: its help says how)
  states.npz     the state, parameter and direction at every special point and branch end: what
                 'contin trace --from DIR --label K' restarts from (K: the # column of the table,
                 or end)
The table of special points and a status line are printed on stdout, progress on stderr. A run
that stops before the end of its path (its step limit, max_steps, was reached) has the status
'incomplete' and exits with 1; its outputs are written.
{{trace_models}}

{_exit_status("the run failed numerically or stopped before its end (the outputs are still written)",
              "scene, --set, model, output directory")}

{{keys}}

{{trace_examples}}
"""

_CLASSIFY_EPILOG = f"""\
The model decides what has to be run, and which scenes it can classify (others are refused with
exit status 2). Printed: the class and the values behind it. --json prints the same as one JSON
object (with the resolved scene, the status, the wall time and the number of steps). Only a sweep
writes a file. Models without a classification are rejected with exit status 2.
{{classify_models}}

sweeps (--sweep SECTION.KEY=SPEC, repeatable):
{{sweep_syntax}}
  Every combination (first --sweep slowest) is resolved and checked like a --set scene before
  anything runs, then classified in --workers processes (default: one per CPU; 1 runs them in
  this process) or, with --scheduler ADDRESS, on a Dask cluster (pip install 'contin[dask]';
  start it with 'dask scheduler' and 'dask worker ADDRESS --nthreads 1'). The rows are the same
  whichever runs them. Each finished combination is appended at once to the CSV (--csv, default
  ./classify_sweep.csv): the swept keys, label (the class), the model's values, wall_time_s,
  failure (empty when classified) and scene (the resolved scene as JSON). Run the same command
  again after an interrupt and the rows already in the CSV are reused; a CSV of another sweep
  (other keys or another fixed scene) is refused, --no-resume overwrites it. Progress is one line
  per combination on stderr. At the end a table is printed: the swept values, the class, the
  normalized values (names ending in _norm) and the time; --json prints the rows as a JSON list
  instead.

{_exit_status("the run failed or the class could not be decided (a sweep: for any combination)",
              "scene, --set, --sweep, model, a model or scene that cannot be classified, a CSV of "
              "another sweep, a Dask scheduler that cannot be used")}

{{keys}}

{{classify_examples}}
"""


def _add_scene_arguments(parser: argparse.ArgumentParser, verb: str) -> None:
    """Arguments shared by the commands that resolve a scene (``trace``, ``classify``)."""
    parser.add_argument("scene", nargs="?", metavar="SCENE.toml",
                        help="scene file (TOML; 'contin models NAME --toml' prints a template); default: the "
                             "model's defaults")
    parser.add_argument("-m", "--model", metavar="NAME", default=None,
                        help=f"registered model to {verb} (default: {_DEFAULT}; list them with 'contin models')")
    parser.add_argument("-s", "--set", dest="overrides", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one scene key; VALUE is read as TOML (1e-8, true, \"text\"), else as a "
                             "bare string; may be repeated; the keys are listed below and by 'contin models'")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress lines on stderr")


def _add_trace_command(sub: argparse._SubParsersAction) -> None:
    """Add ``contin trace`` (its scene arguments and ``--out``) to the sub-commands ``sub``."""
    trace = sub.add_parser(
        "trace", help="trace a scene and write summary.json, branch.csv and diagram.png",
        formatter_class=_LazyHelpFormatter, epilog=_TRACE_EPILOG,
        description="Trace the scene of a model.\n\n"
                    "The scene is the model's defaults, updated by the optional TOML file SCENE.toml and\n"
                    "then by each --set, in order. It is validated completely before anything runs.")
    _add_scene_arguments(trace, "trace")
    trace.add_argument("-o", "--out", metavar="DIR", default="out", help="output directory (default: ./out)")
    trace.add_argument("--pdf", action="store_true",
                       help="also write the figures as PDF (diagram.pdf, shapes.pdf; the scene key output.pdf "
                            "where the model has one)")
    trace.add_argument("--from", dest="restart_from", metavar="OUT", default=None,
                       help="restart from a point saved by an earlier run in OUT (its states.npz), with its scene "
                            "updated by each --set (not SCENE.toml); needs --label")
    trace.add_argument("--label", metavar="K", default=None,
                       help="with --from: the saved point, the number in the # column of the special-point table, "
                            "'end' (the end of the first branch, 'end:B' of branch B) or a unique label")


def _add_classify_command(sub: argparse._SubParsersAction) -> None:
    """Add ``contin classify`` (its scene arguments, ``--json`` and the sweep options) to ``sub``."""
    classify = sub.add_parser(
        "classify", help="classify a scene (the model defines the classes) and print why",
        formatter_class=_LazyHelpFormatter, epilog=_CLASSIFY_EPILOG,
        description="Classify the scene of a model that can classify.\n\n"
                    "The scene is resolved as for 'contin trace' (defaults, SCENE.toml, each --set).")
    _add_scene_arguments(classify, "classify")
    classify.add_argument("--json", action="store_true",
                          help="print the result as one JSON object on stdout (a sweep: a JSON list of rows)")
    classify.add_argument("--sweep", action="append", default=[], metavar="SECTION.KEY=SPEC",
                          help="classify every combination of the values of this key with those of the other "
                               "--sweep keys; SPEC: 0.6,0.8,1.0 or start:stop:count or log:start:stop:count; "
                               "may be repeated")
    classify.add_argument("--csv", metavar="PATH", default=None,
                          help=f"with --sweep: the results file, one row per combination, appended as each "
                               f"finishes and reused by a rerun (default: ./{DEFAULT_SWEEP_CSV})")
    classify.add_argument("-j", "--workers", metavar="N", type=int, default=None,
                          help="with --sweep: worker processes (default: one per CPU; 1 runs in this process)")
    classify.add_argument("--scheduler", metavar="ADDRESS", default=None,
                          help="with --sweep: run on the Dask cluster of this scheduler (tcp://HOST:8786; "
                               "needs pip install 'contin[dask]'); not with --workers")
    classify.add_argument("--no-resume", action="store_true",
                          help="with --sweep: recompute every combination, overwriting the CSV")


def _add_models_command(sub: argparse._SubParsersAction) -> None:
    """Add ``contin models`` (the model names and ``--toml``) to the sub-commands ``sub``."""
    models = sub.add_parser(
        "models", help="list the registered models with their scene keys, defaults and allowed ranges",
        formatter_class=_LazyHelpFormatter,
        description="List the models registered in the 'contin.models' entry-point group, each with what it\n"
                    "can do (trace, classify) and its scene as commented TOML: every key, its default and\n"
                    "its allowed range.",
        epilog="{models_examples}")
    models.add_argument("names", nargs="*", metavar="NAME", help="only these models")
    models.add_argument("--toml", action="store_true",
                        help="print only the scene of one model (default: the default model) as a TOML file")


def _add_plot_command(sub: argparse._SubParsersAction) -> None:
    """Add ``contin plot`` (saved runs, ``--out``, the axes) to the sub-commands ``sub``."""
    plot = sub.add_parser(
        "plot", help="draw saved runs again, or several of them overlaid, without recomputing",
        description="Draw the output directories of 'contin trace' again: one run re-draws its diagram (or "
                    "another pair of quantities with -x / -y), several are overlaid in one figure, one colour "
                    "per run.  Stable parts solid, unstable dashed, special points marked, as 'contin trace' "
                    "draws them.")
    plot.add_argument("runs", nargs="+", metavar="OUT", help="output directory of a 'contin trace' run")
    plot.add_argument("-o", "--out", metavar="FILE", default=None,
                      help="the figure to write, PNG or PDF by its suffix (default: OUT/diagram.png for one run, "
                           "./overlay.png for several)")
    plot.add_argument("--pdf", action="store_true", help="also write the figure as PDF beside the PNG")
    plot.add_argument("-x", metavar="NAME", default=None, help="quantity on the x axis (default: the run's own)")
    plot.add_argument("-y", metavar="NAME", default=None, help="quantity on the y axis (default: the run's own)")


def _build_parser() -> _ArgumentParser:
    """The parser of the ``contin`` command: the top-level options and one sub-parser per command.

    Returns
    -------
    _ArgumentParser
        The parser; the sub-commands are added in the order the help lists them.
    """
    parser = _ArgumentParser(
        prog="contin", formatter_class=_LazyHelpFormatter,
        description="Pseudo-arclength continuation: trace equilibrium branches of a registered model,\n"
                    "locate folds, branch points and snaps, and classify stability.",
        epilog="""\
{default_line}

examples:
  contin trace                     # trace the default scene into ./out
  contin classify                  # print its class
  contin models                    # the models, their scene keys, defaults and allowed ranges

Run 'contin COMMAND --help' for the options of a command.""")
    parser.add_argument("--version", action="version", version=f"contin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands")

    _add_trace_command(sub)
    _add_classify_command(sub)
    _add_models_command(sub)
    _add_plot_command(sub)
    return parser


# ---------------------------------------------------------------------------------------------------
# commands
# ---------------------------------------------------------------------------------------------------
def _cmd_plot(args: argparse.Namespace) -> int:
    """``contin plot``: saved runs drawn again (:mod:`contin.app.saved`), overlaid when there are several."""
    from .saved import SavedRunError, load_run

    try:
        runs = [load_run(path) for path in args.runs]
    except SavedRunError as exc:
        raise CliError(str(exc)) from None
    first = runs[0]
    x, y = args.x or first.x, args.y or first.y
    for run in runs:
        known = list(dict.fromkeys([run.summary.get("parameter", "p"),
                                    *(run.branches[0].observables if run.branches else ())]))
        for axis in (x, y):
            if axis is not None and axis not in ("p", *known):
                raise CliError(f"contin plot: {str(run.path)!r} has no quantity {axis!r}; it has "
                               f"{', '.join(repr(n) for n in known)}")
    target = Path(args.out) if args.out else (first.path / "diagram.png" if len(runs) == 1 else Path("overlay.png"))
    from ..plot.style import FORMATS

    fmt = target.suffix.lower().lstrip(".")
    if fmt not in FORMATS:
        raise CliError(f"contin plot: --out {str(target)!r} must end in .png or .pdf")
    from .figures import figure_files, saved_runs_figure

    # FILE in the format its suffix names, and the PDF beside a PNG when --pdf asks for it
    formats = [fmt] + (["pdf"] if args.pdf and fmt != "pdf" else [])
    try:
        written = atomic_write(figure_files(target.with_suffix(""), lambda: saved_runs_figure(runs, x, y), formats))
    except OSError as exc:
        raise CliError(f"cannot write {str(target)!r}: {exc.strerror or exc}") from None
    print(f"wrote {', '.join(str(path) for path in written)}")
    return 0


def _cmd_models(args: argparse.Namespace) -> int:
    available = registered_models()
    default = registry.default_model()
    if args.toml:
        if len(args.names) > 1:
            raise CliError(f"--toml prints the scene of one model; got {len(args.names)}: {', '.join(args.names)}")
        if not args.names and default is None:
            raise CliError("--toml without a NAME prints the default model's scene, and no default model is "
                           f"registered; name one of: {', '.join(available) or '(none)'}")
        name = args.names[0] if args.names else default
        model = load_model(name)
        print(f"# scene of the model {name!r}: every key at its default (edit, then run "
              f"'contin trace --model {name} SCENE.toml')")
        print(schema_as_toml(model.schema))
        return 0
    names = args.names or list(available)
    unknown = [n for n in names if n not in available]
    if unknown:
        raise CliError(f"unknown model(s) {', '.join(map(repr, unknown))}; registered models: "
                       f"{', '.join(available) or '(none)'}")
    if not names:
        print(f"no models are registered in the entry-point group {ENTRY_POINT_GROUP!r}")
        return 0
    status = 0
    for i, name in enumerate(names):
        try:
            model = load_model(name)
        except CliError as exc:
            print(f"contin: warning: {exc}", file=sys.stderr)
            status = 1
            continue
        if i:
            print()
        tags = (["default"] if name == default else []) + ["trace"] + (["classify"] if can_classify(model) else [])
        print(f"{name} ({', '.join(tags)}): {model.description}")
        print(schema_as_toml(model.schema, indent="    "))
    if not args.names:
        print("\nset a key with --set SECTION.KEY=VALUE; 'contin models NAME --toml' prints a scene file")
    return status


@contextmanager
def _output_dir(name: str) -> Iterator[Path]:
    """``--out``: created (and checked) before the run, removed again if the run writes nothing into it."""
    if not str(name):  # Path("") would be the current directory
        raise CliError("--out is empty; give a directory to write into")
    try:
        # checked before the run: an output that cannot replace what is there would leave the others half-updated
        directory = OutputDirectory(name, reserved=OUTPUT_FILES)
    except OutputError as exc:
        raise CliError(f"--out: {exc}") from None
    try:
        yield directory.path
    finally:
        directory.remove_if_empty()


def _unknown_key_hint(exc: SceneError, args: argparse.Namespace, name: str) -> str:
    if exc.kind == "unknown" and args.model is None:
        return (f" (the scene was checked against the default model {name!r}; choose another with --model, see "
                f"'contin models')")
    return ""


def _resolve_scene(model: ModelRunner, name: str, args: argparse.Namespace) -> dict[str, dict[str, Any]]:
    """The scene of ``args`` (file, then ``--set``) for ``model``; bad input raises :class:`CliError`."""
    try:
        return load_scene(model.schema, args.scene, args.overrides)
    except SceneError as exc:
        raise CliError(f"{exc}{_unknown_key_hint(exc, args, name)}") from None


def _forecast(model: ModelRunner, scene: dict[str, dict[str, Any]]) -> None:
    """Say the model's warning about the cost of running ``scene`` (``forecast``), if it has one.

    Said even with ``--quiet``: it is a warning, not progress, and it comes before a run that would
    otherwise be silent for minutes.
    """
    forecast = getattr(model, "forecast", None)
    note = forecast(scene) if forecast is not None else None
    if note:
        print(status_text(f"contin: warning: {note}"), file=sys.stderr, flush=True)


def _say(quiet: bool) -> Callable[[str], None]:
    def say(msg: str) -> None:
        if not quiet:
            print(status_text(f"contin: {msg}"), file=sys.stderr, flush=True)
    return say


def _status_message(model: ModelRunner, scene: dict, result: TraceResult | Classification) -> str:
    """The result's message; for a run cut short by its step limit, which scene key raises it."""
    message = result.message
    if not result.complete:
        keys = [f"{section}.{key} (now {scene[section][key]})" if scene[section][key] != "auto" else
                f"{section}.{key} (now \"auto\": give a number of steps above the automatic limit)"
                for section, fields in model.schema.sections.items() for key in fields if key == "max_steps"]
        if keys:
            message += f"; to reach the end, raise {' or '.join(keys)}"
    return message


def _cmd_trace(args: argparse.Namespace) -> int:
    start = None
    if args.restart_from is not None or args.label is not None:
        name, model, scene, start = _restart(args)
    else:
        name = _model_name(args)
        model = load_model(name)
        scene = _resolve_scene(model, name, args)
    say = _say(args.quiet)
    with _output_dir(args.out) as out:
        say(f"tracing model {name!r}{' from ' + repr(args.scene) if args.scene else ''}"
            f"{' from ' + start.describe() + ' of ' + repr(args.restart_from) if start is not None else ''}")
        _forecast(model, scene)
        t0 = time.perf_counter()
        result = _run(model, scene, progress=not args.quiet, start=start)
        if start is not None:
            _describe_restart(result, args, start)
        table = _numbered(result)  # before the summary is written: the records get their numbers
        wall = time.perf_counter() - t0
        message = _status_message(model, scene, result)
        if start is not None:
            message = f"{result.summary['restart']['note']}; {message}"
        written = write_outputs(out, name, scene, result, wall, message=message, pdf=args.pdf)
    say(f"wrote {', '.join(str(p) for p in written)} ({wall:.2f} s)")

    print(format_table(table, title=f"special points ({name}):", width=LINE_WIDTH,
                       optional=_optional_columns(table), elsewhere="summary.json has every column"))
    print(status_text(f"status: {result.status} - {message}"))
    return 0 if result.success else 1


def _optional_columns(rows: Sequence[dict[str, Any]]) -> list[str]:
    """The columns of a special-point table that may be left out to fit the terminal, least important first.

    The residual and whether the point was located, then the values from the last back to the second (the
    first, the parameter or what folds, and the point's number, kind, label, branch and stability always stay).
    """
    keys: list[str] = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    values = [k for k in keys if k not in ("#", "on", "kind", "label", "residual", "located", "stability")]
    return ["residual", "located", *reversed(values[1:])]


def _numbered(result: TraceResult) -> list[dict[str, Any]]:
    """The special-point table with its ``#`` column: the labels of ``contin trace --from OUT --label K``."""
    from .restart import number_points

    return number_points(result.special_points, result.table)


def _restart(args: argparse.Namespace) -> tuple[str, ModelRunner, dict[str, dict[str, Any]], Any]:
    """``--from OUT --label K``: the saved run's model, its scene updated by ``--set``, and the saved point."""
    from .restart import RestartError, attach_saved_path, can_resume, read_start, restart_scene

    if args.restart_from is None or args.label is None:
        raise CliError("--from OUT and --label K go together: --from names the saved run, --label the point of it "
                       "to restart from")
    if args.scene is not None:
        raise CliError(f"--from takes the scene of the saved run; give changes to it with --set, not the scene file "
                       f"{args.scene!r}")
    try:
        summary, start = read_start(args.restart_from, args.label)
    except RestartError as exc:
        raise CliError(str(exc)) from None
    name = str(summary.get("model") or "")
    if args.model is not None and args.model != name:
        raise CliError(f"--model {args.model}: the run in {args.restart_from!r} was traced with the model {name!r}; "
                       f"a restart continues with it (leave --model out)")
    model = load_model(name)
    if not can_resume(model):
        raise CliError(f"model {name!r} cannot restart from a saved point; trace it anew")
    try:
        scene = restart_scene(model, summary, args.overrides)
        args.not_joined = attach_saved_path(model, start, summary, scene)
    except RestartError as exc:
        raise CliError(str(exc)) from None
    except SceneError as exc:
        raise CliError(f"{exc} (the scene of the saved run {args.restart_from!r} with the --set given)") from None
    return name, model, scene, start


def _describe_restart(result: TraceResult, args: argparse.Namespace, start: Any) -> None:
    """Say in the summary, the status line and the diagram's title what a restarted run's results describe:
    the whole path (joined to the saved run's) or only the part traced from the point."""
    from .restart import restart_record

    record = restart_record(args.restart_from, start, args.overrides, getattr(args, "not_joined", ()))
    where = f"{start.describe()} of {str(args.restart_from)!r}"
    if start.continues_saved_path:
        record["note"] = f"restarted from {where}, joined to the saved path before it: the results describe the whole path"
        title = f"restarted from {args.restart_from} (point {start.name}), joined to its path"
    else:
        record["note"] = (f"restarted from {where}; the results describe only the part traced from there "
                          f"({'; '.join(getattr(args, 'not_joined', ()))})")
        title = f"only the part traced from point {start.name} of {args.restart_from}"
    result.summary["restart"] = record
    result.plot_options["title"] = "\n".join(t for t in (result.plot_options.get("title"), title) if t)


def _run(model: ModelRunner, scene: dict, progress: bool, start: Any = None) -> TraceResult:
    from .restart import RestartError

    try:
        result = model.run(scene, progress) if start is None else model.resume(scene, start, progress)  # type: ignore[attr-defined]
    except (SceneError, RestartError) as exc:  # a runner may reject a combination only it can judge: still bad input
        raise CliError(str(exc)) from None
    except engine_failures() as exc:  # the outputs are still written for these
        return TraceResult(branches=[], failure=f"run failed: {type(exc).__name__}: {exc}")
    if not isinstance(result, TraceResult):
        raise TypeError(f"model {model.name!r}: run() returned {type(result).__name__}, expected TraceResult")
    return result


def _classifying_models() -> list[str]:
    names = []
    for n in registered_models():
        try:
            if can_classify(load_model(n)):
                names.append(n)
        except CliError:
            pass
    return names


def _classify_scenes(model: ModelRunner, name: str,
                     args: argparse.Namespace) -> list[tuple[dict[str, Any], dict[str, dict[str, Any]]]]:
    """The scenes a ``classify`` invocation asks for, each with its swept values by ``section.key``.

    Without ``--sweep``: the one scene of the file and ``--set`` (no swept values).  With it: every
    combination, each resolved and validated like a ``--set`` scene; bad input raises :class:`CliError`.
    """
    try:
        if not args.sweep:
            scenes = [({}, load_scene(model.schema, args.scene, args.overrides))]
        else:
            from .sweep import parse_sweep, sweep_scenes

            axes = [parse_sweep(spec, model.schema) for spec in args.sweep]
            scenes = sweep_scenes(model.schema, axes, args.scene, args.overrides)
        # a scene the model traces but cannot classify is refused before anything runs
        from .sweep import check_sweep_classifiable

        check_sweep_classifiable(model, scenes)
    except SceneError as exc:
        raise CliError(f"{exc}{_unknown_key_hint(exc, args, name)}") from None
    return scenes


def _classify_one(model: ModelRunner, scene: dict, progress: bool) -> Classification:
    try:
        result = model.classify(scene, progress)  # type: ignore[attr-defined]
    except SceneError as exc:
        raise CliError(str(exc)) from None
    except engine_failures() as exc:
        return Classification(label=None, failure=f"run failed: {type(exc).__name__}: {exc}")
    if not isinstance(result, Classification):
        raise TypeError(f"model {model.name!r}: classify() returned {type(result).__name__}, expected Classification")
    return result


def _check_sweep_options(args: argparse.Namespace) -> None:
    """Refuse the sweep options of ``contin classify`` without ``--sweep``, or in a combination that cannot run.

    Raises
    ------
    CliError
        ``--csv``, ``--workers``, ``--scheduler`` or ``--no-resume`` without ``--sweep``; fewer than one
        worker; ``--workers`` with ``--scheduler``; an empty ``--scheduler``.
    """
    if not args.sweep:
        given = [opt for opt, value in (("--csv", args.csv), ("--workers", args.workers),
                                        ("--scheduler", args.scheduler), ("--no-resume", args.no_resume))
                 if value not in (None, False)]
        if given:
            raise CliError(f"{', '.join(given)} {'applies' if len(given) == 1 else 'apply'} only to a sweep: add "
                           f"--sweep SECTION.KEY=SPEC, where {_sweep_syntax()}")
    if args.workers is not None and args.workers < 1:
        raise CliError(f"--workers {args.workers}: give at least 1 worker process")
    if args.scheduler is not None:
        if args.workers is not None:
            raise CliError(f"--workers {args.workers} and --scheduler {args.scheduler} exclude each other: with "
                           f"--scheduler the Dask cluster's workers run the sweep (drop --workers)")
        if not args.scheduler.strip():
            raise CliError("--scheduler needs the address of a Dask scheduler, e.g. tcp://127.0.0.1:8786")


def _cmd_classify(args: argparse.Namespace) -> int:
    name = _model_name(args)
    model = load_model(name)
    if not can_classify(model):
        able = _classifying_models()
        raise CliError(f"model {name!r} cannot classify: it provides no classification "
                       f"(models that can: {', '.join(able) or 'none'}); 'contin trace --model {name}' traces it")
    _check_sweep_options(args)
    scenes = _classify_scenes(model, name, args)
    if args.sweep:
        return _classify_sweep(name, model, scenes, args)
    say = _say(args.quiet)
    docs: list[dict[str, Any]] = []
    results: list[Classification] = []
    messages: list[str] = []
    for _, scene in scenes:
        say(f"classifying model {name!r}{' from ' + repr(args.scene) if args.scene else ''}")
        _forecast(model, scene)
        t0 = time.perf_counter()
        result = _classify_one(model, scene, progress=not args.quiet)
        wall = time.perf_counter() - t0
        say(f"classified in {wall:.2f} s")
        results.append(result)
        messages.append(_status_message(model, scene, result) if not result.success else "")
        docs.append(classification_document(name, scene, result, wall, message=messages[-1]))
    if args.json:
        print(json.dumps(docs[0] if len(docs) == 1 else docs, indent=2, allow_nan=False))
    else:
        for result, message in zip(results, messages):
            print(format_classification(name, result, message))
    return 0 if all(r.success for r in results) else 1


def _swept_cell(value: Any) -> Any:
    # a float key's value reads as a float (1.0, not 1), to 8 significant digits like the other columns
    if isinstance(value, float) and math.isfinite(value):
        text = f"{value:.8g}"
        return text if any(c in text for c in ".e") else text + ".0"
    return value


def _row_status(row: dict[str, Any]) -> str:
    """A sweep row's status (a row of a CSV written before rows had one: ``ok`` unless it failed)."""
    return row.get("status") or ("failed" if row["failure"] else "ok")


def _sweep_table(rows: Sequence[dict[str, Any]], axes: Sequence[str]) -> list[dict[str, Any]]:
    """The lines of the printed sweep table: the swept values, the class, the norms, the time, the failure.

    Parameters
    ----------
    rows : sequence of dict
        The rows of :func:`contin.app.sweep.run_sweep`.
    axes : sequence of str
        The swept keys.

    Returns
    -------
    list of dict
        One line per row, for :func:`format_table`.
    """
    table = []
    for row in rows:
        line: dict[str, Any] = {axis: _swept_cell(row[axis]) for axis in axes}
        status = _row_status(row)
        line["class"] = row["label"] or ("failed" if row["failure"] and status != "incomplete" else "undecided")
        line["status"] = "" if status == "ok" else status  # a column only where a row is not ok
        line.update({k: v for k, v in row.items() if k.endswith("_norm") and k not in axes})
        line["time_s"] = f"{row['wall_time_s']:.2f}" if row["wall_time_s"] is not None else ""
        line["failure"] = row["failure"]
        table.append(line)
    return table


def _classify_sweep(name: str, model: ModelRunner, scenes: list[tuple[dict[str, Any], dict[str, dict[str, Any]]]],
                    args: argparse.Namespace) -> int:
    """``contin classify --sweep``: run the combinations, print the table (or JSON), return the exit status."""
    csv_path = Path(args.csv if args.csv is not None else DEFAULT_SWEEP_CSV)
    axes = list(scenes[0][0])
    say = _say(args.quiet)
    say(f"sweeping model {name!r}{' from ' + repr(args.scene) if args.scene else ''}: {len(scenes)} combinations "
        f"of {' x '.join(axes)}; rows go to {str(csv_path)!r}")
    from .executors import ExecutorError, make_executor
    from .sweep import run_sweep

    t0 = time.perf_counter()
    try:  # before the CSV is touched: a scheduler that cannot be used leaves no file behind
        executor = make_executor(args.workers, args.scheduler)
    except ExecutorError as exc:
        raise CliError(f"--scheduler: {exc}" if args.scheduler is not None else str(exc)) from None
    try:
        with executor:
            rows = run_sweep(name, scenes, csv_path, progress=not args.quiet, resume=not args.no_resume,
                             executor=executor, runner=model)
    except SceneError as exc:  # the CSV belongs to another sweep or cannot be written: before any work
        raise CliError(str(exc)) from None
    except KeyboardInterrupt:
        if csv_path.exists():
            print(f"contin: the finished combinations are in {str(csv_path)!r}; run the same command again to "
                  f"resume", file=sys.stderr)
        else:  # the CSV is created with its first row
            print(f"contin: no combination finished; {str(csv_path)!r} was not written", file=sys.stderr)
        raise
    failed = [row for row in rows if row["failure"]]
    say(f"swept {len(rows)} combinations in {time.perf_counter() - t0:.2f} s; wrote {str(csv_path)!r}")
    if args.json:
        print(json.dumps(json_ready(rows), indent=2, allow_nan=False))
        return 1 if failed else 0
    table = _sweep_table(rows, axes)
    norms = [k for k in table[0] if k.endswith("_norm") and k not in axes] if table else []
    print(format_table(table, title=status_text(f"classification sweep ({name}): {len(rows)} combinations, rows "
                                                f"in {str(csv_path)!r}"),
                       width=LINE_WIDTH, optional=["time_s", *reversed(norms)], abbreviate="failure",
                       elsewhere=f"{str(csv_path)!r} has every column"))
    counts: dict[str, int] = {}
    for line in table:
        counts[line["class"]] = counts.get(line["class"], 0) + 1
    print("classes: " + ", ".join(f"{label} {n}" for label, n in counts.items()))
    if failed:
        short = sum(1 for row in failed if _row_status(row) == "incomplete")
        parts = [f"{short} of {len(rows)} combinations stopped before the end of their path (a class shown was "
                 f"proved on the part traced)"] if short else []
        if len(failed) > short:
            parts.append(f"{len(failed) - short} of {len(rows)} could not be classified")
        print(status_text(f"status: {'incomplete' if short == len(failed) else 'failed'} - {'; '.join(parts)} (see "
                          f"the failure column)"))
        return 1
    print(f"status: ok - all {len(rows)} combinations classified")
    return 0


# ---------------------------------------------------------------------------------------------------
# outputs
# ---------------------------------------------------------------------------------------------------
def summary_document(model_name: str, scene: dict, result: TraceResult, wall_time_s: float,
                     message: str | None = None) -> dict[str, Any]:
    """The content of ``summary.json``; the runner's extra fields never replace the standard ones.

    ``complete`` is false when a branch stopped at its step limit before the end of its path
    (:attr:`TraceResult.complete`); ``message`` replaces the result's own when given.
    """
    from .saved import REPLOT_OPTIONS

    doc: dict[str, Any] = {
        "model": model_name,
        "status": result.status,
        "success": result.success,
        "complete": result.complete,
        "message": result.message if message is None else message,
        "parameter": result.parameter_name,
        "scene": scene,
        "special_points": result.special_points,
        "wall_time_s": wall_time_s,
        "n_steps": int(sum(br.meta.get("n_steps", max(len(br) - 1, 0)) for br in result.branches)),
        "branches": [
            {"label": result.labels[i] if i < len(result.labels) else f"branch {i}", "status": br.status,
             "message": br.message, "n_points": len(br), "n_steps": br.meta.get("n_steps"),
             "wall_time_s": br.meta.get("wall_time_s")}
            for i, br in enumerate(result.branches)],
        "jumps": [
            {"p": j.p, "success": j.success, "message": j.message, "iterations": j.iterations,
             "residual": j.residual, "energy_drop": j.energy_from - j.energy_to}
            for j in result.jumps],
        "contin_version": __version__,
        # what 'contin plot' needs to draw the run again as it was drawn
        "diagram": {"x": result.x, "y": result.y, "stability": result.stability,
                    **{k: result.plot_options[k] for k in REPLOT_OPTIONS if k in result.plot_options}},
    }
    for key, value in result.summary.items():
        doc.setdefault(key, value)
    return json_ready(doc)


def classification_document(model_name: str, scene: dict, result: Classification,
                            wall_time_s: float, message: str | None = None) -> dict[str, Any]:
    """What ``contin classify --json`` prints; the model's values never replace the standard fields.

    ``message`` replaces the result's own (the command line adds which key raises a step limit).
    """
    doc: dict[str, Any] = {
        "model": model_name,
        "classification": result.label,
        "success": result.success,
        "status": result.status,
        "complete": result.complete,
        "message": result.message if message is None else message,
    }
    for key, value in result.values.items():
        doc.setdefault(key, value)
    doc.setdefault("wall_time_s", wall_time_s)
    doc.setdefault("n_steps", result.n_steps)
    doc.setdefault("scene", scene)
    doc.setdefault("contin_version", __version__)
    return json_ready(doc)


def format_classification(model_name: str, result: Classification, message: str | None = None) -> str:
    """The text ``contin classify`` prints: the class, the model's lines, and the status (with ``message`` in place
    of the result's own, when given)."""
    lines = [f"classification ({model_name}): {result.label or 'undecided'}"]
    lines += [f"  {line}" for line in result.lines]
    text = result.message if message is None else message
    lines.append(status_text(f"status: {result.status}" + (f" - {text}" if not result.success else "")))
    return "\n".join(lines)


def _write_json(fh: io.TextIOBase, doc: dict) -> None:
    fh.write(json.dumps(doc, indent=2, allow_nan=False) + "\n")


def _csv_cell(v: Any) -> str:
    import numpy as np

    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, str):  # a text column (an operator family's key that is not a number)
        return v
    f = float(v)
    return repr(f) if math.isfinite(f) else ""


def _write_csv(fh: io.TextIOBase, columns: dict[str, np.ndarray]) -> None:
    import numpy as np

    writer = csv.writer(fh, lineterminator="\n")
    names = list(columns)
    writer.writerow(names)
    cols = [np.asarray(columns[n]).tolist() for n in names]
    for row in zip(*cols):
        writer.writerow([_csv_cell(v) for v in row])


def _write_npz(fh: io.BufferedIOBase, arrays: dict[str, np.ndarray]) -> None:
    import numpy as np

    np.savez(fh, **arrays)


def write_outputs(out: Path, model_name: str, scene: dict, result: TraceResult, wall_time_s: float,
                  message: str | None = None, pdf: bool = False) -> list[Path]:
    """Write ``summary.json``, ``branch.csv``, ``diagram.png``, when the model saves shapes, ``shapes.npz`` and
    ``shapes.png``, and ``states.npz`` (:func:`contin.app.restart.restart_states`, when a branch has states)
    into ``out``; the figures also as PDF when ``pdf`` or the scene's ``output.pdf`` asks for it
    (:func:`contin.app.figures.figure_formats`).

    All files are written at once (:func:`contin.results.io.atomic_write`): a failure or an interrupt never
    leaves a partial output or a mix of two runs.  A scene with ``output.figure = false``
    (:func:`contin.app.scene.wants_figure`) gets no figure, and a file of an earlier run that this run does
    not write is removed.

    Returns
    -------
    list of Path
        The written files.

    Raises
    ------
    CliError
        When a file cannot be written.
    """
    files: list[FileWriter] = [
        (out / "summary.json", lambda fh: _write_json(fh, summary_document(model_name, scene, result, wall_time_s,
                                                                            message))),
        (out / "branch.csv", lambda fh: _write_csv(fh, result.csv_columns))]
    # matplotlib only when a figure is drawn
    from .figures import figure_files, figure_formats, shapes_figure, trace_figure
    from ..plot.style import FORMATS

    formats = figure_formats(scene, pdf)
    figures = figure_files(out / "diagram", lambda: trace_figure(model_name, result), formats)
    if wants_figure(scene):
        files += figures
    shapes = out / "shapes.npz"
    if result.shapes:
        files.append((shapes, lambda fh: _write_npz(fh, result.shapes), True))
    drawn_shapes = bool(result.shapes) and result.draw_shapes is not None and wants_figure(scene)
    shape_figures = figure_files(out / "shapes", lambda: shapes_figure(result), formats)
    if drawn_shapes:
        files += shape_figures
    from .restart import STATES_FILE, restart_states

    states_file, states = out / STATES_FILE, restart_states(result)
    if states:
        files.append((states_file, lambda fh: _write_npz(fh, states), True))
    # a file left by an earlier run would show another run than the summary beside it
    stale = [(out / f"{stem}.{fmt}", keep and fmt in formats) for stem, keep in
             (("diagram", wants_figure(scene)), ("shapes", drawn_shapes)) for fmt in FORMATS]
    try:
        written = atomic_write(files)
        for path, keep in stale + [(shapes, bool(result.shapes)), (states_file, bool(states))]:
            if not keep and path.exists():
                path.unlink()
    except OSError as exc:
        raise CliError(f"cannot write the outputs to {str(out)!r}: {exc.strerror or exc}") from None
    return written


def _cell(key: str, v: Any) -> str:
    import numpy as np

    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        if v == 0.0:
            v = 0.0  # a negative zero prints as 0 (issue 18: no "-0" in the tables)
        return f"{v:.1e}" if key == "residual" else f"{v:.8g}"
    return str(v)


def format_table(rows: Sequence[dict[str, Any]], title: str = "", *, width: int | None = None,
                 optional: Sequence[str] = (), abbreviate: str | None = None, elsewhere: str = "") -> str:
    """Rows of dicts as an aligned text table (columns in order of first appearance).

    Parameters
    ----------
    rows : sequence of dict
        One dict per line, column header -> value; a column empty in every row is left out.
    title : str
        A line above the table.
    width : int, optional
        Fit the table in this many columns (``contin`` prints with :data:`contin.results.io.LINE_WIDTH`): the
        ``optional`` columns are left out, in their order, until the lines fit; then the cells of the
        ``abbreviate`` column are cut (ending in ``...``).  A last line names what was left out or cut,
        and ``elsewhere`` says where the whole table is.  None: every column, however wide.
    """
    if not rows:
        return f"{title} none" if title else "none"
    keys: list[str] = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    keys = [k for k in keys if any(_cell(k, row.get(k)) for row in rows)]
    cells = {k: [_cell(k, row.get(k)) for row in rows] for k in keys}
    widths = {k: max(len(k), *(len(c) for c in cells[k])) for k in keys}

    def line_width() -> int:
        return sum(widths[k] for k in keys) + 2 * (len(keys) - 1)

    left_out, cut = [], False
    if width is not None:
        for k in optional:
            if line_width() <= width:
                break
            if k in keys and len(keys) > 1:
                keys.remove(k)
                left_out.append(k)
        if abbreviate in keys and line_width() > width:
            room = max(width - (line_width() - widths[abbreviate]), len(abbreviate), 12)
            short = [c if len(c) <= room else c[:room - 3].rstrip() + "..." for c in cells[abbreviate]]
            cut = short != cells[abbreviate]
            cells[abbreviate] = short
            widths[abbreviate] = max(len(abbreviate), *(len(c) for c in short))
    lines = [title] if title else []
    lines.append("  ".join(k.ljust(widths[k]) for k in keys).rstrip())
    for i in range(len(rows)):
        lines.append("  ".join(cells[k][i].ljust(widths[k]) for k in keys).rstrip())
    if left_out or cut:
        said = ([f"not shown: {', '.join(left_out)}"] if left_out else []) + ([f"{abbreviate} cut short"] if cut else [])
        lines.append(status_text(f"({'; '.join(said)}, to fit {width} columns{'; ' + elsewhere if elsewhere else ''})"))
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------------
def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``contin`` command.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments without the program name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0 success, 1 the run failed (numerically, no class decided, or an internal error,
        which is printed as one paragraph; ``CONTIN_TRACEBACK=1`` re-raises it), 2 bad input,
        130 interrupted.
    """
    parser = _build_parser()
    try:
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help and --version
            return int(exc.code or 0)
        commands = {"trace": _cmd_trace, "classify": _cmd_classify, "models": _cmd_models, "plot": _cmd_plot}
        if args.command not in commands:
            raise CliError(f"a command is required: {', '.join(map(repr, commands))} (see 'contin --help')")
        return commands[args.command](args)
    except CliError as exc:
        print(f"contin: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("contin: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # stdout closed early (e.g. piped into head): not an error of the run
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0
    except Exception as exc:  # an internal error (a bug in a model or in contin): one paragraph, no traceback
        if os.environ.get("CONTIN_TRACEBACK"):
            raise
        print(f"contin: internal error: {type(exc).__name__}: {' '.join(str(exc).split())} (this is a bug; run "
              f"with CONTIN_TRACEBACK=1 to see where it happened)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
