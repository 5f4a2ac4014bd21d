"""The 2-D densities' jets at general states, in C where the extension was built: :data:`kernels`, :data:`COMPILED`.

The kernels of :mod:`contin_models.shell._density_generated` (``<name>_jet(y, *params)``, value, gradient
and Hessian of a density in its local variables, see :mod:`contin_models.shell.density_codegen`) with the
C extension ``contin_models.shell._density_ckernels`` in their place where it imports
(:func:`contin.numerics.compiled.prefer_compiled`).  Either way a kernel takes ``y`` as a ``(k, ...)``
array (``(k, E, Q)`` for ``E`` elements at ``Q`` angles, ``(k, m)``, or ``(k,)`` for one station) and
its parameters as numbers or arrays that broadcast to the station shape ``y.shape[1:]``, and returns
the value ``(...)``, the gradient ``(k, ...)`` and the Hessian ``(k, k, ...)`` (numbers and small arrays
for one station).

The compiled kernels run over the stations four at a time where the processor has AVX2, two at a time
where the compiler has vector types, the last ones one by one (each station the same operations in
the same order, so the same bits whichever way it is computed; ``tests/test_compiled_vectors.py``): the
namespace passes each of the ``k`` variables and each array parameter flattened over the stations,
copying those that are not contiguous and broadcasting parameters given per element, say, to every
station first.  An input the
extension does not take (not float64, a ``y`` of another first extent) is computed by the numpy
kernel; the two give the same numbers to rounding (``tests/test_compiled_kernels.py``).
"""

from __future__ import annotations

from contin.numerics.compiled import prefer_compiled

from . import _density_generated

__all__ = ["kernels", "COMPILED", "KERNELS"]

kernels, COMPILED = prefer_compiled(_density_generated, "contin_models.shell._density_ckernels")
"""``kernels``: a namespace holding every kernel of :mod:`contin_models.shell._density_generated` under its
name (``kernels.bend_cur_jet(y, lbar, rbar, k11bar, k22bar, kb, nu)``); ``COMPILED``: whether they run in
C (False where the extension was not built or ``CONTIN_COMPILED=0``)."""

#: Every kernel's name (:data:`contin_models.shell._density_generated.KERNELS`).
KERNELS = _density_generated.KERNELS
