"""From the axisymmetric trace's bifurcation into ``n`` waves onto the ``n``-wave branch, in the 3-D view.

The traced model of a shell of revolution (:class:`~contin_models.shell.structure.ShellOfRevolution`, or the
paper's :class:`~contin_models.shell.problem.ShellPointLoad`) watches the harmonic blocks and locates a
bifurcation into ``n`` waves as a ``"bifurcation"`` of the operator family ``"n"`` with ``info["key"] == n``
and the block's null vector in ``info["mode"]``.  In the 3-D view restricted to ``D_n``
(:class:`~contin_models.shell.problem3d.Shell3D` with ``AngularBasis(n, K)``) the same point is a simple branch
point of the traced class: its kernel is the ``cos n theta`` mode alone.

:func:`shell_lift` is the :class:`contin.analyses.lift.Lift` between the two: the state through
:meth:`~contin_models.shell.fourier.FourierShell.axisymmetric_state`, the parameter unchanged, the mode's
per-node amplitudes ``(a, b, c)`` (the family's ``mode_shape``,
:func:`~contin_models.shell.harmonic.harmonic_mode`) onto the coefficients of ``R cos n theta``,
``Z cos n theta`` and ``T sin n theta`` (:meth:`~contin_models.shell.fourier.FourierShell.dofs_of_wave`).
:func:`follow_waves` does the whole step: lift, re-locate (the view integrates the angle exactly on
quadratic forms about an axisymmetric state, so the point does not move beyond the tolerances), switch,
trace, without tracing the axisymmetric path again in 3-D.

The two halves of the pitchfork
-------------------------------
The rotation by ``pi / n`` about the axis maps ``D_n``-symmetric states to ``D_n``-symmetric states (it maps
the mirror planes of ``D_n`` onto each other) and fixes the axisymmetric branch, while it turns
``cos(k n theta)`` and ``sin(k n theta)`` into ``(-1)^k`` times themselves.  It therefore maps the mode to minus
itself, and the branch that leaves along ``+mode`` onto the one that leaves along ``-mode``, for every ``n``
(odd or even): the two halves are one branch seen from two angles, with the same load, deflection and
stability, and the coefficients of the odd multiples of ``n`` reversed.  :func:`follow_waves` traces the
``+1`` half (:func:`rotated_half` gives the other).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from contin.analyses.lift import Lift, LiftError, lift_branch_point
from contin.problem import Problem
from contin.results.branch import Branch, SpecialPoint

from .fourier import AngularBasis
from .problem3d import Shell3D

__all__ = ["shell_lift", "follow_waves", "rotated_half", "WavesBranch"]


def _harmonic_family(source: Problem) -> Any:
    for fam in getattr(source, "operator_families", ()) or ():
        if fam.name == "n":
            return fam
    raise LiftError("shell_lift: the source problem watches no harmonic blocks (operator family 'n'): build it "
                    "with harmonics (ShellOfRevolution(..., harmonics=n_max), or the scene's stability.harmonics)")


def shell_lift(source: Problem, target: Shell3D, n: int) -> Lift:
    """The lift of an axisymmetric shell problem's bifurcation into ``n`` waves into the 3-D view ``target``.

    Parameters
    ----------
    source : Problem
        The traced axisymmetric model: its ``full_state(u, p)`` is the structure's state ``[r_0, z_0, ...]``
        and it watches the harmonic blocks (operator family ``"n"``).
    target : Shell3D
        The 3-D view of the same structure, load and control, in a basis that carries the wave ``n``
        (``AngularBasis(n, K)``: the ``D_n`` class).
    n : int
        The bifurcation's wave number (``info["key"]``), ``>= 1``.

    Returns
    -------
    Lift
        ``state``: ``target.unknowns(view.axisymmetric_state(source.full_state(u, p)))``; ``parameter``
        unchanged; ``mode``: the block's null vector onto ``R cos n theta``, ``Z cos n theta``,
        ``T sin n theta``; ``family = "n"``, ``key = n``.

    Raises
    ------
    LiftError
        ``n`` is not a wave of the target's basis, the two problems' parameters or meshes differ, or the
        source watches no harmonic blocks.
    """
    n = int(n)
    view = target.view
    waves = [int(k) for k in target.basis.wave_numbers.tolist() if k > 0]
    if n < 1 or n not in waves or target.basis.parity != "even":
        raise LiftError(f"shell_lift: a bifurcation into n = {n} waves needs a symmetric basis that carries "
                        f"cos({n} theta); the target's basis {target.basis!r} carries the waves {waves}")
    if source.parameter_name != target.parameter_name:
        raise LiftError(f"shell_lift: the source's parameter is {source.parameter_name!r} but the target's "
                        f"{target.parameter_name!r}: build the 3-D view with the same load and control")
    family = _harmonic_family(source)
    if family.mode_shape is None:
        raise LiftError("shell_lift: the source's harmonic family has no mode_shape to read its modes with")
    dofs = view.dofs_of_wave(n)

    def state(u: np.ndarray, p: float) -> np.ndarray:
        x = np.asarray(source.full_state(u, p), dtype=float)
        if x.shape != (2 * view.N,):
            raise LiftError(f"shell_lift: the source's state has {x.size} entries, the 3-D view's mesh {2 * view.N}: "
                            "the two problems must share the structure's mesh")
        return target.unknowns(view.axisymmetric_state(x))

    def mode(vector: np.ndarray) -> np.ndarray:
        amplitudes = np.asarray(family.mode_shape(n, vector), dtype=float)   # (N, 3): a, b, c per node
        c = np.zeros(view.size)
        c[dofs] = amplitudes.reshape(-1)
        return target.unknowns(c)

    return Lift(state=state, mode=mode, family="n", key=n, name=f"shell_lift(n = {n})")


@dataclass
class WavesBranch:
    """The ``n``-wave branch followed from the axisymmetric trace's bifurcation (:func:`follow_waves`).

    Attributes
    ----------
    problem : Shell3D
        The 3-D view it was traced in (``AngularBasis(n, K)``).
    branch_point : SpecialPoint
        The lifted branch point, re-located on :attr:`problem` (``info["moved_p"]``, ``info["mode_angle"]``).
    branch : Branch
        The ``+1`` half of the ``n``-wave branch, from the branch point.
    """

    problem: Shell3D
    branch_point: SpecialPoint
    branch: Branch


def follow_waves(source: Problem, point: SpecialPoint, K: int = 2, *, structure: Any = None,
                 settings: Any = None, **overrides: Any) -> WavesBranch:
    """Follow the ``n``-wave branch from the axisymmetric trace's located bifurcation into ``n`` waves.

    The point is lifted into the 3-D view in the ``D_n`` basis with ``K`` harmonics (:func:`shell_lift`),
    re-located there (:func:`contin.analyses.lift.lift_branch_point`) and the ``+1`` half of the
    bifurcating branch traced by :func:`contin.switch_branch`; the ``-1`` half is its image under the
    rotation by ``pi / n`` (module docstring, :func:`rotated_half`).  The axisymmetric path is not traced
    again in 3-D.

    Parameters
    ----------
    source : Problem
        The traced axisymmetric model that located ``point``: a
        :class:`~contin_models.shell.structure.ShellOfRevolution` with ``harmonics``, or the paper's
        :class:`~contin_models.shell.problem.ShellPointLoad` given the harmonic blocks
        (:func:`contin_models.shell_scene.build.watch_harmonics`).
    point : SpecialPoint
        A located ``"bifurcation"`` of the family ``"n"`` on the source's branch (its key is ``n``).
    K : int
        Harmonics of the 3-D view above ``0`` (waves ``0, n, ..., K n``), ``>= 1``.
    structure : ShellStructure, optional
        The structure whose energy the source's is; default ``source.structure`` (a shell of revolution).
        For the paper's point-load model give :func:`contin_models.shell_scene.build.traced_structure`'s.
    settings : contin.Settings, optional
        Settings of the branch's trace; ``overrides`` as :func:`contin.switch_branch` takes them (``p_max``,
        ``ds``, ``stability``, ...).

    Returns
    -------
    WavesBranch
        The 3-D view, the re-located branch point and the traced branch.

    Raises
    ------
    LiftError
        The point is not a located bifurcation into waves, the source is an indenter's problem, or the 3-D
        view has no branch point near it.
    """
    from contin.palc import switch_branch

    if point.kind != "bifurcation" or point.info.get("family") != "n":
        raise LiftError(f"follow_waves: the point must be a located bifurcation into n waves (kind 'bifurcation' of "
                        f"the family 'n'), got a {point.kind!r}"
                        + (f" of the family {point.info.get('family')!r}" if point.kind == "bifurcation" else ""))
    if not isinstance(K, (int, np.integer)) or K < 1:
        raise LiftError(f"follow_waves: K (the harmonics of the 3-D view above 0) must be an integer >= 1, got {K!r}")
    n = int(point.info["key"])
    st = structure if structure is not None else getattr(source, "structure", None)
    if st is None:
        raise LiftError("follow_waves: give the structure whose energy the source's is (structure=...)")
    if getattr(source, "barrier", None) is not None:
        raise LiftError("follow_waves: the source is pressed by an indenter, which this lift does not carry into the "
                        "3-D view; the point, ring and pressure loads are lifted")
    # the source's load: a shell of revolution names it; the paper's model is a point load
    load = getattr(source, "load", "point")
    node = getattr(source, "node", None) if load == "ring" else None
    target = Shell3D(st, AngularBasis(n, int(K)), load, source.control, node=node,
                     length=getattr(source, "length", None),
                     p_c=getattr(source, "p_c", None) if load == "pressure" else None)
    bp = lift_branch_point(point, source, target, shell_lift(source, target, n))
    branch = switch_branch(target, bp, settings, direction=1, **overrides)
    return WavesBranch(target, bp, branch)


def rotated_half(problem: Shell3D, u: np.ndarray, p: float) -> np.ndarray:
    """The state ``u`` of a ``D_n`` view turned by ``pi / n`` about the axis: the coefficients of the odd
    multiples of ``n`` reversed.  On the ``n``-wave branch it maps the ``+1`` half onto the ``-1`` half."""
    basis: AngularBasis = problem.basis
    sign = np.array([-1.0 if (k // basis.n) % 2 else 1.0 for _, _, k in basis.terms])
    c = problem.full_state(np.asarray(u, dtype=float), p)
    return problem.unknowns(c * np.tile(sign, problem.view.N))
