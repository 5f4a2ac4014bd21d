"""Shallow-arch (Marguerre) theory of a pinned arch under a central dead load, in sine modes.

The reference model for :class:`contin_models.benchmarks.arch.ShallowArch`: the same arch (span
``L``, rise ``h``, bending stiffness ``EI``, axial stiffness ``EA = EI / r^2``, load ``P`` positive
downwards at mid-span) described by the classical shallow-arch equations instead of bars and hinges.

Theory (facts taken from the literature, written out here in our own notation):

* Marguerre (1938, "Zur Theorie der gekrümmten Platte grosser Formänderung", Proc. 5th Int. Congr.
  Appl. Mech.): for a shallow curved member the membrane strain is ``u' + w0' v' + v'^2 / 2`` and the
  bending strain is the change of curvature ``v''``, with ``w0(x)`` the initial height and ``v`` the
  (upward) deflection.  With both ends pinned and held (``u = 0`` at ``x = 0, L``), the axial force is
  constant along the span and equal to ``EA / L * integral (w0' v' + v'^2 / 2) dx``.
* Fung and Kaplan, NACA TN 2840 (1952), "Buckling of low arches or curved beams of small
  curvature": the treatment of the pinned low arch by a Fourier sine series of the deflection, which
  turns the equilibrium into algebraic equations in the modal amplitudes, and the distinction
  between a symmetric snap-through (limit point) and an asymmetric bifurcation.  That on the
  symmetric path the antisymmetric modes are unloaded and the path bifurcates into mode 2 where the
  compressive axial force reaches ``4 pi^2 EI / L^2`` follows from the equations below.
* Bazant and Cedolin, "Stability of Structures" (1991), and Simitses, "An Introduction to the Elastic
  Stability of Structures" (1976), their sections on shallow arches: the same energy formulation and
  the classification of the pinned shallow arch's behaviour by the rise parameter ``e / r``.

We cite these for the theory only; the formulas here are written out and derived for this module,
and we did not have the texts at hand to compare numbers with their tables or figures.

Energy (``v`` the upward deflection, the unknowns are its sine amplitudes ``a_k``, ``k = 1..K``):

    U = EI / 2 int v''^2 dx + EA / (2 L) [int (w0' v' + v'^2 / 2) dx]^2 + P v(L / 2)

``v = 0`` at the unloaded state, ``P > 0`` pushes the crown down, ``deflection = -v(L / 2)``: the same
conventions as ``ShallowArch`` (``+ P u_y(crown)``, ``deflection = -u_y(crown)``).  The sine series
is exact for the bending term of the pinned beam, and the integrals are sums by orthogonality:
``int v''^2 = L / 2 sum a_k^2 alpha_k^4``, ``int w0' v' = L / 2 sum c_k a_k alpha_k^2`` and
``int v'^2 = L / 2 sum a_k^2 alpha_k^2`` with ``alpha_k = k pi / L`` and ``c_k`` the sine coefficients
of ``w0`` (only ``k <= K`` enter, so the initial shape is not truncated further).  The only
approximation beyond the theory's is the truncation at ``K`` modes, which converges as ``K`` grows.

Nondimensional form (derived here): with ``q_k = a_k / r``, ``g_k = c_k / r`` and
``Q = 4 P L^3 / (pi^4 EI r)`` the energy is ``EI pi^4 r^2 / (4 L^3)`` times

    sum k^4 q_k^2 + 1/8 [sum k^2 (2 g_k q_k + q_k^2)]^2 + Q sum q_k sin(k pi / 2).

Closed form for the half-sine arch ``w0 = e sin(pi x / L)`` truncated to modes 1 and 2 (derived here
from the equations above; ``eps = e / r``): the symmetric path bifurcates into mode 2 at
``Q_b = 2 eps + 6 sqrt(eps^2 - 16)`` (needs ``eps >= 4``) and has a limit point at
``Q_l = 2 eps + ((eps^2 - 4) / 3)^(3/2)`` (needs ``eps > 2``); the bifurcation comes first when
``eps > sqrt(22)``.  The same equations (``Q`` then the generalized load on mode 1) hold exactly for
the half-sine arch under a *half-sine distributed* load, which excites mode 1 only: the case for which the literature states the
classification by ``e / r`` (we recall the criterion in this form but did not check it against the
books); under the central point load modes 3, 5, ... are excited too, so the converged values
(``K`` large) differ from them.  :func:`two_mode_half_sine` returns these numbers.
"""

from __future__ import annotations

import numpy as np

from contin import Problem

__all__ = ["MarguerreArch", "two_mode_half_sine", "load_unit"]

SHAPES = ("sine", "parabola", "circle")


def load_unit(span: float, EI: float, r: float) -> float:
    """The load that is ``Q = 1``: ``P = Q * pi^4 EI r / (4 L^3)`` (module docstring)."""
    return np.pi ** 4 * EI * r / (4.0 * span ** 3)


def two_mode_half_sine(eps: float) -> dict[str, float]:
    """Closed-form loads ``Q`` of the half-sine arch with modes 1 and 2 only (module docstring).

    Parameters
    ----------
    eps : float
        ``e / r``, rise over radius of gyration.

    Returns
    -------
    dict
        ``branch_point`` (nan if ``eps < 4``), ``fold`` (nan if ``eps <= 2``) and ``criterion``
        (``sqrt(22)``: above it the branch point comes first).
    """
    bp = 2 * eps + 6 * np.sqrt(eps ** 2 - 16) if eps >= 4 else float("nan")
    fold = 2 * eps + ((eps ** 2 - 4) / 3) ** 1.5 if eps > 2 else float("nan")
    return {"branch_point": float(bp), "fold": float(fold), "criterion": float(np.sqrt(22.0))}


