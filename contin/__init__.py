"""contin: pseudo-arclength continuation and bifurcation analysis.

The engine is generic: a :class:`Problem` gives a residual ``f(u, p)``, its sparse Jacobian and
``df/dp`` (and, for conservative models, an energy whose Hessian is the Jacobian).
:func:`continuation` traces a branch and returns a :class:`Branch` with located folds, branch
points and events; :func:`jump` finds the stable state a snap lands on; :func:`diagram` assembles
branches and jumps into a ``networkx`` graph.  Every public name is imported from here
(``contin.continuation``, ``contin.Branch``, ...); the subpackages are where they live.

The engine is built in layers, each importing only from the layers below it, bottom first
(``tests/test_engine_layers.py`` holds this order and checks every import against it, those inside
functions too):

=========================  ===========================================================================================
``lazy``                   public names imported on first use (this ``__init__``, which also holds the version)
``numerics/``              linear algebra: factorizations, bordered solves, inertia and eigenvalues, C extensions
``settings``, ``problem``  the vocabulary a user writes: :class:`Settings`, the model interface :class:`Problem`
``results/``               results as data: :class:`Branch`, :class:`SpecialPoint`, result files
``path/``                  the curve ``f = 0``, predictor and corrector, step-size control, segments between points
``modelkit/``              writing a model: energy-first models, code generation, derivative checks
``watch/``                 what a branch watches: folds, branch points, events, bifurcations into other modes
``recorder``, ``palc``     the driver: the continuation loop (:func:`continuation`, :func:`switch_branch`), its record
``analyses/``              jumps, quasi-static sweeps, fold curves, load controls, diagrams as graphs
``plot/``                  figures: the only place matplotlib is imported
``app/``                   the ``contin`` command: scenes, sweeps, restarts, saved runs and their figures
``launch``, ``__main__``   the console script's entry, ``python -m contin`` (nothing heavy: Ctrl-C is an interrupt)
=========================  ===========================================================================================

Why these modules stay at the top: ``settings`` and ``problem`` are what a user imports to state a
problem, and everything from the path up is written against them; ``palc`` is the driver every analysis
and the command line call, and ``recorder`` is its own bookkeeping (it needs the watch's operator
families, so it cannot live with the results it fills); ``lazy``, ``launch`` and ``__main__`` are how the
package and its command start without loading the engine.  Where each part lives:

========================  =========================================================================================
``problem``               the model interface (:class:`Problem`; stability operators, :class:`LeadingBlock`)
``settings``              :class:`Settings` and their ranges
``palc``                  the continuation loop (:func:`continuation`, the switches :func:`switch_branch` and its ``_along``)
``recorder``              accepted points, their stability, special points -> :class:`Branch`
``numerics.linalg``       factorizations and bordered solves
``numerics.stability``    Morse index and smallest eigenvalues of symmetric operators
``numerics.compiled``     C extensions where built (``numerics/_banded.c``), numpy elsewhere
``numerics.threads``      one BLAS thread, set before numpy loads
``results.branch``        results as data (:class:`Branch`, :class:`SpecialPoint`), saved and loaded
``results.io``            atomic writes of output files, JSON conversion, bundles
``path.curve``            the curve ``f = 0``: metric, linearization, tangent, :class:`~contin.path.curve.Point`
``path.scales``           the state and load scales a run measures at its start, from its sizes and its stiffness
``path.corrector``        predictors and the PALC corrector (:class:`~contin.path.corrector.Correction`)
``path.stepsize``         the step-size controller
``path.segment``          the curve between two accepted points, where special points are located
``modelkit.energy``       energy-first models: :class:`EnergyProblem` assembles generated element kernels
``modelkit.codegen``      sympy element energies -> numpy (and C) kernels (:func:`generate_kernels`), their checks
``modelkit.check``        derivatives of a model against finite differences of its residual (:func:`check_problem`)
``watch.testfunctions``   what a branch watches: folds, branch points, events, bounds (one protocol)
``watch.modes``           families of stability operators (:class:`OperatorFamily`): bifurcations into other modes
``watch.fold``            fold location by the minimally augmented system (also used by ``analyses.twopar``)
``watch.events``          user events (:func:`crossing`, :func:`extremum`)
``watch.watchlist``       the test functions of one run
``watch.multiple``        changes of the Morse index the test functions miss: multiple points, branch jumps
``watch.koiter``          Koiter's coefficients at a simple branch point (:func:`koiter_coefficients`)
``watch.branching``       the branches through a multiple point: the equivariant branching lemma, the reduced equation
``analyses.jump``         snaps to a stable state at fixed load
``analyses.quasistatic``  load to a fold, snap, resume
``analyses.twopar``       fold curves in a second parameter
``analyses.deadload``     force control of a displacement-controlled problem (one bordered row)
``analyses.conjugate``    displacement control of a force-controlled problem (the load a Lagrange multiplier)
``analyses.diagram``      bifurcation diagrams as ``networkx`` graphs
``analyses.autodiagram``  automatic diagrams: switching at every branch point to a depth, repeats and copies merged
``analyses.deflation``    solutions no traced branch reaches (:func:`deflate`), and the branches through them
``analyses.lift``         a located bifurcation carried into another problem and located there again (:class:`Lift`)
``plot.branches``         plots of branches, their special points and snaps (:func:`plot_branches`)
``plot.framing``          the part of a diagram with its snaps, as a detail panel or limited axes
``plot.style``            the project's figure style
``app.cli``               the ``contin`` command line
``app.scene``             declarative scene schemas, validation, trace and classification results
``app.registry``          the models registered as ``contin.models`` entry points
``app.sweep``             sweeps over scene keys; ``app.executors`` run them in parallel
``app.restart``           runs started again from a saved run's states
``app.saved``             saved runs read back; ``app.figures`` draws the command line's figures
``launch``                the console script's entry
``lazy``                  packages whose public names are imported on first use (this one, the models')
========================  =========================================================================================
"""

