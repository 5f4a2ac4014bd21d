"""One BLAS thread for the continuation: the environment variables that set it, and their defaults.

The engine's linear algebra is banded and sparse, and its dense calls are level-1 BLAS on vectors of
the size of the state (inner products, norms).  OpenBLAS runs those on every core once a vector has
more than about ten thousand entries, and each call then waits for the other threads to wake: a
hundred microseconds where one thread takes two, thousands of times a step, and worse when the other
cores are busy.  One thread per process is the engine's setting: the
``contin`` command defaults to it (:func:`default_to_one_thread`, before numpy is loaded), the local
worker processes of :mod:`contin.app.executors` get it, and the studies and the tests set it.  A
variable the user has set is left as it is.

This module imports nothing but :mod:`os`: the command's launcher uses it before anything else.
"""

from __future__ import annotations

import os

__all__ = ["THREAD_ENV", "default_to_one_thread"]

#: The thread counts of the BLAS and OpenMP libraries numpy and scipy may be built with.
THREAD_ENV = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
              "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")


def default_to_one_thread() -> None:
    """Set every variable of :data:`THREAD_ENV` that is not set to ``"1"``.

    It takes effect only if numpy (and with it the BLAS library) is not imported yet.
    """
    for var in THREAD_ENV:
        os.environ.setdefault(var, "1")
