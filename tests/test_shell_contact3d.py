"""Contact with a rigid indenter in the shell's 3-D view (:mod:`contin_models.shell.contact3d`).

Against what nobody tuned: on an axisymmetric state the barrier over the surface is the traced model's
barrier (its energy, gradient and Hessian, computed by the contact package's own kernels and C support
search), for a sphere, a point (a sphere of radius 0) and a plate pressing on a flattened cap; its
Hessian on wave ``k`` is the harmonic blocks' contact block; at a state with no symmetry its gradient
and Hessian are the energy's derivatives (central differences).
"""

from __future__ import annotations

import numpy as np
import pytest

from contin_models.shell.contact3d import Contact3D
from contin_models.shell.fourier import AngularBasis, FourierShell
from contin_models.shell.harmonic import harmonic_block
from studies.harmonic_probe import indented_state


@pytest.fixture(scope="module")
def pressed():
    return indented_state(40)


@pytest.mark.parametrize("which", [0, 1, 2])  # sphere, point, plate
def test_axisymmetric_states_see_the_traced_barrier(pressed, which: int) -> None:
    st, x, contacts = pressed
    barrier, position = contacts[which]
    view = FourierShell(st, AngularBasis(3, 2))
    c, ax = view.axisymmetric_state(x), view.axisymmetric_dofs()
    contact = Contact3D(view, barrier)
    E1, (g1, _) = barrier.energy(x, position), barrier.gradient(x, position)
    H1 = barrier.evaluate(x, position).hessian_matrix().toarray()
    assert E1 > 0
    assert abs(contact.energy(c, position) - E1) <= 1e-13 * E1
    g = contact.gradient(c, position)
    assert np.max(np.abs(g[ax] - g1)) <= 1e-13 * np.max(np.abs(g1))
    assert np.max(np.abs(np.delete(g, ax))) <= 1e-14 * np.max(np.abs(g1))
    keep = np.array([d for d in range(2 * st.N) if not (d % 2 == 0 and d // 2 in st.poles)])
    H = contact.hessian(c, position).toarray()
    assert np.max(np.abs(H[np.ix_(ax, ax)] - H1)[np.ix_(keep, keep)]) <= 1e-13 * np.max(np.abs(H1))
    # on a wave number, the harmonic blocks' contact term
    whole = H + view.hessian(c).toarray()
    for k in (3, 6):
        block = harmonic_block(st, x, k, reduced=False, contact=(barrier, position)).toarray()
        d = view.dofs_of_wave(k)
        assert np.max(np.abs(whole[np.ix_(d, d)] - block)) <= 1e-13 * np.max(np.abs(block))


def wrinkled(st, x: np.ndarray, seed: int) -> tuple[FourierShell, np.ndarray]:
    """The view without symmetry (waves 0 .. 2) and the pressed state ``x`` with a small random wave-1 and
    wave-2 wrinkle on its free unknowns (the pole's tied unknowns stay tied)."""
    view = FourierShell(st, AngularBasis(1, 2, mirror=False))
    red = view.reduction()
    rng = np.random.default_rng(seed)
    c = red.full(red.T.T @ view.axisymmetric_state(x) + 2e-5 * rng.standard_normal(red.free.size),
                 view.axisymmetric_state(x))
    return view, c


@pytest.mark.parametrize("which", [0, 2])
def test_derivatives_are_those_of_the_energy_off_symmetry(pressed, which: int) -> None:
    st, x, contacts = pressed
    barrier, position = contacts[which]
    view, c = wrinkled(st, x, seed=7)
    red = view.reduction()
    contact = Contact3D(view, barrier)
    g, H = contact.gradient(c, position), contact.hessian(c, position)
    assert np.max(np.abs(g)) > 0
    for seed in range(2):
        d = red.T @ np.random.default_rng(20 + seed).standard_normal(red.free.size)
        h = 1e-7
        dE = (contact.energy(c + h * d, position) - contact.energy(c - h * d, position)) / (2 * h)
        assert abs(dE - g @ d) <= 1e-6 * np.abs(g) @ np.abs(d)
        dg = (contact.gradient(c + h * d, position) - contact.gradient(c - h * d, position)) / (2 * h)
        assert np.max(np.abs(dg - H @ d)) <= 1e-5 * np.max(np.abs(H @ d))


def test_a_point_inside_the_indenter_is_refused(pressed) -> None:
    st, x, contacts = pressed
    barrier, position = contacts[2]  # the plate
    view = FourierShell(st, AngularBasis(2, 1))
    with pytest.raises(ValueError, match="inside the indenter"):
        Contact3D(view, barrier).energy(view.axisymmetric_state(x), position - 0.01)


@pytest.mark.slow
@pytest.mark.parametrize("indenter", ["sphere", "plate"])
def test_an_indenter_traced_in_the_3d_view_is_the_traced_model_on_axisymmetric_states(indenter: str) -> None:
    """``Shell3D`` under an indenter's travel (the position as the parameter, the step filter in 3-D):
    the trace in the ``D_3`` basis stays axisymmetric and ends at the traced model's force."""
    import contin
    from contin_models.contact.barrier import Plate, Sphere
    from contin_models.contact.indentation import ShellIndentation
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellStructure

    one = ShellIndentation(N=30, indenter=Sphere(0.5) if indenter == "sphere" else Plate())
    el = one.elastic
    st = ShellStructure(el.cap, el.E, el.nu, el.h, boundary="sliding", edge_bending="none")  # that model's energy
    shell = Shell3D(st, AngularBasis(3, 1), indenter, "displacement", barrier=one.barrier)
    assert shell.c0 == one.c0
    b1 = contin.continuation(one, one.reference_unknowns(), 0.0, p_max=0.05, ds=0.01, ds_max=0.02, max_steps=200)
    b3 = contin.continuation(shell, shell.reference_unknowns(), 0.0, p_max=0.05, ds=0.01, ds_max=0.02,
                             max_steps=200)
    assert b1.status == b3.status == "bound"
    F1, F3 = b1.observable("F")[-1], b3.observable("F")[-1]
    assert F3 > 0 and abs(F3 - F1) <= 1e-8 * F1
    c = shell.full_state(b3.u[-1], b3.p[-1])
    assert np.max(np.abs(np.delete(c, shell.view.axisymmetric_dofs()))) < 1e-12
    with pytest.raises(ValueError, match="needs barrier"):
        Shell3D(st, AngularBasis(3, 1), indenter, "displacement")


@pytest.mark.parametrize("which", [0, 2])
def test_position_derivatives_and_the_step_filter(pressed, which: int) -> None:
    st, x, contacts = pressed
    barrier, position = contacts[which]
    view, c = wrinkled(st, x, seed=9)
    contact = Contact3D(view, barrier)
    Ec, mixed, Ecc = contact.position_derivatives(c, position)
    h = 1e-8
    assert abs((contact.energy(c, position + h) - contact.energy(c, position - h)) / (2 * h) - Ec) <= 1e-6 * abs(Ec)
    dg = (contact.gradient(c, position + h) - contact.gradient(c, position - h)) / (2 * h)
    assert np.max(np.abs(dg - mixed)) <= 1e-5 * np.max(np.abs(mixed))
    dEc = (contact.position_derivatives(c, position + h)[0] - contact.position_derivatives(c, position - h)[0]) / (2 * h)
    assert abs(dEc - Ecc) <= 1e-5 * abs(Ecc)
    # the filter: lowering the indenter by twice the smallest gap of the samples is cut short before contact
    assert contact.max_safe_fraction(c, position, np.zeros_like(c), 0.0) == 1.0
    gap = contact.points(c, position)  # every point of the integral is within dhat
    assert gap["q"].size > 0
    f = contact.max_safe_fraction(c, position, np.zeros_like(c), -2.0 * barrier.dhat)
    assert 0.0 < f < 0.9 * 0.5 + 1e-12


@pytest.mark.slow
def test_a_dead_load_on_the_indenter_is_the_traced_models() -> None:
    """Force control of the indenter: ``contin.DeadLoad`` on the 3-D view's travel-driven problem (its
    ``conjugate_force`` is the contact force) ends where the traced model's force control ends."""
    import contin
    from contin.analyses.deadload import DeadLoad
    from contin_models.contact.barrier import Sphere
    from contin_models.contact.indentation import ShellIndentation, ShellIndentationForce
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellStructure

    one = ShellIndentation(N=30, indenter=Sphere(0.5))
    el = one.elastic
    st = ShellStructure(el.cap, el.E, el.nu, el.h, boundary="sliding", edge_bending="none")
    shell = Shell3D(st, AngularBasis(3, 1), "sphere", "displacement", barrier=one.barrier)
    start = contin.continuation(shell, shell.reference_unknowns(), 0.0, p_max=0.05, ds=0.01, ds_max=0.02)
    force = DeadLoad(shell)
    U, F = force.from_displacement_state(start.u[-1], float(start.p[-1]))
    bf = contin.continuation(force, U, F, p_max=1.3 * F, ds=0.5, ds_max=2.0, max_steps=200)
    traced = ShellIndentationForce(N=30, indenter=Sphere(0.5))
    U1, F1 = traced.contact_start(0.05)
    b1 = contin.continuation(traced, U1, F1, p_max=1.3 * F, ds=0.5, ds_max=2.0, max_steps=200)
    assert bf.status == b1.status == "bound"
    assert abs(force.split(bf.u[-1])[1] - b1.observable("w_b")[-1]) < 1e-10


def test_an_indenters_3d_view_names_the_travel_and_the_normalised_force_as_the_traced_model() -> None:
    """The followed path writes pieces of both models into one branch.csv: the 3-D view has ``w_b`` and
    ``F_norm`` too, equal to the traced model's at an axisymmetric state."""
    from contin_models.contact.barrier import Sphere
    from contin_models.contact.indentation import ShellIndentation
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellStructure

    one = ShellIndentation(N=30, indenter=Sphere(0.5))
    el = one.elastic
    st = ShellStructure(el.cap, el.E, el.nu, el.h, boundary="sliding", edge_bending="none")
    shell = Shell3D(st, AngularBasis(3, 1), "sphere", "displacement", barrier=one.barrier)
    import contin

    pressed = contin.continuation(one, one.reference_unknowns(), 0.0, p_max=0.02, ds=0.01, ds_max=0.02)
    u, w_b = pressed.u[-1], float(pressed.p[-1])
    mine = shell.evaluate_observables(shell.unknowns(shell.view.axisymmetric_state(one.full_state(u, w_b))), w_b)
    theirs = one.evaluate_observables(u, w_b)
    assert mine["w_b"] == theirs["w_b"] == w_b
    assert mine["F"] > 0 and mine["F_norm"] == pytest.approx(theirs["F_norm"], rel=1e-9)


def test_the_slots_of_the_nodes_a_contact_touches_are_kept_for_the_last_few_sets_only(pressed) -> None:
    """The nodes a contact touches change as the load moves, and each set's Hessian slots hold every harmonic of
    every node: kept for every set ever touched, they took more than 20 GB on a long indentation with ten
    harmonics.  Now the memory they hold stays bounded however many sets pass, and a set asked for again is
    the same array."""
    import tracemalloc

    from contin_models.shell.fourier import SLOT_CACHE_SIZE

    st, _, _ = pressed
    view = FourierShell(st, AngularBasis(3, 2))
    first = view.hessian_slots(view.element_dofs(np.array([[30, 31], [31, 32]])), False, transient=True)
    assert view.hessian_slots(view.element_dofs(np.array([[30, 31], [31, 32]])), False, transient=True) is first
    tracemalloc.start()
    base = tracemalloc.get_traced_memory()[0]
    for k in range(40):  # forty sets of touched nodes
        nodes = np.array([[j, j + 1] for j in range(k % 20, k % 20 + 8 + k // 20)])
        view.hessian_slots(view.element_dofs(nodes), False, transient=True)
    held = tracemalloc.get_traced_memory()[0] - base
    tracemalloc.stop()
    one = view.hessian_slots(view.element_dofs(np.array([[j, j + 1] for j in range(9)])), False, transient=True).nbytes
    assert held < (SLOT_CACHE_SIZE + 2) * one
