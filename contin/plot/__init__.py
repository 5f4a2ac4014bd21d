"""Plotting: the only part of the engine that imports matplotlib.  It reads results, never computes them.

============  =============================================================================================
``branches``  branches drawn smooth, stable solid and unstable dashed, special points and snaps marked
``framing``   the part of a diagram worth looking at (its snaps), as a detail panel or limited axes
``style``     one look for every figure: rcParams, sizes, colours, markers, writing PNG and PDF
============  =============================================================================================
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
