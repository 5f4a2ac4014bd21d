"""The 3-D view's assembly (:class:`contin_models.shell.fourier.FourierShell`) against a direct evaluation.

The view evaluates its energy, gradient and Hessian by large matrix products on the kernels' own layout,
split by frame component (:meth:`FourierShell._element_hessians`).  Here the same sums are written out
term by term, ``sum_q w_q B_q^T h_eq B_q`` per element with ``einsum`` and scattered one entry at a time,
from the same local maps and the same kernels: the two must agree to rounding.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contin_models.shell import layouts
from contin_models.shell.fourier import AngularBasis, FourierShell
from contin_models.shell.geometry import spherical_cap
from contin_models.shell.meridian import complete_sphere_meridian
from contin_models.shell.structure import ShellStructure

RTOL = 1e-14


def _family_terms(view: FourierShell, family: tuple, c: np.ndarray, w: np.ndarray) -> tuple:
    """One family's energy, gradient and Hessian (dense), each element and angle in turn."""
    name, nodes, B, kernel, params, offset = family
    dofs = view.element_dofs(nodes)
    y = np.einsum("qka,ea->keq", B, c[dofs])
    if offset is not None:
        y = y + offset[:, None, None]
    E, Q = dofs.shape[0], B.shape[0]
    v, g, h = kernel(y, *[np.asarray(p, float)[:, None] * np.ones((1, Q)) if np.ndim(p) else p for p in params])
    energy = float(np.sum(np.broadcast_to(v, (E, Q)) * w))
    grad = np.zeros(view.size)
    np.add.at(grad, dofs, np.einsum("qka,keq,q->ea", B, g, w))
    hess = np.zeros((view.size, view.size))
    np.add.at(hess, (dofs[:, :, None], dofs[:, None, :]), np.einsum("qka,kleq,qlb,q->eab", B, h, B, w))
    return energy, grad, hess


def _pole_terms(view: FourierShell, pole: tuple, B: np.ndarray, c: np.ndarray, w: np.ndarray) -> tuple:
    """The pole element's ``A kb ((3 nu - 1) <B>^2 + 2 (1 - nu) <B^2>)``, its gradient and Hessian (dense)."""
    nodes, kernel, lbar, kbar, Akb = pole
    nu, wm = view.nu, w / (2.0 * math.pi)
    dofs = view.element_dofs(nodes)[0]
    v, g, h = kernel(np.einsum("qka,a->kq", B, c[dofs]), lbar)
    b = v - kbar
    G = np.einsum("qka,kq->qa", B, g)
    Hq = np.einsum("qka,klq,qlb->qab", B, h, B)
    mean, mean2, dmean = wm @ b, wm @ (b * b), wm @ G
    energy = Akb * ((3.0 * nu - 1.0) * mean ** 2 + 2.0 * (1.0 - nu) * mean2)
    grad, hess = np.zeros(view.size), np.zeros((view.size, view.size))
    grad[dofs] = Akb * (2.0 * (3.0 * nu - 1.0) * mean * dmean + 4.0 * (1.0 - nu) * ((wm * b) @ G))
    hess[np.ix_(dofs, dofs)] = Akb * (
        2.0 * (3.0 * nu - 1.0) * (np.outer(dmean, dmean) + mean * np.einsum("q,qab->ab", wm, Hq))
        + 4.0 * (1.0 - nu) * (np.einsum("q,qa,qb->ab", wm, G, G) + np.einsum("q,qab->ab", wm * b, Hq)))
    return energy, grad, hess


def direct(view: FourierShell, c: np.ndarray, pressure: float) -> tuple[float, np.ndarray, np.ndarray]:
    """Energy, gradient and dense Hessian of ``view`` at ``c``, every term written out."""
    w = view.basis.weights
    terms = [(f, 1.0) for f in view._families] + [(f, pressure) for f in view._volume if pressure]
    energy, grad, hess = 0.0, np.zeros(view.size), np.zeros((view.size, view.size))
    for family, factor in terms:
        e, g, h = _family_terms(view, family, c, w)
        energy, grad, hess = energy + factor * e, grad + factor * g, hess + factor * h
    for pole in view._poles:
        e, g, h = _pole_terms(view, pole, view._pole_map, c, w)
        energy, grad, hess = energy + e, grad + g, hess + h
    return energy, grad, hess


