"""Build of the optional C extensions; everything else is declared in pyproject.toml.

Generated C (from the committed numpy kernels, see each generator's ``python -m``):
``contin_models.shell._ckernels``, ``contin_models.shell._harmonic_ckernels`` and
``contin_models.shell._density_ckernels`` (``contin_models.shell.codegen``, ``contin_models.shell.harmonic_codegen``,
``contin_models.shell.density_codegen``) hold the shell's element kernels, the harmonic blocks' local
Hessian kernels and the 2-D densities' jets at general states, ``contin_models.contact._ckernels``
(``contin_models.contact.codegen``) the contact barrier's point kernels.  Hand-written C: ``contin.numerics._banded`` holds the tridiagonal LU of
:class:`contin.numerics.linalg.TridiagonalLU` and the pivot-free banded ``L D L^T`` of
:meth:`contin.numerics.linalg.SymmetricBand.negative_pivots`, ``contin_models.contact._cbarrier`` the contact
barrier's support integration, chain rule and step filter.  They are optional: where no C compiler
is found the install still succeeds and the same steps run in numpy (``contin_models.shell.energy.COMPILED``,
``contin_models.shell.harmonic.COMPILED``, ``contin_models.shell.density_kernels.COMPILED``,
``contin_models.contact.barrier.COMPILED`` and
:func:`contin_models.contact.barrier.barrier_extension` tell which ones run) and the engine LAPACK.
"""

from setuptools import Extension, setup

_FLAGS = ["-O2", "-fno-fast-math"]

_EXTENSIONS = {"contin_models.shell._ckernels": "models/shell/_ckernels.c",
               "contin_models.shell._harmonic_ckernels": "models/shell/_harmonic_ckernels.c",
               "contin_models.shell._density_ckernels": "models/shell/_density_ckernels.c",
               "contin.numerics._banded": "contin/numerics/_banded.c",
               "contin_models.contact._ckernels": "models/contact/_ckernels.c",
               "contin_models.contact._cbarrier": "models/contact/_cbarrier.c"}

setup(ext_modules=[Extension(name, [source], optional=True, extra_compile_args=_FLAGS)
                   for name, source in _EXTENSIONS.items()])
