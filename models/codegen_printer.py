"""The sympy printer of the models' generated kernels (``contin_models.shell.codegen``, ``contin_models.contact.codegen``).

The printer is the engine's (:func:`contin.codegen.kernel_printer`): one printer for every generated
kernel, the models' and the energy-first tools'.  Needs sympy: imported by the generators only,
never on a model's import path.
"""

from __future__ import annotations

from contin.codegen import kernel_printer

__all__ = ["KernelPrinter", "kernel_printer"]

#: The printer's class (a ``sympy`` ``NumPyPrinter``), built by the engine on first use.
KernelPrinter = type(kernel_printer())
