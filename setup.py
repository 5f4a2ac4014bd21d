"""Build of the optional C extension; everything else is declared in pyproject.toml.

``contin_models.shell._ckernels`` (generated C, see ``python -m contin_models.shell.codegen``) holds the
shell's fast element kernels.  It is optional: where no C compiler is found the install still
succeeds and the shell uses the same kernels in numpy (``contin_models.shell.energy.COMPILED`` tells
which ones run).
"""

from setuptools import Extension, setup

setup(ext_modules=[Extension("contin_models.shell._ckernels", ["models/shell/_ckernels.c"], optional=True,
                             extra_compile_args=["-O2", "-fno-fast-math"])])
