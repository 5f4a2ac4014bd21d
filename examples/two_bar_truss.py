"""Two-bar von Mises truss, energy first: declare the elements in sympy, trace both limit points.

Two elastic bars (axial stiffness ``EA``, rest length ``L0``) join the supports ``(-s, 0)`` and
``(s, 0)`` to the apex, first at ``(0, h)``; a dead load ``P`` pushes the apex down (potential
``P y``).  On the symmetric path the limit points satisfy ``L^3 = L0 s^2`` (bar length ``L``), and for
a shallow truss ``P_max -> 2 / (3 sqrt 3) EA (h / s)^3``.

Run ``python examples/two_bar_truss.py`` (``--write`` regenerates ``two_bar_truss_kernels.py``,
the committed kernels that the tests check byte for byte and use without sympy).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

import contin

KERNELS = Path(__file__).with_name("two_bar_truss_kernels.py")


def elements() -> list:
    """The bar and the dead load as :class:`contin.modelkit.codegen.Element` (needs sympy)."""
    import sympy as sp

    x1, y1, x2, y2, EA, L0, y, P = sp.symbols("x1 y1 x2 y2 EA L0 y P", real=True)
    L = sp.sqrt((x2 - x1) ** 2 + (y2 - y1) ** 2)
    bar = contin.Element("bar", EA / (2 * L0) * (L - L0) ** 2, (x1, y1, x2, y2), (EA, L0),
                         doc="elastic bar, energy EA / (2 L0) (L - L0)^2")
    load = contin.Element("load", P * y, (y,), parameter=P, doc="dead load P pushing a node down")
    return [bar, load]


def generate_source() -> str:
    """The text of ``two_bar_truss_kernels.py``."""
    return contin.generate_kernels(elements(), title="Kernels of the two-bar truss example.",
                                   generator="python examples/two_bar_truss.py --write")


def truss(kernels, span: float = 1.0, rise: float = 0.1, EA: float = 1.0) -> contin.EnergyProblem:
    """The truss: global dofs 0-1 and 2-3 the supports (fixed), 4-5 the apex ``(x, y)``."""
    L0 = math.hypot(span, rise)
    return contin.EnergyProblem(kernels, {"bar": ([[0, 1, 4, 5], [2, 3, 4, 5]], [EA, L0]), "load": [[5]]},
                                n_dofs=6, fixed={0: -span, 1: 0.0, 2: span, 3: 0.0}, parameter_name="P",
                                observables={"y": lambda u, P: float(u[1])}, name="two_bar_truss")


def limit_load(span: float, rise: float, EA: float) -> float:
    """Closed form: ``L*^3 = L0 s^2``, ``P_max = 2 (EA / L0) y* (L0 / L* - 1)``."""
    L0 = math.hypot(span, rise)
    Ls = (L0 * span**2) ** (1 / 3)
    return 2 * EA / L0 * math.sqrt(Ls**2 - span**2) * (L0 / Ls - 1)


def main(argv: list[str]) -> None:
    if "--write" in argv:
        contin.modelkit.codegen.write_generated(generate_source, KERNELS)
        return
    span, rise, EA = 1.0, 0.1, 1.0
    problem = truss(elements(), span, rise, EA)  # kernels generated in process
    bound = 3 * limit_load(span, rise, EA)
    branch = contin.continuation(problem, [0.0, rise], 0.0, p_max=bound, p_min=-bound)
    exact = limit_load(span, rise, EA)
    print(f"shallow-truss asymptote 2/(3 sqrt 3) EA (h/s)^3 = {2 / (3 * math.sqrt(3)) * EA * (rise / span) ** 3:.12e}")
    for fold in (sp for sp in branch.special_points if sp.kind == "fold"):
        ref = math.copysign(exact, fold.p)
        print(f"limit load {fold.p:+.12e}   closed form {ref:+.12e}   relative error {abs(fold.p / ref - 1):.1e}")


if __name__ == "__main__":
    main(sys.argv[1:])
