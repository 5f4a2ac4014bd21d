"""The shell's kernels in C (contin_models.shell._ckernels, _harmonic_ckernels, _density_ckernels) against the same
kernels in numpy.

The C source is generated from the committed numpy module (contin.modelkit.codegen.c_extension_text); the
extension is built by the package install where a C compiler is found, and the shell falls back on
numpy elsewhere.  The numbers must not depend on which ran.
"""

from __future__ import annotations

import os
import subprocess
import sys
import types

import numpy as np
import pytest

from contin.modelkit.codegen import c_extension_text
from contin.numerics.compiled import prefer_compiled
from contin_models.shell import _density_generated, _generated, _harmonic_generated, density_kernels, harmonic
from contin_models.shell.energy import COMPILED, compiled_rows, kernels

ROWS = compiled_rows(_generated.NDOF)
needs_compiled = pytest.mark.skipif(not COMPILED, reason="the C extension contin_models.shell._ckernels is not built")


def _inputs(name: str, m: int, rng: np.random.Generator) -> list:
    """Plausible element inputs: positive lengths and radii, parameters of either sign."""
    n_in = getattr(_generated, name).__code__.co_argcount - 1  # all but out
    args = [rng.uniform(0.2, 1.5, m) for _ in range(n_in)]
    args[-1] = 0.3  # nu, a number as the shell passes it
    return args


def test_c_source_is_generated_from_the_committed_numpy_kernels():
    from contin_models.shell.codegen import C_OUTPUT, generate_c_source

    assert C_OUTPUT.read_text(encoding="utf-8") == generate_c_source(), (
        "models/shell/_ckernels.c is out of date: run `python -m contin_models.shell.codegen`")


def test_harmonic_c_source_is_generated_from_the_committed_numpy_kernels():
    from contin_models.shell.harmonic_codegen import C_OUTPUT, generate_c_source

    assert C_OUTPUT.read_text(encoding="utf-8") == generate_c_source(), (
        "models/shell/_harmonic_ckernels.c is out of date: run `python -m contin_models.shell.harmonic_codegen`")


def test_density_c_source_is_generated_from_the_committed_numpy_kernels():
    from contin_models.shell.density_codegen import C_OUTPUT, generate_c_source

    assert C_OUTPUT.read_text(encoding="utf-8") == generate_c_source(), (
        "models/shell/_density_ckernels.c is out of date: run `python -m contin_models.shell.density_codegen`")


def test_the_ci_build_has_the_compiled_kernels():
    if os.environ.get("CI") != "true":
        pytest.skip("only CI, whose machine has a C compiler, must have built the extensions")
    assert COMPILED, "the package install did not build contin_models.shell._ckernels"
    assert harmonic.COMPILED, "the package install did not build contin_models.shell._harmonic_ckernels"
    assert density_kernels.COMPILED, "the package install did not build contin_models.shell._density_ckernels"
    from contin.numerics import linalg

    assert linalg.banded_extension() is not None, "the package install did not build contin.numerics._banded"


HARMONIC_PER_ELEMENT = ("bend_cur_hessian", "bend_ref_hessian", "stretch_hessian")
HARMONIC_POLE = ("pole_north_cur_jet", "pole_north_ref_jet", "pole_south_cur_jet", "pole_south_ref_jet",
                 "free_edge_hessian")


@pytest.mark.skipif(not harmonic.COMPILED, reason="the C extension contin_models.shell._harmonic_ckernels is not built")
@pytest.mark.parametrize("name", HARMONIC_PER_ELEMENT + HARMONIC_POLE)
def test_compiled_harmonic_kernel_gives_the_numpy_numbers(name):
    rng = np.random.default_rng(7)
    numpy_kernel = getattr(_harmonic_generated, name)
    n_in = numpy_kernel.__code__.co_argcount
    if name in HARMONIC_PER_ELEMENT:
        args = [rng.uniform(0.3, 1.5, 31) for _ in range(n_in)]
    else:  # one pole: numbers in, numbers and small arrays out
        args = [float(v) for v in rng.uniform(0.3, 1.5, n_in)]
    expected, got = numpy_kernel(*args), getattr(harmonic._hgen, name)(*args)
    expected = expected if isinstance(expected, tuple) else (expected,)
    got = got if isinstance(got, tuple) else (got,)
    assert len(got) == len(expected)
    for e, g in zip(expected, got):
        assert np.shape(g) == np.shape(e) and isinstance(g, np.ndarray) == isinstance(e, np.ndarray)
        # libm's pow and numpy's differ in the last bit for the odd powers (x**3, x**5) these kernels
        # take; the rest is the same operations in the same order
        np.testing.assert_allclose(g, e, rtol=1e-11, atol=1e-12 * max(np.abs(e).max(), 1.0))


