"""The ``contin`` command: trace a model's scene and write a summary, a CSV table and a diagram.

Models are found only through the ``contin.models`` entry-point group (the engine never imports a
model).  An entry point resolves to a :class:`contin.scene.ModelRunner` (or a zero-argument factory
returning one).

Exit status: 0 success, 1 the run failed numerically (outputs are still written), 2 bad input
(scene, ``--set``, unknown model, unwritable output directory), 130 interrupted.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import os
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from importlib.metadata import EntryPoint, entry_points
from pathlib import Path
from typing import Any

import numpy as np

from . import __version__
from .scene import ModelRunner, SceneError, TraceResult, load_scene, schema_as_toml

__all__ = ["main", "DEFAULT_MODEL", "ENTRY_POINT_GROUP", "CliError", "registered_models", "load_model"]

#: Model traced when ``--model`` is not given.
DEFAULT_MODEL = "bratu"
#: Entry-point group in which models register their scene runners.
ENTRY_POINT_GROUP = "contin.models"

OUTPUT_FILES = ("summary.json", "branch.csv", "diagram.png")


class CliError(Exception):
    """A user error: printed as one paragraph after ``contin: error:``, exit status 2."""


class _ArgumentParser(argparse.ArgumentParser):
    # argparse would print usage and call sys.exit; the contract is one paragraph and main() returning 2
    def error(self, message: str) -> None:  # type: ignore[override]
        raise CliError(f"{message} (see '{self.prog} --help')")


# ---------------------------------------------------------------------------------------------------
# model registry
# ---------------------------------------------------------------------------------------------------
def registered_models() -> dict[str, EntryPoint]:
    """Entry points of the ``contin.models`` group, by name (the first registration wins)."""
    found: dict[str, EntryPoint] = {}
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        found.setdefault(ep.name, ep)
    return dict(sorted(found.items()))


def load_model(name: str) -> ModelRunner:
    """Load the runner registered as ``name``.

    Raises
    ------
    CliError
        If no such model is registered or its entry point does not load a runner.
    """
    models = registered_models()
    if name not in models:
        if not models:
            raise CliError(f"unknown model {name!r}: no models are registered in the entry-point group "
                           f"{ENTRY_POINT_GROUP!r} (is the package installed with 'pip install -e .'?)")
        raise CliError(f"unknown model {name!r}; registered models: {', '.join(models)} (see 'contin models')")
    ep = models[name]
    try:
        obj = ep.load()
    except Exception as exc:  # any import-time failure of a plugin is reported, not raised
        raise CliError(f"model {name!r} could not be loaded from {ep.value}: {type(exc).__name__}: {exc}") from None
    if not hasattr(obj, "run") and callable(obj):
        obj = obj()
    missing = [a for a in ("name", "description", "schema", "run") if not hasattr(obj, a)]
    if missing:
        raise CliError(f"model {name!r} ({ep.value}) is not a scene runner: it lacks {', '.join(missing)}")
    return obj


# ---------------------------------------------------------------------------------------------------
# argument parsing
# ---------------------------------------------------------------------------------------------------
_TRACE_EPILOG = f"""\
outputs (in DIR):
  summary.json   resolved scene, special points, status, wall time, number of steps
  branch.csv     one row per converged point: parameter, observables, residual, stability
  diagram.png    the bifurcation diagram (stable solid, unstable dashed, special points marked)

exit status: 0 success, 1 the run failed numerically (outputs are still written),
2 bad input (scene, --set, model, output directory), 130 interrupted.

examples:
  contin trace                                   # default model ({DEFAULT_MODEL}) with its defaults
  contin trace --set model.n=50 --out /tmp/run
  contin trace scene.toml --model truss --set load.cycle=true
  contin models                                  # the models and their scene keys
