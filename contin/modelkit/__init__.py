"""The model kit: what a model's author uses to write a :class:`contin.Problem` and to check it.

============  =============================================================================================
``energy``    energy-first models: :class:`EnergyProblem` assembles generated element kernels
``codegen``   element energies in sympy -> numpy kernels and their C, byte-for-byte checks (sympy on demand)
``check``     a model's derivatives against finite differences of its residual (:func:`check_problem`)
============  =============================================================================================
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