needs_density_compiled = pytest.mark.skipif(not density_kernels.COMPILED,
                                            reason="the C extension contin_models.shell._density_ckernels is not built")


def _density_inputs(name: str, stations: tuple[int, ...], rng: np.random.Generator) -> tuple[np.ndarray, list]:
    """A general state's local variables ``(k, *stations)`` (every entry nonzero, of either sign, no symmetry)
    and the kernel's parameters as arrays of the station shape, nu a number as the shell passes it."""
    kernel = getattr(_density_generated, name)
    k = {"stretch": 6, "skirt": 6, "free_edge": 12, "volume": 12}.get(name.removesuffix("_jet").removesuffix("_general"),
                                                                      15)
    y = rng.uniform(0.1, 1.0, (k, *stations)) * rng.choice([-1.0, 1.0], (k, *stations))
    names = kernel.__code__.co_varnames[1:kernel.__code__.co_argcount]
    params = [0.3 if p == "nu" else rng.uniform(0.3, 1.5, stations) for p in names]
    return y, params


def _assert_density_outputs_equal(got: tuple, expected: tuple, rtol: float) -> None:
    """Same shapes and types, and each output within ``rtol`` of its largest entry."""
    assert len(got) == len(expected) == 3
    for g, e in zip(got, expected):
        assert np.shape(g) == np.shape(e) and isinstance(g, np.ndarray) == isinstance(e, np.ndarray)
        np.testing.assert_allclose(g, e, rtol=rtol, atol=rtol * np.abs(e).max())


@needs_density_compiled
@pytest.mark.parametrize("name", _density_generated.KERNELS)
def test_compiled_density_kernel_gives_the_numpy_numbers(name):
    rng = np.random.default_rng(8)
    for stations in [(27, 10), (31,)]:  # (elements, angles) as the 3-D view passes them, and a flat list
        y, params = _density_inputs(name, stations, rng)
        expected, got = getattr(_density_generated, name)(y, *params), getattr(density_kernels.kernels, name)(y, *params)
        # the same operations in the same order, but for numpy's own power (x**3, x**5) against libm's
        _assert_density_outputs_equal(got, expected, 1e-14)


def _compiled_only_density_kernels() -> types.ModuleType:
    """The density kernels of the C extension, with numpy kernels that fail: what the C does not take fails."""
    def refused(*inputs):
        raise AssertionError("the compiled kernel refused these inputs")

    numpy_kernels = types.ModuleType("refusing")
    for name in _density_generated.KERNELS:
        setattr(numpy_kernels, name, refused)
    namespace, compiled = prefer_compiled(numpy_kernels, "contin_models.shell._density_ckernels")
    assert compiled
    return namespace


@needs_density_compiled
def test_compiled_density_kernel_takes_strided_states_broadcast_parameters_and_one_station():
    name = "bend_cur_jet"
    rng = np.random.default_rng(9)
    y, params = _density_inputs(name, (12, 8), rng)
    numpy_kernel, kernel = getattr(_density_generated, name), getattr(_compiled_only_density_kernels(), name)
    expected = numpy_kernel(y, *params)
    strided = np.ascontiguousarray(np.moveaxis(y, 2, 1)).swapaxes(1, 2)  # the same values, not C-contiguous
    assert not strided.flags.c_contiguous
    per_element = [p[:, :1] if np.ndim(p) else p for p in params]  # (E, 1): the same at every angle...
    same = [np.broadcast_to(p, (12, 8)) if np.ndim(p) else p for p in per_element]  # ...as at (E, Q)
    _assert_density_outputs_equal(kernel(strided, *per_element), numpy_kernel(y, *same), 1e-14)
    _assert_density_outputs_equal(kernel(y, *params), expected, 1e-14)
    station = [y[:, 3, 4], *[p[3, 4] if np.ndim(p) else p for p in params]]  # numbers in: a number out
    one = kernel(*station)
    assert np.isscalar(one[0]) and one[1].shape == (15,) and one[2].shape == (15, 15)
    _assert_density_outputs_equal(one, numpy_kernel(*station), 1e-14)
    _assert_density_outputs_equal(one, tuple(o[..., 3, 4][()] for o in expected), 1e-14)


