"""What every study shares: its command line, its output directory and how results are written.

A study is run as ``python -m studies.<name> [--out DIR] [--full]``: fast by default (under a minute
on a laptop-class core), faithful to the paper with ``--full``.  It writes its figures as PNG and PDF,
its data as CSV and a ``summary.json``, and prints a short table.  Every file is written to a temporary
name in the output directory and moved into place when complete (:func:`contin.results.io.atomic_write`), so an
interrupted study never leaves a half-written file behind.  Run through :func:`run_study` (its
``__main__`` block), a study behaves like the ``contin`` command: Ctrl-C exits with 130 and one line,
an output directory that cannot be written with 2 and one paragraph, never a traceback, and no empty
output directory is left behind.

A study whose cases are independent runs them through an executor (:mod:`contin.app.executors`):
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
import time
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from contin.app.executors import Executor, ExecutorError, make_executor
from contin.app.scene import SceneError
from contin.results.io import OutputDirectory, OutputError, atomic_write, json_ready
from contin_models.shell.boundaries import depth_parameter

__all__ = ["study_parser", "executor_from_args", "output_dir", "run_study", "save_figure", "save_figures", "write_csv",
           "write_json", "write_text", "json_ready", "print_table", "shell_lambda", "say", "alternate_timings"]


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
    contin.app.executors.Executor
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


#: Output directories made by :func:`output_dir` in this run: :func:`run_study` removes them again if empty.
_MADE: list[OutputDirectory] = []


def _refuse(message: str) -> NoReturn:
    """Bad input, as the command line reports it: one paragraph on stderr, exit status 2."""
    print(f"error: {' '.join(message.split())}", file=sys.stderr)
    raise SystemExit(2)


def output_dir(path: str | os.PathLike) -> Path:
    """Create the output directory (and parents) and check that it can be written.

    A directory this makes is removed again by :func:`run_study` if the study ends without writing
    into it (an interrupt, an error).

    Raises
    ------
    SystemExit
        Status 2 with one paragraph on stderr when the directory cannot be created or written.
    """
    try:
        made = OutputDirectory(path)
    except OutputError as exc:
        _refuse(str(exc))
    _MADE.append(made)
    return made.path


def run_study(main: Callable[..., int | None], argv: Sequence[str] | None = None) -> int:
    """Run a study's ``main`` as the ``contin`` command runs: the exit status, and no traceback for the user.

    The study's figures are drawn in the project's style (:func:`contin.plot.style.use`).

    Parameters
    ----------
    main : callable
        The study's entry point, called as ``main(argv)`` (``main()`` when ``argv`` is None).
    argv : sequence of str, optional
        Its arguments.

    Returns
    -------
    int
        What ``main`` returned (None: 0); 130 after an interrupt (Ctrl-C), with one line on stderr;
        2 for a scene the models refuse, with its one-paragraph message.  Whatever the end, an
        output directory the study made and left empty is removed.
    """
    # run as python -m studies.NAME, the module is __main__: its spec still knows the name (a script has none)
    spec = getattr(sys.modules.get(main.__module__), "__spec__", None)
    if spec is not None:
        prog = f"python -m {spec.name}"
    else:
        prog = os.path.basename(sys.argv[0]) if main.__module__ == "__main__" else main.__module__
        prog = prog if prog and not prog.startswith("-") else "study"  # python -c gives argv[0] = "-c"
    from contin.plot import style

    style.use()  # every figure of the study in the project's look (contin/plot/style.py)
    try:
        status = main() if argv is None else main(argv)
        return int(status or 0)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except SceneError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 2
    finally:
        while _MADE:
            _MADE.pop().remove_if_empty()


def write_json(path: str | os.PathLike, doc: dict[str, Any]) -> Path:
    """Write ``doc`` as indented JSON (atomically)."""
    text = json.dumps(json_ready(doc), indent=2, allow_nan=False)
    return write_text(path, text + "\n")


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically (a temporary name in the same folder, then a rename)."""
    return atomic_write([(path, lambda fh: fh.write(text))])[0]


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
    return atomic_write([(path, write)])[0]


