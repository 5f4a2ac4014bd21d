"""The path: the curve ``f(u, p) = 0`` and how the continuation steps along it.

=============  ============================================================================================
``curve``      the curve's metric, linearization, tangent and :class:`~contin.path.curve.Point`
``scales``     the state and load scales of the metric, measured at a start from its sizes and stiffness
``corrector``  predictors and the pseudo-arclength corrector
``stepsize``   the step-size controller
``segment``    the curve between two accepted points, where special points are located
=============  ============================================================================================
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
