"""Build of the optional C extensions; everything else is declared in pyproject.toml.

``contin_models.shell._ckernels`` and ``contin_models.shell._harmonic_ckernels`` (generated C, see
``python -m contin_models.shell.codegen`` and ``python -m contin_models.shell.harmonic_codegen``) hold
the shell's element kernels and the harmonic blocks' local Hessian kernels; ``contin._banded``
(hand-written) the tridiagonal LU of :class:`contin.linalg.TridiagonalLU` and the pivot-free banded
``L D L^T`` of :meth:`contin.linalg.SymmetricBand.negative_pivots`.  They are optional: where
no C compiler is found the install still succeeds and the shell uses the same kernels in numpy
(``contin_models.shell.energy.COMPILED`` and ``contin_models.shell.harmonic.COMPILED`` tell which
ones run) and the engine LAPACK.
"""

from setuptools import Extension, setup

_FLAGS = ["-O2", "-fno-fast-math"]

setup(ext_modules=[Extension(f"contin_models.shell.{name}", [f"models/shell/{name}.c"], optional=True,
                             extra_compile_args=_FLAGS)
                   for name in ("_ckernels", "_harmonic_ckernels")]
      + [Extension("contin._banded", ["contin/_banded.c"], optional=True, extra_compile_args=_FLAGS)])
