"""The sympy printer of the models' generated kernels (``contin_models.shell.codegen``, ``contin_models.contact.codegen``).

Needs sympy: imported by the generators only, never on a model's import path.
"""

from __future__ import annotations

from typing import Any

from sympy.printing.numpy import NumPyPrinter

__all__ = ["KernelPrinter", "kernel_printer"]


class KernelPrinter(NumPyPrinter):
    """NumPy printer with plain reciprocals and square roots instead of float powers, and integer
    powers above 2 as products (``numpy.power`` is slow for them)."""

    def _print_Pow(self, expr: Any, rational: bool = False) -> str:
        base, exp = expr.base, expr.exp
        if exp.is_Integer or (exp.is_Rational and exp.q == 2):
            k = int(exp * 2) if not exp.is_Integer else int(exp)
            half = not exp.is_Integer
            b = f"numpy.sqrt({self._print(base)})" if half else self.parenthesize(base, 60)
            # For half-integer powers k counts halves.
            mag = abs(k)
            if half or mag <= 2:
                core = b if mag == 1 else f"{b}**{mag}"
            else:  # numpy's power is slow for exponents other than 2: multiply
                core = "*".join([f"{b}**2"] * (mag // 2) + [b] * (mag % 2))
            return core if k > 0 else f"(1/{core})"
        return super()._print_Pow(expr, rational=rational)


def kernel_printer() -> KernelPrinter:
    """The printer the generators use: :class:`KernelPrinter` with fully qualified ``numpy.`` names.

    Returns
    -------
    KernelPrinter
        A fresh printer.
    """
    return KernelPrinter(settings={"fully_qualified_modules": True})