@needs_density_compiled
def test_density_inputs_the_extension_does_not_take_fall_back_on_numpy():
    name = "stretch_jet"
    rng = np.random.default_rng(10)
    y, params = _density_inputs(name, (7,), rng)
    numpy_kernel, kernel = getattr(_density_generated, name), getattr(density_kernels.kernels, name)
    single = y.astype(np.float32)  # not float64: computed by numpy, in numpy's precision
    for g, e in zip(kernel(single, *params), numpy_kernel(single, *params)):
        np.testing.assert_array_equal(g, e)
    with pytest.raises(ValueError):  # too few variables: numpy's own error
        kernel(y[:5], *params)


def test_translation_of_kernels_that_unpack_stacked_variables():
    source = ("def k(y, c):\n"
              "    y0, y1 = y\n"
              "    _shape = numpy.shape(y0)\n"
              "    _g = numpy.zeros((2,) + _shape)\n"
              "    _v = y1*c\n"
              "    _g[1] = y0\n"
              "    return _v, _g\n")
    text = c_extension_text(source, {}, "_k", "test", returning=["k"])
    assert "Input in[3];" in text  # y0, y1 and c: one input each
    assert "const double y1 = in[1].data[_i * in[1].stride];" in text
    assert "const double c = in[2].data[_i * in[2].stride];" in text
    assert "out_g[1 * _m + _i] = y0;" in text and "out_v[_i] = _v;" in text
    assert "\"{'k': (True, [(), (2,)])}\"" in text and "\"{'k': 2}\"" in text


@needs_compiled
@pytest.mark.parametrize("name", sorted(ROWS))
def test_compiled_kernel_gives_the_numpy_numbers(name):
    rng = np.random.default_rng(3)
    args = _inputs(name, 57, rng)
    expected = getattr(_generated, name)(*args)
    got = getattr(kernels, name)(*args)
    assert got.shape == expected.shape == (ROWS[name], 57)
    # the same operations in the same order: equal up to the last bit on this machine, and within
    # rounding anywhere (a compiler may contract a multiply-add)
    np.testing.assert_allclose(got, expected, rtol=1e-13, atol=1e-13 * np.abs(expected).max())


@needs_compiled
def test_compiled_kernel_takes_strided_inputs_numbers_and_a_given_out():
    name = "bend_cur_fast_gradient_hessian"
    rng = np.random.default_rng(4)
    dense = _inputs(name, 40, rng)
    strided = [np.repeat(a, 2)[::2] if isinstance(a, np.ndarray) else a for a in dense]  # stride 2
    assert not strided[0].flags.c_contiguous
    strided[6] = float(dense[6][0])  # a parameter passed as a number...
    dense[6] = np.full(40, dense[6][0])  # ...is the same as that value for every element
    out = np.full((ROWS[name], 40), np.nan)
    assert getattr(kernels, name)(*strided, out=out) is out
    np.testing.assert_allclose(out, getattr(_generated, name)(*dense), rtol=1e-13, atol=1e-300)


