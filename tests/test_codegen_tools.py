"""The generators' shared toolbox in :mod:`contin.modelkit.codegen` (issue 15, item 1): packed pair order and the
emitted helpers, the stepwise kernel body, row emission and the generator command line."""

from __future__ import annotations

import numpy as np
import pytest

sympy = pytest.importorskip("sympy")

from contin.modelkit.codegen import (KernelBody, count_operations, emitted_helpers, function_header,  # noqa: E402
                            generator_main, kernel_printer, upper_pairs)


def _run(source: str) -> dict:
    namespace: dict = {"numpy": np}
    exec(compile(source, "<generated>", "exec"), namespace)  # noqa: S102 - our own text
    return namespace


@pytest.mark.parametrize("n", [1, 3, 6])
def test_emitted_helpers_follow_the_packed_pair_order(n: int) -> None:
    helpers = _run(emitted_helpers("_unpack", "_prepare"))
    assert helpers["_upper"](n) == upper_pairs(n)  # _unpack brings _upper along
    full = np.random.default_rng(n).normal(size=(n, n, 4))
    full = full + full.transpose(1, 0, 2)
    packed = np.array([full[a, b] for a, b in upper_pairs(n)])
    assert np.array_equal(helpers["_unpack"](packed, n), np.moveaxis(full, 2, 0))
    *arrays, shape = helpers["_prepare"](1, np.zeros(3))
    assert shape == (3,) and all(a.dtype == float for a in arrays)
    with pytest.raises(ValueError, match="unknown helpers"):
        emitted_helpers("_nothing")


def test_kernel_body_reuses_up_to_sign_drops_dead_and_fills_rows() -> None:
    x, y = sympy.symbols("x y", real=True)
    body = KernelBody()
    a = body.name([sympy.sin(x) * y + x])[0]
    b = body.name([-(sympy.sin(x) * y + x)])[0]
    assert b == -a and len(body.assignments) == 1  # the repeat up to sign is not assigned again
    body.name([sympy.cos(y) * x])  # a temporary the rows below never use
    rows = body.reduce([a * x, a + 2])
    printer = kernel_printer()
    header = function_header("k", ["x", "y", "out=None"], ["Rows.", "", "More."])
    source = "\n".join(header + body.row_lines([], rows, printer, like="x"))
    assert "cos" not in source and source.count("_c") >= 1
    k = _run(source)["k"]
    xv, yv = np.array([0.5, 1.5]), np.array([2.0, -1.0])
    c = np.sin(xv) * yv + xv
    assert np.allclose(k(xv, yv), [c * xv, c + 2])
    out = np.empty((2, 2))
    assert k(xv, yv, out=out) is out
    assert count_operations(["a = b*c + numpy.sqrt(d)", "e = -a", "f = 2*3"]) == 4


def test_generator_main_writes_and_checks(tmp_path, capsys) -> None:
    path = tmp_path / "gen.py"
    assert generator_main(["--output", str(path)], lambda: "X = 1\n", path, "python make.py", "Make.") == 0
    assert path.read_text() == "X = 1\n"
    assert generator_main(["--check"], lambda: "X = 1\n", path, "python make.py", "Make.") == 0
    assert generator_main(["--check"], lambda: "X = 2\n", path, "python make.py", "Make.") == 1
    assert "python make.py" in capsys.readouterr().err
