"""What every study shares: its command line, its output directory and how results are written.

A study is run as ``python -m studies.<name> [--out DIR] [--full]``: fast by default (under a minute
on a laptop-class core), faithful to the paper with ``--full``.  It writes its figures as PNG and PDF,
its data as CSV and a ``summary.json``, and prints a short table.  Every file is written to a temporary
name in the output directory and moved into place when complete, so an interrupted study never leaves
a half-written file behind.

A study whose cases are independent runs them through an executor (:mod:`contin.executors`):
``--workers N`` local processes (1: in the study's process) or ``--scheduler ADDRESS``, a Dask
cluster (:func:`study_parser` with ``executor_options=True``, then :func:`executor_from_args`); its
results do not depend on which.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import sys
import tempfile
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from contin.cli import _json_ready as _cli_json_ready
from contin.executors import Executor, ExecutorError, make_executor
from models.shell.boundaries import depth_parameter

__all__ = ["study_parser", "executor_from_args", "output_dir", "save_figure", "write_csv", "write_json", "write_text",
           "json_ready", "print_table", "shell_lambda", "say"]


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value}: give at least 1 worker process")
    return value


def study_parser(name: str, description: str, *, executor_options: bool = False,
                 workers_default: str = "one per CPU") -> argparse.ArgumentParser:
    """The command line shared by the studies.

    Parameters
    ----------
    name : str
        The study's module name (``python -m studies.<name>``).
    description : str
        One line for ``--help``.
    executor_options : bool
        Also ``--workers N`` and ``--scheduler ADDRESS`` (mutually exclusive), read by
        :func:`executor_from_args`.  Off by default, because some studies define their own ``--workers``.
    workers_default : str
        What ``--workers`` is when not given, for its help (what the study passes to
        :func:`executor_from_args`).

    Returns
    -------
    argparse.ArgumentParser
        With ``--out DIR`` (default ``out/<name>``), ``--full`` and ``--quiet``.
    """
    parser = argparse.ArgumentParser(prog=f"python -m studies.{name}", description=description)
    parser.add_argument("--out", default=os.path.join("out", name), metavar="DIR",
                        help=f"output directory (default: out/{name})")
    parser.add_argument("--full", action="store_true",
                        help="the paper's resolution (N = 200, fine sweeps); slower")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress lines on stderr")
    if executor_options:
        where = parser.add_mutually_exclusive_group()
        where.add_argument("--workers", "-j", type=_positive_int, default=None, metavar="N",
                           help=f"local worker processes for the independent runs (1: in this process; "
                                f"default: {workers_default})")
        where.add_argument("--scheduler", default=None, metavar="ADDRESS",
                           help="run them on the Dask cluster of this scheduler instead (tcp://HOST:8786; "
                                "needs pip install 'contin[dask]')")
    return parser


def executor_from_args(args: argparse.Namespace, default_workers: int | None = None) -> Executor:
    """The executor a study's ``--workers`` / ``--scheduler`` ask for (close it when done).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed by a :func:`study_parser` with ``executor_options=True`` (without them: the default).
    default_workers : int, optional
        Local processes when neither option is given (default: one per CPU).

    Returns
    -------
    contin.executors.Executor
        Serial for one worker, a local process pool for more, a Dask executor for ``--scheduler``.

    Raises
    ------
    SystemExit
        Status 2 with one line on stderr when the Dask scheduler cannot be used (dask not installed,
        address not reached).
    """
    workers, scheduler = getattr(args, "workers", None), getattr(args, "scheduler", None)
    if workers is None and scheduler is None:
        workers = default_workers
    try:
        return make_executor(workers, scheduler)
    except ExecutorError as exc:
        option = "--scheduler" if scheduler is not None else "--workers"
        print(f"error: {option}: {' '.join(str(exc).split())}", file=sys.stderr)
        raise SystemExit(2) from None


def output_dir(path: str | os.PathLike) -> Path:
    """Create the output directory (and parents); a clear error if that is impossible."""
    out = Path(path)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise SystemExit(f"error: cannot create the output directory {str(out)!r}: {exc.strerror or exc}")
    return out


def _atomic_write(path: Path, write: Any, mode: str = "w") -> Path:
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, mode, **({"newline": ""} if "b" not in mode else {})) as fh:
            write(fh)
        umask = os.umask(0)  # mkstemp makes the file private; an output gets a new file's permissions
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def json_ready(obj: Any) -> Any:
    """``obj`` with numpy scalars and arrays made plain, and NaN or infinity made None (JSON has neither).

    The same conversion ``contin trace`` applies to ``summary.json``.
    """
    return _cli_json_ready(obj)


def write_json(path: str | os.PathLike, doc: dict[str, Any]) -> Path:
    """Write ``doc`` as indented JSON (atomically)."""
    text = json.dumps(json_ready(doc), indent=2, allow_nan=False)
    return _atomic_write(Path(path), lambda fh: fh.write(text + "\n"))


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (a temporary name in the same folder, then a rename)."""
    return _atomic_write(Path(path), lambda fh: fh.write(text))


def write_csv(path: str | os.PathLike, rows: Sequence[dict[str, Any]], columns: Sequence[str] | None = None) -> Path:
    """Write rows (dicts) as CSV with a header, floats in full precision, None as an empty cell."""
    cols = list(columns) if columns is not None else list(dict.fromkeys(k for r in rows for k in r))

    def cell(v: Any) -> Any:
        v = json_ready(v)
        return "" if v is None else (repr(v) if isinstance(v, float) else v)

    def write(fh: Any) -> None:
        w = csv.writer(fh)
        w.writerow(cols)
        for r in rows:
            w.writerow([cell(r.get(c)) for c in cols])
    return _atomic_write(Path(path), write)


def save_figure(fig: Any, out: str | os.PathLike, stem: str) -> list[Path]:
    """Save a matplotlib figure as ``<stem>.png`` and ``<stem>.pdf`` in ``out`` (atomically) and close it."""
    import matplotlib.pyplot as plt

    paths = []
    for ext, kw in (("png", {"dpi": 150}), ("pdf", {})):
        path = Path(out) / f"{stem}.{ext}"
        _atomic_write(path, lambda fh: fig.savefig(fh, format=ext, bbox_inches="tight", **kw), mode="wb")
        paths.append(path)
    plt.close(fig)
    return paths


def print_table(rows: Iterable[dict[str, Any]], columns: Sequence[str], digits: int = 6,
                file: Any = None) -> None:
    """Print rows as an aligned plain-text table (floats with ``digits`` significant digits)."""
    def fmt(v: Any) -> str:
        if v is None:
            return "-"
        if isinstance(v, (float, np.floating)):
            return f"{float(v):.{digits}g}"
        return str(v)
    body = [[fmt(r.get(c)) for c in columns] for r in rows]
    widths = [max([len(c)] + [len(b[i]) for b in body]) for i, c in enumerate(columns)]
    out = file or sys.stdout
    print("  ".join(c.ljust(w) for c, w in zip(columns, widths)), file=out)
    for b in body:
        print("  ".join(x.ljust(w) for x, w in zip(b, widths)), file=out)


def shell_lambda(phi_hat: float | np.ndarray, h_over_R: float | np.ndarray, nu: float = 0.5) -> Any:
    """Shell depth parameter ``lambda`` (physics.md section 1); see :func:`models.shell.boundaries.depth_parameter`."""
    return depth_parameter(phi_hat, h_over_R, nu)


def say(quiet: bool, msg: str) -> None:
    """A progress line on stderr unless ``quiet``."""
    if not quiet:
        print(msg, file=sys.stderr, flush=True)
