"""Generated C kernels computing stations four or two at once (``c_extension_text(..., simd=True)``).

The vectors run the scalar code's operations in the same order on each lane of a register, so a
station computed in a quad or a pair has the bits it has when computed alone (the scalar loop).
"""

from __future__ import annotations

import numpy as np
import pytest

from contin.modelkit.codegen import c_extension_text
from contin_models.shell import _density_generated, density_kernels

SOURCE = ("def k(y, c):\n"
          "    y0, y1 = y\n"
          "    _shape = numpy.shape(y0)\n"
          "    _g = numpy.zeros((2,) + _shape)\n"
          "    _a = 2.0**0.5\n"
          "    _v = numpy.sqrt(y1)*c + _a + y0**3\n"
          "    _g[1] = y0\n"
          "    _g[0] = _g[1]*numpy.cos(c)\n"
          "    return _v, _g\n")


def test_translation_in_vectors() -> None:
    text = c_extension_text(SOURCE, {}, "_k", "test", returning=["k"], simd=True)
    assert "#ifdef CONTIN_PAIRS" in text and "for (; _i + 1 < _m; _i += 2) {" in text
    assert "const pair y1 = pair_of(in[1].data[_i * in[1].stride], in[1].data[(_i + 1) * in[1].stride]);" in text
    assert "pair _a = pair_splat(sqrt(2.0));" in text  # a number made a pair
    # four at a time in a function compiled for AVX2, called where the processor has it
    assert "QUADS static Py_ssize_t c_k_quads(const Input *in, double *out_v, double *out_g, Py_ssize_t _m) {" in text
    assert "quad _v = (((quad_sqrt(y1) * c) + _a) + quad_pow(y0, 3.0));" in text
    assert "if (__builtin_cpu_supports(\"avx2\")) {" in text and "_i = c_k_quads(in, out_v, out_g, _m);" in text
    assert "pair _v = (((pair_sqrt(y1) * c) + _a) + pair_pow(y0, 3.0));" in text
    assert "pair_store(&out_g[1 * _m + _i], y0);" in text
    assert "pair_store(&out_g[0 * _m + _i], (pair_load(&out_g[1 * _m + _i]) * pair_cos(c)));" in text
    assert "pair_store(&out_v[_i], _v);" in text
    # the scalar loop is still there for the last station (and for compilers without vector types)...
    assert "for (; _i < _m; _i++) {" in text and "double _v = (((sqrt(y1) * c) + _a) + pow(y0, 3.0));" in text
    # ...and without simd nothing of the vectors is emitted
    assert "pair" not in c_extension_text(SOURCE, {}, "_k", "test", returning=["k"])


@pytest.mark.skipif(not density_kernels.COMPILED, reason="the density kernels' C extension is not built")
@pytest.mark.parametrize("name", _density_generated.KERNELS)
def test_a_station_in_a_quad_or_a_pair_has_the_bits_it_has_alone(name: str) -> None:
    kernel = getattr(density_kernels.kernels, name)
    numpy_kernel = getattr(_density_generated, name)
    k = {"stretch": 6, "skirt": 6, "free_edge": 12, "volume": 12}.get(name.removesuffix("_jet").removesuffix("_general"),
                                                                      15)
    rng = np.random.default_rng(11)
    m = 7  # a quad (with AVX2), a pair and one station alone
    y = rng.uniform(0.1, 1.0, (k, m)) * rng.choice([-1.0, 1.0], (k, m))
    names = numpy_kernel.__code__.co_varnames[1:numpy_kernel.__code__.co_argcount]
    params = [0.3 if p == "nu" else rng.uniform(0.3, 1.5, m) for p in names]
    together = kernel(y, *params)
    for i in range(m):
        alone = kernel(y[:, i:i + 1], *[p[i:i + 1] if np.ndim(p) else p for p in params])
        for t, a in zip(together, alone):
            np.testing.assert_array_equal(np.asarray(t)[..., i], np.asarray(a)[..., 0])
