"""contin: pseudo-arclength continuation and bifurcation analysis.

The engine is generic: a :class:`Problem` gives a residual ``f(u, p)``, its sparse Jacobian and
``df/dp`` (and, for conservative models, an energy whose Hessian is the Jacobian).
:func:`continuation` traces a branch and returns a :class:`Branch` with located folds, branch
points and events; :func:`jump` finds the stable state a snap lands on; :func:`diagram` assembles
branches and jumps into a ``networkx`` graph.
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
    "Problem", "LeadingBlock", "NonFiniteError", "Settings", "SettingsError", "continuation", "locate_fold", "switch_branch", "CorrectorFailure",
    "jump", "JumpResult", "JumpError", "diagram", "hysteresis_cycles", "plot_branches",
    "Branch", "BranchFileError", "SpecialPoint", "Event", "crossing", "extremum", "FoldCurveProblem", "FamilyProblem", "cusp_curve_problem",
    "StabilityInfo", "stability_info", "BorderedSolver", "factorize", "quasistatic", "QuasiStaticResult", "restate_jump",
]