"""


def _build_parser() -> _ArgumentParser:
    parser = _ArgumentParser(
        prog="contin", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Pseudo-arclength continuation: trace equilibrium branches of a registered model,\n"
                    "locate folds, branch points and snaps, and classify stability.",
        epilog="Run 'contin trace --help' or 'contin models' for details.")
    parser.add_argument("--version", action="version", version=f"contin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", title="commands")

    trace = sub.add_parser(
        "trace", help="trace a scene and write summary.json, branch.csv and diagram.png",
        formatter_class=argparse.RawDescriptionHelpFormatter, epilog=_TRACE_EPILOG,
        description="Trace the scene of a model.\n\n"
                    "The scene is the model's defaults, updated by the optional TOML file SCENE.toml and\n"
                    "then by each --set, in order. It is validated completely before anything runs.")
    trace.add_argument("scene", nargs="?", metavar="SCENE.toml", help="scene file (TOML); default: the model's defaults")
    trace.add_argument("-m", "--model", metavar="NAME", default=None,
                       help=f"registered model to trace (default: {DEFAULT_MODEL}; list them with 'contin models')")
    trace.add_argument("-s", "--set", dest="overrides", action="append", default=[], metavar="SECTION.KEY=VALUE",
                       help="override one scene key; VALUE is read as TOML (1e-8, true, \"text\"), else as a "
                            "bare string; may be repeated")
    trace.add_argument("-o", "--out", metavar="DIR", default="out", help="output directory (default: ./out)")
    trace.add_argument("-q", "--quiet", action="store_true", help="no progress lines on stderr")

    models = sub.add_parser(
        "models", help="list the registered models with their scene keys and defaults",
        formatter_class=argparse.RawDescriptionHelpFormatter,
        description="List the models registered in the 'contin.models' entry-point group, each with its\n"
                    "scene as commented TOML (defaults and allowed ranges): a starting point for SCENE.toml.")
    models.add_argument("names", nargs="*", metavar="NAME", help="only these models")
    return parser


# ---------------------------------------------------------------------------------------------------
# commands
# ---------------------------------------------------------------------------------------------------
def _cmd_models(args: argparse.Namespace) -> int:
    available = registered_models()
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
        default = " (default)" if name == DEFAULT_MODEL else ""
        print(f"{name}{default}: {model.description}")
        print(schema_as_toml(model.schema, indent="    "))
    return status


def _prepare_out(path: Path) -> Path:
    if path.exists() and not path.is_dir():
        raise CliError(f"--out {str(path)!r} exists and is not a directory; give a directory to write into")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CliError(f"cannot create the output directory {str(path)!r}: {exc.strerror or exc}") from None
    try:
        fd, probe = tempfile.mkstemp(dir=path, prefix=".contin-probe.", suffix=".tmp")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise CliError(f"the output directory {str(path)!r} is not writable: {exc.strerror or exc}") from None
    return path


def _cmd_trace(args: argparse.Namespace) -> int:
    quiet = args.quiet
    name = args.model or DEFAULT_MODEL
    model = load_model(name)
    try:
        scene = load_scene(model.schema, args.scene, args.overrides)
    except SceneError as exc:
        hint = ""
        if exc.kind == "unknown" and args.model is None:
            hint = f" (the scene was checked against the default model {DEFAULT_MODEL!r}; choose another with --model)"
        raise CliError(f"{exc}{hint}") from None
    out = _prepare_out(Path(args.out))

    def say(msg: str) -> None:
        if not quiet:
            print(f"contin: {msg}", file=sys.stderr, flush=True)

    say(f"tracing model {name!r}{' from ' + repr(args.scene) if args.scene else ''}")
    t0 = time.perf_counter()
    result = _run(model, scene, progress=not quiet)
    wall = time.perf_counter() - t0
    written = write_outputs(out, name, scene, result, wall)
    say(f"wrote {', '.join(str(p) for p in written)} ({wall:.2f} s)")

    print(format_table(result.table, title=f"special points ({name}):"))
    print(f"status: {result.status} - {result.message}")
    return 0 if result.success else 1


def _run(model: ModelRunner, scene: dict, progress: bool) -> TraceResult:
    # a runner normally reports numerical failure in its result; these are the engine's exceptions
    # for failures it cannot put into a branch, and the outputs are still written for them
    from .jump import JumpError
    from .linalg import SingularMatrixError
    from .palc import CorrectorFailure
    from .problem import NonFiniteError

    try:
        result = model.run(scene, progress)
    except SceneError as exc:  # a runner may reject a combination only it can judge: still bad input
        raise CliError(str(exc)) from None
    except (CorrectorFailure, NonFiniteError, JumpError, SingularMatrixError, np.linalg.LinAlgError) as exc:
        return TraceResult(branches=[], failure=f"run failed: {type(exc).__name__}: {exc}")
    if not isinstance(result, TraceResult):
        raise TypeError(f"model {model.name!r}: run() returned {type(result).__name__}, expected TraceResult")
    return result


# ---------------------------------------------------------------------------------------------------
# outputs
# ---------------------------------------------------------------------------------------------------
def _json_ready(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {str(k): _json_ready(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_ready(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _json_ready(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        # JSON has no NaN or infinity
        return float(obj) if math.isfinite(obj) else None
    return obj


def summary_document(model_name: str, scene: dict, result: TraceResult, wall_time_s: float) -> dict[str, Any]:
    """The content of ``summary.json``; the runner's extra fields never replace the standard ones."""
    doc: dict[str, Any] = {
        "model": model_name,
        "status": result.status,
        "success": result.success,
        "message": result.message,
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
    }
    for key, value in result.summary.items():
        doc.setdefault(key, value)
    return _json_ready(doc)


def _write_json(fh: io.BufferedWriter, doc: dict) -> None:
    fh.write((json.dumps(doc, indent=2, allow_nan=False) + "\n").encode())