def shells() -> dict:
    cap = spherical_cap(1.0, 0.8, 24)
    return {"sliding cap (pole, free edge)": (ShellStructure(cap, 1e6, 0.5, 0.02, boundary="sliding"), 0.0),
            "clamped cap (clamp)": (ShellStructure(cap, 1e6, 0.3, 0.02, boundary="clamped",
                                                   kappa11_length="reference"), 0.0),
            "sphere under pressure (two poles, volume)": (ShellStructure(complete_sphere_meridian(1.0, 25, 1.0),
                                                                         1.0, 0.3, 0.02), 3e-4)}


def state(view: FourierShell, amplitude: float, seed: int) -> np.ndarray:
    """The reference state with every coefficient moved (not axisymmetric: every term of the kernels works)."""
    return view.reference_state() + amplitude * np.random.default_rng(seed).standard_normal(view.size)


@pytest.mark.parametrize("basis", [AngularBasis(3, 3), AngularBasis(1, 2, mirror=False)], ids=["D3", "none"])
@pytest.mark.parametrize("name", list(shells()))
def test_energy_gradient_and_hessian_are_the_direct_sums(name: str, basis: AngularBasis) -> None:
    st, pressure = shells()[name]
    view = FourierShell(st, basis)
    c = state(view, 2e-3, 1)
    energy, grad, hess = direct(view, c, pressure)
    assert abs(view.energy(c, pressure) - energy) <= RTOL * abs(energy)
    np.testing.assert_allclose(view.gradient(c, pressure), grad, rtol=0, atol=RTOL * np.abs(grad).max())
    H = view.hessian(c, pressure)
    np.testing.assert_allclose(H.toarray(), hess, rtol=0, atol=RTOL * np.abs(hess).max())
    # the same state again gives the kept Hessian, which a caller changing its copy does not reach
    H.data[:] = 0.0
    np.testing.assert_allclose(view.hessian(c, pressure).toarray(), hess, rtol=0, atol=RTOL * np.abs(hess).max())


def test_element_hessians_of_a_map_without_the_component_split() -> None:
    # a local map mixing every component with every unknown: the products without the split
    st, _ = shells()["sliding cap (pole, free edge)"]
    view = FourierShell(st, AngularBasis(3, 1))
    rng = np.random.default_rng(4)
    Q, k, A, E = 5, 9, 8, 7
    B, w = rng.standard_normal((Q, k, A)), rng.uniform(0.1, 1.0, Q)
    h = rng.standard_normal((k, k, Q, E))
    h = h + h.transpose(1, 0, 2, 3)
    He, rows = view._element_hessians(h, B, w)
    expected = np.einsum("qia,ijqe,qjb,q->abe", B, h, B, w)
    np.testing.assert_allclose(He, expected[rows], rtol=0, atol=RTOL * np.abs(expected).max())


#: The Bloch blocks fold the sum over the circle onto half a period: the same sums in another order.
BLOCK_RTOL = 1e-12


