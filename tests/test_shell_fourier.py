"""The shell's 3-D view (Fourier series in the angle, :mod:`contin_models.shell.fourier`).

What is checked, against what nobody tuned:

* restricted to axisymmetric states it is the traced 1-D model: energy, gradient and Hessian to
  roundoff, for a sliding cap with its rotating edge's element, a clamped cap, a closed sphere under
  pressure (volume and pole elements at both ends) and a sliding cap under pressure (the skirt), off
  equilibrium: the hand-written 1-D pole, edge and volume elements agree with the densities;
* its Hessian at an axisymmetric state, restricted to the unknowns of wave number ``k``, is the
  harmonic block of ``k`` (:mod:`contin_models.shell.harmonic`, computed by other kernels and another
  assembly), so the blocks' branch points are this view's;
* an unsupported shell has exactly six zero modes (three translations, three rotations);
* a ``D_n`` state computed in the ``D_n`` basis (half a period of angles) has the energy, gradient and
  Hessian of the same state in the basis without symmetry (the whole circle); the gradient has no
  component that breaks the symmetry;
* gradient and Hessian are the derivatives of the energy (central differences) at a state with no
  symmetry at all;
* bad bases are refused with the field named.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contin_models.shell.fourier import AngularBasis, FourierShell
from contin_models.shell.geometry import spherical_cap
from contin_models.shell.harmonic import harmonic_block
from contin_models.shell.meridian import complete_sphere_meridian
from contin_models.shell.structure import ShellStructure
from contin_models.shell.volume import enclosed_volume, volume_gradient, volume_hessian


def perturbed(x: np.ndarray, amplitude: float, seed: int) -> np.ndarray:
    """An axisymmetric state off equilibrium (the radii on the axis stay zero)."""
    rng = np.random.default_rng(seed)
    y = x * (1.0 + amplitude * rng.standard_normal(x.size))
    return y


def traced(st: ShellStructure, x: np.ndarray, pressure: float, z_ref: float) -> tuple:
    E, g, H = st.energy(x), st.gradient(x), st.hessian(x).toarray()
    if pressure:
        E += pressure * enclosed_volume(x, z_ref)
        g = g + pressure * volume_gradient(x, z_ref)
        H = H + pressure * volume_hessian(x, z_ref).toarray()
    return E, g, H


def structures() -> dict:
    cap = spherical_cap(1.0, 0.8, 30)
    sphere = complete_sphere_meridian(1.0, 31, 1.0)
    return {"sliding cap": (ShellStructure(cap, 1e6, 0.5, 0.02, boundary="sliding"), 0.0),
            "clamped cap": (ShellStructure(cap, 1e6, 0.3, 0.02, boundary="clamped", kappa11_length="reference"), 0.0),
            "sphere under pressure": (ShellStructure(sphere, 1.0, 0.3, 0.02), 3e-4),
            # off equilibrium the edge ring leaves the base plane: the skirt's volume counts
            "sliding cap under pressure": (ShellStructure(cap, 1e6, 0.3, 0.02, boundary="sliding"), 50.0)}


@pytest.mark.parametrize("name", ["sliding cap", "clamped cap", "sphere under pressure", "sliding cap under pressure"])
def test_axisymmetric_restriction_is_the_traced_model(name: str) -> None:
    st, p = structures()[name]
    x = perturbed(st.reference_state(), 0.02, 1)
    view = FourierShell(st, AngularBasis(3, 2))
    c = view.axisymmetric_state(x)
    ax = view.axisymmetric_dofs()
    E1, g1, H1 = traced(st, x, p, view.z_ref)
    assert abs(view.energy(c, p) - E1) <= 1e-13 * abs(E1)
    g = view.gradient(c, p)
    scale = np.max(np.abs(g1))
    assert np.max(np.abs(g[ax] - g1)) <= 1e-13 * scale
    # no component along a wave: an axisymmetric state is a critical point of every symmetry-breaking field
    assert np.max(np.abs(np.delete(g, ax))) <= 1e-14 * scale
    # the radius of a pole is held in both (a point on the axis); every other entry agrees
    keep = np.array([d for d in range(2 * st.N) if not (d % 2 == 0 and d // 2 in st.poles)])
    H = view.hessian(c, p).toarray()[np.ix_(ax, ax)]
    assert np.max(np.abs(H - H1)[np.ix_(keep, keep)]) <= 2e-12 * np.max(np.abs(H1))


@pytest.mark.parametrize("name", ["sliding cap", "clamped cap", "sphere under pressure", "sliding cap under pressure"])
def test_hessian_on_a_wave_number_is_the_harmonic_block(name: str) -> None:
    st, p = structures()[name]
    x = perturbed(st.reference_state(), 0.02, 2)
    for n, K in ((1, 3), (4, 2)):
        view = FourierShell(st, AngularBasis(n, K))
        H = view.hessian(view.axisymmetric_state(x), p).toarray()
        for k in view.basis.wave_numbers[1:]:
            block = harmonic_block(st, x, int(k), pressure=p, z_ref=view.z_ref, reduced=False).toarray()
            d = view.dofs_of_wave(int(k))
            assert np.max(np.abs(H[np.ix_(d, d)] - block)) <= 2e-12 * np.max(np.abs(block)), (n, k)
            # and a wave couples to no other unknown at an axisymmetric state
            others = np.setdiff1d(np.arange(view.size), d)
            assert np.max(np.abs(H[np.ix_(d, others)])) <= 1e-13 * np.max(np.abs(block))


def test_unsupported_shell_has_exactly_six_rigid_zero_modes() -> None:
    st = ShellStructure(spherical_cap(1.0, 0.8, 20), 1e6, 0.3, 0.02, boundary="free")
    view = FourierShell(st, AngularBasis(1, 3, mirror=False))
    red = view.reduction(remove_rigid=False)
    H = (red.T.T @ view.hessian(view.reference_state()) @ red.T).toarray()
    ev = np.linalg.eigvalsh(H) / np.max(np.abs(H))
    assert np.all(np.abs(ev[:6]) < 1e-14) and ev[6] > 1e-8, ev[:8]
    # with the rigid motions removed at the structure's node: none left
    red = view.reduction()
    H = (red.T.T @ view.hessian(view.reference_state()) @ red.T).toarray()
    assert np.linalg.eigvalsh(H)[0] > 1e-8 * np.max(np.abs(H))


def test_dihedral_basis_is_the_full_circle_on_symmetric_states() -> None:
    st = ShellStructure(spherical_cap(1.0, 0.8, 20), 1e6, 0.3, 0.02, boundary="free")
    sym = FourierShell(st, AngularBasis(3, 2, M=36))
    full = FourierShell(st, AngularBasis(1, 6, mirror=False, M=36))
    rng = np.random.default_rng(3)
    red = sym.reduction(remove_rigid=False)
    c = sym.reference_state() + red.T @ (1e-2 * rng.standard_normal(red.free.size))
    where = np.array([full.basis.index(*t) for t in sym.basis.terms])
    idx = (np.arange(st.N)[:, None] * full.m + where[None, :]).ravel()
    cf = np.zeros(full.size)
    cf[idx] = c
    E = sym.energy(c)
    assert abs(full.energy(cf) - E) <= 1e-13 * abs(E)
    g, gf = sym.gradient(c), full.gradient(cf)
    assert np.max(np.abs(gf[idx] - g)) <= 1e-13 * np.max(np.abs(g))
    assert np.max(np.abs(np.delete(gf, idx))) <= 1e-13 * np.max(np.abs(g))
    H, Hf = sym.hessian(c).toarray(), full.hessian(cf).toarray()
    assert np.max(np.abs(Hf[np.ix_(idx, idx)] - H)) <= 1e-13 * np.max(np.abs(H))


def test_derivatives_are_those_of_the_energy_without_symmetry() -> None:
    sphere = complete_sphere_meridian(1.0, 15, 1.0)
    st = ShellStructure(sphere, 1.0, 0.3, 0.05)
    view = FourierShell(st, AngularBasis(1, 2, mirror=False))
    rng = np.random.default_rng(4)
    red = view.reduction(remove_rigid=False)
    c = view.reference_state() + red.T @ (2e-2 * rng.standard_normal(red.free.size))
    p = 1e-3
    g, H = view.gradient(c, p), view.hessian(c, p)
    for seed in range(3):
        d = red.T @ np.random.default_rng(10 + seed).standard_normal(red.free.size)
        h = 1e-5
        dE = (view.energy(c + h * d, p) - view.energy(c - h * d, p)) / (2 * h)
        assert abs(dE - g @ d) <= 1e-7 * np.max(np.abs(g)) * np.linalg.norm(d, 1)
        dg = (view.gradient(c + h * d, p) - view.gradient(c - h * d, p)) / (2 * h)
        assert np.max(np.abs(dg - H @ d)) <= 1e-6 * np.max(np.abs(H @ d))


def test_a_pole_is_one_point_and_the_points_are_cartesian() -> None:
    st = ShellStructure(spherical_cap(1.0, 0.8, 12), 1e6, 0.3, 0.02, boundary="sliding")
    view = FourierShell(st, AngularBasis(1, 2, mirror=False))
    red = view.reduction()
    c = red.full(np.random.default_rng(5).standard_normal(red.free.size), view.reference_state())
    th = np.linspace(0.0, 2.0 * math.pi, 7)
    X = view.points(c, th)
    pole = st.N - 1
    assert np.max(np.abs(X[pole] - X[pole, :1])) < 1e-14  # the same point at every angle
    assert np.max(np.abs(X[0, :, 2] - X[0, 0, 2])) < 1e-14  # the sliding edge keeps its height
    ref = view.points(view.reference_state(), th)
    r = np.hypot(ref[..., 0], ref[..., 1])
    assert np.allclose(r, st.reference_state()[0::2][:, None], atol=1e-15)


@pytest.mark.parametrize("kwargs, field", [({"n": 0, "K": 1}, "n"), ({"n": 2, "K": -1}, "K"),
                                           ({"n": 3, "K": 2, "M": 15}, "M"), ({"n": 3, "K": 2, "M": 12}, "M")])
def test_bad_bases_are_refused_with_the_field_named(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match=f"{field} "):
        AngularBasis(**kwargs)


def test_the_3d_view_traces_the_axisymmetric_path_and_meets_the_blocks_branch_point() -> None:
    """The paper's cap under the pole's deflection: in the ``D_3`` basis the trace is the 1-D one until
    the blocks' ``n = 3`` bifurcation, which the 3-D view finds as a simple branch point of its own at
    the same deflection (the blocks and the view differentiate the same energy with exact
    ``theta``-derivatives)."""
    import contin
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellOfRevolution

    st = ShellStructure(spherical_cap(1.0, 0.8, 30), 1e6, 0.5, 0.02, boundary="sliding")
    one = ShellOfRevolution(st, "point", "displacement", harmonics=3)
    b1 = contin.continuation(one, one.reference_unknowns(), 0.0, p_max=0.37, ds=0.01, ds_max=0.02, max_steps=100,
                             stability=True)
    w3 = [sp_.p for sp_ in b1.special_points if sp_.kind == "bifurcation" and sp_.info.get("key") == 3]
    assert len(w3) == 1
    view = Shell3D(st, AngularBasis(3, 2), "point", "displacement")
    b3 = contin.continuation(view, view.reference_unknowns(), 0.0, p_max=0.37, ds=0.01, ds_max=0.02, max_steps=100,
                             stability=True)
    assert b3.success
    bps = [sp_ for sp_ in b3.special_points if sp_.kind == "branch_point"]
    assert len(bps) == 1 and bps[0].info["n_negative_after"] == 1
    assert abs(bps[0].p - w3[0]) < 1e-10
    # before it, every state of the 3-D trace is axisymmetric and an equilibrium of the 1-D model
    ax = view.view.axisymmetric_dofs()
    for u, p in zip(b3.u, b3.p):
        if p < bps[0].p:
            c = view.full_state(u, p)
            assert np.max(np.abs(np.delete(c, ax))) < 1e-12
            r = one.residual(one.unknowns(c[ax]), p)
            assert np.max(np.abs(r)) < 1e-11 * one.residual_scale, np.max(np.abs(r)) / one.residual_scale


def test_bloch_blocks_are_the_hessian_on_every_perturbation() -> None:
    """At a ``D_3`` state (off equilibrium: the splitting is kinematic), the spectrum of the Hessian on
    every perturbation (the basis without symmetry, waves 0 .. 7) is the union of the Bloch blocks'
    spectra, the two-dimensional class counted twice."""
    st = ShellStructure(spherical_cap(1.0, 0.8, 12), 1e6, 0.3, 0.02, boundary="sliding")
    sym = FourierShell(st, AngularBasis(3, 2))
    full = FourierShell(st, AngularBasis(1, 7, mirror=False, M=sym.basis.M))
    red = sym.reduction()
    c = red.full(np.random.default_rng(6).standard_normal(red.free.size) * 3e-3 + red.T.T @ sym.reference_state(),
                 sym.reference_state())
    cf = np.zeros(full.size)
    for j, term in enumerate(sym.basis.terms):
        cf[full.basis.index(*term)::full.m] = c[j::sym.m]
    fred = full.reduction()
    whole = np.linalg.eigvalsh((fred.T.T @ full.hessian(cf) @ fred.T).toarray())
    parts = []
    for j, parity, multiplicity in sym.bloch_classes():
        ev = np.linalg.eigvalsh(sym.bloch_block(c, j, parity).toarray())
        parts += [ev] * multiplicity
    parts = np.sort(np.concatenate(parts))
    assert parts.size == whole.size
    assert np.max(np.abs(parts - whole)) <= 1e-12 * np.max(np.abs(whole))
    assert np.sum(whole < 0) > 0  # the state is far enough from the reference to test the count
    index = sym.morse_index(c)
    assert sum(m * index[j, par] for j, par, m in sym.bloch_classes()) == np.sum(whole < 0)


def test_pressure_in_the_3d_view_meets_the_blocks_bifurcation() -> None:
    """A clamped cap under pressure (lambda = 7, R/h = 400): the harmonic blocks locate its first
    bifurcation (into ``n = 3``, before the axisymmetric snap); the ``D_3`` view, started at zero
    pressure, finds a branch point of its own at the same pressure."""
    import contin
    from contin_models.shell.meridian import spherical_cap_meridian
    from contin_models.shell.pressure import phi_hat_for_lambda
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellOfRevolution

    nu, R, h = 0.3, 400.0, 1.0
    E = math.sqrt(3 * (1 - nu * nu)) / (2 * (h / R) ** 2)  # p_c = 1
    st = ShellStructure(spherical_cap_meridian(R, phi_hat_for_lambda(7.0, R, h, nu), 40, 1.0), E, nu, h, "clamped")
    settings = contin.Settings(ds=0.05, ds_max=0.05, max_steps=200, stability=True)
    one = ShellOfRevolution(st, "pressure", p_c=1.0, length=R, harmonics=4)
    b1 = contin.continuation(one, one.reference_unknowns(), 0.0, settings, p_max=1.0, stop_at=("fold", "bifurcation"))
    first = b1.special_points[-1]
    assert first.kind == "bifurcation" and first.info["key"] == 3
    view = Shell3D(st, AngularBasis(3, 2), "pressure", length=R)
    b3 = contin.continuation(view, view.reference_unknowns(), 0.0, settings, p_max=1.0, stop_at=("branch_point",))
    bp = b3.special_points[-1]
    assert bp.kind == "branch_point" and bp.located
    assert abs(bp.p - first.p) < 1e-9 * abs(first.p)


def test_ring_line_loads_and_the_volume_control() -> None:
    """The other loads: a ring force is the traced model's on axisymmetric states; a line load of wave 3
    works only on wave 3 (its work is the integral of the density against the ring's displacement); a
    prescribed volume (contin.ConjugateControl) meets the pressure-controlled states."""
    import contin
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellOfRevolution

    st = ShellStructure(spherical_cap(1.0, 0.8, 20), 1e6, 0.3, 0.02, boundary="clamped")
    ring = Shell3D(st, AngularBasis(3, 2), "ring", node=10)
    one = ShellOfRevolution(st, "ring", node=10)
    b3 = contin.continuation(ring, ring.reference_unknowns(), 0.0, p_max=5.0, ds=1.0, ds_max=2.0, max_steps=50)
    ax = ring.view.axisymmetric_dofs()
    for u, p in zip(b3.u, b3.p):  # axisymmetric and in equilibrium as the traced model
        c = ring.full_state(u, p)
        assert np.max(np.abs(np.delete(c, ax))) < 1e-12
        assert np.max(np.abs(one.residual(one.unknowns(c[ax]), p))) < 1e-9 * one.residual_scale
        assert abs(ring.observables["w"](u, p) - one.observables["w"](one.unknowns(c[ax]), p)) < 1e-14
    # a line load q_z cos(3 theta) on ring 10: its work on a unit wave-3 height coefficient is pi q_z
    line = Shell3D(st, AngularBasis(3, 2), "forces", line_loads=[(10, 3, (0.0, 0.0, -2.0))])
    k = 10 * line.view.m + line.basis.index("Z", "cos", 3)
    assert line.load_vector[k] == pytest.approx(-2.0 * math.pi, rel=1e-14)
    assert np.count_nonzero(np.abs(line.load_vector) > 1e-14) == 1
    with pytest.raises(ValueError, match="wave number 2"):
        Shell3D(st, AngularBasis(3, 2), "forces", line_loads=[(10, 2, (0.0, 0.0, 1.0))])
    # volume control against pressure control
    pressure = Shell3D(st, AngularBasis(3, 2), "pressure")
    volume = contin.ConjugateControl(pressure, "dV", linear=True, multiplier_unit=1e2)
    p0 = 200.0  # about 0.4 of the classical buckling pressure
    bp = contin.continuation(pressure, pressure.reference_unknowns(), 0.0, p_max=p0, ds=50.0, ds_max=100.0)
    assert bp.status == "bound"
    dV = -pressure.conjugate_force(bp.u[-1], p0)
    assert dV > 0  # an external pressure pushes the cap in
    U0, q0 = volume.from_load_state(pressure.reference_unknowns(), 0.0)
    bv = contin.continuation(volume, U0, q0, p_max=dV, ds=dV / 5, ds_max=dV / 2)
    assert bv.status == "bound"
    u, p = volume.split(bv.u[-1])
    assert p == pytest.approx(p0, rel=1e-8)
    assert np.max(np.abs(u - bp.u[-1])) < 1e-9


def test_every_mode_watches_the_other_classes_and_locates_the_blocks_bifurcations() -> None:
    """With ``every_mode`` the D_3 trace of the paper's cap counts its stability against every
    perturbation: the class ``j = 1`` (the representation ``E1``: waves 1, 2, 4, 5, 7) becomes singular where the harmonic blocks
    locate their ``n = 1`` and ``n = 2`` bifurcations, and the Morse index counts that class twice."""
    import contin
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellOfRevolution

    st = ShellStructure(spherical_cap(1.0, 0.8, 30), 1e6, 0.5, 0.02, boundary="sliding")
    one = ShellOfRevolution(st, "point", "displacement", harmonics=3)
    b1 = contin.continuation(one, one.reference_unknowns(), 0.0, p_max=0.38, ds=0.01, ds_max=0.02, max_steps=200,
                             stability=True)
    blocks = {s.info["key"]: s.p for s in b1.special_points if s.kind == "bifurcation"}
    shell = Shell3D(st, AngularBasis(3, 2), "point", "displacement", every_mode=True)
    b3 = contin.continuation(shell, shell.reference_unknowns(), 0.0, p_max=0.38, ds=0.01, ds_max=0.02,
                             max_steps=200, stability=True)
    assert b3.success
    j1 = [s for s in b3.special_points if s.kind == "bifurcation" and s.info["key"] == "E1" and s.located]
    assert len(j1) == 2
    assert abs(j1[0].p - blocks[1]) < 1e-9 and abs(j1[1].p - blocks[2]) < 1e-9
    # before the first: stable against everything; after it, the pair of a two-dimensional class
    index = np.asarray(b3.n_negative)
    assert index[np.asarray(b3.p) < j1[0].p].max() == 0
    assert index[(np.asarray(b3.p) > j1[0].p) & (np.asarray(b3.p) < blocks[3])].min() == 2


@pytest.mark.parametrize("kwargs, message", [
    ({"load": "pressure", "boundary": "free"}, "free edge cannot carry pressure"),
    ({"load": "ring", "node": 0}, "ring load needs node"),
    ({"load": "point", "boundary": "free"}, "needs a support in z"),
    ({"load": "forces"}, "needs forces"),
    ({"load": "pressure", "control": "displacement"}, "takes control='force'"),
    ({"load": "forces", "forces": [(0, 0.0, (0.0, 0.0, 0.0))]}, "nonzero"),
    ({"load": "gravity"}, "load must be one of")])
def test_bad_problems_are_refused_with_the_reason(kwargs: dict, message: str) -> None:
    from contin_models.shell.problem3d import Shell3D

    st = ShellStructure(spherical_cap(1.0, 0.8, 12), 1e6, 0.3, 0.02, boundary=kwargs.pop("boundary", "sliding"))
    with pytest.raises(ValueError, match=message):
        Shell3D(st, AngularBasis(2, 1), **kwargs)


def test_energy_of_a_smooth_three_wave_field_converges_at_second_order() -> None:
    """The discrete energy of a prescribed smooth field (displacements ``f(s) cos 3 theta`` and
    ``f(s) sin 3 theta``, ``f`` vanishing at the pole and the edge) converges at second order in the
    meridian, as that of an axisymmetric field does: the 2-D densities are consistent away from
    axisymmetry (observed: 2.06, 2.03, 2.02 for both, N = 25 .. 400)."""
    def energy(N: int, wave: int) -> float:
        st = ShellStructure(spherical_cap(1.0, 0.8, N), 1e6, 0.3, 0.02, boundary="clamped")
        view = FourierShell(st, AngularBasis(3, 1))
        x = st.reference_state()
        s = np.arctan2(x[0::2], x[1::2]) / np.arctan2(x[0], x[1])  # 1 at the edge, 0 at the pole
        f = 0.8 * s ** 2 * (1.0 - s) ** 2
        c = view.reference_state()
        tr = "sin" if wave else "cos"
        c[view.basis.index("R", "cos", wave)::view.m] += f
        c[view.basis.index("Z", "cos", wave)::view.m] += f
        if wave:
            c[view.basis.index("T", tr, wave)::view.m] += 0.5 * f
        return view.energy(c)

    for wave in (0, 3):
        E = [energy(N, wave) for N in (25, 50, 100, 200, 400)]
        d = np.abs(np.diff(E))
        orders = np.log2(d[:-1] / d[1:])
        assert np.all(orders > 1.95), (wave, orders)


@pytest.mark.parametrize("control", ["displacement", "force"])
def test_both_controls_stability_labels_are_the_traced_models(control: str) -> None:
    """Shell3D labels every point as the traced model does: ``"force"`` (the loaded node's height free) and
    ``"displacement"`` (held), the control's own first; on axisymmetric states (K = 0) the counts are the same."""
    import contin
    from contin_models.shell.problem3d import Shell3D
    from contin_models.shell.structure import ShellOfRevolution

    st = ShellStructure(spherical_cap(1.0, 0.8, 30), 1e6, 0.5, 0.02, boundary="sliding")
    # steps of about 0.01 R in w either way: the force changes by about 100 D / R over 0.01 R
    steps = ({"p_max": 0.45, "ds": 0.01, "ds_max": 0.02} if control == "displacement" else
             {"bounds": {"w": (None, 0.45)}, "ds": 0.5, "ds_max": 2.0, "param_weight": 1e-2})
    runs = [contin.continuation(P, P.reference_unknowns(), 0.0, max_steps=80, stability=True, n_eigs=0, **steps)
            for P in (ShellOfRevolution(st, "point", control), Shell3D(st, AngularBasis(3, 0), "point", control))]
    one, three = runs
    assert list(three.stability_by) == list(one.stability_by) == [control, {"force": "displacement",
                                                                              "displacement": "force"}[control]]
    for label in one.stability_by:
        assert np.array_equal(three.n_negative_under(label), one.n_negative_under(label))
    assert max(one.n_negative_under(label).max() for label in one.stability_by) > 0


def test_a_sphere_on_a_point_support_keeps_the_rotations_about_it() -> None:
    """A complete sphere pinned at its south pole (``boundary="pinned"``): the pole's point is held, which leaves
    the three rotations about it (the spin about the axis and the two tilts); with the rigid motions removed
    (the spin held mid-meridian; the tilts are what a probe holding the north pole removes, not the support)
    two zero modes remain."""
    st = ShellStructure(complete_sphere_meridian(1.0, 21, 1.0), 1.0, 0.3, 0.02, boundary="pinned")
    view = FourierShell(st, AngularBasis(1, 3, mirror=False))
    for remove, zeros in ((False, 3), (True, 2)):
        red = view.reduction(remove_rigid=remove)
        H = (red.T.T @ view.hessian(view.reference_state()) @ red.T).toarray()
        ev = np.linalg.eigvalsh(H) / np.max(np.abs(H))
        assert np.all(np.abs(ev[:zeros]) < 1e-12) and ev[zeros] > 1e-8, ev[:5]
