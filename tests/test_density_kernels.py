"""The generated value/gradient/Hessian kernels of the 2-D densities at general states.

:mod:`contin_models.shell._density_generated` (generator :mod:`contin_models.shell.density_codegen`).
What is checked, against references that the generator does not produce:

* at random states with every local variable nonzero (those of an axisymmetric configuration of
  three rings, each moved), each kernel's value is the density evaluated directly in numpy,
  its gradient and Hessian are the exact forward-mode derivatives of :class:`harmonic.Jet` on the
  same density (to roundoff), the gradient agrees with central differences of the density and the
  Hessian with central differences of the kernel's own gradient; the Hessian is symmetric;
* at axisymmetric states the Hessians equal the harmonic blocks' generated kernels
  (:mod:`contin_models.shell._harmonic_generated`, every entry, zeros included), and the pole jets too.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from contin_models.shell import _density_generated as G
from contin_models.shell import _harmonic_generated as HG
from contin_models.shell import density as D
from contin_models.shell import harmonic as H

M = 6  # stations per check


def _vectors(y: Any) -> list[tuple]:
    return [tuple(y[i:i + 3]) for i in range(0, len(y), 3)]


def _rings(rng: np.random.Generator, m: int) -> dict[str, np.ndarray]:
    """Three neighbouring rings of an axisymmetric state at ``m`` angles: positions ``P0, P1, P2 = (r, 0, z)`` and
    their theta-derivatives ``Q = P' = (0, r, 0)`` and ``S = P'' = (-r, 0, 0)`` in the local frame, each
    ``(3, m)`` (radii 0.4 .. 0.9, chords about 0.1)."""
    r = np.sort(rng.uniform(0.4, 0.9, (3, m)), axis=0)
    z = np.cumsum(rng.uniform(-0.1, -0.05, (3, m)), axis=0)
    zero = np.zeros(m)
    out = {}
    for i in range(3):
        out[f"P{i}"] = np.array([r[i], zero, z[i]])
        out[f"Q{i}"] = np.array([zero, r[i], zero])
        out[f"S{i}"] = np.array([-r[i], zero, zero])
    return out


def _local(name: str, x: dict[str, np.ndarray]) -> np.ndarray:
    """A kernel's local variables ``(k, m)`` at the axisymmetric state ``x`` (the densities' argument order)."""
    P0, P1, P2, Q0, Q1, Q2, S0, S1 = (x[k] for k in ("P0", "P1", "P2", "Q0", "Q1", "Q2", "S0", "S1"))
    if name.startswith("stretch"):
        parts = [P1 - P0, (Q0 + Q1) / 2]
    elif name.startswith("bend"):
        parts = [P1 - P0, P2 - P1, Q2 - Q0, Q1, S1]
    elif name.startswith("free_edge"):
        parts = [P1 - P0, Q1 - Q0, Q0, S0]
    elif name == "volume":
        parts = [P0, P1, Q0, Q1]
    elif name == "skirt":
        parts = [P0, Q0]
    else:  # a pole on the axis at P1's height, its neighbour ring P0 at theta and (in theta's frame) at theta + pi
        zero = np.zeros_like(P0[0])
        parts = [P0, Q0, np.array([zero, zero, P1[2]]), np.array([-P0[0], -P0[1], P0[2]]),
                 np.array([-Q0[0], -Q0[1], Q0[2]])]
    return np.concatenate(parts)


LBAR, RBAR, K11BAR, K22BAR, KB, KS, NU = 0.11, 0.65, 1.1, 1.2, 2.0, 3.0, 0.3
E12BAR, K12BAR = 0.04, -0.7  # a reference's shear and twist (the general kernels)
#: kernel -> (the density as a function of the local variables, the kernel's parameters)
DENSITIES: dict[str, tuple[Callable[[Any], Any], tuple]] = {
    "stretch": (lambda y: H.stretch_density(*_vectors(y), LBAR, RBAR, KS, NU), (LBAR, RBAR, KS, NU)),
    "bend_cur": (lambda y: H.bend_density(*_vectors(y), LBAR, RBAR, K11BAR, K22BAR, KB, NU),
                 (LBAR, RBAR, K11BAR, K22BAR, KB, NU)),
    "bend_ref": (lambda y: H.bend_density(*_vectors(y), LBAR, RBAR, K11BAR, K22BAR, KB, NU, LBAR),
                 (LBAR, RBAR, K11BAR, K22BAR, KB, NU)),
    "free_edge": (lambda y: H.free_edge_density(*_vectors(y), 0.7, 1.3, NU), (0.7, 1.3, NU)),
    "volume": (lambda y: H.volume_density(*_vectors(y)), ()),
    "skirt": (lambda y: H.skirt_density(*_vectors(y), -0.4), (-0.4,)),
    **{f"pole_{side}_{length}": ((lambda y, north=side == "north", L=None if length == "cur" else LBAR:
                                  H.pole_curvature(*_vectors(y), north, L)), (LBAR,))
       for side in ("north", "south") for length in ("cur", "ref")},
    "stretch_general": (lambda y: D.general_stretch_density(*_vectors(y), LBAR, RBAR, E12BAR, KS, NU),
                        (LBAR, RBAR, E12BAR, KS, NU)),
    "bend_cur_general": (lambda y: D.general_bend_density(*_vectors(y), LBAR, RBAR, K11BAR, K22BAR, K12BAR, KB, NU),
                         (LBAR, RBAR, K11BAR, K22BAR, K12BAR, KB, NU)),
    "bend_ref_general": (lambda y: D.general_bend_density(*_vectors(y), LBAR, RBAR, K11BAR, K22BAR, K12BAR, KB, NU,
                                                          LBAR), (LBAR, RBAR, K11BAR, K22BAR, K12BAR, KB, NU)),
    "free_edge_general": (lambda y: D.general_free_edge_density(*_vectors(y), 0.7, 1.3, K12BAR, NU),
                          (0.7, 1.3, K12BAR, NU)),
}


def _general(name: str, seed: int = 0) -> np.ndarray:
    """Local variables of a general state: an axisymmetric one with every variable moved by up to 0.05."""
    rng = np.random.default_rng(seed)
    y = _local(name, _rings(rng, M))
    return y + rng.uniform(-0.05, 0.05, y.shape)


def test_every_kernel_is_checked() -> None:
    assert set(G.KERNELS) == {f"{name}_jet" for name in DENSITIES}


@pytest.mark.parametrize("name", list(DENSITIES))
def test_kernel_is_the_density_and_its_exact_derivatives(name: str) -> None:
    """Value against the density in numpy, gradient and Hessian against forward-mode differentiation."""
    density, params = DENSITIES[name]
    y = _general(name)
    assert np.all(y != 0)
    v, g, h = getattr(G, f"{name}_jet")(y, *params)
    k = y.shape[0]
    assert v.shape == (M,) and g.shape == (k, M) and h.shape == (k, k, M)
    direct = density(y)
    np.testing.assert_allclose(v, direct, rtol=1e-13, atol=0)
    jet = density(H.Jet.variables(list(y)))
    np.testing.assert_allclose(jet.v, direct, rtol=1e-14, atol=0)  # the jet evaluates the same density
    for ours, exact in ((g, jet.g), (h, jet.h)):
        scale = np.max(np.abs(exact), axis=tuple(range(exact.ndim - 1)))  # per station
        assert np.max(np.abs(ours - exact) / scale) < 1e-12
    assert np.array_equal(h, h.transpose(1, 0, 2))


@pytest.mark.parametrize("name", list(DENSITIES))
def test_kernel_against_differences(name: str) -> None:
    """Gradient against central differences of the density, Hessian against those of the kernel's gradient
    (Richardson-extrapolated, along a random direction)."""
    density, params = DENSITIES[name]
    kernel = getattr(G, f"{name}_jet")
    y = _general(name, seed=1)
    d = np.random.default_rng(2).standard_normal(y.shape)
    _, g, h = kernel(y, *params)

    def central(f: Callable[[np.ndarray], np.ndarray], e: float) -> np.ndarray:
        return (f(y + e * d) - f(y - e * d)) / (2 * e)

    for f, exact in ((density, np.einsum("km,km->m", g, d)),
                     (lambda x: kernel(x, *params)[1], np.einsum("klm,lm->km", h, d))):
        e = 1e-4  # the chords are about 0.1
        fd = (4 * central(f, e / 2) - central(f, e)) / 3
        assert np.max(np.abs(fd - exact)) < 1e-7 * np.max(np.abs(exact))


@pytest.mark.parametrize("variant", ["bend_cur", "bend_ref"])
def test_axisymmetric_bending_and_stretching_hessians_are_the_harmonic_kernels(variant: str) -> None:
    rings = _rings(np.random.default_rng(5), M)
    lbar, rbar, k11bar, k22bar, kb = (np.random.default_rng(6).uniform(0.5, 1.5, (5, M)))
    y = _local(variant, rings)
    _, _, h = getattr(G, f"{variant}_jet")(y, lbar, rbar, k11bar, k22bar, kb, NU)
    ref = getattr(HG, f"{variant}_hessian")(*y[[0, 2, 3, 5, 7, 10]], lbar, rbar, k11bar, k22bar, kb, NU)
    assert np.max(np.abs(h - ref)) < 1e-13 * np.max(np.abs(ref))
    y = _local("stretch", rings)
    _, _, h = G.stretch_jet(y, lbar, rbar, KS, NU)
    ref = HG.stretch_hessian(*y[[0, 2, 4]], lbar, rbar, KS, NU)
    assert np.max(np.abs(h - ref)) < 1e-13 * np.max(np.abs(ref))


def test_axisymmetric_free_edge_and_pole_are_the_harmonic_kernels() -> None:
    rings = _rings(np.random.default_rng(7), M)
    y = _local("free_edge", rings)
    _, _, h = G.free_edge_jet(y, 0.7, 1.3, NU)
    for i in range(M):  # the harmonic kernel is per element (numbers)
        ref = HG.free_edge_hessian(*y[list(H.FREE_EDGE_FREE), i], 0.7, 1.3, NU)
        assert np.max(np.abs(h[:, :, i] - ref)) < 1e-13 * np.max(np.abs(ref))
    for side in ("north", "south"):
        for length in ("cur", "ref"):
            name = f"pole_{side}_{length}"
            y = _local(name, rings)
            v, g, h = getattr(G, f"{name}_jet")(y, LBAR)
            for i in range(M):
                rv, rg, rh = getattr(HG, f"{name}_jet")(*y[list(H.POLE_FREE), i], LBAR)
                assert abs(v[i] - rv) <= 1e-13 * abs(rv)
                assert np.max(np.abs(g[:, i] - rg)) < 1e-13 * np.max(np.abs(rg))
                assert np.max(np.abs(h[:, :, i] - rh)) < 1e-13 * np.max(np.abs(rh))


@pytest.mark.slow
def test_generated_module_is_up_to_date() -> None:
    """Regenerating ``_density_generated.py`` (about half a minute of sympy) reproduces the committed file."""
    pytest.importorskip("sympy")
    from pathlib import Path

    from contin.modelkit.codegen import check_generated
    from contin_models.shell import density_codegen

    path = Path(__file__).resolve().parents[1] / "models" / "shell" / "_density_generated.py"
    check_generated(density_codegen.generate_source, path, "python -m contin_models.shell.density_codegen")
