"""The shallow-shell cap (``contin_models.benchmarks.shallow_cap``) against closed forms from the literature.

* the flat plate (``lambda = 0``): a clamped circular plate under a central force deflects by ``P a^2 / (16 pi D)``
  (Timoshenko & Woinowsky-Krieger, *Theory of plates and shells*, sec. 19), approached at second order in the
  element size on a uniform mesh;
* the shallow sphere far from its edge: Reissner's point-load stiffness ``P R / (E t^3) = 4 / sqrt(3 (1 - nu^2))
  w / t`` (Reissner 1946/47), approached as lambda grows;
* the Hessian of an ``n``-wave state splits into the classes of ``D_n``: the spectrum in every harmonic up to a
  wave number is the union of the classes' spectra (the ``E`` classes twice);
* an in-plane field through the pole, ``u_x = 1 - r^2 / a^2`` (harmonic 1, tied at the pole), and its membrane energy
  in closed form;
* the derivatives of the model (residual, Jacobian, ``df/dp``) against its energy.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

import contin
from contin_models.benchmarks.shallow_cap import (FourierSpace, Harmonic, ShallowCap, plate_point_load_deflection,
                                                  point_load_stiffness, representation_harmonics)


def _equilibrium(cap: ShallowCap, w: float) -> np.ndarray:
    """The equilibrium at apex deflection ``w`` by Newton's method from the unloaded state."""
    x = cap.reference_unknowns()
    start = np.max(np.abs(cap.residual(x, w)))
    for _ in range(20):
        f = cap.residual(x, w)
        if np.max(np.abs(f)) < 1e-11 * start:
            return x
        x = x - spsolve(cap.jacobian(x, w).tocsc(), f)
    raise AssertionError("Newton did not converge")


def _plate_error(N: int, grading: float) -> float:
    """Relative error of the clamped plate's central stiffness against ``16 pi D / a^2``."""
    cap = ShallowCap(0.0, 0.3, N=N, grading=grading)
    w = 1e-4                                 # small against t: the membrane's w'^2 does not show
    q = cap.apex_force(_equilibrium(cap, w), w)
    return plate_point_load_deflection(q) / w - 1.0


def test_flat_plate_matches_the_clamped_plate_under_a_central_force() -> None:
    assert abs(_plate_error(40, 2.0)) < 1e-6
    # on a uniform mesh the error falls as h^2: 4 times per halving
    coarse, fine = _plate_error(10, 1.0), _plate_error(20, 1.0)
    assert coarse > fine > 0.0                # a conforming discretisation is too stiff
    assert 3.7 < coarse / fine < 4.3


def test_deep_shallow_cap_tends_to_reissners_point_load_stiffness() -> None:
    excess = {}
    for lam in (20.0, 40.0):
        cap = ShallowCap(lam, 0.3, N=80, grading=2.0)
        w = 1e-4
        P = cap.observables["P"](_equilibrium(cap, w), w)
        excess[lam] = P / w / point_load_stiffness(0.3) - 1.0
    assert 0.0 < excess[40.0] < 1.5e-3
    # the clamped edge stiffens the cap through the membrane stresses, which fall off as 1 / r^2 only
    assert 3.0 < excess[20.0] / excess[40.0] < 5.0


def test_the_hessian_of_a_wavy_state_splits_into_the_classes_of_dn() -> None:
    n, K = 3, 1
    cap = ShallowCap(6.0, 0.3, n=n, K=K, N=4)
    x = np.random.default_rng(1).normal(size=cap.space.n_free)
    p = 0.7
    classes = representation_harmonics(n, K)
    top = max(h.m for hs in classes.values() for h in hs)
    every = [Harmonic(m, par) for m in range(top + 1) for par in ("cos", "sin")]
    # the full space is not mapped to itself by t -> -t: a plain uniform rule over the circle, exact for the products
    M = 2 * K * n + 2 * top + 1
    theta, weights = 2 * np.pi * np.arange(M) / M, np.full(M, 2 * np.pi / M)
    state = FourierSpace(cap.nodes, cap.space.harmonics, theta, weights)
    full = FourierSpace(cap.nodes, every, theta, weights, apex_parameter=False)
    psi2 = cap.density(state.fields(state.local(x, p)), state.rho[:, :, None], 2)[2]
    everything = np.linalg.eigvalsh(full.hessian(psi2)[0].toarray())
    parts = []
    for label, hs in classes.items():
        H = cap.class_hessian(hs, x, p)[0].toarray()
        parts += list(np.linalg.eigvalsh(H)) * (2 if label.startswith("E") else 1)
    assert len(parts) == len(everything)
    np.testing.assert_allclose(np.sort(parts), everything, rtol=1e-9, atol=1e-9 * np.max(np.abs(everything)))


def test_a_field_that_slides_through_the_pole_has_its_closed_form_energy() -> None:
    # u_x = g(r) = 1 - r^2 (in units t^2 / a): u_r = g cos t, u_t = -g sin t, a field of harmonic 1 whose pole values
    # are tied (u_t(0) = -u_r(0)); its strains e_xx = -2 x, e_xy = -y give 6 int (e_xx^2 + 2 (1 - nu) e_xy^2) dA =
    # 3 pi (3 - nu) over the unit disc (the quadratic elements hold g exactly)
    nu = 0.3
    cap = ShallowCap(0.0, nu, n=1, K=1, N=6)
    mid = 0.5 * (cap.nodes[:-1] + cap.nodes[1:])

    def g(pos: int) -> float:
        rho = cap.nodes[pos // 2] if pos % 2 == 0 else mid[pos // 2]
        return 1.0 - rho ** 2

    x = np.array([(g(pos) if c == "u" else -g(pos)) if (m == 1 and c in "uv") else 0.0
                  for m, _, c, pos, _ in cap.space.labels])
    assert cap.energy(x, 0.0) == pytest.approx(3 * np.pi * (3 - nu), rel=1e-12)


@pytest.mark.parametrize("n,K", [(0, 0), (4, 2)])
def test_derivatives_agree_with_the_energy(n: int, K: int) -> None:
    cap = ShallowCap(9.0, 0.3, n=n, K=K, N=8)
    x = 0.5 * np.random.default_rng(2).normal(size=cap.space.n_free)
    report = contin.check_problem(cap, x, 3.0)
    assert report.ok, str(report)


def test_bad_input_names_the_field() -> None:
    with pytest.raises(ValueError, match="lam"):
        ShallowCap(-1.0)
    with pytest.raises(ValueError, match="N = 1"):
        ShallowCap(10.0, N=1)
    with pytest.raises(ValueError, match="K = 0 when n = 0"):
        ShallowCap(10.0, n=0, K=2)