def save_figure(fig: Any, out: str | os.PathLike, stem: str) -> list[Path]:
    """Save a matplotlib figure as ``<stem>.png`` and ``<stem>.pdf`` in ``out`` (atomically) and close it.

    In the project's style (:mod:`contin.plot.style`, made the process' default by :func:`run_study`): the
    command line's resolution, no creation date in the PDF, cropped to the drawing.
    """
    import matplotlib.pyplot as plt

    from contin.plot import style

    def draw(ext: str) -> Callable[[Any], None]:
        meta = {"CreationDate": None} if ext == "pdf" else {"Software": None}
        return lambda fh: fig.savefig(fh, format=ext, bbox_inches="tight", pad_inches=0.03, dpi=style.DPI,
                                      metadata=meta)

    try:
        return atomic_write([(Path(out) / f"{stem}.{ext}", draw(ext)) for ext in style.FORMATS], binary=True)
    finally:
        plt.close(fig)


def save_figures(out: str | os.PathLike, result: Any, builders: dict[str, Callable[[Any], Any]]) -> list[Path]:
    """Draw each figure of a study's result and save it with :func:`save_figure`, one figure open at a time.

    Parameters
    ----------
    out : str or PathLike
        The output directory.
    result : Any
        The study's result, passed to each builder.
    builders : dict of str to callable
        File stem (``<stem>.png``, ``<stem>.pdf``) to the function drawing that figure from ``result``,
        saved in this order.

    Returns
    -------
    list of Path
        The files written.
    """
    return [path for stem, build in builders.items() for path in save_figure(build(result), out, stem)]


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
    """Shell depth parameter ``lambda`` (``docs/model.md#geometry``); see :func:`contin_models.shell.boundaries.depth_parameter`."""
    return depth_parameter(phi_hat, h_over_R, nu)


def clearest_offset(ax: Any, xy: Sequence[float], offsets: Sequence[Sequence[float]],
                    placed: Sequence[np.ndarray] = ()) -> tuple[int, np.ndarray]:
    """Where a label beside the data point ``xy`` of ``ax`` hides least: the index of the offset of
    ``offsets`` (in points, to the label's centre) whose place lies farthest from every line, marker and
    annotation arrow drawn on ``ax`` and from the labels already ``placed`` (their centres, in display
    pixels), inside the axes; and that place.  Call it once the layout is final: a fixed offset lands on
    another curve or mark wherever the data crowd, and where they crowd changes from run to run.
    """
    segments = []
    for line in ax.lines:
        pts = line.get_transform().transform(np.asarray(line.get_xydata(), float))
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) == 1 or (len(pts) and line.get_linestyle() in ("None", "none", "")):
            segments.append(np.hstack([pts, pts]))  # markers alone: points
        elif len(pts) > 1:
            segments.append(np.hstack([pts[:-1], pts[1:]]))
    for ann in ax.texts:
        if getattr(ann, "xyann", None) is not None and ann.get_text() == "":  # an arrow
            a = ax.transData.transform(ann.xy)
            b = ax.transData.transform(ann.xyann)
            segments.append(np.array([[*b, *a]]))
    seg = np.vstack(segments) if segments else np.zeros((0, 4))
    box = ax.get_window_extent()
    px = ax.figure.dpi / 72.0
    base = ax.transData.transform(xy)
    a, d = seg[:, :2], seg[:, 2:] - seg[:, :2]
    best, best_place, best_score = 0, base + np.asarray(offsets[0]) * px, -np.inf
    for k, off in enumerate(offsets):
        c = base + np.asarray(off, dtype=float) * px
        t = np.clip(np.einsum("ij,ij->i", c - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-12), 0.0, 1.0)
        score = float(np.min(np.hypot(*(a + t[:, None] * d - c).T), initial=np.inf))
        for q in placed:
            score = min(score, float(np.hypot(*(q - c))))
        margin = 8 * px
        if not (box.x0 + margin < c[0] < box.x1 - margin and box.y0 + margin < c[1] < box.y1 - margin):
            score -= 1e6
        if score > best_score:
            best, best_place, best_score = k, c, score
    return best, best_place


def say(quiet: bool, msg: str) -> None:
    """A progress line on stderr unless ``quiet``."""
    if not quiet:
        print(msg, file=sys.stderr, flush=True)


def alternate_timings(calls: Sequence[Callable[[], Any]], repeat: int) -> list[list[float]]:
    """Wall times of each call, ``repeat`` rounds with the calls alternating (a shared, noisy machine
    drifts alike for all of them); one list of times per call.  Warm-up is the caller's."""
    times: list[list[float]] = [[] for _ in calls]
    for _ in range(repeat):
        for call, out in zip(calls, times):
            start = time.perf_counter()
            call()
            out.append(time.perf_counter() - start)
    return times
