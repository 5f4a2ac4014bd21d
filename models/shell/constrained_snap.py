"""Snaps under a prescribed volume: the descent in the energy on the constraint.

Under a prescribed displacement that is the work-conjugate of a load (a volume change under a pressure,
:class:`contin.ConjugateControl` of the pressure-controlled problem) the load is a Lagrange multiplier and the
problem's Lagrangian is a saddle in it, so :func:`contin.jump`, a descent in the energy, does not apply.  Where the
shell snaps at the prescribed volume it goes to a minimum of the elastic energy ``E0(u)`` on the constraint
``c(u) + q = 0`` (``c = dE/dp``, the load entering the energy linearly: ``E(u, p) = E0(u) + p c(u)``).
:func:`jump_on_constraint` descends to one:

* each iterate lies on the constraints: a trial state is brought back onto them along ``(H + mu I)^-1 B`` (``B``
  the constraints' gradients, ``a = dc/du`` first; ``H`` the Hessian: the way the state moves under a change of the
  load, which costs least energy; along ``a`` itself the stiff membrane would pay for it), by Newton's iteration
  on the constraints;
* the step is Newton's on the constraints, ``[[H + mu I, B], [B^T, 0]] [d; dl] = [-f; 0]`` (``f`` the gradient of
  the Lagrangian at the least-squares multipliers), by block elimination on the base's own banded factorization of
  ``H + mu I`` (O(N) per solve, the dense border never formed); the shift ``mu`` is raised until ``H + mu I`` is
  positive on the constraints' tangent space (its count from the inertia of ``H + mu I`` and of the Schur
  complement ``-B^T (H + mu I)^-1 B``: Sylvester's law) and a backtracking search on ``E0`` accepts the step;
* it starts by a kick along the given direction (the mode of the bifurcation snapped from), or along the lowest
  eigenvector of the Hessian on the tangent space (inverse iteration on the banded factorization), on the side and of the smallest
  size that lowers ``E0``; a converged saddle is kicked off the same way.  A kick is relaxed before it is judged:
  ``E0`` minimised on the constraint with the kick's amplitude held (a second constraint), since a straight kick
  along a mode at a finite amplitude stretches the membrane at second order and climbs where the valley it
  starts bends away from the straight line;
* it lands where the gradient on the constraint meets the tolerance and the state is stable under the prescribed
  displacement (the constrained count of :class:`contin.ConjugateControl`'s primary label).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import scipy.sparse as sp

from contin.analyses.conjugate import ConjugateControl
from contin.analyses.jump import JumpError, JumpResult, state_scale
from contin.numerics.stability import stability_info

__all__ = ["jump_on_constraint"]

#: Relative kicks tried at the start, smallest first (times the state's scale).
KICKS = (1e-3, 1e-2, 1e-1)
#: Steps of the scalar Newton iteration that brings a state back onto the constraint, and its relative tolerance.
RESTORE_STEPS, RESTORE_TOL = 30, 1e-13
#: Relative fall of the energy a kick must bring to be taken at once; below it (beside a singular point, where the
#: curvature along the kick is as small as the distance past the point) the kick that lowers the energy most is taken,
#: so that the descent does not start where the energy is flat to roundoff.
KICK_GAIN = 1e-9
#: Halvings of a step in the backtracking search.
BACKTRACKS = 40


def jump_on_constraint(problem: ConjugateControl, U: np.ndarray, q: float, *, direction: np.ndarray | None = None,
                       tol: float = 1e-10, max_iter: int = 500) -> JumpResult:
    """Snap from ``U`` (an unstable state or a fold of ``problem``) to a stable state at the prescribed ``q``.

    Parameters
    ----------
    problem : contin.ConjugateControl
        A linear one (``linear=True``: the load enters the base's energy linearly) whose base factorizes its own
        Hessian (``factorize``).
    U : ndarray
        The start, in ``problem``'s unknowns (its multiplier is re-estimated).
    q : float
        The prescribed displacement held during the descent.
    direction : ndarray, optional
        The first kick's direction in ``problem``'s unknowns (its multiplier entry is ignored); default the lowest
        eigenvector of the Hessian on the constraint's tangent space.
    tol : float
        Relative tolerance of the gradient on the constraint (times ``problem.residual_scale``).
    max_iter : int
        Newton iterations at most.

    Returns
    -------
    contin.JumpResult
        ``p`` is ``q``; ``u_from`` and ``u_to`` in ``problem``'s unknowns; the energies are the elastic energy
        ``E0`` (the Lagrangian on the constraint); ``success`` where the landing is converged and stable.

    Raises
    ------
    contin.JumpError
        The problem's load does not enter linearly, or no kick lowers the energy on the constraint.
    """
    if not problem.linear:
        raise JumpError("jump_on_constraint: the load must enter the energy linearly (ConjugateControl(linear=True))")
    U0 = np.asarray(U, dtype=float)
    x0, _ = problem.split(U0)
    ms = _OnConstraint(problem, float(q), tol * problem.residual_scale)
    ref = state_scale(x0, problem.base.reference_scales)
    e_from = ms.energy(x0)
    x = ms.restore(x0.copy(), ms.load_directions(x0))
    if x is None:
        raise JumpError(f"jump_on_constraint: the start does not reach the constraint {problem.displacement_name} = {q!r}")
    v = (np.asarray(direction, dtype=float)[:-1] if direction is not None
         else _lowest_on_tangent(problem.base.factorize, problem.base.jacobian(x, ms.gradient(x)[1][0]),
                               ms.border(x)[:, 0]))
    y = ms.kick(x, v, ref)
    if y is None and float(np.max(np.abs(ms.gradient(x)[0]))) <= ms.abs_tol:
        raise JumpError("jump_on_constraint: no kick along the unstable direction lowers the energy on the constraint")
    x, it, res, landed, message = ms.descend(x if y is None else y, max_iter, ref)
    p = float(ms.gradient(x)[1][0])
    n_negative = ms.count(x, p)
    return JumpResult(p=float(q), u_from=U0, u_to=problem.join(x, p), energy_from=e_from, energy_to=ms.energy(x),
                      iterations=it, residual=res, n_negative=n_negative, smallest_eigenvalue=math.nan,
                      success=landed and n_negative == 0, message=message,
                      info={"kick": float(np.max(np.abs(x - x0)))})


class _OnConstraint:
    """The descent in ``E0`` on ``c(u) + q = 0`` and, while a kick is relaxed, on ``v . u = t`` too."""

    def __init__(self, problem: ConjugateControl, q: float, abs_tol: float,
                 held: tuple[np.ndarray, float] | None = None) -> None:
        self.problem, self.base, self.q, self.abs_tol, self.held = problem, problem.base, q, abs_tol, held
        self.size = max(abs(q), 1e-300)

    def with_held(self, v: np.ndarray, t: float) -> "_OnConstraint":
        return _OnConstraint(self.problem, self.q, self.abs_tol, (v, t))

    def energy(self, x: np.ndarray) -> float:
        with np.errstate(all="ignore"):
            e = float(self.base.energy(x, 0.0))
        return e if math.isfinite(e) else math.inf

    def gap(self, x: np.ndarray) -> np.ndarray:
        g = [float(self.base.conjugate_force(x, 0.0)) + self.q]
        if self.held is not None:
            g.append(float(self.held[0] @ x) - self.held[1])
        return np.array(g)

    def border(self, x: np.ndarray) -> np.ndarray:
        a = np.asarray(self.base.dresidual_dp(x, 0.0), dtype=float)
        return a[:, None] if self.held is None else np.column_stack([a, self.held[0]])

    def restore(self, x: np.ndarray, W: np.ndarray) -> np.ndarray | None:
        """``x`` moved in the span of ``W`` onto the constraints (None: it does not get there)."""
        scales = np.array([self.size] + ([max(abs(self.held[1]), float(np.max(np.abs(self.held[0]))) * self.size)]
                                         if self.held is not None else []))
        for _ in range(RESTORE_STEPS):
            g = self.gap(x)
            if not np.all(np.isfinite(g)):
                return None
            if np.all(np.abs(g) <= RESTORE_TOL * scales):
                return x
            try:
                x = x - W @ np.linalg.solve(self.border(x).T @ W, g)
            except np.linalg.LinAlgError:
                return None
        return None

    def gradient(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The Lagrangian's gradient at the least-squares multipliers (the load first), and them."""
        f0, B = np.asarray(self.base.residual(x, 0.0), dtype=float), self.border(x)
        lam = np.linalg.lstsq(B, -f0, rcond=None)[0]
        return f0 + B @ lam, lam

    def count(self, x: np.ndarray, p: float) -> int:
        """Negative eigenvalues of the Hessian on the volume constraint's tangent space: ``problem``'s primary count."""
        return int(self.problem.stability(self.problem.join(x, p), self.q)[self.problem.labels[0]].n_negative)

    def load_directions(self, x: np.ndarray) -> np.ndarray:
        """``H^-1 B`` (shifted where ``H`` is singular): how the state follows a change of the multipliers."""
        H = self.base.jacobian(x, float(self.gradient(x)[1][0]))
        return _shifted_step(self.base.factorize, H, self.border(x), np.zeros(H.shape[0]), 0.0,
                             float(np.max(np.abs(H.diagonal()))) or 1.0, count=False)[2]

    def kick(self, x: np.ndarray, v: np.ndarray, ref: float) -> np.ndarray | None:
        """The smallest kick along ``+-v``, relaxed on the constraint with its amplitude held, that lowers ``E0`` by
        :data:`KICK_GAIN`, else the one that lowers it most (None: none lowers it)."""
        e0 = self.energy(x)
        best = None
        v = v - self.border(x)[:, 0] * (float(self.border(x)[:, 0] @ v) / float(self.border(x)[:, 0] @ self.border(x)[:, 0]))
        v = v / float(np.linalg.norm(v))
        amplitude = ref / float(np.max(np.abs(v)))
        for size in KICKS:
            trials = []
            for sign in (1.0, -1.0):
                held = self.with_held(v, float(v @ x) + sign * size * amplitude)
                y = held.restore(x + sign * size * amplitude * v, held.load_directions(x))
                if y is not None:
                    y = held.descend(y, RELAX_STEPS, ref, relax=True)[0]
                    trials.append(y)
            if trials:
                y = min(trials, key=self.energy)
                if self.energy(y) < e0 - KICK_GAIN * abs(e0):
                    return y
                if self.energy(y) < e0 - 1e-12 * abs(e0) and (best is None or self.energy(y) < self.energy(best)):
                    best = y
        return best

    def descend(self, x: np.ndarray, max_iter: int, ref: float,
                relax: bool = False) -> tuple[np.ndarray, int, float, bool, str]:
        """Shifted Newton on the constraints to a stable state (with ``relax``: to ``max_iter`` steps or a stationary
        state): ``(x, iterations, residual, landed, message)``."""
        mu, it, res, moved, polished = 0.0, 0, math.inf, math.inf, 0
        for it in range(1, max_iter + 1):
            f, lam = self.gradient(x)
            res = float(np.max(np.abs(f)))
            H = self.base.jacobian(x, float(lam[0]))
            # beside a singular point (a snap just past a pitchfork) a small gradient leaves the soft mode's amplitude
            # far from its root: the state counts as converged once Newton's steps are small too, or after a few
            # steps within the tolerance (on a singular point itself they shrink only linearly)
            polished = polished + 1 if res <= self.abs_tol else 0
            if res <= self.abs_tol and (relax or moved <= STEP_TOL * ref or polished > POLISH_STEPS):
                if relax:
                    return x, it, res, True, "stationary"
                if self.count(x, float(lam[0])) == 0:
                    return (x, it, res, True, f"landed on a stable state at the prescribed "
                            f"{self.problem.displacement_name} after {it - 1} iterations")
                # a saddle on the constraint: off along its unstable side
                y = self.kick(x, _lowest_on_tangent(self.base.factorize, H, self.border(x)[:, 0]), ref)
                if y is None:
                    return x, it, res, False, "converged to a saddle on the constraint that no kick leaves"
                x = y
                continue
            scale_H = float(np.max(np.abs(H.diagonal()))) or 1.0
            d, mu, W = _shifted_step(self.base.factorize, H, self.border(x), f, mu, scale_H)
            e, t, step = self.energy(x), 1.0, None
            for _ in range(BACKTRACKS):
                y = self.restore(x + t * d, W)
                if y is not None and self.energy(y) < e - 1e-4 * t * abs(float(f @ d)):
                    step = y
                    break
                t *= 0.5
            if step is None:
                # the energy at its roundoff near a minimum: a full step is taken where it lowers the gradient
                y = self.restore(x + d, W)
                if y is not None and float(np.max(np.abs(self.gradient(y)[0]))) < res:
                    step, t = y, 1.0
            if step is None and res <= self.abs_tol:
                moved = 0.0  # the gradient at its roundoff: no step lowers the energy measurably
                continue
            if step is None:
                if relax:
                    return x, it, res, False, "the relaxation stalled"
                return (x, it, res, False,
                        f"the search along the step on the constraint failed to lower the energy (gradient {res:.3e})")
            moved, x = float(np.max(np.abs(step - x))), step
            mu = 0.0 if t == 1.0 else max(4.0 * mu, 1e-8 * scale_H)
        return x, it, res, False, f"no stable state within {max_iter} iterations (gradient {res:.3e})"


#: Relative size of the last Newton step below which a state whose gradient meets the tolerance has converged.
STEP_TOL = 1e-9
#: Newton steps taken within the gradient's tolerance, at most, before a state counts as converged.
POLISH_STEPS = 40
#: Inverse of the least singular value of the constraints' Schur complement, relative to its columns' sizes, taken.
S_CONDITION = 1e8
#: Newton steps that relax a kick with its amplitude held, at most.
RELAX_STEPS = 30


def _shifted_step(factorize: Callable, H: sp.spmatrix, B: np.ndarray, f: np.ndarray, mu: float,
                  scale_H: float, count: bool = True) -> tuple[np.ndarray, float, np.ndarray]:
    """Newton's step on the tangent space of the constraints with gradients ``B`` (``n x k``), ``H + mu I`` positive
    there (``mu`` raised until it is), the shift, and ``Y = (H + mu I)^-1 B``.

    With ``z = (H + mu I)^-1 f`` and ``S = B^T Y`` the step is ``d = -z + Y S^-1 B^T z`` (``B^T d = 0``); the tangent
    space's count is that of ``H + mu I`` plus that of ``-S``, minus ``k``.  Without ``count`` any regular
    ``H + mu I`` is taken."""
    n, k = H.shape[0], B.shape[1]
    for _ in range(200):
        Hs = H + mu * sp.identity(n, format="csr") if mu > 0.0 else H
        negative = stability_info(Hs, 0).n_negative if count else 0
        try:
            lu = factorize(Hs)
            Y = np.column_stack([lu.solve(B[:, j]) for j in range(k)])
            z = lu.solve(f)
            S = B.T @ Y
            # S relative to its columns' sizes: at a fold in the prescribed displacement the load's direction
            # (H^-1 a) is tangent to the constraint (a.y = 0), a shift turns it off the tangent
            scale = np.sqrt(np.outer(*(2 * [np.linalg.norm(B, axis=0) * np.linalg.norm(Y, axis=0)])))
            if np.all(np.isfinite(Y)) and np.all(np.isfinite(z)) and np.linalg.svd(S / scale, compute_uv=False).min() > 1.0 / S_CONDITION:
                tangent = negative + int(np.count_nonzero(np.linalg.eigvalsh(-0.5 * (S + S.T)) < 0.0)) - k
                if not count or tangent == 0:
                    return -z + Y @ np.linalg.solve(S, B.T @ z), mu, Y
        except (np.linalg.LinAlgError, ValueError, ArithmeticError):
            pass
        mu = max(4.0 * mu, 1e-8 * scale_H)
    raise JumpError("jump_on_constraint: no shift makes the Hessian positive on the constraint's tangent space")


def _lowest_on_tangent(factorize: Callable, H: sp.spmatrix, a: np.ndarray) -> np.ndarray:
    """The lowest eigenvector of ``H`` on the tangent space ``a.v = 0``: inverse iteration with the constraint, each
    step ``w = z - (a.z / a.y) y`` with ``z = (H - s I)^-1 v`` and ``y = (H - s I)^-1 a`` on the banded factorization,
    the shift ``s`` just below zero (the lowest eigenvalue at a fold or a branch point is about zero, at a saddle
    below it)."""
    n = H.shape[0]
    sigma = -SHIFT * (float(np.max(np.abs(H.diagonal()))) or 1.0)
    lu = factorize(H - sigma * sp.identity(n, format="csr"))
    y = lu.solve(a)
    v = np.random.default_rng(0).standard_normal(n)
    for _ in range(INVERSE_STEPS):
        v = v - (float(a @ v) / float(a @ a)) * a
        v = v / float(np.linalg.norm(v))
        z = lu.solve(v)
        w = z - (float(a @ z) / float(a @ y)) * y
        w = w / float(np.linalg.norm(w))
        if abs(abs(float(w @ v)) - 1.0) < 1e-12:
            return w
        v = w
    return v


#: Relative shift below zero of the inverse iteration for the lowest mode on the constraint, and its steps at most.
SHIFT = 1e-6
INVERSE_STEPS = 50
