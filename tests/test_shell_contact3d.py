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


@pytest.mark.parametrize("which", [0, 2])
def test_derivatives_are_those_of_the_energy_off_symmetry(pressed, which: int) -> None:
    st, x, contacts = pressed
    barrier, position = contacts[which]
    view = FourierShell(st, AngularBasis(1, 2, mirror=False))
    red = view.reduction()
    rng = np.random.default_rng(7)
    # a small wave-1 and wave-2 wrinkle on the pressed state, away from the pole's tied unknowns
    c = red.full(red.T.T @ view.axisymmetric_state(x) + 2e-5 * rng.standard_normal(red.free.size),
                 view.axisymmetric_state(x))
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
