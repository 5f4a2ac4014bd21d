"""Second-order forward differentiation, vectorised over elements: :class:`Jet`.

A :class:`Jet` carries the value, the gradient and the Hessian of a function of ``k`` variables at ``m``
points through the arithmetic of the shell's 2-D densities (:mod:`contin_models.shell.density`), so the
same Python function gives an element's energy on numbers and its local Hessian on jets.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Jet"]


class Jet:
    """Value, gradient and Hessian of a function of ``k`` variables at ``m`` points.

    ``v`` has shape ``(m,)``, ``g`` ``(k, m)`` and ``h`` ``(k, k, m)`` (``None`` for zero).  The
    arithmetic is exact second-order forward differentiation (products by the Leibniz rule, unary
    functions by the chain rule).
    """

    __slots__ = ("v", "g", "h")
    __array_priority__ = 100

    def __init__(self, v, g, h=None):
        self.v, self.g, self.h = v, g, h

    @staticmethod
    def variables(values: list) -> list["Jet"]:
        """Independent variables: ``values[i]`` with unit gradient ``i``."""
        k = len(values)
        vals = [np.asarray(v, dtype=float) for v in values]
        m = max(v.size for v in vals)
        out = []
        for i, v in enumerate(vals):
            g = np.zeros((k, m))
            g[i] = 1.0
            out.append(Jet(np.broadcast_to(v, (m,)).astype(float), g))
        return out

    @staticmethod
    def linear(values: np.ndarray, grads: np.ndarray) -> "Jet":
        """A jet linear in the variables: value ``(m,)`` and gradient ``(k, m)``."""
        return Jet(np.asarray(values, dtype=float), np.asarray(grads, dtype=float))

    @staticmethod
    def _hadd(a, b):
        if a is None:
            return b
        if b is None:
            return a
        return a + b

    def __add__(self, o):
        if isinstance(o, Jet):
            return Jet(self.v + o.v, self.g + o.g, Jet._hadd(self.h, o.h))
        return Jet(self.v + o, self.g, self.h)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.g, None if self.h is None else -self.h)

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def __mul__(self, o):
        if isinstance(o, Jet):
            g = self.g * o.v + o.g * self.v
            cross = self.g[:, None, :] * o.g[None, :, :]
            h = cross + cross.transpose(1, 0, 2)
            if self.h is not None:
                h += self.h * o.v
            if o.h is not None:
                h += o.h * self.v
            return Jet(self.v * o.v, g, h)
        return Jet(self.v * o, self.g * o, None if self.h is None else self.h * o)

    __rmul__ = __mul__

    def _unary(self, f0, f1, f2):
        g = self.g * f1
        h = f2 * (self.g[:, None, :] * self.g[None, :, :])
        if self.h is not None:
            h += self.h * f1
        return Jet(f0, g, h)

    def __truediv__(self, o):
        if isinstance(o, Jet):
            return self * o.reciprocal()
        return self * (1.0 / o)

    def __rtruediv__(self, o):
        return self.reciprocal() * o

    def reciprocal(self):
        iv = 1.0 / self.v
        return self._unary(iv, -iv * iv, 2.0 * iv * iv * iv)

    def sqrt(self):
        s = np.sqrt(self.v)
        return self._unary(s, 0.5 / s, -0.25 / (s * self.v))

    def take(self, idx):
        """The jet at the points ``idx`` (an index array into the ``m`` points)."""
        return Jet(self.v[idx], self.g[:, idx], None if self.h is None else self.h[:, :, idx])

    def total(self):
        """The sum over the points, as a jet at one point."""
        return Jet(self.v.sum(keepdims=True), self.g.sum(axis=1, keepdims=True),
                   None if self.h is None else self.h.sum(axis=2, keepdims=True))

    def log(self):
        return self._unary(np.log(self.v), 1.0 / self.v, -1.0 / (self.v * self.v))

    def square(self):
        return self._unary(self.v * self.v, 2.0 * self.v, np.full_like(self.v, 2.0))
