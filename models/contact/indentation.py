"""The spherical cap indented by a rigid sphere or plate through the log barrier, as a :class:`contin.Problem`.

Indenter travel ``w_b`` is the continuation parameter (displacement control of the indenter): the
indenter position is ``c = c_0 - w_b`` with ``c_0`` the position at which the barrier just reaches
the undeformed pole (gap ``dhat``), so ``w_b = 0`` is the first touch of the barrier and no offset of
order ``dhat`` enters ``w_b``.  The shell's unknowns are those of
the free shell (:meth:`contin_models.shell.ShellPointLoad.free_state`): every dof except the base height
``z_0`` and the pole radius ``r_{N-1} = 0``, the pole height last.  The energy is the shell's elastic energy
plus the barrier (:class:`contin_models.contact.ContactBarrier`); the barrier's cell blocks lie inside the
shell's band, so the Jacobian keeps half-bandwidth 5 and every solve stays O(N).

Snap under displacement control (``docs/model.md#snaps``): as the contact force falls towards
zero the barrier softens and the path turns back in ``w_b``: a fold in the parameter, located by the
engine's minimally augmented system.

Observables: ``F`` (indenter force, ``-dE/dc``, positive while it pushes), ``w_b``, ``w_s`` (pole
displacement), ``Delta_H`` (pole-indenter gap beyond the barrier's range ``dhat``: zero while the
pole is in contact, positive once it has detached), ``kappa_p_R`` (pole curvature times R),
``n_contact`` (nodes within ``dhat``), ``contact_first`` / ``contact_last`` (the range of node
indices in contact, base = 0, pole = N-1; -1 when none), ``base_gap`` (distance from the base node, which cannot move
vertically, to the indenter: an indenter that reaches it presses on the support) and the normalized ``w_b_over_R``, ``w_s_over_R``,
``Delta_H_over_R``, ``F_norm = F R / (2 pi D)``.

Stability labels: ``"displacement"`` (indenter position held: the Hessian on the shell's unknowns)
and ``"force"`` (a dead load on the indenter: the same Hessian bordered by the indenter position).
The first is declared as the leading block of the second (:class:`contin.problem.LeadingBlock`), so
the engine counts both from one pivot-free factorization of the bordered matrix, or, at a fold in
``w_b`` where that cannot be trusted, from the banded leading block and the sign of the Schur
complement (:func:`contin.numerics.stability.nested_inertias`).

Force control of the indenter: :class:`ShellIndentationForce`, the generic dead load
(:class:`contin.analyses.deadload.DeadLoad`) on the indenter travel (``w_b`` an unknown, a dead load ``F`` on
the indenter the parameter; its Jacobian is the displacement-control Hessian bordered by one row and
column, solved by block elimination on the band with :class:`BorderedBandedLU`).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.linalg import lapack

from contin.analyses.deadload import DeadLoad, bordered_matrix
from contin.numerics.linalg import BandedLU, Factorization, SingularMatrixError, SparseLU, inf_norm, same_values
from contin.numerics.linalg import factorize as generic_factorize
from contin.problem import LeadingBlock, NonFiniteError, Problem
from contin_models.shell.energy import HALF_BANDWIDTH
from contin_models.shell.geometry import POLE_RATIO
from contin_models.shell.problem import ShellPointLoad

from .barrier import QUADRATURE_POINTS, SUPPORT_POINTS, ContactBarrier, ContactState, Plate, Sphere, default_barrier, length_weights

__all__ = ["ShellIndentation", "ShellIndentationForce", "BorderedBandedLU"]


class ShellIndentation(Problem):
    """Spherical cap under a rigid sphere or plate, indenter travel ``w_b`` prescribed.

    Parameters
    ----------
    R, E, nu, h, phi_hat, N
        The shell, as in :class:`contin_models.shell.ShellPointLoad`.
    indenter : Sphere or Plate
        The rigid indenter (``Sphere(radius)`` with its centre on the axis, or ``Plate()``).
    K, dhat : float, optional
        Barrier stiffness and range; default :func:`contin_models.contact.default_barrier` (``dhat = 1e-3 R``,
        ``K = 100 E R``, the paper's values for ``E = 1 MPa``, ``R = 1 m``).
    pole_ratio : float
        Node spacing at the pole over the spacing elsewhere (the shell's mesh grading).
    quadrature : int
        Fixed Gauss points per contact cell (:data:`contin_models.contact.barrier.QUADRATURE_POINTS`).
    support_points : int
        Gauss points on each piece of a cell within ``dhat``
        (:data:`contin_models.contact.barrier.SUPPORT_POINTS`; 0: integrate at the fixed points).
    """

    def __init__(self, R: float = 1.0, E: float = 1e6, nu: float = 0.5, h: float = 0.02, phi_hat: float = 0.8,
                 N: int = 200, indenter: Sphere | Plate | None = None, K: float | None = None,
                 dhat: float | None = None, pole_ratio: float = POLE_RATIO,
                 quadrature: int = QUADRATURE_POINTS, support_points: int = SUPPORT_POINTS) -> None:
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
                             "contin_models.shell.ShellPointLoad, or a sphere much smaller than the cap)")
        # the barrier per unit meridian length (the paper's nodal one on its mesh): converges with N
        self.barrier = ContactBarrier(self.indenter, self.K, self.dhat, quadrature=quadrature,
                                      cell_weights=length_weights(el.cap.x), support_points=support_points)
        # the indenter's barrier first touches the meridian's curve where it crosses the axis
        self.c0 = float(self.indenter.contact_position(self.barrier.pole_height(el.cap.x))) + self.dhat
        self.idx = el.idx_force
        self.n_full = el.n_full
        self._cell_slots = self._free_cell_slots()
        observables = {"F": self._obs("F"), "w_b": lambda u, p: float(p), "w_s": self._obs("w_s"),
                       "Delta_H": self._obs("Delta_H"), "kappa_p_R": self._obs("kappa_p_R"),
                       "n_contact": self._obs("n_contact"),
                       "w_b_over_R": lambda u, p: float(p) / self.R, "w_s_over_R": self._obs("w_s_over_R"),
                       "Delta_H_over_R": self._obs("Delta_H_over_R"), "F_norm": self._obs("F_norm"),
                       "base_gap": self._obs("base_gap"), "contact_first": self._obs("contact_first"),
                       "contact_last": self._obs("contact_last")}
        # the displacement Hessian is the force one without its border (the indenter position, last)
        ops = {"displacement": LeadingBlock("force", -1), "force": self._op_force}
        # the force's exact derivatives give the stored path its tangent in F: the diagram draws F smooth
        F_unit = self.R / (2.0 * math.pi * self.D)
        derivatives = {"F": self._force_derivative,
                       "F_norm": lambda u, p: tuple(F_unit * d for d in self._force_derivative(u, p))}
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         stability_operators=ops, name=f"shell_{self.indenter.name}_indentation", parameter_name="w_b",
                         residual_scale=el.residual_scale)
        self._contact_cache: tuple[np.ndarray, float, ContactState] | None = None

    # ---- state maps ------------------------------------------------------------------------------
    def reference_unknowns(self) -> np.ndarray:
        """Unknowns of the undeformed cap (the equilibrium at ``w_b = 0``, where the barrier is just off)."""
        return self.elastic.free_unknowns(self.elastic.cap.x)

    def full_state(self, u: np.ndarray, p: float = 0.0) -> np.ndarray:
        """Full interleaved state from the unknowns (the indenter does not enter it)."""
        return self.elastic.free_state(u)

    def unknowns(self, x: np.ndarray) -> np.ndarray:
        """The unknowns of a full interleaved shell state (the inverse of :meth:`full_state`)."""
        return self.elastic.free_unknowns(x)

    def position(self, w_b: float) -> float:
        """Indenter position ``c = c_0 - w_b``."""
        return self.c0 - float(w_b)

    def _full_step(self, du: np.ndarray) -> np.ndarray:
        dx = np.zeros(self.n_full)
        dx[self.idx] = du
        return dx

    def contact(self, u: np.ndarray, p: float, hessian: bool = True) -> ContactState:
        """Barrier state at ``(u, w_b)``; raises :class:`contin.NonFiniteError` if a node penetrates."""
        # keyed by the unknowns: the observables of a stored point ask for the same state a dozen times
        cached = self._contact_cache
        if cached is not None and cached[1] == p and same_values(cached[0], u) and (
                not hessian or cached[2].hess_blocks is not None):
            return cached[2]
        try:
            state = self.barrier.evaluate(self.full_state(u), self.position(p), hessian=hessian)
        except ValueError as exc:  # d <= 0: outside the model's domain
            raise NonFiniteError(f"{self.name}: {exc}") from None
        self._contact_cache = (np.array(u, dtype=float), float(p), state)
        return state

    # ---- the Problem interface -------------------------------------------------------------------
    def energy(self, u: np.ndarray, p: float) -> float:
        x = self.full_state(u)
        return self.elastic.elastic_energy(x) + self.contact(u, p, hessian=False).energy

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        x = self.full_state(u)
        # with the barrier's Hessian: the Jacobian is asked for at almost every state whose residual is
        g = self.elastic.elastic_gradient(x) + self.contact(u, p).gradient
        return g[self.idx]

    def _free_cell_slots(self) -> np.ndarray:
        """Places of every contact cell's 6x6 block in the values of the Jacobian, shape ``(N, 36)``.

        The block of cell ``i`` (nodes ``i-1, i, i+1``, :meth:`ContactState.hessian_triplets`'s order)
        lands in the shell's full Hessian pattern (:meth:`ContactBarrier.hessian_slots`); the slots are
        carried to the pattern of its block on the unknowns, -1 for an entry of a fixed dof (the base
        height, the pole radius).  Repeated slots (the pole's mirrored neighbour) accumulate.
        """
        H = self.elastic.elastic_hessian(self.elastic.cap.x)
        full = self.barrier.hessian_slots(H)
        H.data = np.arange(1, H.nnz + 1, dtype=float)  # each entry tagged by its slot (+ 1)
        origin = self.elastic.free_block(H, "force").data.astype(np.int64) - 1
        to_free = np.full(H.nnz, -1, dtype=np.int64)
        to_free[origin] = np.arange(origin.size)
        return to_free[full]

    def jacobian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        J = self.elastic.free_hessian(self.full_state(u), "force")
        st = self.contact(u, p)
        if st.active.size:
            slots = self._cell_slots[st.active].ravel()
            kept = slots >= 0
            np.add.at(J.data, slots[kept], st.hess_blocks.reshape(-1)[kept])
        return J

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        # c = c0 - w_b: d/dw_b of the barrier gradient is -d2E/dx dc
        return -self.contact(u, p).hess_xc[self.idx]

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        """``dE/dw_b``: the indenter force ``F`` (``c = c_0 - w_b``, so ``dE/dw_b = -dE/dc``)."""
        return float(self.contact(u, p, hessian=False).force)

    def conjugate_stiffness(self, u: np.ndarray, p: float) -> float:
        """``d2E/dw_b^2 = d2E/dc^2`` of the barrier (the shell's energy does not depend on ``w_b``)."""
        return float(self.contact(u, p).hess_cc)

    def _force_derivative(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        """``(dF/du, dF/dw_b)`` of the force ``F = -dE/dc`` (``c = c_0 - w_b``): ``-d2E/dc dx`` on the free
        unknowns and ``d2E/dc2``."""
        st = self.contact(u, p)
        return -st.hess_xc[self.idx], float(st.hess_cc)

    def factorize(self, J) -> Factorization:
        return BandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH)

    def max_step_fraction(self, u: np.ndarray, p: float, du: np.ndarray, dp: float) -> float:
        """The barrier's IPC filter: no node may reach the indenter along the step."""
        return self.barrier.max_safe_fraction(self.full_state(u), self.position(p), self._full_step(du), -float(dp))

    # ---- stability -------------------------------------------------------------------------------
    def _op_force(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        """Hessian with the indenter position as a further unknown (dead load on the indenter)."""
        st = self.contact(u, p)
        return bordered_matrix(self.jacobian(u, p), st.hess_xc[self.idx], st.hess_cc)

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
            d_pole = self.barrier.pole_distance(x, self.position(p))
            gap = max(d_pole - self.dhat, 0.0)
            return gap if name == "Delta_H" else gap / self.R
        if name == "kappa_p_R":
            return el.pole_curvature(x) * self.R
        if name == "base_gap":  # distance from the (vertically fixed) base node to the indenter
            return float(self.contact(u, p, hessian=False).distances[0])
        if name in ("contact_first", "contact_last"):  # range of node indices in contact, -1 when none
            active = self.contact(u, p, hessian=False).active
            return float(-1 if active.size == 0 else (active.min() if name == "contact_first" else active.max()))
        if name == "n_contact":
            return float(self.contact(u, p, hessian=False).n_active)
        raise KeyError(name)


# ---------------------------------------------------------------------------------------------------
# force control of the indenter
# ---------------------------------------------------------------------------------------------------
#: Backward error (max norms, relative to ``||J|| ||x|| + ||b||``) a block-eliminated solve of
#: :class:`BorderedBandedLU` must reach; otherwise one step of iterative refinement, and if that is
#: not enough the whole matrix is factorized by a sparse LU.  Banded LU with partial pivoting has a
#: backward error of a few ``eps``; block elimination keeps it unless the leading block is far worse
#: conditioned than the bordered matrix (its solves then cancel).
BLOCK_REFINE_TOL = 1e-14


class NotBorderedBandError(ValueError):
    """The matrix is not a banded leading block bordered by one row and column."""


class BorderedBandedLU(Factorization):
    """Factorization of ``J = [[A, b], [c^T, d]]`` whose leading block ``A`` is banded: O(n) solves.

    Block elimination: a banded LU (LAPACK ``gbtrf``) of ``A`` alone, ``y = A^{-1} b`` and the 1x1
    Schur complement ``s = d - c^T y``; a solve of ``J [x; z] = [f; g]`` is
    ``x1 = A^{-1} f``, ``z = (g - c^T x1) / s``, ``x = x1 - y z`` (transposed: the same with
    ``A^T``, ``b`` and ``c`` exchanged, ``s`` unchanged).  ``det J = det A * s``.  The border
    never enters the band, so every factorization and solve costs O(n (kl + ku)^2) and O(n (kl + ku)).

    Safety.  Block elimination is exact algebra but loses accuracy when ``A`` is (nearly) singular
    while ``J`` is not (``x1`` and ``y z`` then cancel).  Every solve therefore checks its backward
    error on ``J`` (one sparse product, O(n)); above :data:`BLOCK_REFINE_TOL` it takes one step of
    iterative refinement, and if that does not reach the bound either, this factorization switches
    for good to a sparse LU of the whole ``J`` (``path = "sparse"``).  An exactly singular ``A``
    (zero pivot) switches at once.  An exactly zero Schur complement means ``J`` itself is singular
    to working precision: ``exactly_singular`` is set and solves raise
    :class:`contin.numerics.linalg.SingularMatrixError`, as a singular :class:`contin.numerics.linalg.BandedLU` does, so
    the engine's bordered solver deflates or factorizes its full matrix instead.

    Parameters
    ----------
    J : sparse matrix, shape ``(n, n)``
        The bordered matrix; entries of the leading ``(n-1) x (n-1)`` block must lie within
        ``kl`` below and ``ku`` above the diagonal (else :class:`NotBorderedBandError`).
    kl, ku : int
        Bandwidths of the leading block.
    refine_tol : float
        The backward-error bound of a solve (default :data:`BLOCK_REFINE_TOL`).
    stats : dict, optional
        Counters updated in place: ``"factorizations"``, ``"sparse"`` (switches to the sparse LU),
        ``"refined"`` (solves that needed a refinement step) and ``"reasons"`` (switches by reason).

    Attributes
    ----------
    path : {"block", "sparse"}
        Which factorization currently answers the solves.
    fallback_reason : str or None
        Why it switched to the sparse LU.
    schur : float
        The Schur complement ``s`` (NaN if the leading block was singular).
    """

    def __init__(self, J, kl: int, ku: int, refine_tol: float = BLOCK_REFINE_TOL,
                 stats: dict | None = None) -> None:
        J = sp.csr_matrix(J)
        if not J.has_canonical_format:
            J = J.copy()
            J.sum_duplicates()
        n = J.shape[0]
        if J.shape != (n, n) or n < 2:
            raise NotBorderedBandError(f"BorderedBandedLU: need a square matrix of size >= 2, got {J.shape}")
        m = n - 1
        self.n, self.m, self.kl, self.ku = n, m, int(kl), int(ku)
        self.J = J
        self.refine_tol = float(refine_tol)
        self.stats = stats
        self.path = "block"
        self.fallback_reason: str | None = None
        self.exactly_singular = False
        self.schur = math.nan
        self._sparse: SparseLU | None = None
        rows = np.repeat(np.arange(n), np.diff(J.indptr))
        cols, vals = J.indices, J.data
        lead = (rows < m) & (cols < m)
        r, c, v = rows[lead], cols[lead], vals[lead]
        off = r - c
        if off.size and (off.max() > self.kl or -off.min() > self.ku):
            raise NotBorderedBandError("BorderedBandedLU: the leading block has entries outside the band "
                                       f"(kl = {self.kl}, ku = {self.ku})")
        self._J_norm = inf_norm(J)  # for the backward-error test
        col_m = (cols == m) & (rows < m)
        row_m = (rows == m) & (cols < m)
        self.b = np.zeros(m)
        self.b[rows[col_m]] = vals[col_m]
        self.c = np.zeros(m)
        self.c[cols[row_m]] = vals[row_m]
        self.d = float(np.sum(vals[(rows == m) & (cols == m)]))
        if stats is not None:
            stats["factorizations"] = stats.get("factorizations", 0) + 1
        ab = np.zeros((2 * self.kl + self.ku + 1, m))
        ab.reshape(-1)[(self.kl + self.ku + off) * m + c] = v  # flat indices: twice as fast as ab[i, j]
        self._lu, self._piv, info = lapack.dgbtrf(ab, self.kl, self.ku)
        if info > 0:
            self._use_sparse("the leading block is exactly singular (zero pivot of its banded LU)")
            return
        y = self._band_solve(self.b, False)
        s = self.d - float(self.c @ y)
        if not (np.isfinite(y).all() and math.isfinite(s)):
            self._use_sparse("the leading block's solve overflowed")
            return
        self._y, self._yT = y, None
        self.schur = s
        self.exactly_singular = s == 0.0

    # -- the two paths ----------------------------------------------------------------------------
    def _band_solve(self, f: np.ndarray, trans: bool) -> np.ndarray:
        x, _ = lapack.dgbtrs(self._lu, self.kl, self.ku, f, self._piv, trans=1 if trans else 0)
        return x

    def _use_sparse(self, reason: str) -> None:
        self.path = "sparse"
        self.fallback_reason = reason
        if self.stats is not None:
            self.stats["sparse"] = self.stats.get("sparse", 0) + 1
            reasons = self.stats.setdefault("reasons", {})
            reasons[reason] = reasons.get(reason, 0) + 1
        self._sparse = SparseLU(self.J)  # raises SingularMatrixError if J is exactly singular
        self.exactly_singular = False

    def _block_solve(self, rhs: np.ndarray, trans: bool) -> np.ndarray:
        m = self.m
        f, g = rhs[:m], rhs[m]
        x1 = self._band_solve(f, trans)
        if trans:
            if self._yT is None:
                self._yT = self._band_solve(self.c, True)
            y, border = self._yT, self.b
        else:
            y, border = self._y, self.c
        z = (g - border @ x1) / self.schur
        if rhs.ndim == 1:
            return np.append(x1 - y * z, z)
        return np.vstack([x1 - np.outer(y, z), z[None, :]])

    def _backward_ok(self, x: np.ndarray, rhs: np.ndarray, trans: bool) -> tuple[bool, np.ndarray]:
        if not np.isfinite(x).all():
            return False, rhs
        r = rhs - ((self.J.T @ x) if trans else (self.J @ x))
        bound = self.refine_tol * (self._J_norm * np.max(np.abs(x), initial=0.0) + np.max(np.abs(rhs), initial=0.0))
        return bool(np.max(np.abs(r), initial=0.0) <= bound), r

    # -- the Factorization interface --------------------------------------------------------------
    def solve(self, b, trans: bool = False) -> np.ndarray:
        rhs = np.asarray(b, dtype=float)
        if self._sparse is None:
            if self.exactly_singular:
                raise SingularMatrixError("bordered matrix is singular (its Schur complement is exactly zero)")
            with np.errstate(all="ignore"):
                x = self._block_solve(rhs, trans)
                ok, r = self._backward_ok(x, rhs, trans)
                if not ok and np.isfinite(x).all():
                    if self.stats is not None:
                        self.stats["refined"] = self.stats.get("refined", 0) + 1
                    x = x + self._block_solve(r, trans)
                    ok, _ = self._backward_ok(x, rhs, trans)
            if ok:
                return x
            self._use_sparse("block elimination missed the backward-error bound (ill-conditioned leading block)")
        return self._sparse.solve(rhs, trans=trans)

    def det_sign_log(self) -> tuple[float, float]:
        if self._sparse is not None:
            return self._sparse.det_sign_log()
        diag = self._lu[self.kl + self.ku, :]
        if self.exactly_singular or np.any(diag == 0.0):
            return 0.0, -math.inf
        swaps = np.count_nonzero(self._piv != np.arange(self._piv.size))
        negative = np.count_nonzero(diag < 0) + (1 if self.schur < 0 else 0)
        sign = -1.0 if (swaps + negative) % 2 else 1.0
        return sign, float(np.sum(np.log(np.abs(diag))) + math.log(abs(self.schur)))

    def pivots(self) -> np.ndarray:
        """Pivots of an LU of ``J`` indexed by the unknowns (small where ``J`` is near singular).

        Block path: the banded LU's pivots of ``A`` followed by ``s`` (the diagonal of the block LU
        ``J = [[P^T L, 0], [c^T U^{-1}, 1]] [[U, L^{-1} P b], [0, s]]``).  Sparse path: SuperLU's
        pivots, each at the index of its column.
        """
        if self._sparse is not None:
            return self._sparse.pivots()
        return np.append(self._lu[self.kl + self.ku, :], self.schur)


class ShellIndentationForce(DeadLoad):
    """Spherical cap under a rigid sphere or plate carrying a dead load ``F``: force control of the indenter.

    The generic dead load (:class:`contin.analyses.deadload.DeadLoad`) on :class:`ShellIndentation`'s indenter
    travel.  Unknowns ``U = [u, w_b]``: the shell unknowns ``u`` of :class:`ShellIndentation` (same
    order) followed by the indenter travel ``w_b`` (the indenter position is ``c = c_0 - w_b`` as
    there).  Parameter: the dead load ``F`` on the indenter (positive pushing down).  Energy::

        E(U, F) = E_shell(x) + E_barrier(x, c_0 - w_b) - F w_b,

    so the last residual row is ``F_contact(u, w_b) - F`` (``F_contact = dE_barrier/dw_b``, the
    indenter force of :class:`ShellIndentation`) and an equilibrium of this problem is one of
    :class:`ShellIndentation` at the travel ``w_b`` whose contact force equals the load.

    Jacobian: the displacement-control Hessian ``A`` (band of half-width 5) bordered by one row and
    column, ``[[A, a], [a^T, d]]`` with ``a = d2E/du dw_b`` (nonzero at the contact nodes only) and
    ``d = d2E/dw_b^2``.  :meth:`factorize` keeps the band: it returns a :class:`BorderedBandedLU`
    (banded LU of ``A``, block elimination of ``w_b`` through a 1x1 Schur complement, a sparse LU of
    the whole matrix only as a checked fallback; :attr:`linear_solver_stats` counts which path ran).

    Starting state.  With ``F = 0`` and no node within ``dhat`` the barrier is zero and ``w_b`` does
    not enter the energy: the indenter floats and the Jacobian is singular, so the trace cannot
    start from the undeformed cap.  Start it from a contact state instead: a converged point
    ``(u, w_b)`` of the displacement-controlled :class:`ShellIndentation` with ``w_b > 0`` and a
    positive force there, mapped by :meth:`from_displacement_state` to ``(U, F)``;
    :meth:`contact_start` traces displacement control from the undeformed cap to a given ``w_b`` and
    does both.  From there the load can be raised to the force limit point (a fold in ``F``, the
    maximum of ``F`` along the displacement path) or lowered towards ``F -> 0+``.

    Stability labels: ``"force"`` (the full Hessian on ``U``, the primary label: the indenter is
    free under its dead load) and ``"displacement"`` (its leading block: the indenter held), both
    from one pivot-free ``L D L^T`` of the Jacobian.

    Observables: the same names as :class:`ShellIndentation`'s, in its order (``F`` is now the
    parameter and ``w_b`` the last unknown; every other one, e.g. ``w_s``, ``Delta_H``,
    ``kappa_p_R``, ``n_contact``, is the displacement problem's at ``(u, w_b)``), with exact
    derivatives of ``F``, ``w_b`` and their normalized forms.

    Parameters
    ----------
    R, E, nu, h, phi_hat, N, indenter, K, dhat, pole_ratio
        As in :class:`ShellIndentation`.  :meth:`from_displacement` wraps an existing
        :class:`ShellIndentation` instead (same scene, shared caches).
    """

    def __init__(self, R: float = 1.0, E: float = 1e6, nu: float = 0.5, h: float = 0.02, phi_hat: float = 0.8,
                 N: int = 200, indenter: Sphere | Plate | None = None, K: float | None = None,
                 dhat: float | None = None, pole_ratio: float = POLE_RATIO) -> None:
        self._setup(ShellIndentation(R=R, E=E, nu=nu, h=h, phi_hat=phi_hat, N=N, indenter=indenter, K=K,
                                     dhat=dhat, pole_ratio=pole_ratio))

    @classmethod
    def from_displacement(cls, problem: ShellIndentation) -> "ShellIndentationForce":
        """The force-controlled problem of the same scene as the displacement-controlled ``problem``."""
        if not isinstance(problem, ShellIndentation):
            raise TypeError(f"from_displacement: need a ShellIndentation, got {type(problem).__name__}")
        self = cls.__new__(cls)
        self._setup(problem)
        return self

    def _setup(self, P: ShellIndentation) -> None:
        self.displacement = P
        self.elastic = P.elastic
        self.R, self.E, self.nu, self.h, self.phi_hat, self.N = P.R, P.E, P.nu, P.h, P.phi_hat, P.N
        self.D, self.K, self.dhat = P.D, P.K, P.dhat
        self.indenter, self.barrier, self.c0 = P.indenter, P.barrier, P.c0
        self.n_shell = P.idx.size
        self.n = self.n_shell + 1
        #: which path :meth:`factorize`'s factorizations took (see :class:`BorderedBandedLU`)
        self.linear_solver_stats: dict = {"factorizations": 0, "sparse": 0, "refined": 0, "reasons": {}}
        super().__init__(P, force="F", scaled={"F_norm": ("F", self.R / (2.0 * math.pi * self.D)),
                                               "w_b_over_R": ("w_b", 1.0 / self.R)},
                         factorize=self._bordered_band)
        self.name = f"shell_{self.indenter.name}_indentation_force"

    # ---- state maps ------------------------------------------------------------------------------
    def split(self, U: np.ndarray) -> tuple[np.ndarray, float]:
        """``(u, w_b)``: the shell unknowns and the indenter travel of ``U``."""
        U = np.asarray(U, dtype=float)
        if U.shape != (self.n,):
            raise ValueError(f"unknown vector must have shape ({self.n},), got {U.shape}")
        return U[:-1], float(U[-1])

    def full_state(self, U: np.ndarray, p: float = 0.0) -> np.ndarray:
        """Full interleaved shell state of ``U`` (the indenter does not enter it)."""
        return self.displacement.full_state(self.split(U)[0])

    def position(self, U: np.ndarray) -> float:
        """Indenter position ``c = c_0 - w_b``."""
        return self.displacement.position(self.split(U)[1])

    def from_displacement_state(self, u: np.ndarray, w_b: float) -> tuple[np.ndarray, float]:
        """Start ``(U, F)`` of force control from a displacement-control point ``(u, w_b)``.

        ``U = [u, w_b]`` and ``F`` is the contact force there, so ``(U, F)`` is an equilibrium of
        this problem exactly when ``(u, w_b)`` is one of :class:`ShellIndentation`.  Raises
        ``ValueError`` without contact (``F <= 0``: the indenter would float, see the class docstring).
        """
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n_shell,):
            raise ValueError(f"displacement-control unknowns must have shape ({self.n_shell},), got {u.shape}")
        U, F = super().from_displacement_state(u, w_b)
        if not F > 0:
            raise ValueError(f"{self.name}: no contact force at w_b = {w_b:g} (F = {F:g}); force control needs "
                             "a contact state to start from (the indenter is undetermined without contact)")
        return U, F

    def contact_start(self, w_b: float, **options) -> tuple[np.ndarray, float]:
        """Trace displacement control from the undeformed cap to the travel ``w_b`` and return its ``(U, F)``.

        ``options`` go to :func:`contin.continuation` (default ``ds = 0.005 R``, ``ds_max = 0.02 R``).
        """
        import contin  # the engine's driver; the model itself only needs its interface

        P = self.displacement
        opts = {"ds": 0.005 * self.R, "ds_max": 0.02 * self.R, "max_steps": 1000, "detect_branch_points": False}
        opts.update(options)
        br = contin.continuation(P, P.reference_unknowns(), 0.0, p_max=float(w_b), **opts)
        if br.status != "bound":
            raise RuntimeError(f"{self.name}: displacement control did not reach w_b = {w_b:g} ({br.message})")
        return self.from_displacement_state(br.u[-1], float(br.p[-1]))

    def _bordered_band(self, J) -> Factorization:
        """Block elimination of ``w_b`` on the banded LU of the leading block (:class:`BorderedBandedLU`)."""
        try:
            return BorderedBandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH, stats=self.linear_solver_stats)
        except NotBorderedBandError:  # not this problem's structure (never for its own Jacobians)
            return generic_factorize(J)

    # ---- observables -----------------------------------------------------------------------------
    def evaluate_one(self, name: str, U: np.ndarray, p: float) -> float:
        """One observable at ``(U, F)`` (see the class docstring)."""
        return float(self.observables[name](U, p))
