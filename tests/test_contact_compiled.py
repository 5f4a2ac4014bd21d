"""The contact barrier's C code against the same steps in numpy, and that a state's work runs in C.

Two extensions serve :class:`contin_models.contact.ContactBarrier` where the install built them: the
point kernels generated from the committed numpy module (``contin_models.contact._ckernels``) and the
hand-written support integration, chain rule and step filter (``contin_models.contact._cbarrier``).
Without them the barrier runs numpy; the numbers must not depend on which ran (to rounding: the C
code takes the numpy code's steps in the same order, and stops the Newton iteration of each root of
the support on its own where numpy stops them together).
"""

from __future__ import annotations

import math
import os
import sys

import numpy as np
import pytest

from contin_models.contact import ContactBarrier, Plate, Sphere, default_barrier
from contin_models.contact import _generated, barrier
from contin_models.contact.barrier import length_weights

#: Whether the barrier runs its C code (False as well in a tree from before it had any).
RUNS_C = getattr(barrier, "barrier_extension", lambda: None)() is not None and getattr(barrier, "COMPILED", False)
needs_compiled = pytest.mark.skipif(not RUNS_C, reason="the contact barrier's C extensions are not built")

RHO = 0.5


def cap(N: int, phi_hat: float = 0.8) -> np.ndarray:
    """The undeformed unit cap's interleaved state, the pole last."""
    theta = np.linspace(phi_hat, math.pi / 2, N)
    x = np.empty(2 * N)
    x[0::2], x[1::2] = np.cos(theta), np.sin(theta)
    x[-2] = 0.0
    return x


def dimpled(N: int, depth: float, seed: int) -> np.ndarray:
    """A cap pushed flat near the pole (a ring of contact under a plate or a large sphere) and jiggled."""
    x = cap(N)
    r, z = x[0::2], x[1::2]
    z[:] = np.minimum(z, 1.0 - depth)
    z += 2e-5 * np.random.default_rng(seed).standard_normal(N)
    return x


def indenter(shape: str):
    return Sphere(RHO) if shape == "sphere" else Plate()


def position(shape: str, x: np.ndarray, gap: float) -> float:
    """The indenter ``gap`` above the highest point of the meridian near the axis."""
    top = float(np.max(x[1::2]))
    return top + gap + (RHO if shape == "sphere" else 0.0)


@pytest.fixture
def numpy_barrier(monkeypatch):
    """Makes a barrier that runs numpy alone, and runs a call with it (the extensions switched off)."""

    def run(make, call):
        with monkeypatch.context() as m:
            m.setattr(barrier, "_EXTENSION", [None])
            m.setattr(barrier, "kernels", _generated)
            return call(make())

    return run


def states():
    """(shape, x, c): light and deep contact at the pole, a ring of contact on a dimple, coarse and fine meshes."""
    K, dhat = default_barrier(1e6, 1.0)
    out = []
    for shape in ("sphere", "plate"):
        for N, frac in ((41, 0.9), (200, 0.3), (200, 0.02)):
            x = cap(N)
            out.append((shape, x, position(shape, x, frac * dhat)))
        for seed in (1, 2):
            x = dimpled(200, 0.01, seed)
            out.append((shape, x, position(shape, x, 0.2 * dhat)))
    return out


CASES = states()
IDS = [f"{shape}-N{x.size // 2}-{k}" for k, (shape, x, _) in enumerate(CASES)]


