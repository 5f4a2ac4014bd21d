"""Writing results: atomic files, JSON-ready values and output directories that clean up after themselves.

Everything the toolkit writes goes through here:

- :func:`atomic_write` writes one or several files so that a reader never sees a partial one: each is
  written under a temporary name in its own directory and renamed into place only when every file of
  the group is complete.  An interrupt or an error leaves the previous files as they were and no
  temporary file behind.
- :func:`json_ready` turns numpy values into plain Python and NaN or infinity into None (JSON has
  neither), for ``summary.json``, ``contin classify --json`` and the studies' summaries; the headers of
  bundles keep NaN and infinity (``keep_nonfinite``), which Python's ``json`` reads back.
- :func:`write_bundle` and :func:`read_bundle` store a result as one ``.npz`` file: its arrays plus
  a JSON header naming the format (branches, jumps, quasi-static sweeps and diagrams all use it).
- :func:`output_directory` creates an output directory, checks that it can be written, and removes
  again what it created if nothing was written into it (an interrupted or failed run leaves no
  empty directory behind).  Its errors are :class:`OutputError`: one paragraph fit to show a user.
- :func:`status_text` is how a status or progress line is printed on a terminal: wrapped at
  :data:`LINE_WIDTH` columns, and without a negative zero.

Nothing here knows about any model.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import tempfile
import textwrap
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np

__all__ = ["OutputError", "ResultFileError", "FileWriter", "atomic_write", "json_ready", "output_directory",
           "OutputDirectory", "write_bundle", "read_bundle", "LINE_WIDTH", "status_text"]

#: Columns of the terminal that status and progress lines and the printed tables fit in (issue 18).
LINE_WIDTH = 100

# a minus sign before a number that is all zeros ("-0", "-0.000", "-0e+00"), not inside a word or a number
_NEGATIVE_ZERO = re.compile(r"(?<![\w.])-(?=0(?:\.0*)?(?:[eE][+-]?\d+)?(?![\w.]))")


def status_text(text: str, width: int = LINE_WIDTH, indent: str = "  ") -> str:
    """A status or progress line as printed: wrapped at ``width`` columns, and no ``-0``.

    The line breaks fall between words (a path or a long number is never split), each continuation line
    starts with ``indent``, and a number printed as a negative zero (``-0``, ``-0.00``) loses its sign,
    as in the tables.  Joining the lines on whitespace gives the text back.
    """
    text = _NEGATIVE_ZERO.sub("", text)
    return textwrap.fill(text, width=width, subsequent_indent=indent, break_long_words=False,
                         break_on_hyphens=False)


class OutputError(OSError):
    """An output that cannot be written: the message is one paragraph naming the path and the reason."""


class ResultFileError(ValueError):
    """A saved result file is missing, unreadable, truncated, of another format or inconsistent."""


def _new_file_mode() -> int:
    # mkstemp makes private files; an output gets the permissions of an ordinary new file
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


#: What :func:`atomic_write` writes: ``(path, write)`` or ``(path, write, binary)``.
_Write = Callable[[IO[Any]], Any]
FileWriter = tuple[str | os.PathLike, _Write] | tuple[str | os.PathLike, _Write, bool]


def atomic_write(files: Sequence[FileWriter], *, binary: bool = False, keep_mode: bool = False) -> list[Path]:
    """Write files all at once: each to a temporary name beside it, then all renamed into place.

    Parameters
    ----------
    files : sequence of (path, write) or (path, write, binary)
        ``write(fh)`` fills the open file ``fh``: text (UTF-8, ``newline=""``) or, when the item's
        third element (else ``binary``) is true, binary.
    binary : bool
        Open the files without their own flag in binary mode.
    keep_mode : bool
        A file that already exists keeps its permissions (else: those of a new file).

    Returns
    -------
    list of Path
        The written paths, in the order given.

    Raises
    ------
    OSError
        From the file system or from ``write``; then no file has been replaced and no temporary
        file is left.  Any exception of ``write`` (and an interrupt) is re-raised the same way.
    """
    temps: list[tuple[Path, Path]] = []
    try:
        for item in files:
            path, write, as_bytes = Path(item[0]), item[1], bool(item[2]) if len(item) > 2 else binary
            mode = path.stat().st_mode & 0o777 if keep_mode and path.exists() else _new_file_mode()
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            temps.append((path, Path(tmp)))
            opened = os.fdopen(fd, "wb") if as_bytes else os.fdopen(fd, "w", encoding="utf-8", newline="")
            with opened as fh:
                write(fh)
            os.chmod(tmp, mode)
        # only now, with every file complete, does any of them replace what was there
        for path, tmp in temps:
            os.replace(tmp, path)
    finally:
        for _, tmp in temps:
            if tmp.exists():
                tmp.unlink()
    return [path for path, _ in temps]


def json_ready(obj: Any, keep_nonfinite: bool = False) -> Any:
    """``obj`` with numpy scalars and arrays made plain Python, as ``json`` writes them.

    Dict keys become strings, tuples become lists; anything else is returned as it is.  NaN and infinity
    become None (JSON has neither: ``summary.json``, ``contin classify --json``), or stay as they are with
    ``keep_nonfinite`` (a bundle's header, :func:`write_bundle`: Python's ``json`` writes and reads them).
    """
    import numpy as np  # here, not at the top: an output directory or a refused scene needs no numpy

    if isinstance(obj, dict):
        return {str(k): json_ready(v, keep_nonfinite) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_ready(v, keep_nonfinite) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_ready(obj.tolist(), keep_nonfinite)
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if keep_nonfinite or math.isfinite(obj) else None
    return obj


class OutputDirectory:
    """An output directory, and the directories that creating it made (removed again if left empty).

    Attributes
    ----------
    path : Path
        The directory.
    created : list of Path
        The directories that did not exist before, deepest first.
    """

    def __init__(self, path: str | os.PathLike, *, reserved: Sequence[str] = ()) -> None:
        """Create ``path`` (and its parents) and check that a file can be written there.

        Parameters
        ----------
        path : str or PathLike
            The directory.
        reserved : sequence of str
            File names the run will write: each may not be a directory there (a file cannot
            replace a directory, and the others would then be half-updated).

        Raises
        ------
        OutputError
            Empty name, a file in the way, a reserved name that is a directory, a directory that
            cannot be created or written.
        """
        if not str(path):  # Path("") would be the current directory
            raise OutputError("the output directory name is empty; give a directory to write into")
        self.path = Path(path)
        if self.path.exists() and not self.path.is_dir():
            raise OutputError(f"the output directory {str(self.path)!r} exists and is not a directory; give a "
                              f"directory to write into")
        blocked = [name for name in reserved if (self.path / name).is_dir()]
        if blocked:
            raise OutputError(f"cannot write the outputs to {str(self.path)!r}: {', '.join(blocked)} "
                              f"{'is a directory' if len(blocked) == 1 else 'are directories'} there; move "
                              f"{'it' if len(blocked) == 1 else 'them'} away or give another output directory")
        missing = [p for p in (self.path, *self.path.parents) if not p.exists()]
        try:
            self.path.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"cannot create the output directory {str(self.path)!r}: "
                              f"{exc.strerror or exc}") from None
        self.created = [p for p in missing if p.is_dir()]
        try:
            fd, probe = tempfile.mkstemp(dir=self.path, prefix=".contin-probe.", suffix=".tmp")
            os.close(fd)
            os.unlink(probe)
        except OSError as exc:
            self.remove_if_empty()
            raise OutputError(f"the output directory {str(self.path)!r} is not writable: "
                              f"{exc.strerror or exc}") from None

    def remove_if_empty(self) -> None:
        """Remove the directories this object created, deepest first, as long as they are empty."""
        for p in self.created:
            try:
                p.rmdir()  # fails on a directory that holds anything: that one and its parents stay
            except OSError:
                break
        self.created = []


@contextlib.contextmanager
def output_directory(path: str | os.PathLike, *, reserved: Sequence[str] = ()) -> Iterator[Path]:
    """Context of a run that writes into ``path``: created on entry, removed on exit if left empty.

    See :class:`OutputDirectory` for the parameters and the errors (raised on entry).  Whatever ends
    the context (success, an error, an interrupt), a directory it created and nothing was written
    into is removed again.
    """
    out = OutputDirectory(path, reserved=reserved)
    try:
        yield out.path
    finally:
        out.remove_if_empty()


def _npz_path(path: str | os.PathLike) -> Path:
    path = Path(path)
    if path.suffix != ".npz":
        path = path.with_suffix(path.suffix + ".npz") if path.suffix else path.with_suffix(".npz")
    return path


def write_bundle(path: str | os.PathLike, fmt: str, header: dict[str, Any], arrays: dict[str, np.ndarray]) -> Path:
    """Write ``arrays`` and a JSON ``header`` (with ``"format": fmt``) to one ``.npz`` file, atomically.

    The suffix ``.npz`` is added when ``path`` lacks it; missing parent directories are created.
    Returns the path written.  The header must be JSON-serialisable (see :func:`json_ready`).
    """
    import json

    import numpy as np

    path = _npz_path(path)
    doc = dict(header, format=fmt)
    data = dict(arrays)
    data["header"] = np.frombuffer(json.dumps(doc).encode(), dtype=np.uint8)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write([(path, lambda fh: np.savez_compressed(fh, **data))], binary=True)
    return path


def read_bundle(path: str | os.PathLike, fmt: str,
                error: type[ResultFileError] = ResultFileError) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """Read a file written by :func:`write_bundle`: its header and arrays.

    Raises ``error`` (a :class:`ResultFileError`) naming the path when the file is missing,
    unreadable, or of another format than ``fmt``.
    """
    import json

    import numpy as np

    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
        header = json.loads(arrays.pop("header").tobytes().decode())
    except FileNotFoundError:
        raise error(f"{path}: no such file") from None
    except Exception as exc:  # zip, JSON and key errors all mean "corrupt"
        raise error(f"{path}: unreadable or corrupt file ({type(exc).__name__}: {exc})") from None
    if header.get("format") != fmt:
        raise error(f"{path}: not a {fmt} file (format {header.get('format')!r})")
    return header, arrays