from .lazy import lazy_exports

__version__ = "0.1.0"

#: Public name -> the engine module that defines it.  The names are imported on first use (PEP 562,
#: :mod:`contin.lazy`), so ``import contin`` (and ``contin.launch``, the console script's entry) costs
#: nothing until an engine function is touched: ``contin --help`` and a refused scene need neither numpy
#: nor the engine.
_EXPORTS: dict[str, str] = {
    **dict.fromkeys(("Bifurcation", "Branch", "BranchFileError", "SpecialPoint"), "results.branch"),
    **dict.fromkeys(("CheckReport", "ModelCheckError", "check_problem"), "modelkit.check"),
    **dict.fromkeys(("Event", "crossing", "extremum"), "watch.events"),
    **dict.fromkeys(("Element", "check_generated", "compile_kernels", "generate_kernels"), "modelkit.codegen"),
    **dict.fromkeys(("EnergyProblem", "GradientProblem"), "modelkit.energy"),
    **dict.fromkeys(("BorderedSolver", "factorize"), "numerics.linalg"),
    **dict.fromkeys(("diagram", "hysteresis_cycles", "load_diagram"), "analyses.diagram"),
    **dict.fromkeys(("AutoDiagram", "SwitchAttempt", "auto_diagram"), "analyses.autodiagram"),
    "plot_branches": "plot.branches", "save_diagram": "analyses.diagram",
    **dict.fromkeys(("JumpError", "JumpResult", "jump"), "analyses.jump"),
    **dict.fromkeys(("CorrectorFailure", "continuation", "locate_fold", "switch_branch", "switch_branch_along"),
                     "palc"),
    **dict.fromkeys(("Constrained", "LeadingBlock", "NonFiniteError", "Problem"), "problem"),
    **dict.fromkeys(("ConjugateControl", "LoadConjugate"), "analyses.conjugate"),
    **dict.fromkeys(("OperatorFamily", "family_counts"), "watch.modes"),
    **dict.fromkeys(("Settings", "SettingsError"), "settings"),
    **dict.fromkeys(("QuasiStaticResult", "quasistatic", "restate_jump"), "analyses.quasistatic"),
    **dict.fromkeys(("KoiterCoefficients", "koiter_coefficients"), "watch.koiter"),
    **dict.fromkeys(("DeflatedBranches", "DeflationAttempt", "DeflationResult", "DeflationSettings", "deflate",
                     "deflated_branches"), "analyses.deflation"),
    **dict.fromkeys(("StabilityInfo", "stability_info"), "numerics.stability"),
    **dict.fromkeys(("Lift", "LiftError", "lift_branch_point"), "analyses.lift"),
    **dict.fromkeys(("FamilyProblem", "FoldCurveProblem", "cusp_curve_problem"), "analyses.twopar"),
}

__all__ = list(_EXPORTS)

lazy_exports(__name__, _EXPORTS)
