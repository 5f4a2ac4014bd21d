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

Leaving a ``D_n`` branch
------------------------
A ``D_n`` view with ``every_mode`` locates where the block of another representation becomes singular.
:func:`breaking` names the isotropy subgroup the bifurcation breaks to, :func:`subgroup_basis` gives its basis
on the same angles, :func:`subgroup_lift` carries the state and the block's null vector into it
(:func:`~contin_models.shell.fourier.transfer_coefficients`) and :func:`follow_symmetry_breaking` re-locates the
point there and traces the branch.  :func:`state_symmetry` reads the symmetry of a state; :func:`jump_in_full_space`
snaps from a state of a symmetric view in the basis of every wave and says what symmetry the landing has.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from contin.analyses.conjugate import ConjugateControl
from contin.analyses.lift import Lift, LiftError, lift_branch_point
from contin.problem import Problem
from contin.results.branch import Branch, SpecialPoint

from .fourier import AngularBasis, FourierShell, representation_name, transfer_coefficients
from .problem3d import Shell3D

__all__ = ["shell_lift", "follow_waves", "waves_view", "rotated_half", "WavesBranch", "Breaking", "breaking", "subgroup_basis",
           "subgroup_lift", "same_load", "BrokenBranch", "follow_symmetry_breaking", "StateSymmetry", "state_symmetry",
           "FullSpaceLanding", "jump_in_full_space", "VolumeView", "controlled_families", "controlled_lift", "is_view",
           "unknowns_of"]


# ---- a prescribed volume: the views under pressure with the volume change as the parameter --------------
def controlled_families(control: ConjugateControl, families: Any) -> tuple:
    """The operator families of ``control.base`` (``(key, u, p)``) as families of ``control`` (``(key, U, q)``): the
    same operators at the base's state and load :meth:`~contin.ConjugateControl.split` from ``U``.  The blocks
    outside the traced class do not see the constraint of a prescribed volume (its gradient lies in the traced
    class), so both controls share them."""
    from contin.watch.modes import OperatorFamily

    return tuple(OperatorFamily(f.name, f.keys, (lambda key, U, q, f=f: f.operator(key, *control.split(U))),
                                f.multiplicity, f.vectors, all_operators=(lambda U, q, f=f: f.operators(*control.split(U))),
                                mode_shape=f.mode_shape) for f in families or ())


class VolumeView(ConjugateControl):
    """A 3-D view under pressure (:class:`Shell3D`, ``load="pressure"``) with its volume change prescribed as the
    traced model's is (``like``): :class:`contin.ConjugateControl` of it, the pressure the multiplier.

    The parameter, its name, the stability labels and the multiplier's unit are ``like``'s, and so are the ratios
    of the parameter and the load it observes (``dV_over_V0``), so that a state lifted from the traced model keeps
    its parameter.  The view's basis, energy and structure (:attr:`basis`, :attr:`view`, :attr:`structure`,
    :attr:`gauge`, :attr:`c_ref`) are the base's; :meth:`full_state` gives the coefficients of every ring,
    :attr:`T` maps the unknowns onto them (the multiplier onto none), and :func:`unknowns_of` the other way.

    Parameters
    ----------
    base : Shell3D
        The view under pressure control.
    like : contin.ConjugateControl
        The traced model under the prescribed volume (or another view of it).
    """

    def __init__(self, base: Shell3D, like: ConjugateControl) -> None:
        from contin_models.contact.indentation import BorderedBandedLU

        if not isinstance(base, Shell3D) or base.load != "pressure" or base.control != "force":
            raise LiftError(f"VolumeView: the base must be a Shell3D under pressure control, got {base!r}")
        super().__init__(base, displacement=like.displacement_name, labels=like.labels, linear=True,
                         multiplier_unit=like.unit, factorize=lambda J: BorderedBandedLU(J, base.kl, base.ku))
        own = set(like.base.observables) | {like.load_name, like.displacement_name}
        for name in [k for k in like.observables if k not in own and k not in self._observables]:
            self._observables[name] = like.observables[name]
            if name in like.observable_derivatives:
                self._observable_derivatives[name] = like.observable_derivatives[name]
        self.operator_families = controlled_families(self, base.operator_families)
        self.T = sp.hstack([base.T, sp.csc_matrix((base.T.shape[0], 1))]).tocsc()

    basis = property(lambda self: self.base.basis, doc="The angular basis of the view.")
    view = property(lambda self: self.base.view, doc="The view's energy (a FourierShell).")
    structure = property(lambda self: self.base.structure, doc="The shell and its supports.")
    gauge = property(lambda self: self.base.gauge, doc="The base's gauge (None: none).")
    c_ref = property(lambda self: self.base.c_ref, doc="The reference state's coefficients.")

    def full_state(self, U: np.ndarray, q: float = 0.0) -> np.ndarray:
        """Every ring's Fourier coefficients of the unknowns ``U`` (the multiplier left out)."""
        return self.base.full_state(*self.split(U))

    def __repr__(self) -> str:
        return f"VolumeView({self.base!r})"


