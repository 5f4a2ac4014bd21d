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
    a[[0, -1]] = 0.0
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
    # the Bloch blocks integrate over the whole circle: the reference's numbers at those angles too
    B0, B1 = default.bloch_block(c, 1).toarray(), general.bloch_block(c, 1).toarray()
    assert np.max(np.abs(B1 - B0)) <= 1e-12 * np.max(np.abs(B0))


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
    if symmetry == "D3":  # stable against every perturbation, the classes that break D_3 too
        assert set(view.morse_index(c_bar).values()) == {0}
    # the problem's unloaded equilibrium: the supports hold their rings where c_bar has them
    from contin_models.shell.problem3d import Shell3D

    prob = Shell3D(st, basis, "point", "force", reference=c_bar)
    assert np.max(np.abs(prob.full_state(prob.reference_unknowns(), 0.0) - c_bar)) <= 1e-15
    assert np.max(np.abs(prob.residual(prob.reference_unknowns(), 0.0))) <= 1e-10 * g_scale


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


# ---- the imperfections users ask for ---------------------------------------------------------------------

@pytest.mark.parametrize("boundary", ["sliding", "clamped"])
def test_axisymmetric_dimple_is_the_imperfect_1d_model(boundary: str) -> None:
    """The 1-D model's own imperfection (a pole dimple, :func:`with_dimple`) given to the perfect structure's
    3-D view as ``c_bar`` is the imperfect 1-D model on axisymmetric states.  Sliding: to roundoff.  Clamped:
    the view keeps the perfect structure's ghost ring, the imperfect meridian's tangent at the edge turns by
    the dimple's tail there (``delta exp(-(alpha / beta0)^2)``, 1e-13 here), so the clamp's element differs
    by that much."""
    from contin_models.shell.meridian import spherical_cap_meridian, with_dimple

    m = spherical_cap_meridian(1.0, 0.8, 30)
    kw = dict(boundary=boundary, kappa11_length="reference" if boundary == "clamped" else "current")
    perfect = ShellStructure(m, 1e6, 0.5, 0.02, **kw)
    imperfect = ShellStructure(with_dimple(m, 0.01, 0.15), 1e6, 0.5, 0.02, **kw)
    basis = AngularBasis(3, 2)
    view = FourierShell(perfect, basis)
    view = FourierShell(perfect, basis, reference=view.axisymmetric_state(imperfect.reference_state()))
    rng = np.random.default_rng(1)
    x = imperfect.reference_state() * (1.0 + 0.02 * rng.standard_normal(2 * perfect.N))
    c, ax = view.axisymmetric_state(x), view.axisymmetric_dofs()
    E1, g1, H1 = imperfect.energy(x), imperfect.gradient(x), imperfect.hessian(x).toarray()
    tol = 1e-14 if boundary == "sliding" else 1e-11
    assert abs(view.energy(c) - E1) <= tol * abs(E1)
    assert np.max(np.abs(view.gradient(c)[ax] - g1)) <= tol * np.max(np.abs(g1))
    keep = np.array([d for d in range(2 * perfect.N) if not (d % 2 == 0 and d // 2 in perfect.poles)])
    H = view.hessian(c).toarray()[np.ix_(ax, ax)]
    assert np.max(np.abs(H - H1)[np.ix_(keep, keep)]) <= 10 * tol * np.max(np.abs(H1))
    # the perfect view sees the dimple strained: the comparison can fail
    assert abs(FourierShell(perfect, basis).energy(c) - E1) > 1e-4 * abs(E1)


def cap() -> ShellStructure:
    return ShellStructure(spherical_cap(1.0, 0.8, 30), 1e6, 0.5, 0.02, boundary="sliding")


def normal_displacement(st: ShellStructure, basis: AngularBasis, c: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """``(N, len(theta))``: each material point's displacement from the perfect reference along the meridian's
    outward normal (Cartesian points projected on the normal turned to the point's angle)."""
    from contin_models.shell.imperfection3d import meridian_normals

    view = FourierShell(st, basis)
    d = view.points(c, theta) - view.points(view.reference_state(), theta)
    nr, nz = meridian_normals(st)
    return (d[..., 0] * np.cos(theta) + d[..., 1] * np.sin(theta)) * nr[:, None] + d[..., 2] * nz[:, None]


def test_dimple_away_from_the_pole() -> None:
    from contin_models.shell.imperfection3d import dimple_imperfection

    st = cap()
    theta = np.linspace(0.0, 2.0 * math.pi, 73)
    node, delta, width = 12, 2e-3, 0.2
    for basis, theta0 in ((AngularBasis(1, 12), 0.0), (AngularBasis(1, 12, mirror=False), 1.0)):
        c = dimple_imperfection(st, basis, delta, width, node=node, theta0=theta0)
        view = FourierShell(st, basis, reference=c)   # the poles stayed points
        w = normal_displacement(st, basis, c, theta)
        k = int(np.argmin(np.abs(theta - theta0)))
        # inward by delta at the centre (to the truncation), the Gaussian elsewhere
        assert abs(w[node, k] + delta) <= 1e-2 * delta
        s = np.concatenate([[0.0], np.cumsum(st.reference.meridian.edge_length)])
        r = st.reference.meridian.x[0::2]
        d2 = (s - s[node])[:, None] ** 2 + (2.0 * r[:, None] * np.sin(0.5 * (theta - theta0))) ** 2
        assert np.max(np.abs(w + delta * np.exp(-d2 / width ** 2))) <= 1e-2 * delta
        assert abs(view.energy(c)) <= 1e-20


def test_dimple_inputs_are_refused_with_the_field_named() -> None:
    from contin_models.shell.imperfection3d import dimple_imperfection

    st = cap()
    basis = AngularBasis(1, 12)
    cases = [(dict(delta=math.nan, width=0.2, node=12), "delta must be a finite number"),
             (dict(delta=1e-3, width=0.0, node=12), "width must be a positive length"),
             (dict(delta=1e-3, width=0.2), "give exactly one of node"),
             (dict(delta=1e-3, width=0.2, node=30), r"node must be an integer in \[0, 29\]"),
             (dict(delta=1e-3, width=0.2, s0=5.0), r"s0 \(arc length from node 0\) must be in \[0, "),
             (dict(delta=1e-3, width=0.2, node=12, theta0=0.5), "theta0 must be 0 or pi"),
             (dict(delta=1e-3, width=0.02, node=12), r"the basis \(K = 12 harmonics\) carries the dimple")]
    for kwargs, message in cases:
        with pytest.raises(ValueError, match=message):
            dimple_imperfection(st, basis, **kwargs)
    with pytest.raises(ValueError, match="a single dimple needs a basis with n = 1"):
        dimple_imperfection(st, AngularBasis(3, 2), 1e-3, 0.2, node=12)


def test_mode_imperfection_has_its_largest_normal_displacement_delta() -> None:
    from contin_models.shell.imperfection3d import branch_mode, mode_imperfection

    st = cap()
    basis = AngularBasis(3, 2)
    mode = branch_mode(st, st.reference_state(), 3)
    delta = 1e-4
    c = mode_imperfection(st, basis, 3, mode, delta)
    FourierShell(st, basis, reference=c)  # the poles stayed points
    theta = np.linspace(0.0, 2.0 * math.pi / 3.0, 41)
    w = normal_displacement(st, basis, c, theta)
    # inward by delta at theta = 0 where the mode's normal amplitude is largest, nowhere more than delta
    k = int(np.argmax(np.abs(w[:, 0])))
    assert abs(w[k, 0] + delta) <= 1e-12 * delta
    assert np.max(np.abs(w)) <= delta * (1.0 + 1e-12)
    assert np.max(np.abs(w - w[:, :1] * np.cos(3 * theta)[None, :])) <= 1e-10 * delta  # the points subtracted
    with pytest.raises(ValueError, match="the basis does not carry the wave n = 4"):
        mode_imperfection(st, basis, 4, mode, delta)
    with pytest.raises(ValueError, match=r"mode must be finite amplitudes of shape \(N, 3\) = \(30, 3\)"):
        mode_imperfection(st, basis, 3, mode[:-1], delta)
    with pytest.raises(ValueError, match="delta must be a finite number"):
        mode_imperfection(st, basis, 3, mode, math.inf)