def shape_coefficients(shape: str, span: float, rise: float, K: int) -> np.ndarray:
    """Sine coefficients ``c_1..c_K`` of the initial shape ``w0`` (zero at both supports, ``rise`` at mid-span).

    ``sine``: ``w0 = rise sin(pi x / L)``.  ``parabola``: ``4 rise x (L - x) / L^2``, the shallow circle to
    leading order, ``c_k = 32 rise / (k pi)^3`` for odd ``k``.  ``circle``: the circular arc through the
    supports and the crown, its coefficients by Gauss-Legendre quadrature (the arc is smooth on
    ``[0, L]``, so 400 points are at roundoff for any ``K`` used here).
    """
    k = np.arange(1, K + 1)
    if shape == "sine":
        c = np.zeros(K)
        c[0] = rise
        return c
    if shape == "parabola":
        return np.where(k % 2 == 1, 32.0 * rise / (k * np.pi) ** 3, 0.0)
    if shape == "circle":
        R = (0.25 * span ** 2 + rise ** 2) / (2 * rise)
        t, wq = np.polynomial.legendre.leggauss(400)
        x = 0.5 * span * (t + 1.0)
        w0 = np.sqrt(R ** 2 - (x - 0.5 * span) ** 2) - (R - rise)
        return (2.0 / span) * 0.5 * span * (np.sin(np.outer(k, x) * np.pi / span) @ (wq * w0))
    raise ValueError(f"MarguerreArch: shape {shape!r} is not one of {SHAPES}")


class MarguerreArch(Problem):
    """Pinned shallow arch in ``K`` sine modes (Marguerre theory); parameter ``P``, the central dead load.

    Parameters
    ----------
    K : int
        Number of sine modes of the deflection (>= 2, so that the first antisymmetric mode is there).
    span, rise : float
        Span ``L`` and rise ``h`` (crown height) of the initial shape.
    EI : float
        Bending stiffness.
    rise_over_gyration : float
        ``h / r`` with ``r = sqrt(EI / EA)``: ``EA = EI (rise_over_gyration / rise)^2``, as in ``ShallowArch``.
    shape : {"circle", "parabola", "sine"}
        Initial shape (see :func:`shape_coefficients`).

    Notes
    -----
    Unknowns: the amplitudes ``a_k`` of ``v = sum a_k sin(k pi x / L)`` (upward).  The Hessian is dense
    ``K x K``: the axial term couples every mode.
    """

    def __init__(self, K: int = 20, span: float = 1.0, rise: float = 0.05, EI: float = 1.0,
                 rise_over_gyration: float = 10.0, shape: str = "circle") -> None:
        if int(K) != K or K < 2:
            raise ValueError(f"MarguerreArch: K = {K!r} must be an integer >= 2")
        if not (span > 0 and rise > 0 and EI > 0 and rise_over_gyration > 0):
            raise ValueError("MarguerreArch: need span, rise, EI, rise_over_gyration > 0")
        self.K, self.span, self.rise, self.EI, self.shape = int(K), float(span), float(rise), float(EI), shape
        self.r = self.rise / float(rise_over_gyration)
        self.EA = self.EI / self.r ** 2
        k = np.arange(1, self.K + 1)
        alpha = k * np.pi / self.span
        self.c = shape_coefficients(shape, self.span, self.rise, self.K)
        # U = 1/2 a.B a + (EA / 2L) T^2 with T = m.a + 1/2 a.M a; B, M diagonal (orthogonality)
        self._B = self.EI * 0.5 * self.span * alpha ** 4
        self._M = 0.5 * self.span * alpha ** 2
        self._m = self._M * self.c
        self._kt = self.EA / self.span
        self._s = np.sin(0.5 * k * np.pi)  # mode shapes at mid-span: 1, 0, -1, 0, ...
        self._s[k % 2 == 0] = 0.0  # exactly zero, so the antisymmetric modes are exactly unloaded
        # modes odd in k are symmetric about mid-span; the quarter points see the antisymmetric ones
        self._quarter = np.sin(0.25 * k * np.pi) - np.sin(0.75 * k * np.pi)
        super().__init__(symmetric=True, name=f"marguerre_arch(K={K}, {shape})", parameter_name="P",
                         residual_scale=self.EI * self.rise / self.span ** 3)
        self._obs = {
            "deflection": lambda a, P: float(-self._s @ a),
            # v(L/4) - v(3L/4), as ShallowArch's asymmetry: zero on the symmetric path
            "asymmetry": lambda a, P: float(self._quarter @ a),
        }

    @property
    def observables(self):
        return self._obs

    def _T(self, a: np.ndarray) -> float:
        """``int (w0' v' + v'^2 / 2) dx``, the axial stretch times ``L`` (the axial force is ``EA T / L``)."""
        return float(self._m @ a + 0.5 * (self._M * a) @ a)

    def energy(self, a, P):
        a = np.asarray(a, dtype=float)
        return float(0.5 * (self._B * a) @ a + 0.5 * self._kt * self._T(a) ** 2 + P * (self._s @ a))

    def residual(self, a, P):
        a = np.asarray(a, dtype=float)
        return self._B * a + self._kt * self._T(a) * (self._m + self._M * a) + P * self._s

    def jacobian(self, a, P):
        a = np.asarray(a, dtype=float)
        g = self._m + self._M * a
        return np.diag(self._B + self._kt * self._T(a) * self._M) + self._kt * np.outer(g, g)

    def dresidual_dp(self, a, P):
        return self._s.copy()

    def load_unit(self) -> float:
        """``P`` for ``Q = 1`` (module docstring)."""
        return load_unit(self.span, self.EI, self.r)