def direct_bloch_block(view: FourierShell, c: np.ndarray, j: int, parity: str, pressure: float) -> np.ndarray:
    """The Bloch block ``(j, parity)`` at the ``D_n`` state ``c`` (dense), every element's second variation
    summed over all ``M`` angles of the whole circle, reduced by the perturbation view's ``T``."""
    st = view.structure
    pview = FourierShell(st, view.basis.bloch(j, parity))
    M = view.basis.M
    theta, w = 2.0 * math.pi * np.arange(M) / M, np.full(M, 2.0 * math.pi / M)
    state_maps, pmaps = view.basis.ring_maps(theta), pview.basis.ring_maps(theta)
    H = np.zeros((pview.size, pview.size))
    terms = [(f, 1.0) for f in view._families] + [(f, pressure) for f in view._volume if pressure]
    for (name, nodes, _, kernel, params, offset), factor in terms:
        layout = view._layouts[name]
        Bs = FourierShell._local_map(layout, nodes.shape[1], state_maps)
        Bp = FourierShell._local_map(layout, nodes.shape[1], pmaps)
        dofs, pdofs = view.element_dofs(nodes), pview.element_dofs(nodes)
        y = np.einsum("qka,ea->keq", Bs, c[dofs])
        if offset is not None:
            y = y + offset[:, None, None]
        _, _, h = kernel(y, *[np.asarray(p, float)[:, None] * np.ones((1, M)) if np.ndim(p) else p for p in params])
        hB = np.einsum("kleq,qlb->keqb", h, Bp)
        np.add.at(H, (pdofs[:, :, None], pdofs[:, None, :]), factor * np.einsum("qka,keqb,q->eab", Bp, hB, w))
    Bs, Bp = (FourierShell._local_map(layouts.POLE, 2, m) for m in (state_maps, pmaps))
    for nodes, kernel, lbar, kbar, Akb in view._poles:
        nu, wm = view.nu, w / (2.0 * math.pi)
        v, g, h = kernel(np.einsum("qka,a->kq", Bs, c[view.element_dofs(nodes)[0]]), lbar)
        b = v - kbar
        G = np.einsum("qka,kq->qa", Bp, g)
        Hq = np.einsum("qka,klq,qlb->qab", Bp, h, Bp)
        mean, dmean = wm @ b, wm @ G
        d = pview.element_dofs(nodes)[0]
        H[np.ix_(d, d)] += Akb * (
            2.0 * (3.0 * nu - 1.0) * (np.outer(dmean, dmean) + mean * np.einsum("q,qab->ab", wm, Hq))
            + 4.0 * (1.0 - nu) * (np.einsum("q,qa,qb->ab", wm, G, G) + np.einsum("q,qab->ab", wm * b, Hq)))
    T = pview.reduction(True).T.toarray()
    return T.T @ H @ T


@pytest.mark.parametrize("n", [3, 4], ids=["D3", "D4"])
@pytest.mark.parametrize("name", list(shells()))
def test_bloch_blocks_are_the_direct_sums(name: str, n: int) -> None:
    """Every class of ``D_3`` (A1, A2, E1 both parities) and of ``D_4`` (B1, B2 too), at a random ``D_n`` state
    under pressure: the blocks as folded onto half a period equal the sums over the whole circle."""
    st, _ = shells()[name]
    pressure = 3e-4 if name.startswith("sphere") else 100.0  # the volume's terms of the size of the elastic ones
    view = FourierShell(st, AngularBasis(n, 2))
    c = state(view, 2e-3, 2)
    classes = [(j, parity) for j in range(n // 2 + 1) for parity in ("even", "odd")]
    for j, parity in classes:
        expected = direct_bloch_block(view, c, j, parity, pressure)
        got = view.bloch_block(c, j, parity, pressure).toarray()
        np.testing.assert_allclose(got, expected, rtol=0, atol=BLOCK_RTOL * np.abs(expected).max(),
                                   err_msg=f"class j = {j}, {parity}")
        if (j, parity) == (1, "odd"):  # the representation E1's two parities: the same spectrum
            even = np.linalg.eigvalsh(view.bloch_block(c, 1, "even", pressure).toarray())
            np.testing.assert_allclose(np.linalg.eigvalsh(got), even, rtol=0, atol=1e-10 * np.abs(even).max())


@pytest.mark.parametrize("mirror", [True, False])
def test_restriction_is_the_product_with_the_reduction(mirror: bool) -> None:
    """``FourierReduction.restriction`` (a gather plus the sums of the pole's tied pairs) equals ``T^T H T``
    by sparse products, with the tied pairs' factors -1 of the basis without symmetry; its matrices share
    one read-only pattern."""
    st = ShellStructure(spherical_cap(1.0, 0.8, 12), 1e6, 0.3, 0.02, boundary="sliding")
    basis = AngularBasis(3, 2) if mirror else AngularBasis(1, 2, mirror=False)
    view = FourierShell(st, basis)
    red = view.reduction()
    assert mirror or np.any(red.T.data < 0)
    restrict = red.restriction(view.pattern())
    rng = np.random.default_rng(4)
    first = None
    for _ in range(2):
        H = view.hessian(view.reference_state() + 1e-3 * rng.standard_normal(view.size))
        reference = (red.T.T @ H @ red.T).toarray()
        got = restrict(H.data)
        np.testing.assert_allclose(got.toarray(), reference, rtol=0, atol=RTOL * np.abs(reference).max())
        assert not got.indices.flags.writeable
        assert first is None or got.indices is first.indices
        first = got