def make_barrier(shape: str, x: np.ndarray) -> ContactBarrier:
    K, dhat = default_barrier(1e6, 1.0)
    return ContactBarrier(indenter(shape), K, dhat, cell_weights=length_weights(cap(x.size // 2)))


# ---- the generated C kernels ------------------------------------------------------------------------
def test_c_kernels_are_generated_from_the_committed_numpy_kernels():
    pytest.importorskip("sympy")  # the generator's module imports it
    from contin_models.contact.codegen import C_OUTPUT, generate_c_source

    assert C_OUTPUT.read_text(encoding="utf-8") == generate_c_source(), (
        "models/contact/_ckernels.c is out of date: run `python -m contin_models.contact.codegen`")


@needs_compiled
@pytest.mark.parametrize("name", ["sphere_distance", "sphere_energy", "sphere_gradient", "sphere_hessian",
                                  "sphere_derivatives", "plate_distance", "plate_energy", "plate_gradient",
                                  "plate_hessian", "plate_derivatives"])
def test_compiled_point_kernels_give_the_numpy_numbers(name):
    K, dhat = default_barrier(1e6, 1.0)
    rng = np.random.default_rng(7)
    d = dhat * rng.uniform(0.01, 0.99, 60)  # inside the barrier's range, where the kernels are valid
    angle = rng.uniform(0.0, 1.4, 60)
    c = 1.2
    if name.startswith("sphere"):
        r, z, params = (RHO + d) * np.sin(angle), c - (RHO + d) * np.cos(angle), (RHO,)
    else:
        r, z, params = np.cos(angle), c - d, ()
    compiled = getattr(barrier.kernels, name)(r, z, c, *params, K, dhat)
    expected = getattr(_generated, name)(r, z, c, *params, K, dhat)
    for got, want in zip(compiled if isinstance(compiled, tuple) else (compiled,),
                         expected if isinstance(expected, tuple) else (expected,)):
        assert got.shape == want.shape
        # numpy's and the C library's log may differ in the last bit
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-14 * float(np.max(np.abs(want))))


# ---- the hand-written C: support, chain rule, step filter --------------------------------------------
@needs_compiled
@pytest.mark.parametrize("shape,x,c", CASES, ids=IDS)
def test_support_points_agree_with_numpy(shape, x, c, numpy_barrier):
    got = make_barrier(shape, x).integration_points(x, c)
    want = numpy_barrier(lambda: make_barrier(shape, x), lambda b: b.integration_points(x, c))
    assert got.weight.size > 0
    np.testing.assert_array_equal(got.cell, want.cell)
    # all of order one; a root that ends a piece where the meridian crosses dhat at a shallow angle is
    # fixed to ~1e-13 only (it moves the energy by the fourth power of that)
    for field in ("weight", "cr", "cz", "r", "z"):
        np.testing.assert_allclose(getattr(got, field), getattr(want, field), rtol=0, atol=1e-12, err_msg=field)


@needs_compiled
@pytest.mark.parametrize("shape,x,c", CASES, ids=IDS)
def test_barrier_state_agrees_with_numpy(shape, x, c, numpy_barrier):
    got = make_barrier(shape, x).evaluate(x, c)
    want = numpy_barrier(lambda: make_barrier(shape, x), lambda b: b.evaluate(x, c))
    np.testing.assert_array_equal(got.active, want.active)
    np.testing.assert_array_equal(got.stencils, want.stencils)
    np.testing.assert_allclose(got.gaps, want.gaps, rtol=0, atol=1e-15)  # lengths on a unit cap
    np.testing.assert_allclose(got.distances, want.distances, rtol=0, atol=1e-15)
    assert got.energy == pytest.approx(want.energy, rel=1e-12)
    assert got.force == pytest.approx(want.force, rel=1e-12)
    assert got.hess_cc == pytest.approx(want.hess_cc, rel=1e-12)
    for field in ("gradient", "node_energy", "node_force", "hess_blocks", "hess_xc"):
        a, b = getattr(got, field), getattr(want, field)
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * float(np.max(np.abs(b))), err_msg=field)
    # the blocks stay exactly symmetric (the engine's symmetric solvers see any difference)
    np.testing.assert_array_equal(got.hess_blocks, got.hess_blocks.transpose(0, 2, 1))


@needs_compiled
@pytest.mark.parametrize("shape,x,c", CASES, ids=IDS)
def test_step_filter_agrees_with_numpy(shape, x, c, numpy_barrier):
    rng = np.random.default_rng(x.size)
    K, dhat = default_barrier(1e6, 1.0)
    b = make_barrier(shape, x)
    fractions = []
    for size in (1e-6, 1e-4, 1e-3, 1e-2):
        dx = size * rng.standard_normal(x.size)
        dx[-2] = 0.0
        for dc in (0.0, -0.5 * size, -2.0 * dhat):
            got = b.max_safe_fraction(x, c, dx, dc)
            want = numpy_barrier(lambda: make_barrier(shape, x), lambda nb: nb.max_safe_fraction(x, c, dx, dc))
            assert got == pytest.approx(want, rel=1e-13), (size, dc)
            fractions.append(got)
    assert min(fractions) < 1.0 and max(fractions) == 1.0  # steps that reach the indenter and steps that do not


@needs_compiled
@pytest.mark.parametrize("shape", ["sphere", "plate"])
def test_a_node_inside_the_indenter_gives_numpys_error(shape, numpy_barrier):
    x = cap(41)
    c = position(shape, x, -1e-4)  # the pole 1e-4 inside
    messages = []
    compiled = (lambda call: call(make_barrier(shape, x)))
    numpy_only = (lambda call: numpy_barrier(lambda: make_barrier(shape, x), call))
    for run in (compiled, numpy_only):
        for call in (lambda b: b.evaluate(x, c), lambda b: b.max_safe_fraction(x, c, np.zeros_like(x), 0.0)):
            with pytest.raises(ValueError, match="is not outside the") as info:
                run(call)
            messages.append(str(info.value))
    assert messages[0] == messages[2] and messages[1] == messages[3]


def test_the_ci_build_has_the_contact_extensions():
    if os.environ.get("CI") != "true":
        pytest.skip("only CI, whose machine has a C compiler, must have built the extensions")
    assert barrier.COMPILED, "the package install did not build contin_models.contact._ckernels"
    assert barrier.barrier_extension() is not None, "the package install did not build contin_models.contact._cbarrier"


# ---- a state's work runs in C -------------------------------------------------------------------------
def test_a_contact_state_costs_few_python_calls():
    """The barrier at a new state (its support integration) and the step filter make a few dozen Python
    calls, not the hundreds of a support found by numpy loops over the cells' polynomials (the sphere
    indentation spent half its time there)."""
    if hasattr(barrier, "barrier_extension") and not RUNS_C:
        pytest.skip("the contact barrier's C extensions are not built")
    K, dhat = default_barrier(1e6, 1.0)
    x = cap(200)
    counts = {}
    for shape in ("sphere", "plate"):
        b = ContactBarrier(indenter(shape), K, dhat, cell_weights=length_weights(x))
        c = position(shape, x, 0.3 * dhat)
        b.evaluate(x, c)  # imports and caches of the first call
        calls = [0]

        def count(frame, event, arg):
            if event == "call":
                calls[0] += 1

        moved = x + 1e-9  # a new state: nothing cached
        sys.setprofile(count)
        try:
            state = b.evaluate(moved, c)
            after_evaluate = calls[0]
            b.max_safe_fraction(moved, c, np.full(x.size, 1e-5), 0.0)
        finally:
            sys.setprofile(None)
        assert state.n_active >= 5
        counts[shape] = (after_evaluate, calls[0] - after_evaluate)
    for shape, (evaluate, step_filter) in counts.items():
        assert evaluate <= 60 and step_filter <= 20, counts
