"""The spherical cap indented by a rigid sphere or plate through the log barrier, as a :class:`contin.Problem`.

Indenter travel ``w_b`` is the continuation parameter (displacement control of the indenter): the
indenter position is ``c = c_0 - w_b`` with ``c_0`` the position at which the barrier just reaches
the undeformed pole (gap ``dhat``), so ``w_b = 0`` is the first touch of the barrier and no offset of
order ``dhat`` enters ``w_b``.  The shell's unknowns are those of
:class:`models.shell.ShellPointLoad` under force control: every dof except the base height ``z_0``
and the pole radius ``r_{N-1} = 0``, the pole height last.  The energy is the shell's elastic energy
plus the barrier (:class:`models.contact.ContactBarrier`); the barrier's node blocks lie inside the
shell's band, so the Jacobian keeps half-bandwidth 5 and every solve stays O(N).

Snap under displacement control (``docs/physics.md`` section 4): as the contact force falls towards
zero the barrier softens and the path turns back in ``w_b``: a fold in the parameter, located by the
engine's minimally augmented system.

Observables: ``F`` (indenter force, ``-dE/dc``, positive while it pushes), ``w_b``, ``w_s`` (pole
displacement), ``Delta_H`` (pole-indenter gap beyond the barrier's range ``dhat``: zero while the
pole is in contact, positive once it has detached), ``kappa_p_R`` (pole curvature times R),
``n_contact`` (nodes within ``dhat``) and the normalized ``w_b_over_R``, ``w_s_over_R``,
``Delta_H_over_R``, ``F_norm = F R / (2 pi D)``.

Stability labels: ``"displacement"`` (indenter position held: the Hessian on the shell's unknowns)
and ``"force"`` (a dead load on the indenter: the same Hessian bordered by the indenter position),
both counted from one pivot-free factorization of the bordered matrix.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from contin.linalg import BandedLU, Factorization
from contin.problem import NonFiniteError, Problem
from contin.stability import leading_inertias
from models.shell.energy import HALF_BANDWIDTH
from models.shell.geometry import POLE_RATIO
from models.shell.problem import ShellPointLoad

from .barrier import ContactBarrier, ContactState, Plate, Sphere, default_barrier

__all__ = ["ShellIndentation"]


class ShellIndentation(Problem):
    """Spherical cap under a rigid sphere or plate, indenter travel ``w_b`` prescribed.

    Parameters
    ----------
    R, E, nu, h, phi_hat, N, pole_ratio
        The shell, as in :class:`models.shell.ShellPointLoad`.
    indenter : Sphere or Plate
        The rigid indenter (``Sphere(radius)`` with its centre on the axis, or ``Plate()``).
    K, dhat : float, optional
        Barrier stiffness and range; default :func:`models.contact.default_barrier` (``dhat = 1e-3 R``,
        ``K = 100 E R``, the paper's values for ``E = 1 MPa``, ``R = 1 m``).
    """

    def __init__(self, R: float = 1.0, E: float = 1e6, nu: float = 0.5, h: float = 0.02, phi_hat: float = 0.8,
                 N: int = 200, indenter: Sphere | Plate | None = None, K: float | None = None,
                 dhat: float | None = None, pole_ratio: float = POLE_RATIO) -> None:
        self.elastic = ShellPointLoad(R=R, E=E, nu=nu, h=h, phi_hat=phi_hat, N=N, control="force",
                                      pole_ratio=pole_ratio)
        el = self.elastic
        self.R, self.E, self.nu, self.h, self.phi_hat, self.N = el.R, el.E, el.nu, el.h, el.phi_hat, el.N
        self.D = el.D
        K0, dhat0 = default_barrier(E, R)
        self.K = float(K0 if K is None else K)
        self.dhat = float(dhat0 if dhat is None else dhat)
        self.indenter = indenter if indenter is not None else Sphere(0.5 * R)
        if isinstance(self.indenter, Sphere) and not self.indenter.radius > 0:
            # a point has no inside the step filter can keep nodes out of: the pole would pass
            # through it; the point load is ShellPointLoad (bilateral) or a small sphere
            raise ValueError("ShellIndentation: the sphere radius must be > 0 (for a point load use "
                             "models.shell.ShellPointLoad, or a sphere much smaller than the cap)")
        self.barrier = ContactBarrier(self.indenter, self.K, self.dhat)
        self.c0 = float(self.indenter.contact_position(el.z_pole_ref)) + self.dhat
        self.idx = el.idx_force
        self.n_full = el.n_full
        # CSR slots of each node's (r, z) diagonal block in the shell's full Hessian pattern
        H0 = el.elastic_hessian(el.cap.x)
        self._pattern = H0
        self._node_slots = np.array([[_slot(H0, 2 * i + a, 2 * i + b) for a in (0, 1) for b in (0, 1)]
                                     for i in range(self.N)])
        observables = {"F": self._obs("F"), "w_b": lambda u, p: float(p), "w_s": self._obs("w_s"),
                       "Delta_H": self._obs("Delta_H"), "kappa_p_R": self._obs("kappa_p_R"),
                       "n_contact": self._obs("n_contact"),
                       "w_b_over_R": lambda u, p: float(p) / self.R, "w_s_over_R": self._obs("w_s_over_R"),
                       "Delta_H_over_R": self._obs("Delta_H_over_R"), "F_norm": self._obs("F_norm")}
        ops = {"displacement": self._op_displacement, "force": self._op_force}
        super().__init__(observables=observables, symmetric=True, stability_operators=ops,
                         name=f"shell_{self.indenter.name}_indentation", parameter_name="w_b",
                         residual_scale=el.residual_scale)
        self._contact_cache: tuple[np.ndarray, float, ContactState] | None = None

    # ---- state maps ------------------------------------------------------------------------------
    def reference_unknowns(self) -> np.ndarray:
        """Unknowns of the undeformed cap (the equilibrium at ``w_b = 0``, where the barrier is just off)."""
        return self.elastic.reference_unknowns()

    def full_state(self, u: np.ndarray, p: float = 0.0) -> np.ndarray:
        """Full interleaved state from the unknowns (the indenter does not enter it)."""
        return self.elastic.full_state(u, 0.0)

    def position(self, w_b: float) -> float:
        """Indenter position ``c = c_0 - w_b``."""
        return self.c0 - float(w_b)

    def _full_step(self, du: np.ndarray) -> np.ndarray:
        dx = np.zeros(self.n_full)
        dx[self.idx] = du
        return dx

    def contact(self, u: np.ndarray, p: float, hessian: bool = True) -> ContactState:
        """Barrier state at ``(u, w_b)``; raises :class:`contin.NonFiniteError` if a node penetrates."""
        x = self.full_state(u)
        c = self.position(p)
        cached = self._contact_cache
        if cached is not None and cached[1] == c and np.array_equal(cached[0], x) and (
                not hessian or cached[2].hess_blocks is not None):
            return cached[2]
        try:
            state = self.barrier.evaluate(x, c, hessian=hessian)
        except ValueError as exc:  # d <= 0: outside the model's domain
            raise NonFiniteError(f"{self.name}: {exc}") from None
        self._contact_cache = (x.copy(), c, state)
        return state

    # ---- the Problem interface -------------------------------------------------------------------
    def energy(self, u: np.ndarray, p: float) -> float:
        x = self.full_state(u)
        return self.elastic.elastic_energy(x) + self.contact(u, p, hessian=False).energy

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        x = self.full_state(u)
        g = self.elastic.elastic_gradient(x) + self.contact(u, p, hessian=False).gradient
        return g[self.idx]

    def _full_hessian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        x = self.full_state(u)
        H = self.elastic._hessian(x).copy()  # the shell's cached matrix is shared: never modify it
        st = self.contact(u, p)
        if st.active.size:
            np.add.at(H.data, self._node_slots[st.active].ravel(), st.hess_blocks.reshape(-1))
        return H

    def jacobian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        return self.elastic._sub["force"](self._full_hessian(u, p))

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        # c = c0 - w_b: d/dw_b of the barrier gradient is -d2E/dx dc
        return -self.contact(u, p).hess_xc[self.idx]

    def factorize(self, J) -> Factorization:
        return BandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH)

    def max_step_fraction(self, u: np.ndarray, p: float, du: np.ndarray, dp: float) -> float:
        """The barrier's IPC filter: no node may reach the indenter along the step."""
        return self.barrier.max_safe_fraction(self.full_state(u), self.position(p), self._full_step(du), -float(dp))

    # ---- stability -------------------------------------------------------------------------------
    def _op_displacement(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        return self.jacobian(u, p)

    def _op_force(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        """Hessian with the indenter position as a further unknown (dead load on the indenter)."""
        J = self.jacobian(u, p)
        st = self.contact(u, p)
        col = st.hess_xc[self.idx].reshape(-1, 1)
        return sp.bmat([[J, sp.csr_matrix(col)], [sp.csr_matrix(col.T), np.array([[st.hess_cc]])]], format="csr")

    def stability_counts(self, u: np.ndarray, p: float) -> dict[str, int] | None:
        counts = leading_inertias(self._op_force(u, p), (self.idx.size, self.idx.size + 1))
        if counts is None:
            return None
        return {"displacement": counts[0], "force": counts[1]}

    # ---- observables -----------------------------------------------------------------------------
    def _obs(self, name: str):
        return lambda u, p: self.evaluate_one(name, u, p)

    def evaluate_one(self, name: str, u: np.ndarray, p: float) -> float:
        """One observable at ``(u, w_b)`` (see the module docstring)."""
        el = self.elastic
        if name in ("F", "F_norm"):
            F = self.contact(u, p, hessian=False).force
            return F if name == "F" else F * self.R / (2.0 * math.pi * self.D)
        x = self.full_state(u)
        if name in ("w_s", "w_s_over_R"):
            w_s = el.pole_displacement(x)
            return w_s if name == "w_s" else w_s / self.R
        if name in ("Delta_H", "Delta_H_over_R"):
            d_pole = float(self.contact(u, p, hessian=False).distances[-1])
            gap = max(d_pole - self.dhat, 0.0)
            return gap if name == "Delta_H" else gap / self.R
        if name == "kappa_p_R":
            a, b = el._pole_ab(x)
            return el._pole.curvature(a, b)[0] * self.R
        if name == "n_contact":
            return float(self.contact(u, p, hessian=False).n_active)
        raise KeyError(name)


def _slot(H: sp.csr_matrix, i: int, j: int) -> int:
    """Index into ``H.data`` of the stored entry ``(i, j)`` (it must be in the pattern)."""
    lo, hi = H.indptr[i], H.indptr[i + 1]
    hits = np.nonzero(H.indices[lo:hi] == j)[0]
    if hits.size != 1:
        raise ValueError(f"entry ({i}, {j}) is not in the shell's Hessian pattern")
    return int(lo + hits[0])
