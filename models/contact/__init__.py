"""Contact of the axisymmetric shell with a rigid indenter (paper section 3(b)): log barrier.

:class:`ContactBarrier` evaluates the barrier of eq. 3.16 between every shell node and a
:class:`Sphere` or :class:`Plate` indenter on the interleaved full state, with exact gradients and
Hessians (also with respect to the indenter position), the contact force on the indenter and an
incremental-potential-contact step filter (:meth:`ContactBarrier.max_safe_fraction`).
:func:`default_barrier` scales the paper's ``K_c = 1e8``, ``dhat = 1e-3`` with ``E`` and ``R``.

The kernels come from :mod:`contin_models.contact._generated`, plain numpy emitted by
``python -m contin_models.contact.codegen`` (the only module that needs sympy; it is not imported here),
and run as the C extension ``contin_models.contact._ckernels`` generated from them where the install
built it; the work per state around them (the support of the barrier integral, the chain rule, the
step filter) runs in ``contin_models.contact._cbarrier`` likewise (numpy elsewhere, the same numbers).
"""

from .barrier import (PAPER_DHAT, PAPER_E, PAPER_K, PAPER_R, ContactBarrier, ContactState, Plate, Sphere,
                      barrier_value, default_barrier)

__all__ = ["ContactBarrier", "ContactState", "PAPER_DHAT", "PAPER_E", "PAPER_K", "PAPER_R", "Plate", "Sphere",
           "barrier_value", "default_barrier"]
