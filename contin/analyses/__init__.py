"""Analyses built on continuation: snaps, sweeps, fold curves, load controls and diagrams.

===============  ==========================================================================================
``jump``         snaps to a stable state at fixed load
``quasistatic``  load to a fold, snap, resume (the one load-snap loop)
``twopar``       fold curves in a second parameter
``deadload``     force control of a displacement-controlled problem (one bordered row)
``conjugate``    displacement control of a force-controlled problem (the load a Lagrange multiplier)
``diagram``      bifurcation diagrams as ``networkx`` graphs of branches and jumps
===============  ==========================================================================================
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
