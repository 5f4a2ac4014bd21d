"""What a branch watches: the test functions that detect and locate its special points.

=================  ========================================================================================
``testfunctions``  the protocol (:class:`TestFunction`), folds, branch points, events and bounds
``modes``          families of stability operators: bifurcations into other modes
``fold``           folds located on the minimally augmented system (also used by ``contin.analyses.twopar``)
``events``         user events (:func:`crossing`, :func:`extremum`)
``watchlist``      the test functions of one run, from its settings, events and problem
``multiple``       changes of the Morse index the test functions do not explain: multiple points, jumps
``koiter``         initial post-buckling at a simple branch point (Koiter's ``a`` and ``b``)
``branching``      the branches through a multiple point: by the declared symmetry, or the reduced equation
=================  ========================================================================================
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
