"""The largest membrane strain along traced branches, and the warning a run gives when it is large.

The shell's material law is linear in the engineering strains ``eps11 = l / lbar - 1`` and
``eps22 = r / rbar - 1`` (``docs/model.md#the-discrete-shell``), which is meaningful for strains of a few
per cent.  Most scenes stay well inside that range (the default scene: 0.076, at the base ring while
the cap passes through flat).  A point load is different: the pole is a singular point of the
continuum solution.  Its bending curvature grows like the logarithm of the mesh spacing there, and
the membrane strain of the last edges grows with N as well, while the strain at any fixed distance
from the axis converges (``docs/robustness.md``, "What remains").  Near eversion of a thick cap that
strain reaches order one on fine meshes, the pole region then deforms at the scale of the mesh, and
the path's extrema and even its class move with N.  The run cannot repair that (it is the point
load's idealisation, not a numerical fault), so it measures the strain and says so.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from contin.results.branch import Branch

__all__ = ["STRAIN_LIMIT", "StrainPeak", "strain_peak", "strain_warning"]

#: Largest membrane strain for which the linear material law is taken as meaningful.
STRAIN_LIMIT = 0.1

#: Edges this close to an end count as "at the pole" / "at the base" in the report.
_END_EDGES = 3


@dataclass(frozen=True)
class StrainPeak:
    """The largest ``|eps11|`` or ``|eps22|`` over every stored point of some branches.

    Attributes
    ----------
    value : float
        The strain (dimensionless).
    load : float
        The load observable (``w`` or ``w_b``) at the state where it occurs.
    edge : int
        The edge that carries it, counted from the base (``0``) to the pole (``n_edges - 1``).
    n_edges : int
        Number of edges of the meridian (``N - 1``).
    """

    value: float
    load: float
    edge: int
    n_edges: int

    @property
    def where(self) -> str:
        """``"pole"``, ``"base"`` or ``"interior"``."""
        if self.edge >= self.n_edges - _END_EDGES:
            return "pole"
        if self.edge < _END_EDGES:
            return "base"
        return "interior"


def strain_peak(problem: Any, branches: Sequence[Branch], load_name: str) -> StrainPeak | None:
    """The largest membrane strain over every stored point of ``branches``.

    Parameters
    ----------
    problem : ShellPointLoad or a contact problem
        The problem the branches were traced with: it maps unknowns to the full state
        (``full_state(u, p)``) and carries the shell energy (``shell``, or ``elastic.shell``).
    branches : sequence of Branch
        Traced branches (empty ones are skipped).
    load_name : str
        The observable reported as the load where the peak occurs (``"w"`` or ``"w_b"``).

    Returns
    -------
    StrainPeak or None
        None when no branch has a stored point.

    Raises
    ------
    FloatingPointError
        When a strain is not finite (a stored point is never allowed to carry a NaN).
    """
    shell = problem.shell if hasattr(problem, "shell") else problem.elastic.shell
    best: StrainPeak | None = None
    for br in branches:
        loads = br.observables.get(load_name)
        for k in range(len(br)):
            eps11, eps22 = shell.strains(problem.full_state(br.u[k], float(br.p[k])))
            size = np.maximum(np.abs(eps11), np.abs(eps22))
            edge = int(np.argmax(size))
            value = float(size[edge])
            if not np.isfinite(value):
                raise FloatingPointError(f"strain_peak: a non-finite strain at stored point {k} of a branch")
            if best is None or value > best.value:
                load = float(loads[k]) if loads is not None else float(br.p[k])
                best = StrainPeak(value, load, edge, size.size)
    return best


def strain_warning(peak: StrainPeak | None, R: float, point_load: bool, load_label: str = "w") -> str:
    """A one-line warning when ``peak`` exceeds :data:`STRAIN_LIMIT`, else ``""``.

    Parameters
    ----------
    peak : StrainPeak or None
        From :func:`strain_peak`.
    R : float
        Sphere radius (the load is reported as ``load / R``).
    point_load : bool
        Whether the load is a point force at the pole (adds the reason a pole peak grows with N).
    load_label : str
        Name of the load in the message.
    """
    if peak is None or peak.value <= STRAIN_LIMIT:
        return ""
    text = (f"the membrane strain reaches {peak.value:.3g} at the {peak.where if peak.where != 'interior' else 'edge'}"
            f"{'' if peak.where != 'interior' else f' {peak.edge} of {peak.n_edges}'} ({load_label}/R = "
            f"{peak.load / R:.4g}), beyond {STRAIN_LIMIT:g}, the range of the model's linear material law")
    if point_load and peak.where == "pole":
        text += ("; under a point load the strain at the pole grows as the mesh is refined (the pole is a singular "
                 "point of the solution), so results near there can change with N: compare with a finer mesh, or "
                 "spread the load with a sphere indenter (load.kind = \"sphere\")")
    return text