def _csv_cell(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    f = float(v)
    return repr(f) if math.isfinite(f) else ""


def _write_csv(fh: io.BufferedWriter, columns: dict[str, np.ndarray]) -> None:
    text = io.TextIOWrapper(fh, encoding="utf-8", newline="")
    writer = csv.writer(text, lineterminator="\n")
    names = list(columns)
    writer.writerow(names)
    cols = [np.asarray(columns[n]).tolist() for n in names]
    for row in zip(*cols):
        writer.writerow([_csv_cell(v) for v in row])
    text.flush()
    text.detach()


def _write_figure(fh: io.BufferedWriter, model_name: str, result: TraceResult) -> None:
    # an explicit Agg canvas: no pyplot state, no GUI backend, safe in-process
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from .diagram import plot_branches

    fig = Figure(figsize=(6.4, 4.8))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    pname = result.parameter_name
    x = "p" if result.x == pname else result.x
    y = "p" if result.y == pname else result.y
    if result.plot is not None:
        result.plot(ax)
    elif result.branches and any(len(br) for br in result.branches):
        jumps = [(j, a, b) for j, (a, b) in zip(result.jumps, result.jump_observables)]
        plot_branches(result.branches, x=x, y=y, ax=ax, jumps=jumps,
                      labels=result.labels if len(result.labels) == len(result.branches) else None)
        ax.set_xlabel(pname if x == "p" else x)
        ax.set_ylabel(pname if y == "p" else (y or ""))
    else:
        ax.text(0.5, 0.5, "no branch traced", ha="center", va="center", transform=ax.transAxes)
    ax.set_title(f"{model_name}: {result.status}", fontsize="medium")
    fig.tight_layout()
    fig.savefig(fh, format="png", dpi=120)


def write_outputs(out: Path, model_name: str, scene: dict, result: TraceResult, wall_time_s: float) -> list[Path]:
    """Write ``summary.json``, ``branch.csv`` and ``diagram.png`` into ``out``.

    Every file is first written under a temporary name in ``out``; only when all three are complete
    are they moved into place, so a failure or an interrupt never leaves a partial output.

    Returns
    -------
    list of Path
        The written files.
    """
    writers: list[tuple[str, Callable[[Any], None]]] = [
        ("summary.json", lambda fh: _write_json(fh, summary_document(model_name, scene, result, wall_time_s))),
        ("branch.csv", lambda fh: _write_csv(fh, result.csv_columns)),
        ("diagram.png", lambda fh: _write_figure(fh, model_name, result)),
    ]
    temps: list[tuple[str, Path]] = []
    # mkstemp creates private files; outputs get the permissions of an ordinary new file
    umask = os.umask(0)
    os.umask(umask)
    try:
        for fname, write in writers:
            fd, tmp = tempfile.mkstemp(dir=out, prefix=f".{fname}.", suffix=".tmp")
            temps.append((fname, Path(tmp)))
            with os.fdopen(fd, "wb") as fh:
                write(fh)
            os.chmod(tmp, 0o666 & ~umask)
        for fname, tmp in temps:
            os.replace(tmp, out / fname)
    except OSError as exc:
        raise CliError(f"cannot write the outputs to {str(out)!r}: {exc.strerror or exc}") from None
    finally:
        for _, tmp in temps:
            if tmp.exists():
                tmp.unlink()
    return [out / fname for fname, _ in writers]


def _cell(key: str, v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        return f"{v:.1e}" if key == "residual" else f"{v:.8g}"
    return str(v)


def format_table(rows: Sequence[dict[str, Any]], title: str = "") -> str:
    """Rows of dicts as an aligned text table (columns in order of first appearance)."""
    if not rows:
        return f"{title} none" if title else "none"
    keys: list[str] = []
    for row in rows:
        keys += [k for k in row if k not in keys]
    keys = [k for k in keys if any(_cell(k, row.get(k)) for row in rows)]
    cells = [[_cell(k, row.get(k)) for k in keys] for row in rows]
    widths = [max(len(k), *(len(c[i]) for c in cells)) for i, k in enumerate(keys)]
    lines = [title] if title else []
    lines.append("  ".join(k.ljust(w) for k, w in zip(keys, widths)).rstrip())
    for c in cells:
        lines.append("  ".join(v.ljust(w) for v, w in zip(c, widths)).rstrip())
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
        Exit status: 0 success, 1 numerical failure, 2 bad input, 130 interrupted.
    """
    parser = _build_parser()
    try:
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help and --version
            return int(exc.code or 0)
        if args.command == "trace":
            return _cmd_trace(args)
        if args.command == "models":
            return _cmd_models(args)
        raise CliError("a command is required: 'trace' or 'models' (see 'contin --help')")
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


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
