"""Jumps (snaps): from an unstable point or a fold to the stable state at the same load.

At the start the state is perturbed along the eigenvector of the smallest Hessian eigenvalue, on the
side that lowers the energy.  Then the energy is minimised at fixed parameter by Newton's method with
the exact Hessian, made globally convergent by a Levenberg shift (``H + mu I`` positive definite,
tested by a Cholesky factorization) and an Armijo backtracking line search on the energy.  The jump
succeeds when the gradient meets the tolerance and the stability operator is positive definite.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..numerics.linalg import ArrowCholesky, ArrowParts, arrow_structure, bandwidths, upper_band
from ..numerics.stability import stability_info
from ..problem import NonFiniteError, Problem
from ..results.branch import BranchFileError, SpecialPoint
from ..results.io import json_ready, read_bundle, write_bundle

__all__ = ["state_scale", "JumpResult", "jump", "JumpError"]


class JumpError(RuntimeError):
    """A jump cannot start (e.g. the point is stable) or did not land on a stable state."""


@dataclass
class JumpResult:
    """Outcome of :func:`jump`.

    Attributes
    ----------
    p : float
        The (fixed) parameter.
    u_from, u_to : ndarray
        Start state and landing state.
    energy_from, energy_to : float
        Energies at start and landing.
    iterations : int
        Minimisation iterations.
    residual : float
        Max-norm gradient at the landing state.
    n_negative : int
        Negative eigenvalues of the stability operator at landing (0 on success).
    smallest_eigenvalue : float
        Smallest eigenvalue at landing.
    success : bool
    message : str
    """

    p: float
    u_from: np.ndarray
    u_to: np.ndarray
    energy_from: float
    energy_to: float
    iterations: int
    residual: float
    n_negative: int
    smallest_eigenvalue: float
    success: bool
    message: str
    info: dict[str, Any] = field(default_factory=dict)

    # ---- persistence -----------------------------------------------------------------------------
    def save(self, path: Any) -> Any:
        """Write the jump to ``path`` (``.npz``, atomically); :meth:`load` reads it back identical."""
        header, arrays = self.to_bundle()
        return write_bundle(path, "contin-jump", header, arrays)

    @classmethod
    def load(cls, path: Any) -> "JumpResult":
        """Load a jump written by :meth:`save`; raises :class:`contin.BranchFileError` if it is corrupt."""
        header, arrays = read_bundle(path, "contin-jump", BranchFileError)
        return cls.from_bundle(header, arrays, where=str(path))

    def to_bundle(self, prefix: str = "") -> tuple[dict[str, Any], dict[str, np.ndarray]]:
        """The jump as a JSON header and its two states (array names start with ``prefix``)."""
        header = {"p": float(self.p), "energy_from": float(self.energy_from), "energy_to": float(self.energy_to),
                  "iterations": int(self.iterations), "residual": float(self.residual),
                  "n_negative": int(self.n_negative), "smallest_eigenvalue": float(self.smallest_eigenvalue),
                  "success": bool(self.success), "message": self.message,
                  "info": json_ready(self.info, keep_nonfinite=True)}
        return header, {prefix + "u_from": np.asarray(self.u_from), prefix + "u_to": np.asarray(self.u_to)}

    @classmethod
    def from_bundle(cls, header: dict[str, Any], arrays: dict[str, np.ndarray], prefix: str = "",
                    where: str = "bundle") -> "JumpResult":
        """The jump stored by :meth:`to_bundle`; raises :class:`contin.BranchFileError` naming ``where``."""
        try:
            return cls(u_from=arrays[prefix + "u_from"], u_to=arrays[prefix + "u_to"],
                       **{k: header[k] for k in ("p", "energy_from", "energy_to", "iterations", "residual",
                                                 "n_negative", "smallest_eigenvalue", "success", "message",
                                                 "info")})
        except Exception as exc:
            raise BranchFileError(f"{where}: inconsistent jump data ({type(exc).__name__}: {exc})") from None

    def special_points(self, problem: Problem | None = None) -> tuple[SpecialPoint, SpecialPoint]:
        """The jump as two special points: ``label="jump_from"`` and ``label="jump_to"``."""
        obs_from = problem.evaluate_observables(self.u_from, self.p) if problem else {}
        obs_to = problem.evaluate_observables(self.u_to, self.p) if problem else {}
        a = SpecialPoint("jump", self.p, self.u_from, obs_from, residual=float("nan"), located=True,
                         label="jump_from", info={"energy": self.energy_from})
        b = SpecialPoint("jump", self.p, self.u_to, obs_to, residual=self.residual, located=self.success,
                         label="jump_to", info={"energy": self.energy_to, "n_negative": self.n_negative,
                                                "smallest_eigenvalue": self.smallest_eigenvalue})
        return a, b


def state_scale(u: np.ndarray, reference: tuple[float, float] | None = None) -> float:
    """The size of a state, ``max|u|`` (1 for a zero state): the unit of kicks and landing distances.

    No absolute floor: a model in millimetres and the same model in metres get the same kicks in
    their own units.  A state at roundoff next to the problem's own state scale (``reference``, its
    :attr:`contin.Problem.reference_scales`: a symmetric state whose unknowns measure departures
    from symmetry, such as the homogeneous state of a chain in mode coordinates) has that scale.
    """
    size = float(np.max(np.abs(np.asarray(u, dtype=float)), initial=0.0))
    if reference is not None and math.isfinite(reference[0]) and size < 1e-8 * reference[0]:
        return float(reference[0])
    return size or 1.0


def _shifted_cholesky_solver(H, mu: float):
    """Return ``solve(b)`` for ``H + mu I`` if it is positive definite, else ``None``."""
    n = H.shape[0]
    kl, ku = bandwidths(H)
    b = max(kl, ku)
    try:
        if n > 400 and b + 1 <= 0.1 * n:
            # the upper band: its positions are computed once per pattern of a model's Hessians
            ab = upper_band(sp.csr_matrix(H), b)
            ab[b] += mu
            c = sla.cholesky_banded(ab, lower=False)
            return lambda rhs: sla.cho_solve_banded((c, False), rhs)
        arrow = arrow_structure(H) if n > 64 else None
        if arrow is not None:  # a band with a few dense border rows (an indenter's travel under a dead load)
            return ArrowCholesky(ArrowParts(H, *arrow), mu).solve
        A = H.toarray() if sp.issparse(H) else np.array(H, dtype=float)
        A[np.diag_indices(n)] += mu
        c = sla.cho_factor(A, lower=True)
        return lambda rhs: sla.cho_solve(c, rhs)
    except (np.linalg.LinAlgError, ValueError):
        return None


def _safe_energy(problem: Problem, u, p) -> float:
    with np.errstate(all="ignore"):
        try:
            e = problem.energy(u, p)
        except (NonFiniteError, FloatingPointError, ValueError):
            return math.inf
    return e if np.isfinite(e) else math.inf


def _kick_inside(problem: Problem, u: np.ndarray, p: float, kick: np.ndarray) -> np.ndarray | None:
    """The kick, shortened to half the way to the model's domain boundary if it would leave it.

    A stiff contact barrier with a short range (e.g. ``dhat`` of 1e-5 R) puts the boundary much
    closer than the default kick sizes; a kick that crossed it would count as an infinite energy in
    both directions and no snap could start.  None when no positive fraction of the kick is allowed.
    """
    fraction = problem.max_step_fraction(u, p, kick, 0.0)
    if fraction >= 1.0:
        return kick
    if not fraction > 0.0:
        return None
    return 0.5 * fraction * kick


def jump(problem: Problem, u, p: float, *, perturbation: float | None = None, tol: float = 1e-10,
         max_iter: int = 500, eig_tol: float = 1e-8, direction: np.ndarray | None = None,
         scale: float | None = None) -> JumpResult:
    """Snap from an unstable point or a fold to a stable equilibrium at the same parameter.

    Parameters
    ----------
    problem : Problem
        A conservative problem (``energy`` and a symmetric Jacobian).
    u, p : the starting state (unstable, or at a fold) and the fixed parameter.
    perturbation : float, optional
        Size of the initial kick along the unstable eigenvector (max-norm); by default the smallest
        of 1e-3, 1e-2, 1e-1 times the state's scale ``max|u|`` (1 for a zero state) that lowers
        the energy by more than ``1e-12 |E(u)|``: both are independent of the model's units.
    tol : float
        Relative gradient tolerance (times ``problem.residual_scale``).
    max_iter : int
        Maximum minimisation iterations.
    eig_tol : float
        A start is accepted as a fold when its smallest eigenvalue is below ``eig_tol`` times the
        Hessian's largest entry.
    direction : ndarray, optional
        Kick direction to use instead of the unstable eigenvector.
    scale : float, optional
        The state's scale for the default kicks (default :func:`state_scale` of ``u``); a model
        whose state has a natural length (a radius) passes it.

    Returns
    -------
    JumpResult
        ``success`` True when the landing state is converged and stable.

    Raises
    ------
    JumpError
        If the problem has no energy or the start is a stable, non-degenerate state.
    """
    if not problem.has_energy or not problem.symmetric:
        raise JumpError(f"jump needs a conservative problem (energy and symmetric Hessian); {problem.name!r} is not")
    u0 = np.array(u, dtype=float)
    p = float(p)
    abs_tol = tol * getattr(problem, "residual_scale", 1.0)
    start = _start(problem, u0, p, abs_tol, perturbation, eig_tol, direction, scale)
    x, it, res, success, message = _descend(problem, start, p, abs_tol, max_iter)
    final = stability_info(problem.stability_operator(x, p), k=1)
    return JumpResult(p=p, u_from=u0, u_to=x, energy_from=start.E0, energy_to=_safe_energy(problem, x, p),
                      iterations=it, residual=res, n_negative=final.n_negative,
                      smallest_eigenvalue=float(final.eigenvalues[0]),
                      success=success and final.n_negative == 0, message=message,
                      info={"kick": float(np.max(np.abs(x - u0)))})


@dataclass
class _Start:
    """The first iterate of a snap and the scales of its start."""

    x: np.ndarray
    E0: float
    scale_H: float
    ref: float


def _start(problem: Problem, u0: np.ndarray, p: float, abs_tol: float, perturbation: float | None,
           eig_tol: float, direction: np.ndarray | None, scale: float | None = None) -> _Start:
    """Kick the start off along its unstable (or given) direction, the smallest kick that lowers the energy.

    A stable Hessian is a snap start only if the state is out of equilibrium: a fold state with the
    parameter moved past the fold (where no equilibrium is near) minimises as it is.
    """
    H0 = problem.stability_operator(u0, p)
    info0 = stability_info(H0, k=1, vectors=True)
    scale_H = float(np.max(np.abs(H0.data if sp.issparse(H0) else H0), initial=1.0))
    lam0 = float(info0.eigenvalues[0])
    E0 = _safe_energy(problem, u0, p)
    ref = state_scale(u0, problem.reference_scales) if scale is None else float(scale)
    x = None
    if info0.n_negative == 0 and lam0 > eig_tol * scale_H:
        if float(np.max(np.abs(problem.checked_residual(u0, p)))) <= abs_tol:
            raise JumpError(f"the start is stable (smallest eigenvalue {lam0:.3e} > 0): nothing to snap from")
        x = u0.copy()
    v = np.asarray(direction, dtype=float) if direction is not None else info0.eigenvectors[:, 0]
    v = v / np.max(np.abs(v))
    if x is not None:
        sizes = []
    else:
        sizes = [perturbation] if perturbation is not None else [1e-3 * ref, 1e-2 * ref, 1e-1 * ref]
    climbing: list[tuple[np.ndarray, float]] = []
    for alpha in sizes:
        kicks = [_kick_inside(problem, u0, p, sign * alpha * v) for sign in (1.0, -1.0)]
        trials = [(u0 + kick, _safe_energy(problem, u0 + kick, p)) for kick in kicks if kick is not None]
        if trials:
            y, e = min(trials, key=lambda trial: trial[1])
            if e < E0 - 1e-12 * abs(E0):
                x = y
                break
            climbing += trials
    if x is None and float(np.max(np.abs(problem.checked_residual(u0, p)))) > abs_tol:
        # no kick along the soft mode lowers the energy measurably (a stiff, short-range barrier
        # leaves room only for kicks far below round-off of the energy), but the start is out of
        # equilibrium: the shifted-Newton descent leaves it without a kick
        x = u0.copy()
    if x is None:
        # every straight kick climbs and the start is in equilibrium: the soft mode's valley may bend
        # away from the straight line, so the kicks are bent back into it, smallest first
        for y, e in climbing:
            bent = _relaxed_across(problem, y, p, v, e)
            if bent is not None and bent[1] < E0 - 1e-12 * abs(E0):
                x = bent[0]
                break
    if x is None:
        raise JumpError("no perturbation along the unstable eigenvector lowers the energy")
    return _Start(x, E0, scale_H, ref)


def _descend(problem: Problem, start: _Start, p: float, abs_tol: float,
             max_iter: int) -> tuple[np.ndarray, int, float, bool, str]:
    """Shifted-Newton energy descent at fixed ``p`` to a stable state: ``(x, iterations, residual, success, message)``.

    A converged saddle is kicked off along its unstable direction and the descent continues.
    """
    x, mu, it = start.x, 0.0, 0
    E = _safe_energy(problem, x, p)
    res = math.inf
    for it in range(1, max_iter + 1):
        g = problem.checked_residual(x, p)
        res = float(np.max(np.abs(g)))
        H = problem.checked_jacobian(x, p)
        if res <= abs_tol:
            if stability_info(problem.stability_operator(x, p), k=0).n_negative == 0:
                return x, it, res, True, f"landed on a stable state after {it - 1} iterations"
            x = _kick_off_saddle(problem, x, p, start.ref)
            E = _safe_energy(problem, x, p)
            continue
        was_shifted = mu > 0.0
        d, mu = _shifted_newton_direction(H, g, mu, start.scale_H)
        step = _line_search(problem, x, p, d, g, E, res)
        if mu > 0.0 and not was_shifted:
            # the Hessian is indefinite here: on a ridge (the gradient nearly orthogonal to the
            # negative curvature) the shifted-Newton step leaves it only by a factor 1 + |lambda| / mu
            # per iteration, which crawls when |lambda| is far below the shift; a step along the
            # negative curvature leaves at once
            curved = _negative_curvature_step(problem, x, p, g, E, start.ref)
            if curved is not None and (step is None or curved[2] < step[2]):
                step = curved
        if step is None:
            return x, it, res, False, "line search failed to lower the energy"
        t, x, E = step
        mu = 0.0 if t == 1.0 else max(mu * 4, 1e-8 * start.scale_H)
    return x, it, res, False, f"no stable state within {max_iter} iterations (gradient {res:.3e})"


def _kick_off_saddle(problem: Problem, x: np.ndarray, p: float, ref: float) -> np.ndarray:
    """A small kick (1e-3 of the state's scale) along the unstable direction of a converged saddle."""
    vec = stability_info(problem.stability_operator(x, p), k=1, vectors=True).eigenvectors[:, 0]
    kick = 1e-3 * ref * vec / np.max(np.abs(vec))
    return x + min(1.0, problem.max_step_fraction(x, p, kick, 0.0)) * kick


#: Sizes of a step along negative curvature, in units of the state's scale.
CURVATURE_STEPS = (1e-3, 1e-2, 1e-1)
#: Smaller sizes, tried when none of :data:`CURVATURE_STEPS` lowers the energy: where the negative
#: eigenvalue is tiny the higher-order terms of the energy outweigh it already at 1e-3 of the scale,
#: and the descent would otherwise crawl off the saddle (the plate under a dead load: 1155 iterations
#: for its two snaps, 194 with these).
SMALL_CURVATURE_STEPS = (1e-4, 1e-5, 1e-6)


def _negative_curvature_step(problem: Problem, x: np.ndarray, p: float, g: np.ndarray, E: float,
                             ref: float) -> tuple[float, np.ndarray, float] | None:
    """The best of :data:`CURVATURE_STEPS` (else of the same relaxed by :func:`_relaxed_across`, else of
    :data:`SMALL_CURVATURE_STEPS`) along the unstable eigenvector, downhill: ``(1, x_new, E_new)``.

    The sign makes the step a descent direction to first order (either sign when the gradient is
    orthogonal to it); None when the stability operator has no negative eigenvalue or no step
    lowers the energy.
    """
    info = stability_info(problem.stability_operator(x, p), k=1, vectors=True)
    if info.n_negative == 0:
        return None
    v = info.eigenvectors[:, 0]
    v = v / np.max(np.abs(v))
    slope = float(g @ v)
    signs = (-1.0,) if slope > 0 else (1.0,) if slope < 0 else (1.0, -1.0)
    # straight steps first; where they all climb, the same steps bent back into the valley, and only
    # then the small straight ones (a valley that bends a short way off admits only those)
    for sizes, relax in ((CURVATURE_STEPS, False), (CURVATURE_STEPS, True), (SMALL_CURVATURE_STEPS, False)):
        best = None
        for size in sizes:
            for sign in signs:
                d = sign * size * ref * v
                y = x + min(1.0, problem.max_step_fraction(x, p, d, 0.0)) * d
                e = _safe_energy(problem, y, p)
                if relax:
                    y, e = _relaxed_across(problem, y, p, v, e) or (y, e)
                if e < E and (best is None or e < best[2]):
                    best = (1.0, y, e)
        if best is not None:
            return best
    return None


#: Shifted-Newton steps that bring a step along the unstable eigenvector back into a bent valley.
RELAX_STEPS = 3


def _relaxed_across(problem: Problem, y: np.ndarray, p: float, v: np.ndarray,
                    E_y: float) -> tuple[np.ndarray, float] | None:
    """``y`` moved to lower energy across the direction ``v``, with its component along ``v`` kept: ``(y, E)``.

    A straight step along the unstable eigenvector leaves the valley it points along when the valley
    bends (a thin structure's soft mode turns into stretching a short way off): there the energy
    rises on the straight line while it falls along the bent valley.  Up to :data:`RELAX_STEPS`
    shifted-Newton steps of the energy restricted to the hyperplane ``v . dy = 0``, each with a
    backtracking search, bring the step back into the valley.  None when the first of them does not
    lower the energy.
    """
    relaxed = None
    for _ in range(RELAX_STEPS):
        try:
            g = problem.checked_residual(y, p)
            H = problem.checked_jacobian(y, p)
        except (NonFiniteError, FloatingPointError, ValueError):
            break
        scale_H = float(np.max(np.abs(H.data if sp.issparse(H) else H), initial=1.0))
        _, mu = _shifted_newton_direction(H, g, 0.0, scale_H)
        solve = _shifted_cholesky_solver(H, mu)
        if solve is None:
            break
        a, b = solve(g), solve(v)
        # (H + mu I) dy + lam v = -g with v . dy = 0
        dy = -a + (float(v @ a) / float(v @ b)) * b
        t = min(1.0, problem.max_step_fraction(y, p, dy, 0.0))
        while t > 1e-3:
            z = y + t * dy
            e = _safe_energy(problem, z, p)
            if e < E_y:
                break
            t *= 0.5
        else:
            break
        y, E_y = z, e
        relaxed = (y, E_y)
    return relaxed


def _shifted_newton_direction(H: Any, g: np.ndarray, mu: float, scale_H: float) -> tuple[np.ndarray, float]:
    """Descent direction ``-(H + mu I)^-1 g`` with the Levenberg shift: the smallest ``mu >= 0`` tried
    (doubling from ``1e-8 * scale_H``) that makes ``H + mu I`` positive definite.  Returns it and ``mu``."""
    solve = _shifted_cholesky_solver(H, 0.0) if mu == 0.0 else None
    trial_mu = mu
    while solve is None:
        trial_mu = max(2 * trial_mu, 1e-8 * scale_H) if trial_mu > 0 else 1e-8 * scale_H
        solve = _shifted_cholesky_solver(H, trial_mu)
        if trial_mu > 1e12 * scale_H:
            raise JumpError("could not make the Hessian positive definite by a shift")
    return -solve(g), trial_mu


def _line_search(problem: Problem, x: np.ndarray, p: float, d: np.ndarray, g: np.ndarray, E: float,
                 res: float) -> tuple[float, np.ndarray, float] | None:
    """Backtracking (Armijo) along ``d`` inside the model's domain: ``(t, x + t d, energy)`` or None."""
    slope = float(g @ d)
    t = min(1.0, problem.max_step_fraction(x, p, d, 0.0))
    while t > 1e-12:
        x_new = x + t * d
        E_new = _safe_energy(problem, x_new, p)
        if E_new <= E + 1e-4 * t * slope:
            return t, x_new, E_new
        # a full Newton step that barely changes the energy near the minimum is fine if the
        # gradient drops (the energy difference is below roundoff there)
        if abs(E_new - E) <= 1e-14 * max(abs(E), abs(E_new)):
            if np.max(np.abs(problem.checked_residual(x_new, p))) < res:
                return t, x_new, E_new
        t *= 0.5
    return None
