"""Writing and checking a generated kernel module: shared by the models' sympy generators.

Each generator (``contin_models.shell.codegen``, ``contin_models.contact.codegen``) builds its module's text with
a ``generate_source()`` function that joins its parts with :func:`module_text`;
:func:`write_generated` writes it and :func:`generator_main` is the command line (``--output``,
``--check``).  ``module_text``, ``write_generated`` and the check are the engine's
(:mod:`contin.codegen`, shared with the energy-first tools), re-exported here.  No sympy here: it
only handles the text.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

from contin.codegen import GeneratedFileOutOfDate, check_generated, module_text, write_generated

__all__ = ["module_text", "write_generated", "generator_main"]


def generator_main(argv: list[str] | None, generate_source: Callable[[], str], default_output: Path, prog: str,
                   description: str) -> int:
    """Command line of a generator: write the module, or with ``--check`` exit 1 if it is out of date.

    Parameters
    ----------
    argv : list of str or None
        Arguments (``None``: ``sys.argv[1:]``).
    generate_source : callable
        Returns the full text of the generated module.
    default_output : Path
        The committed generated file.
    prog, description : str
        For the help text (``prog`` is also the command the out-of-date message suggests).

    Returns
    -------
    int
        The exit status.
    """
    parser = argparse.ArgumentParser(prog=prog, description=description)
    parser.add_argument("--output", type=Path, default=default_output, help="file to write")
    parser.add_argument("--check", action="store_true",
                        help="do not write; exit 1 if the file differs from what would be generated")
    args = parser.parse_args(argv)
    if args.check:
        try:
            check_generated(generate_source, args.output, prog)
        except GeneratedFileOutOfDate as exc:
            print(exc, file=sys.stderr)
            return 1
        return 0
    write_generated(generate_source, args.output)
    return 0
