"""Numerics: the linear algebra under every layer above.

==============  ===========================================================================================
``linalg``      factorizations (sparse, banded, arrow, dense) and bordered solves
``stability``   the Morse index and smallest eigenvalues of symmetric operators, from their inertia
``compiled``    C extensions where the install built them, numpy elsewhere (:func:`prefer_compiled`)
``threads``     one BLAS thread for continuation: the environment it sets before numpy loads
``_banded.c``   the tridiagonal LU and the pivot-free band ``L D L^T`` in C (built by ``setup.py``)
==============  ===========================================================================================
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