def is_view(problem: Problem) -> bool:
    """Whether ``problem`` is a 3-D view (a :class:`Shell3D`, or one under a prescribed volume)."""
    return isinstance(problem, (Shell3D, VolumeView))


def unknowns_of(problem: Problem, c: np.ndarray, load: float = 0.0) -> np.ndarray:
    """The unknowns of ``problem`` of the coefficients (or the traced model's full state) ``c``; under a prescribed
    volume (:class:`contin.ConjugateControl`) with the multiplier ``load`` (the pressure; zero for a mode)."""
    if isinstance(problem, ConjugateControl):
        return problem.join(problem.base.unknowns(c), load)
    return problem.unknowns(c)


def controlled_lift(lift: Lift, source: ConjugateControl, target: ConjugateControl) -> Lift:
    """``lift`` between two problems under pressure control as the lift between them under the prescribed volume:
    the state at the source's pressure (the multiplier carried over), the parameter (the volume change) unchanged, a
    mode with no multiplier (the mode of a bifurcation out of the traced class does not change the volume)."""
    def state(U: np.ndarray, q: float) -> np.ndarray:
        u, p = source.split(U)
        return target.join(lift.state(u, p), p)

    return Lift(state=state, mode=lambda vector: target.join(lift.mode(vector), 0.0), family=lift.family,
                key=lift.key, name=f"{lift.name} under a prescribed {target.displacement_name}")

#: The last Newton step on a branch point's extended system (relative) when it is located again in a 3-D view
#: (:func:`contin.analyses.lift.lift_branch_point`): the error left after a step that small is about its square,
#: and further steps in a view of thousands of unknowns only confirm a point the lift already carried exactly.
RELOCATE_TOL = 1e-9


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
    if isinstance(target, VolumeView):  # the pressure-controlled lift, the multiplier carried along
        if not isinstance(source, ConjugateControl):
            raise LiftError("shell_lift: a view under a prescribed volume lifts from the traced model under one")
        return controlled_lift(shell_lift(source.base, target.base, n), source, target)
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
                 settings: Any = None, every_mode: bool = False, **overrides: Any) -> WavesBranch:
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
    every_mode : bool
        Watch the stability of the branch against every representation of ``D_n`` (the view's operator
        family ``"representation"``), not only against the ``D_n``-symmetric perturbations it traces.

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
    target = waves_view(source, st, n, int(K), every_mode)
    bp = lift_branch_point(point, source, target, shell_lift(source, target, n), tol=RELOCATE_TOL)
    branch = switch_branch(target, bp, settings, direction=1, **overrides)
    return WavesBranch(target, bp, branch)


