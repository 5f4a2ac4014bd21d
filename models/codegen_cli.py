"""Writing and checking a generated kernel module: shared by the models' sympy generators.

Each generator (``contin_models.shell.codegen``, ``contin_models.contact.codegen``) builds its module's text with
a ``generate_source()`` function that joins its parts with :func:`module_text`;
:func:`write_generated` writes it and :func:`generator_main` is the command line (``--output``,
``--check``).  No sympy here: it only handles the text.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

__all__ = ["module_text", "write_generated", "generator_main"]


def module_text(preamble: str, exported: list[str], constants: str, chunks: list[str]) -> str:
    """Join the parts of a generated module: preamble, ``__all__``, constants, then the kernels.

    Parameters
    ----------
    preamble : str
        Module docstring and imports.
    exported : list of str
        Public names; ``__all__`` lists them sorted.
    constants : str
        Module-level constants with their docstrings.
    chunks : list of str
        Source of each generated function.

    Returns
    -------
    str
        The module text: parts separated by two blank lines, ending with one newline.
    """
    exports = "__all__ = [\n" + "".join(f'    "{f}",\n' for f in sorted(exported)) + "]"
    return "\n\n\n".join([preamble.rstrip("\n"), exports, constants, *chunks]) + "\n"


def write_generated(generate_source: Callable[[], str], path: str | Path | None) -> str:
    """Generate the module text and write it to ``path`` (``None``: only return it).

    Parameters
    ----------
    generate_source : callable
        Returns the full text of the generated module.
    path : str or Path or None
        Output file, written with ``\\n`` line endings so that regeneration is byte-identical.

    Returns
    -------
    str
        The generated source.
    """
    text = generate_source()
    if path is not None:
        Path(path).write_text(text, encoding="utf-8", newline="\n")
    return text


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
        text = write_generated(generate_source, None)
        current = args.output.read_text(encoding="utf-8") if args.output.exists() else None
        if current != text:
            print(f"{args.output} is out of date; run {prog}", file=sys.stderr)
            return 1
        return 0
    write_generated(generate_source, args.output)
    return 0