@needs_compiled
def test_inputs_the_extension_does_not_take_fall_back_on_numpy():
    from contin_models.shell import _ckernels

    name = "stretch_fast_gradient"
    rng = np.random.default_rng(5)
    args = _inputs(name, 12, rng)
    with pytest.raises(TypeError, match="not float64"):
        _ckernels.stretch_fast_gradient(*[a.astype(np.float32) if isinstance(a, np.ndarray) else a for a in args],
                                        np.empty((ROWS[name], 12)))
    with pytest.raises(TypeError, match="elements"):
        _ckernels.stretch_fast_gradient(args[0][:5], *args[1:], np.empty((ROWS[name], 12)))
    # the public kernels answer with numpy: integer arrays, a transposed 2-D block
    integers = [np.arange(1, 13) + k if isinstance(a, np.ndarray) else a for k, a in enumerate(args)]
    np.testing.assert_array_equal(getattr(kernels, name)(*integers), getattr(_generated, name)(*integers))
    block = [np.tile(a, (3, 1)).T if isinstance(a, np.ndarray) else a for a in args]  # (12, 3), F-ordered
    np.testing.assert_allclose(getattr(kernels, name)(*block), getattr(_generated, name)(*block), rtol=1e-13)


@needs_compiled
def test_non_finite_inputs_give_non_finite_outputs_as_in_numpy():
    name = "stretch_fast_hessian"
    args = _inputs(name, 6, np.random.default_rng(6))
    args[0][2] = np.nan
    args[1][4] = np.inf
    with np.errstate(all="ignore"):
        expected = getattr(_generated, name)(*args)
    got = getattr(kernels, name)(*args)
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(expected))
    assert not np.isfinite(got[:, 2]).any()


def test_numpy_kernels_when_compiled_kernels_are_switched_off():
    code = ("from contin_models.shell.energy import COMPILED, kernels\n"
            "from contin_models.shell import _generated\n"
            "assert not COMPILED\n"
            "assert kernels.stretch_fast_gradient is _generated.stretch_fast_gradient\n"
            "print('numpy')")
    env = dict(os.environ, CONTIN_COMPILED="0")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "numpy"


def test_translation_refuses_what_it_cannot_translate():
    source = ("def k_fast_gradient(a, b, out=None):\n"
              "    for i in range(3):\n"
              "        out[i] = a\n"
              "    return out\n")
    with pytest.raises(ValueError, match="k_fast_gradient: no C translation for statement"):
        c_extension_text(source, {"k_fast_gradient": 3}, "_k", "test")
    source = "def k_fast_gradient(a, b, out=None):\n    out[0] = numpy.arctan2(a, b)\n    return out\n"
    with pytest.raises(ValueError, match="no C translation for 'numpy.arctan2"):
        c_extension_text(source, {"k_fast_gradient": 1}, "_k", "test")
    with pytest.raises(ValueError, match="no kernel named missing"):
        c_extension_text(source, {"missing": 1}, "_k", "test")


def test_translation_of_kernels_that_return_their_outputs():
    source = ("def k(y0, c):\n"
              "    _m = numpy.shape(y0)[0]\n"
              "    _h = numpy.zeros((2, 2, _m))\n"
              "    _v = y0*c\n"
              "    _h[0, 1] = numpy.sign(y0)\n"
              "    _h[1, 0] = _h[0, 1]\n"
              "    return _v, _h\n")
    text = c_extension_text(source, {}, "_k", "test", returning=["k"])
    assert "out_h[1 * _m + _i] = sign_of(y0);" in text and "out_h[2 * _m + _i] = out_h[1 * _m + _i];" in text
    assert "out_v[_i] = _v;" in text
    assert "\"{'k': (True, [(), (2, 2)])}\"" in text
    with pytest.raises(ValueError, match="outside the shape"):
        c_extension_text(source.replace("_h[1, 0] = _h[0, 1]", "_h[2, 0] = _h[0, 1]"), {}, "_k", "t", returning=["k"])


def test_translation_of_powers_and_constants():
    source = ("def k_fast_gradient(a, b, out=None):\n"
              "    t = (1/2)*a**2 + b**(-1) + numpy.sqrt(a)**3 - numpy.pi*abs(b)\n"
              "    out[0] = t\n"
              "    out[1] = -1/4*t**0.5\n"
              "    return out\n")
    text = c_extension_text(source, {"k_fast_gradient": 2}, "_k", "test")
    assert ("double t = (((((1.0 / 2.0) * (a * a)) + (1.0 / b)) + pow(sqrt(a), 3.0)) - "
            "(3.141592653589793 * fabs(b)));") in text
    assert "out[1 * _m + _i] = (((-1.0) / 4.0) * sqrt(t));" in text