def waves_view(source: Problem, structure: Any, n: int, K: int, every_mode: bool = False) -> Shell3D:
    """The 3-D view restricted to ``D_n`` (``AngularBasis(n, K)``) of the traced model ``source``: its structure,
    load (a shell of revolution names it; the paper's model is a point load), control, ring and pressure scale; under
    a prescribed volume (:class:`contin.ConjugateControl` of the traced model) the view under pressure with its volume
    prescribed alike (:class:`VolumeView`)."""
    if isinstance(source, ConjugateControl):
        return VolumeView(waves_view(source.base, structure, n, K, every_mode), source)
    barrier = getattr(source, "barrier", None)
    if barrier is not None:  # a rigid indenter driven by its travel, as the traced model's
        return Shell3D(structure, AngularBasis(n, int(K)), barrier.indenter.name, "displacement",
                       length=getattr(source, "length", None), every_mode=every_mode, barrier=barrier)
    load = getattr(source, "load", "point")
    node = getattr(source, "node", None) if load == "ring" else None
    return Shell3D(structure, AngularBasis(n, int(K)), load, source.control, node=node,
                   length=getattr(source, "length", None),
                   p_c=getattr(source, "p_c", None) if load == "pressure" else None, every_mode=every_mode)


def rotated_half(problem: Shell3D, u: np.ndarray, p: float) -> np.ndarray:
    """The state ``u`` of a ``D_n`` view turned by ``pi / n`` about the axis: the coefficients of the odd
    multiples of ``n`` reversed.  On the ``n``-wave branch it maps the ``+1`` half onto the ``-1`` half."""
    basis: AngularBasis = problem.basis
    sign = np.array([-1.0 if (k // basis.n) % 2 else 1.0 for _, _, k in basis.terms])
    c = problem.full_state(np.asarray(u, dtype=float), p)
    return problem.unknowns(c * np.tile(sign, problem.view.N))


# ---- leaving a D_n branch where it breaks its symmetry ------------------------------------------------
@dataclass(frozen=True)
class Breaking:
    """What a bifurcation of a ``D_n`` branch in one representation breaks the symmetry to (:func:`breaking`).

    Attributes
    ----------
    representation : str
        The representation of ``D_n`` (``A2``, ``B1``, ``B2``, ``E1``, ...).
    j, parity : int, str
        Its Bloch class (the waves ``q n +- j``, one parity).
    symmetry : str
        The isotropy subgroup of the mode's symmetric copy: ``"C<n>"``, ``"D<d>"``.
    n, mirror : int, bool
        The subgroup's basis: rotations by ``2 pi / n``, with or without the mirror.
    K_min : int
        The fewest harmonics above ``0`` of that basis that carry the state's waves and the mode's.
    turn : float
        The angle of the subgroup's mirror plane in the ``D_n`` basis's angle (``pi / n`` for ``B2``, else 0).
    """

    representation: str
    j: int
    parity: str
    symmetry: str
    n: int
    mirror: bool
    K_min: int
    turn: float


def breaking(basis: AngularBasis, representation: str) -> Breaking:
    """The isotropy subgroup a bifurcation of the ``D_n`` branch (``basis``) in ``representation`` breaks to.

    The equivariant branching lemma gives a branch for each isotropy subgroup with a one-dimensional fixed space
    in the representation; the mode's copy fixed by it is a simple branch point of the subgroup's states:

    * ``A2`` (waves ``0, n, ...``, antisymmetric about every mirror plane): the mirrors are lost, the rotations
      kept: ``C_n`` (``AngularBasis(n, K, mirror=False)``).
    * ``B1`` (``n`` even; waves ``n/2, 3n/2, ...``, symmetric about ``theta = 0``): the rotation by ``2 pi / n`` changes
      their sign, the mirror in ``theta = 0`` keeps it: ``D_{n/2}`` with the same mirror plane.
    * ``B2`` (``n`` even; the same waves, antisymmetric about ``theta = 0``): the mirror in ``theta = 0`` and the
      rotation by ``2 pi / n`` both change the sign, their product (the mirror in ``theta = pi / n``) keeps it:
      ``D_{n/2}`` with its mirror plane turned by ``pi / n`` (:attr:`Breaking.turn`).
    * ``Ej`` (two-dimensional, waves ``q n +- j``): the rotations by multiples of ``2 pi / d``, ``d = gcd(n, j)``, act
      trivially and the mirror in ``theta = 0`` fixes the symmetric copy: ``D_d`` (``D_1``, the mirror alone, where
      ``j`` and ``n`` are coprime).  The other axes of ``Ej`` are the first one's images under ``D_n``.

    Raises
    ------
    LiftError
        ``basis`` is not a ``D_n`` state basis, or ``representation`` is not one of its symmetry-breaking ones.
    """
    if not (basis.mirror and basis.j == 0 and basis.parity == "even"):
        raise LiftError(f"breaking: the branch's basis must be a D_n basis of states (mirror=True, j = 0), got {basis!r}")
    n, K = basis.n, basis.K
    classes = {representation_name(n, j, par): (j, par) for j in range(n // 2 + 1) for par in ("even", "odd")}
    classes.pop("A1")
    if representation not in classes:
        raise LiftError(f"breaking: representation must be one of the classes of D_{n} that break its symmetry, "
                        f"{sorted(classes)}, got {representation!r}")
    j, parity = classes[representation]
    if j == 0:
        return Breaking(representation, 0, "odd", f"C{n}", n, False, K, 0.0)
    if 2 * j == n:
        return Breaking(representation, j, parity, f"D{j}", j, True, 2 * K + 1, 0.0 if parity == "even" else math.pi / n)
    d = math.gcd(n, j)
    return Breaking(representation, j, "even", f"D{d}", d, True, (K * n + j) // d, 0.0)


def subgroup_basis(basis: AngularBasis, representation: str, K: int | None = None) -> AngularBasis:
    """The basis of the states of the isotropy subgroup of ``representation`` (:func:`breaking`).

    ``K`` harmonics above ``0`` (default and least :attr:`Breaking.K_min`: exactly the ``D_n`` basis's states and
    the Bloch class's waves, so that the located point does not move).  The quadrature is the ``D_n`` basis's ``M``
    where it integrates the subgroup's quadratic forms exactly (``M > 2 K n'``), the same angles: the ``D_n``
    states then have the same energy and the class's block is the subgroup's Hessian on the mode's waves.
    Otherwise the default ``M`` of the subgroup's basis, and the lifted point moves by the change of quadrature.
    """
    b = breaking(basis, representation)
    K = b.K_min if K is None else K
    if not isinstance(K, (int, np.integer)) or K < b.K_min:
        raise LiftError(f"subgroup_basis: K (harmonics above 0 of the {b.symmetry} basis) must be an integer >= "
                        f"{b.K_min} to carry the D_{basis.n} states and the {representation} modes, got {K!r}")
    M = basis.M if basis.M > 2 * int(K) * b.n else None
    return AngularBasis(b.n, int(K), mirror=b.mirror, M=M)


def same_load(problem: Shell3D, basis: AngularBasis, turn: float = 0.0, every_mode: bool = False,
              gauge: tuple[int, int] | None = None) -> Shell3D:
    """``problem``'s structure, load and control in another basis (its reference carried over, turned by ``turn``;
    with ``every_mode`` where the basis has a mirror, and the ``gauge`` of :class:`Shell3D`).

    Raises
    ------
    LiftError
        ``problem`` is not a :class:`Shell3D`, or its load is not a point, ring or pressure load.
    """
    if isinstance(problem, VolumeView):  # under a prescribed volume: the base in the other basis, prescribed alike
        return VolumeView(same_load(problem.base, basis, turn, every_mode, gauge), problem)
    if not isinstance(problem, Shell3D):
        raise LiftError(f"the problem must be a Shell3D (the 3-D view), got {type(problem).__name__}")
    if problem.load not in ("point", "ring", "pressure", "sphere", "plate"):
        raise LiftError(f"the {problem.load!r} load is not carried into another basis; the point, ring and pressure "
                        "loads and the indenters are")
    view = problem.view
    shape = np.delete(problem.c_ref, view.axisymmetric_dofs())
    # an axisymmetric reference is the structure's own: the view's default, without the general kernels
    reference = (transfer_coefficients(problem.c_ref, problem.basis, basis, turn) if np.any(shape) else None)
    barrier = problem.contact.barrier if problem.contact is not None else None
    return Shell3D(problem.structure, basis, problem.load, problem.control, length=problem.length,
                   node=problem.node if problem.load == "ring" else None, p_c=problem.p_c,
                   every_mode=every_mode and basis.mirror, reference=reference, gauge=gauge, barrier=barrier)


def subgroup_lift(problem: Shell3D, target: Shell3D, representation: str) -> Lift:
    """The lift of a ``D_n`` branch's bifurcation in ``representation`` into the isotropy subgroup's view ``target``.

    Parameters
    ----------
    problem : Shell3D
        The view in a ``D_n`` basis that located the bifurcation (``every_mode``).
    target : Shell3D
        The same structure, load and control in the subgroup's basis (:func:`subgroup_basis`).
    representation : str
        The bifurcation's class (``info["key"]``).

    Returns
    -------
    Lift
        ``state``: the coefficients of the waves ``0, n, 2n, ...`` carried over (turned by :attr:`Breaking.turn`),
        the target's other waves zero; ``parameter`` unchanged; ``mode``: the Bloch block's null vector
        (the block's reduced unknowns) through the class's coefficients ``q n +- j`` of its parity;
        ``family = "representation"``, ``key = representation``.

    Raises
    ------
    LiftError
        The target's basis is not the subgroup's (rotations, mirror, too few harmonics), or the problems differ
        in parameter.
    """
    if isinstance(target, VolumeView):  # the pressure-controlled lift, the multiplier carried along
        if not isinstance(problem, VolumeView):
            raise LiftError("subgroup_lift: a view under a prescribed volume lifts from a view under one")
        return controlled_lift(subgroup_lift(problem.base, target.base, representation), problem, target)
    b = breaking(problem.basis, representation)
    tb = target.basis
    if tb.n != b.n or tb.mirror != b.mirror or tb.j != 0 or tb.K < b.K_min:
        raise LiftError(f"subgroup_lift: a bifurcation in {representation} of D_{problem.basis.n} breaks to "
                        f"{b.symmetry}: the target needs AngularBasis({b.n}, K >= {b.K_min}, mirror={b.mirror}), "
                        f"got {tb!r}")
    if problem.parameter_name != target.parameter_name:
        raise LiftError(f"subgroup_lift: the source's parameter is {problem.parameter_name!r} but the target's "
                        f"{target.parameter_name!r}: build the target with the same load and control")
    block_basis = problem.basis.bloch(b.j, b.parity)
    # the block's reduced unknowns are its perturbation view's free ones (FourierShell.bloch_block)
    to_block = FourierShell(problem.structure, block_basis).reduction().T

    def state(u: np.ndarray, p: float) -> np.ndarray:
        return target.unknowns(transfer_coefficients(problem.full_state(u, p), problem.basis, tb, b.turn))

    def mode(vector: np.ndarray) -> np.ndarray:
        v = np.asarray(vector, dtype=float)
        if v.shape != (to_block.shape[1],):
            raise LiftError(f"subgroup_lift: the {representation} mode must have the block's {to_block.shape[1]} "
                            f"unknowns, got shape {v.shape}")
        return target.unknowns(transfer_coefficients(to_block @ v, block_basis, tb, b.turn))

    return Lift(state=state, mode=mode, family="representation", key=representation,
                name=f"subgroup_lift({representation} of D_{problem.basis.n} -> {b.symmetry})")


@dataclass
class BrokenBranch:
    """The branch that leaves a ``D_n`` branch where it breaks its symmetry (:func:`follow_symmetry_breaking`).

    Attributes
    ----------
    problem : Shell3D
        The subgroup's view it was traced in.
    breaking : Breaking
        The representation and the subgroup.
    branch_point : SpecialPoint
        The lifted point, re-located on :attr:`problem` (``info["moved_p"]``, ``info["mode_angle"]``).
    branch : Branch
        The branch traced from it (one direction).
    """

    problem: Shell3D
    breaking: Breaking
    branch_point: SpecialPoint
    branch: Branch


def follow_symmetry_breaking(problem: Shell3D, point: SpecialPoint, K: int | None = None, *,
                             settings: Any = None, direction: int = 1, every_mode: bool = True,
                             key: str | None = None, **overrides: Any) -> BrokenBranch:
    """Leave a ``D_n`` branch at its located bifurcation in another representation and trace the branch that
    has the isotropy subgroup's symmetry.

    The point is lifted into the subgroup's view (:func:`subgroup_basis`, :func:`subgroup_lift`; ``every_mode``
    where the subgroup has a mirror), re-located there (:func:`contin.analyses.lift.lift_branch_point`: the same
    angles and waves, so it stays put to the tolerances unless ``K`` adds waves) and the bifurcating branch traced
    by :func:`contin.switch_branch` in ``direction``.  For a one-dimensional representation the two directions
    are images of each other under the broken symmetry; for ``Ej`` they generally are not (``D_3``'s ``E1`` is
    transcritical), so trace both where both matter.

    Parameters
    ----------
    problem : Shell3D
        The view in a ``D_n`` basis that located ``point`` (``every_mode=True``).
    point : SpecialPoint
        A located ``"bifurcation"`` of the family ``"representation"``.
    K : int, optional
        Harmonics above ``0`` of the subgroup's basis (default the fewest that carry the state and the mode).
    settings, overrides
        Of the branch's trace, as :func:`contin.switch_branch` takes them.
    direction : {1, -1}
        The side of the branch point.
    key : str, optional
        The representation to leave into, where several cross at the point: the engine records the first crossing
        along the path under ``info["key"]`` and lists the others that it located on the same step in
        ``info["also"]`` (two representations that are one representation of ``O(2)`` at an axisymmetric state,
        ``B1`` and ``B2`` of the waves ``n/2`` say, cross at the same point).  Default: the point's own key.  The
        mode of another key is the null vector of its operator at the point.

    Returns
    -------
    BrokenBranch

    Raises
    ------
    LiftError
        The point is not a located bifurcation of the family ``"representation"``, or the subgroup's view has no
        simple branch point near it.
    """
    from contin.palc import switch_branch

    if point.kind != "bifurcation" or point.info.get("family") != "representation":
        raise LiftError("follow_symmetry_breaking: the point must be a located bifurcation of a D_n branch into another "
                        f"representation (kind 'bifurcation' of the family 'representation'), got a {point.kind!r}"
                        + (f" of the family {point.info.get('family')!r}" if point.kind == "bifurcation" else ""))
    if direction not in (1, -1):
        raise LiftError(f"follow_symmetry_breaking: direction must be 1 or -1, got {direction!r}")
    if key is not None and key != str(point.info["key"]):
        point = _crossing_of(problem, point, str(key))
    key = str(point.info["key"])
    b = breaking(problem.basis, key)
    target = same_load(problem, subgroup_basis(problem.basis, key, K), b.turn, every_mode)
    bp = lift_branch_point(point, problem, target, subgroup_lift(problem, target, key), tol=RELOCATE_TOL)
    branch = switch_branch(target, bp, settings, direction=direction, **overrides)
    return BrokenBranch(target, b, bp, branch)


def _crossing_of(problem: Shell3D, point: SpecialPoint, key: str) -> SpecialPoint:
    """The located ``point`` as the crossing of ``key``, one of the others the engine located on its step
    (``info["also"]``): the same state, with ``key``'s operator's null vector as its mode."""
    import dataclasses

    from contin.watch.modes import eigenvalues_near_zero

    if key not in [str(k) for k in point.info.get("also", [])]:
        raise LiftError(f"follow_symmetry_breaking: key {key!r} did not cross at this point (its key "
                        f"{point.info.get('key')!r}, also located on its step: {point.info.get('also', [])})")
    family = next(f for f in problem.operator_families if f.name == "representation")
    _, V = eigenvalues_near_zero(family.operator(key, point.u, point.p), 1, vectors=True)
    return dataclasses.replace(point, info={**point.info, "key": key, "mode": V[:, 0] / np.linalg.norm(V[:, 0])})


# ---- the symmetry of a state, and snaps with no symmetry imposed -------------------------------------
@dataclass(frozen=True)
class StateSymmetry:
    """The symmetry of a state of the 3-D view (:func:`state_symmetry`).

    Attributes
    ----------
    label : str
        ``"O(2)"`` (axisymmetric), ``"SO(2)"`` (axisymmetric but twisted), ``"D<g>"`` (``g``-fold rotations and a
        mirror plane) or ``"C<g>"`` (rotations only); ``g`` the greatest common divisor of the waves present.
    order : int
        ``g`` (0 for an axisymmetric state).
    mirror : float or None
        The angle of a mirror plane (radians, in the basis's angle), None where there is none.
    amplitudes : dict
        Per wave number its largest amplitude (``sqrt(a^2 + b^2)`` of ``a cos + b sin``, any component and node).
    """

    label: str
    order: int
    mirror: float | None
    amplitudes: dict


def state_symmetry(basis: AngularBasis, c: np.ndarray, tol: float = 1e-6) -> StateSymmetry:
    """The symmetry of the state ``c`` (every ring's coefficients in ``basis``).

    A wave is present when its amplitude exceeds ``tol`` times the largest axisymmetric coefficient (the shell's
    size).  A mirror plane is sought among those of the strongest wave (where its ``R`` or ``Z`` field at the node of
    its largest coefficient is symmetric) and kept where the whole state, turned onto it, has no antisymmetric
    coefficient above the same threshold.
    """
    c = np.asarray(c, dtype=float)
    rows = c.reshape(-1, basis.m)
    waves = sorted({t[2] for t in basis.terms})
    amplitudes = {k: _wave_amplitude(basis, rows, k) for k in waves}
    size = float(np.max(np.abs(rows[:, [i for i, t in enumerate(basis.terms) if t[2] == 0 and t[0] != "T"]])))
    floor = tol * size
    present = [k for k in waves if k > 0 and amplitudes[k] > floor]
    odd_terms = [i for i, t in enumerate(basis.terms) if (t[0] == "T") == (t[1] == "cos")]
    if not present:
        twisted = bool(odd_terms) and float(np.max(np.abs(rows[:, odd_terms]))) > floor
        return StateSymmetry("SO(2)" if twisted else "O(2)", 0, None if twisted else 0.0, amplitudes)
    g = math.gcd(*present)
    if basis.parity == "even":
        return StateSymmetry(f"D{g}", g, 0.0, amplitudes)
    both = AngularBasis(1, max(waves), mirror=False, M=2 * max(waves) + 2)
    k = max(present, key=lambda q: amplitudes[q])
    # the strongest R or Z field of the wave k: a cos(k theta) + b sin(k theta), symmetric about phi + pi l / k
    cols = {trig: [i for i, t in enumerate(basis.terms) if t[2] == k and t[1] == trig and t[0] != "T"]
            for trig in ("cos", "sin")}
    node, which = np.unravel_index(int(np.argmax(np.abs(rows[:, cols["cos"]]) + np.abs(rows[:, cols["sin"]]))),
                                   (rows.shape[0], len(cols["cos"])))
    comp = basis.terms[cols["cos"][which]][0]
    a = rows[node, basis.index(comp, "cos", k)]
    b = rows[node, basis.index(comp, "sin", k)]
    phi = math.atan2(b, a) / k
    antisymmetric = [i for i, t in enumerate(both.terms) if (t[0] == "T") == (t[1] == "cos")]
    for plane in (phi + math.pi * q / k for q in range(k)):
        turned = transfer_coefficients(c, basis, both, plane).reshape(-1, both.m)
        if float(np.max(np.abs(turned[:, antisymmetric]))) <= floor:
            return StateSymmetry(f"D{g}", g, plane % (2.0 * math.pi / g), amplitudes)
    return StateSymmetry(f"C{g}", g, None, amplitudes)


def _wave_amplitude(basis: AngularBasis, rows: np.ndarray, k: int) -> float:
    """The largest amplitude ``sqrt(a^2 + b^2)`` of ``a cos(k theta) + b sin(k theta)`` over the components and
    nodes (independent of the angle the state is read from)."""
    out = 0.0
    for comp in ("R", "T", "Z"):
        parts = [rows[:, i] for i, t in enumerate(basis.terms) if t[0] == comp and t[2] == k]
        if parts:
            out = max(out, float(np.max(np.sqrt(sum(x * x for x in parts)))))
    return out


@dataclass
class FullSpaceLanding:
    """A snap in the 3-D view with no symmetry imposed (:func:`jump_in_full_space`).

    Attributes
    ----------
    problem : Shell3D
        The view in ``AngularBasis(1, K, mirror=False)``: every wave ``0 .. K``, both parities.
    jump : contin.JumpResult
        The energy descent from the lifted state (``u_to`` the landing, in :attr:`problem`'s unknowns).
    symmetry : StateSymmetry
        The landing's symmetry and the largest coefficient of each wave.
    n_negative : int
        Negative eigenvalues of the landing's Hessian in that basis (against every wave up to ``K``).
    """

    problem: Shell3D
    jump: Any
    symmetry: StateSymmetry
    n_negative: int


def jump_in_full_space(problem: Shell3D, u: np.ndarray, p: float, K: int | None = None, *,
                       tol: float = 1e-6, mode: np.ndarray | None = None, **jump_options: Any) -> FullSpaceLanding:
    """From a state of a symmetric view (a fold of a ``D_n`` branch, or any state) to the next stable state with no
    symmetry imposed, and what symmetry it has.

    The state is carried into ``AngularBasis(1, K, mirror=False)`` (the basis's quadrature where it integrates that
    basis's quadratic forms exactly, so the state's energy is unchanged), :func:`contin.jump` descends from it at
    the fixed parameter, and the landing is classified by :func:`state_symmetry` (``tol``): axisymmetric, the
    start's symmetry, or another.

    Parameters
    ----------
    problem : Shell3D
        The symmetric view the state lies on (point, ring or pressure load).
    u, p : the state and the parameter (held during the jump).
    K : int, optional
        The highest wave of the full basis (default the highest wave of ``problem``'s basis; it must carry them).
    tol : float
        Relative size below which a wave counts as absent.
    mode : ndarray, optional
        The direction of the first kick, as coefficients of ``problem``'s basis (``problem.T @ v`` for a vector ``v``
        of its unknowns), e.g. the mode of the bifurcation the shell snaps from.  By default :func:`contin.jump`
        kicks along the lowest eigenvector, which in the basis without symmetry may be the state's turning about
        the axis (a null vector up to the quadrature, whose sign is noise): give the mode where it is known.
    jump_options
        Passed to :func:`contin.jump` (``perturbation``, ``max_iter``, ...).

    Raises
    ------
    LiftError
        ``K`` does not carry the state's waves, or the problem's load is not carried.
    contin.JumpError
        The state is stable and not degenerate in the full space too (nothing to jump from).
    """
    from contin.analyses.jump import jump

    top = int(problem.basis.wave_numbers.max())
    K = top if K is None else K
    if not isinstance(K, (int, np.integer)) or K < max(top, 1):
        raise LiftError(f"jump_in_full_space: K (the highest wave of the full basis) must be an integer >= {max(top, 1)} "
                        f"to carry the state's waves, got {K!r}")
    M = problem.basis.M if problem.basis.M > 2 * int(K) else None
    full = AngularBasis(1, int(K), mirror=False, M=M)
    target = same_load(problem, full)
    start = target.unknowns(transfer_coefficients(problem.full_state(np.asarray(u, dtype=float), p), problem.basis,
                                                  full))
    if mode is not None:
        jump_options["direction"] = target.unknowns(transfer_coefficients(np.asarray(mode, dtype=float), problem.basis,
                                                                          full))
    result = jump(target, start, float(p), **jump_options)
    from contin.numerics.stability import stability_info

    n_negative = int(stability_info(target.jacobian(result.u_to, result.p), 0).n_negative)
    return FullSpaceLanding(target, result, state_symmetry(full, target.full_state(result.u_to, result.p), tol),
                            n_negative)
