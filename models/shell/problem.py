"""Point load at the pole of the discrete axisymmetric shell, as a :class:`contin.Problem`.

Boundary conditions
-------------------
* Sliding base: the base node's height ``z_0`` is fixed at its reference value, its radius ``r_0``
  is free (paper section 2 / 4a, ``docs/model.md#supports``).
* Pole on the axis: ``r_{N-1} = 0`` is eliminated from the unknowns.

Pole treatment
--------------
Two symmetric treatments are available (``pole=``):

``"mirror"`` (default)
    The meridian is continued across the axis by the mirror image ``(-r_{N-2}, z_{N-2})`` of the
    last interior node.  The pole then is an ordinary bending node whose turning angle ``xi``
    between the last edge and its mirror satisfies ``tan(xi/2) = b / a`` with
    ``a = r_{N-2} - r_{N-1} = r_{N-2}`` and ``b = z_{N-1} - z_{N-2}``, so
    ``kappa11 = 2 b / (a L)``; by symmetry ``kappa22 = kappa11`` at the pole.  ``L`` is the pole's
    Voronoi length with the mirror edge, i.e. the last edge length (reference ``lbar`` or current
    ``l`` according to ``kappa11_length``), and the element's area is the disc
    ``A = pi (lbar/2)^2``, so its energy is
    ``(A/2) kb (B11^2 + 2 nu B11 B22 + B22^2) = A kb (1 + nu) B^2`` with ``B = kappa11 - kappabar``.
``"skip"``
    The pole carries no bending element: in the quadrature ``sum_i pi rbar_i lbar_i (...)`` of
    eq. (3.12) its weight vanishes because ``rbar = 0`` (the trapezoidal rule in ``r``).

Measured by ``python -m studies.shell_mesh_convergence`` (default scene, N = 50..800,
successive-difference orders).  On the default mesh, graded towards the pole
(:func:`contin_models.shell.geometry.theta_nodes`), the mirror treatment converges at orders 1.94, 1.92,
1.92 for ``F`` at ``w/R = 0.1`` and 2.03, 2.01, 2.00 for the first maximum ``F_max``.  On the
paper's uniform mesh (``pole_ratio = 1``) ``F(w/R = 0.1)`` converges at 1.79, 1.81, 1.82 with
errors 1.3 to 1.8 times larger: its error is ``N^-2`` times a logarithmic factor from the
point-load singularity, whose coefficient the grading shrinks.  Skipping the pole gives orders
1.40, 1.57, 1.64 (graded; 0.85, 1.36, 1.54 uniform) and errors 5 (N = 50) to 11 (N = 800) times
larger.  The mirror treatment is therefore the default.

The mirror element's area ``pi (lbar/2)^2`` is the exact area of the pole's cell: with the
interior nodes' rings ``2 pi rbar_i lbar_i`` the cells tile the cap.  That weight sets the
coefficient of the logarithmic error term, and other weights are consistent too but worse or
tuned: scaling it by 0.5 or 2 gives orders 1.71..1.74 or 1.98..3.45 (erratic) for
``F(w/R = 0.1)``; 1.25 happens to cancel the log term for this load (orders 2.07..2.09), which
nothing in the model gives a reason for.  The reference length ``lbar`` in the pole curvature
alone (interior nodes with current lengths) would make the pole the one node that fails the
pure-dilation check of ``docs/model.md#checks`` (its curvature would stay ``kappabar`` instead of
``kappabar / (1 + e)``).  Neither is used.

Controls
--------
``control="displacement"``: parameter ``w`` (pole displacement downwards, ``w = zbar_pole -
z_pole``, bilateral).  Unknowns: every dof except ``z_0``, ``r_{N-1}``, ``z_{N-1}``, in the
interleaved order ``[r_0, r_1, z_1, ..., r_{N-2}, z_{N-2}]`` (``2N - 3`` values).

``control="force"``: parameter ``F`` (dead load pushing the pole down), built once for every model
by :class:`contin.analyses.deadload.DeadLoad` on the displacement-controlled shell.  The unknowns are the
displacement-control ones followed by the pole displacement ``w`` (``2N - 2`` values); the energy
is ``E_el(x) - F w``.

The *free shell* (used by models that add their own loads, such as the contact) has the unknowns
:attr:`ShellPointLoad.idx_force` of the full state: every dof except ``z_0`` and ``r_{N-1}``, the
pole height ``z_{N-1}`` last (:meth:`ShellPointLoad.free_state`, :meth:`ShellPointLoad.free_unknowns`,
:meth:`ShellPointLoad.free_block`).

In every ordering the Hessian keeps half-bandwidth at most 5 (:data:`HALF_BANDWIDTH`), and
:meth:`ShellPointLoad.factorize` uses a banded LU.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
import scipy.sparse as sp

from contin.analyses.deadload import DeadLoad
from contin.numerics.linalg import BandedLU, Factorization, FixedPattern, inf_norm, same_values, symmetric_column
from contin.problem import LeadingBlock, Problem

from .elements import PoleMirror
from .energy import HALF_BANDWIDTH, ShellEnergy
from .geometry import POLE_RATIO, spherical_cap
from .reference import ShellReference

__all__ = ["ShellPointLoad", "PoleMirror", "ROUNDOFF_MARGIN", "SubMatrix", "csr_slots", "shell_residual_scale"]

#: States whose Hessians :class:`ShellPointLoad` keeps (see ``_hessian``).
_HESSIAN_CACHE_SIZE = 3

ROUNDOFF_MARGIN = 1e-5
"""Residual scale factor on ``||H_ref||_inf R`` (see :class:`ShellPointLoad`)."""


def shell_residual_scale(E: float, h: float, R: float, H: sp.csr_matrix) -> float:
    """``max(E h R, ROUNDOFF_MARGIN ||H||_inf R)`` for a shell Hessian ``H`` on the unknowns.

    The residual scale of every shell problem (see the Notes of :class:`ShellPointLoad` for why).
    """
    return max(E * h * R, ROUNDOFF_MARGIN * inf_norm(H) * R)


def _scaled(derivative: tuple[np.ndarray, float], factor: float) -> tuple[np.ndarray, float]:
    return derivative[0] * factor, derivative[1] * factor


def csr_slots(A: sp.csr_matrix, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
    """Positions in ``A.data`` of the entries ``(rows[k], cols[k])`` (which must be stored; ``A`` canonical)."""
    rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
    n = A.shape[1]
    # the stored entries' keys row * n + col are sorted in a canonical CSR matrix
    keys = np.repeat(np.arange(A.shape[0], dtype=np.int64), np.diff(A.indptr)) * n + A.indices
    want = rows * n + cols
    out = np.searchsorted(keys, want)
    missing = (out >= keys.size) | (keys[np.minimum(out, keys.size - 1)] != want)
    if np.any(missing):
        k = int(np.flatnonzero(missing)[0])
        raise KeyError(f"entry ({rows[k]}, {cols[k]}) is not in the sparsity pattern")
    return out


#: Submatrix maps of fixed patterns (read-only index arrays, matched by identity) and index sets: a
#: family of shells on one mesh shares them (see ``contin_models.shell.energy._PATTERNS``).
_SUBMATRICES: dict[tuple, tuple] = {}


class SubMatrix:
    """Fast extraction of a principal submatrix ``H[idx][:, idx]`` for a fixed CSR pattern."""

    def __init__(self, pattern: sp.csr_matrix, idx: np.ndarray) -> None:
        idx = np.asarray(idx)
        shared = not (pattern.indices.flags.writeable or pattern.indptr.flags.writeable)
        key = (id(pattern.indices), id(pattern.indptr), idx.tobytes())
        hit = _SUBMATRICES.get(key) if shared else None
        if hit is None or hit[0] is not pattern.indices:
            tagged = sp.csr_matrix((np.arange(1, pattern.nnz + 1, dtype=float), pattern.indices.copy(),
                                    pattern.indptr.copy()), shape=pattern.shape)
            sub = tagged[idx][:, idx].tocsr()
            sub.sort_indices()
            hit = (pattern.indices, sub.data.astype(np.int64) - 1, FixedPattern(sub.indices, sub.indptr, sub.shape))
            if shared:
                _SUBMATRICES[key] = hit
                while len(_SUBMATRICES) > 16:
                    del _SUBMATRICES[next(iter(_SUBMATRICES))]
        _, self.take, self.pattern = hit
        self.indices, self.indptr, self.shape = self.pattern.indices, self.pattern.indptr, self.pattern.shape

    def __call__(self, H: sp.csr_matrix) -> sp.csr_matrix:
        return self.pattern.matrix(H.data[self.take])


class ShellPointLoad(Problem):
    """Spherical cap loaded by a point force at the pole (displacement or force control).

    Parameters
    ----------
    R, E, nu, h, phi_hat : float
        Sphere radius, Young's modulus, Poisson's ratio, thickness, base angle
        (``docs/model.md#geometry``).
    N : int
        Number of nodes (base = 0, pole = ``N-1``).
    control : {"displacement", "force"}
        Parameter ``w`` (prescribed pole displacement, downwards positive) or ``F`` (dead load,
        downwards positive).
    kappa11_length : {"reference", "current"}
        Length in ``kappa11 = 2 tan(xi/2) / L`` (see :class:`contin_models.shell.ShellEnergy`).
    pole : {"mirror", "skip"}
        Pole treatment (module docstring).
    pole_ratio : float
        Node spacing at the pole relative to the rest of the cap, in ``(0, 1]`` (default 1/2: a mesh
        graded towards the point load; 1: uniform, as in the paper).  See
        :func:`contin_models.shell.geometry.theta_nodes`.

    Notes
    -----
    ``residual_scale = max(E h R, ROUNDOFF_MARGIN ||H_ref||_inf R)``.  The residual is a vector of
    nodal forces.  The membrane terms that cancel in it are forces ``~ (E h / (1 - nu^2)) eps``
    acting along a circumference ``~ 2 pi r``, independent of ``N``; ``E h R`` is that force at
    unit strain, so the engine's default ``tol = 1e-10`` means a force imbalance of 1e-10 ``E h R``
    -- for the default scene 2e-6 N against ``F ~ 30 N`` at ``w/R = 0.1``.  The bending terms that
    cancel (as a discrete fourth difference) are ``~ ||H_bend|| |dx|``, which grows like
    ``E h^3 N^3 / R^2``: the measured rounding floor of the residual at a converged state is
    ``~ 3e-17 ||H||_inf R`` (max norm), which passes ``1e-10 E h R`` near ``N = 800`` for
    ``h/R = 0.02``.  The second term keeps the default tolerance a factor ~30 above that floor on
    fine meshes (``ROUNDOFF_MARGIN = 1e-5``); it is inactive for the default scene.
    """

    def __init__(self, R: float = 1.0, E: float = 1e6, nu: float = 0.5, h: float = 0.02,
                 phi_hat: float = 0.8, N: int = 200,
                 control: Literal["displacement", "force"] = "displacement",
                 kappa11_length: Literal["reference", "current"] = "current",
                 pole: Literal["mirror", "skip"] = "mirror", pole_ratio: float = POLE_RATIO) -> None:
        if control not in ("displacement", "force"):
            raise ValueError(f"ShellPointLoad: control must be 'displacement' or 'force', got {control!r}")
        if pole not in ("mirror", "skip"):
            raise ValueError(f"ShellPointLoad: pole must be 'mirror' or 'skip', got {pole!r}")
        if control == "force":
            # a dead load on the pole is the generic dead load on the displacement-controlled shell
            twin = ShellPointLoad(R, E, nu, h, phi_hat, N, "displacement", kappa11_length, pole, pole_ratio)
            self._load_by_force(twin)
            return
        self.cap = spherical_cap(R, phi_hat, N, pole_ratio)
        # the paper's supports: a sliding base without an edge element, the pole by the choice made;
        # the force-controlled problem shares this table through its twin
        self.reference = ShellReference.build(self.cap, E, nu, h, kappa11_length, "sliding", "none", pole)
        self.shell = ShellEnergy(reference=self.reference)
        self.R, self.E, self.nu, self.h, self.phi_hat, self.N = float(R), float(E), float(nu), float(h), float(phi_hat), int(N)
        self.control = "displacement"
        self.pole = pole
        self.D = self.shell.kb
        self.n_full = 2 * self.N
        self.z_pole_ref = float(self.cap.z[-1])
        # the reference state that full_state fills in, built once (ReferenceCap.x interleaves anew)
        self._x_reference = self.cap.x
        self._x_reference.setflags(write=False)
        n = self.n_full
        base = np.concatenate([[0], np.arange(2, n - 2)])
        self.idx_displacement = base
        self.idx_force = np.concatenate([base, [n - 1]])
        self.idx = self.idx_displacement

        H0 = self.shell.hessian(self._x_reference)
        self._sub = {"displacement": SubMatrix(H0, self.idx_displacement),
                     "force": SubMatrix(H0, self.idx_force)}

        if pole == "mirror":
            (pole_reference,) = self.reference.poles
            self._pole = pole_reference.element
            loc = pole_reference.dofs
            self._pole_dofs = loc
            rr, cc = np.meshgrid(loc, loc, indexing="ij")
            self._pole_slots = csr_slots(H0, rr.ravel(), cc.ravel())
        else:
            self._pole = None

        self._hessian(self._x_reference, H0)  # the reference Hessian, for the residual scale and the first steps
        scale = self._residual_scale("displacement")
        observables = {"F": self._obs_F, "w": self._obs_w, "w_over_R": self._obs_w_over_R,
                       "F_norm": self._obs_F_norm}
        # the control's own stability comes first: it is the primary label (Branch.n_negative) and
        # the operator contin.jump minimises with; the force-control unknowns are the displacement
        # ones followed by the pole's position, so the displacement Hessian is the leading block of
        # the force one and one L D L^T counts both Morse indices
        ops = {"displacement": LeadingBlock("force", self.idx_displacement.size), "force": self._op_force}
        derivatives = {"F": self._dobs_F, "w": self._dobs_w,
                       "w_over_R": lambda u, p: _scaled(self._dobs_w(u, p), 1.0 / self.R),
                       "F_norm": lambda u, p: _scaled(self._dobs_F(u, p), self.R / (2.0 * math.pi * self.D))}
        super().__init__(observables=observables, observable_derivatives=derivatives, symmetric=True,
                         stability_operators=ops,
                         name="shell_point_displacement", parameter_name="w", residual_scale=scale,
                         difference_scale=self.h)

    def _residual_scale(self, control: str) -> float:
        """``max(E h R, ROUNDOFF_MARGIN ||H_ref||_inf R)`` on the unknowns of ``control`` (class Notes)."""
        H = self._sub[control](self._hessian(self._x_reference))
        self.hessian_norm = inf_norm(H)
        return shell_residual_scale(self.E, self.h, self.R, H)

    def _load_by_force(self, twin: "ShellPointLoad") -> None:
        """Become the dead load ``F`` at the pole: :class:`contin.analyses.deadload.DeadLoad` of ``twin``.

        The unknowns are the displacement-control ones followed by the pole displacement ``w``; the
        energy is ``E_el(x) - F w``.  ``twin`` (the displacement-controlled shell of the same scene)
        lends its mesh, energy, sparsity maps and Hessian cache, so both see the same states.
        """
        twin.__dict__.setdefault("_hess_cache", [])  # shared: the twin evaluates every state of this problem
        vars(self).update(vars(twin))
        self.twin = twin
        self.control = "force"
        self.idx = self.idx_force
        scale = self._residual_scale("force")
        f_norm = self.R / (2.0 * math.pi * self.D)
        # the bordered Hessian keeps the band: the pole's column couples only to the last nodes
        self.dead_load = DeadLoad(twin, force="F", scaled={"w_over_R": ("w", 1.0 / self.R), "F_norm": ("F", f_norm)},
                                  factorize=twin.factorize, residual_scale=scale)
        dead = self.dead_load
        # the displacement Hessian is the bordered dead-load Jacobian without its border
        ops = {"force": dead.jacobian, "displacement": LeadingBlock("force", self.idx_displacement.size)}
        Problem.__init__(self, observables=dead.observables, observable_derivatives=dead.observable_derivatives,
                         symmetric=True, stability_operators=ops, name="shell_point_force", parameter_name="F",
                         residual_scale=scale)

    # ---- maps between the full state and the unknowns --------------------------------------------
    @property
    def n(self) -> int:
        """Number of unknowns of this control."""
        return self.idx.size

    def reference_unknowns(self) -> np.ndarray:
        """Unknown vector of the reference (stress-free) state, the equilibrium at ``p = 0``."""
        return self.unknowns(self.cap.x)

    def full_state(self, u: np.ndarray, p: float) -> np.ndarray:
        """Full interleaved state ``[r_0, z_0, ..., r_{N-1}, z_{N-1}]`` from unknowns and parameter."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n,):
            raise ValueError(f"unknown vector must have shape ({self.n},), got {u.shape}")
        if self.control == "force":  # the last unknown is the pole displacement
            return self.twin.full_state(u[:-1], float(u[-1]))
        x = self._x_reference.copy()
        x[self.idx] = u
        x[-1] = self.z_pole_ref - float(p)
        return x

    def unknowns(self, x: np.ndarray) -> np.ndarray:
        """Unknowns of this control from a full state (the fixed dofs are dropped, not checked)."""
        u = np.asarray(x, dtype=float)[self.idx_displacement].copy()
        return np.append(u, self.pole_displacement(x)) if self.control == "force" else u

    def free_state(self, v: np.ndarray) -> np.ndarray:
        """Full state from the free shell's unknowns ``x[idx_force]`` (the pole height among them)."""
        x = self._x_reference.copy()
        x[self.idx_force] = np.asarray(v, dtype=float)
        return x

    def free_unknowns(self, x: np.ndarray) -> np.ndarray:
        """The free shell's unknowns ``x[idx_force]`` of a full state."""
        return np.asarray(x, dtype=float)[self.idx_force].copy()

    def pole_displacement(self, x: np.ndarray) -> float:
        """``w = zbar_pole - z_pole`` of a full state."""
        return self.z_pole_ref - float(x[-1])

    # ---- elastic energy with the pole treatment --------------------------------------------------
    def _pole_ab(self, x: np.ndarray) -> tuple[float, float]:
        return float(x[-4]), float(x[-1] - x[-3])

    def pole_curvature(self, x: np.ndarray) -> float:
        """Curvature ``kappa11 = kappa22`` at the pole of a full state, by the pole's mirror element.

        Raises ``ValueError`` for ``pole="skip"`` (the pole then carries no bending element).
        """
        if self._pole is None:
            raise ValueError("pole_curvature needs the mirror pole treatment (pole='mirror')")
        return float(self._pole.curvature(*self._pole_ab(x))[0])

    @property
    def pole_element(self) -> PoleMirror | None:
        """The pole's bending element (None for ``pole="skip"``)."""
        return self._pole

    def use_pole_element(self, element: PoleMirror) -> None:
        """Replace the pole's bending element, e.g. to survey other pole treatments (mirror pole only).

        The cached gradients and Hessians hold the old element and are dropped; under force control
        the displacement-controlled twin that evaluates the energy gets the element too.
        """
        if self._pole is None:
            raise ValueError("use_pole_element needs the mirror pole treatment (pole='mirror')")
        if self.control == "force":
            self.twin.use_pole_element(element)
        self._pole = element
        for key in [k for k in vars(self) if k.endswith("_cache")]:
            del self.__dict__[key]
        if self.control == "force":
            self._hess_cache = self.twin.__dict__.setdefault("_hess_cache", [])

    def free_block(self, H: sp.csr_matrix, control: Literal["displacement", "force"]) -> sp.csr_matrix:
        """The principal block of a full ``2N x 2N`` Hessian (this shell's pattern) on the unknowns of ``control``.

        Other models that add terms to the shell's energy (a contact barrier) restrict their full
        Hessian with it, in O(nnz), to the unknowns they share with the shell.
        """
        return self._sub[control](H)

    def elastic_energy(self, x: np.ndarray) -> float:
        """Elastic energy of a full state (stretching + bending + pole element)."""
        e = self.shell.energy(x)
        if self._pole is not None:
            e += self._pole.energy(*self._pole_ab(x))
        return e

    def elastic_gradient(self, x: np.ndarray) -> np.ndarray:
        """Gradient of :meth:`elastic_energy` in all ``2N`` dofs."""
        # one-state cache: the residual, the reaction force F and F_norm are asked for at the same state
        cached = self.__dict__.get("_grad_cache")
        if cached is not None and same_values(cached[0], x):
            return cached[1].copy()
        g = self.shell.gradient(x)
        if self._pole is not None:
            gp, _ = self._pole.gradient_hessian(*self._pole_ab(x))
            g[self._pole_dofs] += gp
        self._grad_cache = (np.array(x, dtype=float), g.copy())
        return g

    def elastic_hessian(self, x: np.ndarray) -> sp.csr_matrix:
        """Hessian of :meth:`elastic_energy` in all ``2N`` dofs (banded CSR, fixed pattern)."""
        return self._hessian(x).copy()

    def free_hessian(self, x: np.ndarray, control: Literal["displacement", "force"]) -> sp.csr_matrix:
        """:meth:`free_block` of :meth:`elastic_hessian`: the Hessian on the unknowns of ``control``.

        A matrix of its own (the caller may add to its values), taken in O(nnz) from the cached
        Hessian without copying all of it first.
        """
        return self._sub[control](self._hessian(x))

    def _hessian(self, x: np.ndarray, shell_hessian: sp.csr_matrix | None = None) -> sp.csr_matrix:
        # Small cache of the last few states: the engine asks for the Jacobian, df/dp, the
        # stability operators and exact observable derivatives at the same state, and the fold
        # Newton alternates between a state and its finite-difference neighbours.  The returned
        # matrix is shared: callers must not modify it.  ``shell_hessian``: the shell's own Hessian
        # at ``x`` when the caller has it already (it becomes the cached matrix).
        cache = self.__dict__.setdefault("_hess_cache", [])
        for i, (xc, Hc) in enumerate(cache):
            if same_values(xc, x):
                if i:
                    cache.insert(0, cache.pop(i))
                return Hc
        H = self.shell.hessian(x) if shell_hessian is None else shell_hessian
        if self._pole is not None:
            _, Hp = self._pole.gradient_hessian(*self._pole_ab(x))
            H.data[self._pole_slots] += Hp.ravel()
        cache.insert(0, (np.array(x, dtype=float), H))
        del cache[_HESSIAN_CACHE_SIZE:]
        return H

    # ---- the Problem interface -------------------------------------------------------------------
    # Under force control every method is the dead load's (contin.analyses.deadload.DeadLoad of the twin);
    # what follows is the displacement control.
    def energy(self, u: np.ndarray, p: float) -> float:
        if self.control == "force":
            return self.dead_load.energy(u, p)
        return self.elastic_energy(self.full_state(u, p))

    def residual(self, u: np.ndarray, p: float) -> np.ndarray:
        if self.control == "force":
            return self.dead_load.residual(u, p)
        return self.elastic_gradient(self.full_state(u, p))[self.idx]

    def jacobian(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        if self.control == "force":
            return self.dead_load.jacobian(u, p)
        return self._sub["displacement"](self._hessian(self.full_state(u, p)))

    def dresidual_dp(self, u: np.ndarray, p: float) -> np.ndarray:
        if self.control == "force":
            return self.dead_load.dresidual_dp(u, p)
        col = self._pole_column(self._hessian(self.full_state(u, p)))
        return -col[self.idx]  # z_pole = zbar - w

    def jacobian_dp(self, u: np.ndarray, p: float):
        if self.control == "force":
            return self.dead_load.jacobian_dp(u, p)
        return super().jacobian_dp(u, p)

    def conjugate_force(self, u: np.ndarray, p: float) -> float:
        """``dE/dw`` under displacement control: the pole force ``F`` (the reaction of the prescribed ``w``)."""
        return self.reaction_force(self.full_state(u, p))

    def conjugate_stiffness(self, u: np.ndarray, p: float) -> float:
        """``d2E/dw2`` under displacement control: the pole's diagonal entry of the Hessian."""
        return float(self._pole_column(self._hessian(self.full_state(u, p)))[-1])

    def _pole_column(self, H: sp.csr_matrix) -> np.ndarray:
        """Dense column of ``z_pole`` of the symmetric full Hessian (read as the last row)."""
        return symmetric_column(H, self.n_full - 1)

    def factorize(self, J) -> Factorization:
        """Banded LU with the model's half-bandwidth (O(N)); the dead load's border stays in the band."""
        return BandedLU(J, HALF_BANDWIDTH, HALF_BANDWIDTH)

    # ---- stability: the Hessian on the free dofs of the force control ---------------------------
    def _op_force(self, u: np.ndarray, p: float) -> sp.csr_matrix:
        """The force-control Hessian; the displacement-control one is its leading block (``LeadingBlock``)."""
        # the dead-load term is linear in the state: its Hessian is zero
        return self.free_hessian(self.full_state(u, p), "force")

    def reaction_force(self, x: np.ndarray) -> float:
        """``F = dE_el/dw = -dE_el/dz_pole`` of a full state (positive when pushing down)."""
        return -float(self.elastic_gradient(x)[-1])

    def _obs_F(self, u: np.ndarray, p: float) -> float:
        return self.reaction_force(self.full_state(u, p))

    def _obs_w(self, u: np.ndarray, p: float) -> float:
        return float(p)

    def _dobs_F(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        """Exact ``(dF/du, dF/dp)``: the pole row of the Hessian (``F = -dE_el/dz_pole``)."""
        row = self._pole_column(self._hessian(self.full_state(u, p)))
        return -row[self.idx], float(row[-1])  # z_pole = zbar - w

    def _dobs_w(self, u: np.ndarray, p: float) -> tuple[np.ndarray, float]:
        """Exact ``(dw/du, dw/dp)``."""
        return np.zeros(self.n), 1.0

    def _obs_w_over_R(self, u: np.ndarray, p: float) -> float:
        return self._obs_w(u, p) / self.R

    def _obs_F_norm(self, u: np.ndarray, p: float) -> float:
        return self._obs_F(u, p) * self.R / (2.0 * math.pi * self.D)

    # ---- linear response -------------------------------------------------------------------------
    def linear_stiffness(self) -> float:
        """Initial slope ``dF/dw`` at the reference state (condensed Hessian, no continuation).

        ``k = H_pp - H_pu H_uu^{-1} H_up`` with ``p`` the pole height and ``u`` the
        displacement-control unknowns.
        """
        x = self.cap.x
        H = self._hessian(x)
        Huu = self._sub["displacement"](H)
        col = self._pole_column(H)
        Hup = col[self.idx_displacement]
        Hpp = col[-1]
        y = BandedLU(Huu, HALF_BANDWIDTH, HALF_BANDWIDTH).solve(Hup)
        return float(Hpp - Hup @ y)

    def reissner_stiffness(self) -> float:
        """Reissner's shallow-shell apex stiffness ``8 sqrt(D E h) / R``."""
        return 8.0 * math.sqrt(self.D * self.E * self.h) / self.R

    def __repr__(self) -> str:
        return (f"ShellPointLoad(R={self.R}, E={self.E}, nu={self.nu}, h={self.h}, phi_hat={self.phi_hat}, "
                f"N={self.N}, control={self.control!r}, kappa11_length={self.shell.kappa11_length!r}, "
                f"pole={self.pole!r}, pole_ratio={self.cap.pole_ratio})")
