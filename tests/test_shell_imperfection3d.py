"""Imperfect shells in the 3-D view: a stress-free reference that need not be axisymmetric.

What is checked, against what nobody tuned:

* the general reference given the structure's own axisymmetric reference is the default path: energy,
  gradient and Hessian at a state with no symmetry, to roundoff (the paper's cap with its rotating edge,
  a clamped cap with ``kappa11`` over the reference length, a closed sphere with two poles);
* an imperfect reference that breaks the axial symmetry (a ``cos 3 theta`` bump, one without any symmetry)
  is stress free: at ``c = c_bar`` the energy and the gradient vanish to roundoff, on the paper's cap and
  a clamped cap, while the perfect view sees the same shape strained;
* gradient and Hessian of the imperfect view are the derivatives of its energy (central differences);
* bad references are refused with the field named.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contin_models.shell.fourier import AngularBasis, FourierShell
from contin_models.shell.geometry import spherical_cap
from contin_models.shell.meridian import complete_sphere_meridian
from contin_models.shell.structure import ShellStructure


def structures() -> dict:
    cap = spherical_cap(1.0, 0.8, 24)
    return {"paper cap": ShellStructure(cap, 1e6, 0.5, 0.02, boundary="sliding"),
            "clamped cap": ShellStructure(cap, 1e6, 0.3, 0.02, boundary="clamped", kappa11_length="reference"),
            "sphere": ShellStructure(complete_sphere_meridian(1.0, 21, 1.0), 1.0, 0.3, 0.02,
                                     kappa11_length="reference")}


def random_state(view: FourierShell, amplitude: float, seed: int) -> np.ndarray:
    """The reference plus a random field of every term, the poles kept single points (pole terms left out)."""
    rng = np.random.default_rng(seed)
    dc = amplitude * rng.standard_normal(view.size)
    for k in view.structure.poles:
        dc[k * view.m:(k + 1) * view.m] = 0.0
    return view.reference_state() + dc


def bump(view: FourierShell, delta: float, wave: int) -> np.ndarray:
    """The reference moved along the meridian's normal by ``delta sin(pi s) cos(wave theta)`` per node (zero
    at both ends, so a pole stays a point); ``wave = 0`` with a basis without symmetry: a bump with a
    ``cos`` and a ``sin`` of the first two waves."""
    m = view.structure.reference.meridian
    x = np.asarray(m.x, dtype=float)
    r, z = x[0::2], x[1::2]
    t = np.gradient(r), np.gradient(z)
    length = np.hypot(*t)
    nr, nz = t[1] / length, -t[0] / length
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(r), np.diff(z)))])
    a = delta * np.sin(math.pi * s / s[-1])
    c = view.reference_state()
    terms = [("cos", wave)] if wave else [("cos", 1), ("sin", 2)]
    for trig, k in terms:
        c[view.basis.index("R", trig, k)::view.m] += a * nr
        c[view.basis.index("Z", trig, k)::view.m] += a * nz
    return c


@pytest.mark.parametrize("name", ["paper cap", "clamped cap", "sphere"])
def test_axisymmetric_reference_given_is_the_default_path(name: str) -> None:
    st = structures()[name]
    basis = AngularBasis(3, 2)
    default = FourierShell(st, basis)
    general = FourierShell(st, basis, reference=default.reference_state())
    c = random_state(default, 0.01, 2)
    E0, E1 = default.energy(c), general.energy(c)
    assert abs(E1 - E0) <= 1e-12 * abs(E0)
    g0, g1 = default.gradient(c), general.gradient(c)
    assert np.max(np.abs(g1 - g0)) <= 1e-12 * np.max(np.abs(g0))
    H0, H1 = default.hessian(c).toarray(), general.hessian(c).toarray()
    assert np.max(np.abs(H1 - H0)) <= 1e-12 * np.max(np.abs(H0))


@pytest.mark.parametrize("name", ["paper cap", "clamped cap"])
@pytest.mark.parametrize("symmetry", ["D3", "none"])
def test_imperfect_reference_is_stress_free(name: str, symmetry: str) -> None:
    st = structures()[name]
    basis = AngularBasis(3, 2) if symmetry == "D3" else AngularBasis(1, 3, mirror=False)
    perfect = FourierShell(st, basis)
    c_bar = bump(perfect, 0.01, 3 if symmetry == "D3" else 0)
    view = FourierShell(st, basis, reference=c_bar)
    # the perfect shell sees the bump strained: the scale of energy and forces the roundoff is measured on
    E_scale, g_scale = perfect.energy(c_bar), np.max(np.abs(perfect.gradient(c_bar)))
    assert E_scale > 0
    assert abs(view.energy(c_bar)) <= 1e-14 * E_scale
    assert np.max(np.abs(view.gradient(c_bar))) <= 1e-10 * g_scale
    # and the Hessian there is a stiffness: no negative direction on the admissible unknowns
    T = view.reduction().T
    assert np.linalg.eigvalsh((T.T @ view.hessian(c_bar) @ T).toarray())[0] > 0


def test_imperfect_derivatives_are_the_energy_s() -> None:
    st = ShellStructure(spherical_cap(1.0, 0.8, 9), 1e6, 0.3, 0.02, boundary="clamped")
    basis = AngularBasis(1, 2, mirror=False)
    c_bar = bump(FourierShell(st, basis), 0.02, 0)
    view = FourierShell(st, basis, reference=c_bar)
    c = random_state(view, 3e-3, 5)
    g, H = view.gradient(c), view.hessian(c).toarray()
    rng = np.random.default_rng(7)
    d = rng.standard_normal(view.size)
    for k in st.poles:
        d[k * view.m:(k + 1) * view.m] = 0.0
    eps = 1e-6
    fd = (view.energy(c + eps * d) - view.energy(c - eps * d)) / (2 * eps)
    assert abs(fd - g @ d) <= 1e-6 * np.abs(g) @ np.abs(d)
    fd_g = (view.gradient(c + eps * d) - view.gradient(c - eps * d)) / (2 * eps)
    assert np.max(np.abs(fd_g - H @ d)) <= 1e-6 * np.max(np.abs(H @ d))


def test_bad_reference_is_refused() -> None:
    st = structures()["paper cap"]
    basis = AngularBasis(3, 2)
    c = FourierShell(st, basis).reference_state()
    with pytest.raises(ValueError, match="reference must be a state of the view"):
        FourierShell(st, basis, reference=c[:-1])
    bad = c.copy()
    bad[3] = math.nan
    with pytest.raises(ValueError, match="reference must be finite"):
        FourierShell(st, basis, reference=bad)
    off = c.copy()
    off[(st.N - 1) * basis.m + basis.index("Z", "cos", 3)] = 1e-3  # the pole's height varies with the angle
    with pytest.raises(ValueError, match="reference must keep every pole"):
        FourierShell(st, basis, reference=off)
