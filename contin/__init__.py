"""contin: pseudo-arclength continuation and bifurcation analysis.

The engine is generic: a :class:`Problem` gives a residual ``f(u, p)``, its sparse Jacobian and
``df/dp`` (and, for conservative models, an energy whose Hessian is the Jacobian).
:func:`continuation` traces a branch and returns a :class:`Branch` with located folds, branch
points and events; :func:`jump` finds the stable state a snap lands on; :func:`diagram` assembles
branches and jumps into a ``networkx`` graph.

Where each part of the engine lives:

==================  ===============================================================================
``problem``         the model interface (:class:`Problem`, stability operators, :class:`LeadingBlock`)
``settings``        :class:`Settings` and their ranges
``palc``            the continuation loop (:func:`continuation`, :func:`switch_branch`)
``curve``           the curve ``f = 0``: arclength metric, linearization, tangent, :class:`~contin.curve.Point`
``corrector``       predictors and the PALC corrector (:class:`~contin.corrector.Correction`)
``stepsize``        the step-size controller
``testfunctions``   what a branch watches: folds, branch points, events, bounds (one protocol)
``segment``         the curve between two accepted points, where special points are located
``fold``            fold location by the minimally augmented system (also used by ``twopar``)
``recorder``        accepted points, their stability, special points -> :class:`Branch`
``branch``          results as data (:class:`Branch`, :class:`SpecialPoint`), saved and loaded
``events``          user events (:func:`crossing`, :func:`extremum`)
``stability``       Morse index and smallest eigenvalues of symmetric operators
``linalg``          factorizations and bordered solves
``jump``            snaps to a stable state at fixed load
``quasistatic``     load to a fold, snap, resume
``diagram``         bifurcation diagrams as graphs, and plots
``twopar``          fold curves in a second parameter
==================  ===============================================================================
"""

from .branch import Branch, BranchFileError, SpecialPoint
from .events import Event, crossing, extremum
from .linalg import BorderedSolver, factorize
from .diagram import diagram, hysteresis_cycles, plot_branches
from .jump import JumpError, JumpResult, jump
from .palc import CorrectorFailure, continuation, locate_fold, switch_branch
from .problem import LeadingBlock, NonFiniteError, Problem
from .settings import Settings, SettingsError
from .quasistatic import QuasiStaticResult, quasistatic, restate_jump
from .stability import StabilityInfo, stability_info
from .twopar import FamilyProblem, FoldCurveProblem, cusp_curve_problem

__version__ = "0.1.0"

__all__ = [
    "Problem", "LeadingBlock", "NonFiniteError", "Settings", "SettingsError",
    "continuation", "locate_fold", "switch_branch", "CorrectorFailure",
    "jump", "JumpResult", "JumpError", "diagram", "hysteresis_cycles", "plot_branches",
    "Branch", "BranchFileError", "SpecialPoint", "Event", "crossing", "extremum",
    "FoldCurveProblem", "FamilyProblem", "cusp_curve_problem",
    "StabilityInfo", "stability_info", "BorderedSolver", "factorize", "quasistatic", "QuasiStaticResult", "restate_jump",
]
