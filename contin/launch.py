"""Entry point of the ``contin`` command: a Ctrl-C while the command starts is an interrupt, not a traceback.

``contin.app.cli`` and the models' scenes load in a few hundredths of a second (no numpy: the help and a
refused scene need none), and a run then imports numpy, scipy and the engine, which takes longer; a
Ctrl-C during an import would print Python's traceback of it and kill the process by the signal.
This module imports nothing but :mod:`gc`, :mod:`sys`, :mod:`signal` and :mod:`contin.numerics.threads` (which imports
:mod:`os`), and importing the ``contin`` package
around it costs nothing either: ``contin/__init__.py`` imports the engine's names on first use.  :func:`main`
imports and runs the command line and turns an interrupt at any point before the command handles
it into the command's own message (``contin: interrupted``) and exit status 130.

The console script names it in ``pyproject.toml``::

    [project.scripts]
    contin = "contin.launch:main"

Run as the command (no ``argv``: the console script and ``python -m contin``), :func:`main` collects
the youngest generation of the garbage collector less often while the command runs
(:data:`COMMAND_GC_THRESHOLD`): the imports of numpy, scipy, matplotlib and the engine allocate
objects that live until the exit, and each collection among them finds nothing to free.  It also
hands the process's objects to its exit: once the command has returned and its output is flushed, it
freezes the garbage collector's generations (:func:`gc.freeze`).  The interpreter's shutdown then
still runs every ``atexit`` handler, flushes and closes the files and tears the modules down, but its
final collections no longer walk the hundred thousand objects that numpy, scipy, matplotlib and the
run left: after a trace of the default scene the exit took about 0.2 s, and takes 0.03 s (issue 18).  Nothing is
skipped and the exit status is the command's.  Called with ``argv`` (in-process, as the tests do), the
collector is left alone.

Run as the command, it also gives the BLAS library one thread unless the user chose otherwise
(:mod:`contin.numerics.threads`): numpy is loaded after that.
"""

from __future__ import annotations

import gc
import signal
import sys
from collections.abc import Sequence
from typing import Any

from contin.numerics.threads import default_to_one_thread

__all__ = ["main", "COMMAND_GC_THRESHOLD"]

#: The collector's thresholds while the command runs (:func:`gc.set_threshold`; Python's default is 700,
#: 10, 10): cycles are still collected, after 200 000 net allocations instead of 700.
COMMAND_GC_THRESHOLD = (200_000, 50, 100)


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``contin``: :func:`contin.app.cli.main` with ``argv``; an interrupt during start-up exits quietly with 130.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments after ``contin``.  None (the console script): ``sys.argv[1:]``, and the process
        exits after the command: the collector runs less often and is frozen for a quick exit
        (module docstring).

    Returns
    -------
    int
        The exit status of :func:`contin.app.cli.main`, or 130 when interrupted before it took over.
    """
    if argv is None:
        default_to_one_thread()  # before numpy is loaded (contin.numerics.threads: why one BLAS thread)
        gc.set_threshold(*COMMAND_GC_THRESHOLD)
    status = _run(argv)
    if argv is None:
        _flush()
        gc.freeze()  # the interpreter's exit need not walk every object to free them (module docstring)
    return status


def _flush() -> None:
    # what the command printed is out before the exit (a closed pipe is not the command's failure)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):
            pass


def _run(argv: Sequence[str] | None) -> int:
    interrupted: list[int] = []

    def on_sigint(signum: int, frame: Any) -> None:
        interrupted.append(signum)
        raise KeyboardInterrupt

    # an interrupt inside a compiled extension's import may come out as an ImportError (numpy wraps
    # it so); the flag tells such an ImportError from a broken installation
    try:
        previous = signal.signal(signal.SIGINT, on_sigint)
    except ValueError:  # not the main thread: signals are not ours to handle there
        previous = None
    try:
        try:
            from contin.app.cli import main as cli_main
        finally:
            if previous is not None:
                signal.signal(signal.SIGINT, previous)
        return cli_main(argv)
    except KeyboardInterrupt:  # while importing, or building the parser (contin.app.cli handles it after that)
        return _interrupted()
    except ImportError:
        if interrupted:
            return _interrupted()
        raise


def _interrupted() -> int:
    try:
        print("contin: interrupted", file=sys.stderr)
    except (KeyboardInterrupt, OSError):
        pass
    return 130
