"""Checks of a model's derivatives against its own residual: :func:`check_problem`.

A model whose Jacobian or ``df/dp`` disagrees with its residual does not fail loudly: the corrector
converges slowly or not at all, the steps shrink to ``ds_min``, and the tangent points off the curve
so that folds are missed.  These checks compare every derivative the engine uses with central finite
differences of the function it is the derivative of:

* the Jacobian along a few random directions and along its *soft* direction (two inverse
  iterations: the direction of its smallest eigenvalue, where a few percent of error changes the
  tangent and the fold most; a random direction hardly sees it);
* ``df/dp`` (a wrong sign or a missing factor is named);
* the first tangent, ``J t_u + f_p t_p = 0``: the residual must not change to first order along it;
* the residual against the gradient of the energy, when the model has one;
* symmetry of the Jacobian when ``problem.symmetric``;
* ``jacobian_directional_derivative`` when the model overrides it.

Directions are measured in the start point's own scales (:func:`contin.path.scales.start_scales`), so the
finite-difference steps are relative to ``|u|`` and ``|p|`` and the checks pass for a correct model in
any units.  Each comparison is tried with two step sizes and keeps the better one: a correct
derivative agrees at one of them (truncation error at the larger, rounding at the smaller), a wrong
one at neither.

:func:`quick_check` is the part :func:`contin.continuation` runs before its first step (two probes:
the tangent and one random direction, four residuals and two matrix-vector products); when it fails,
the full check says which derivative is wrong.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..numerics.linalg import SingularMatrixError
from ..path.curve import roundoff_floor
from ..path.scales import start_scales
from ..problem import NonFiniteError, Problem

__all__ = ["CheckResult", "CheckReport", "ModelCheckError", "check_problem", "quick_check", "FD_TOL"]

#: Relative disagreement between a derivative and its finite difference that fails a check.  A
#: correct derivative agrees to about 1e-6 or better at one of the steps tried; an error of a
#: few percent (a Jacobian 5 % off in one direction) is five times above this.
FD_TOL = 1e-2
#: Relative asymmetry ``|w.Jv - v.Jw| / (|w| |Jv| + |v| |Jw|)`` that fails the symmetry check.
SYMMETRY_TOL = 1e-8
#: Finite-difference steps tried, relative to the start point's scales (central differences), in
#: turn until one agrees.  The largest is for stiff models whose residual's rounding noise swamps the
#: smaller ones (the point-loaded cap in displacement form at N = 200 from rest: 1.8 % at the best
#: of 1e-5 and 1e-7 along its tangent, 2e-4 at 1e-3).  The smallest is for a residual that curves
#: sharply on the start point's scales: a log barrier whose contact lies a small fraction of its range
#: from the indenter, where the central difference's truncation error falls as the step squared and
#: is still a few percent at 1e-7 (a sphere pressing a thin cap after a snap: 2.4 % at the best of the
#: three larger steps, about 1e-5 at 1e-9 along random directions).
FD_STEPS = (1e-5, 1e-7, 1e-3, 1e-9)


class ModelCheckError(ValueError):
    """A model's derivatives disagree with its residual; ``report`` holds every check."""

    def __init__(self, report: CheckReport) -> None:
        super().__init__(str(report))
        self.report = report


@dataclass
class CheckResult:
    """One comparison.

    Attributes
    ----------
    name : what was checked (``"jacobian"``, ``"jacobian (soft direction)"``, ``"df/dp"``, ``"tangent"``,
        ``"energy gradient"``, ``"symmetry"``, ``"jacobian_directional_derivative"``).
    error : measured relative error.
    tol : the tolerance it was held to.
    passed : ``error <= tol``.
    message : a sentence saying what agrees, or which derivative is wrong and how.
    """

    name: str
    error: float
    tol: float
    passed: bool
    message: str


@dataclass
class CheckReport:
    """The results of :func:`check_problem` or :func:`quick_check` at one point."""

    problem: str
    p: float
    results: list[CheckResult] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """All checks passed."""
        return all(r.passed for r in self.results)

    @property
    def failures(self) -> list[CheckResult]:
        """The checks that failed."""
        return [r for r in self.results if not r.passed]

    def summary(self) -> str:
        """One sentence: the failures' messages, or that everything agrees."""
        if self.ok:
            return f"the derivatives of {self.problem!r} agree with its residual at p = {self.p:.6g}"
        return f"model check of {self.problem!r} at p = {self.p:.6g}: " + "; ".join(r.message for r in self.failures)

    def raise_if_failed(self) -> CheckReport:
        """Raise :class:`ModelCheckError` when a check failed; return the report otherwise."""
        if not self.ok:
            raise ModelCheckError(self)
        return self

    def __str__(self) -> str:
        lines = [self.summary()]
        lines += [f"  {'ok  ' if r.passed else 'FAIL'} {r.name}: error {r.error:.2e} (tol {r.tol:.0e}) - {r.message}"
                  for r in self.results]
        return "\n".join(lines)


class _Probe:
    """Central finite differences of a model at one point, in the point's own scales."""

    def __init__(self, problem: Problem, u: np.ndarray, p: float, J: Any, fp: np.ndarray, U: float, P: float) -> None:
        self.problem, self.u, self.p, self.J, self.fp, self.U, self.P = problem, u, p, J, fp, U, P
        # derivative values below this are rounding noise of the residual divided by the step
        self.floor = 10.0 * roundoff_floor(J, fp, u, p)

    def measured_noise(self, du: np.ndarray, dp: float) -> float:
        """The residual's rounding noise along ``(du, dp)``, measured: ``||(f(x + d) - f(x - d)) / 2 - J_x d||``
        for ``d`` of 1e-10 of the point's scales along it (central, so no second-order part is left);
        a central difference at step ``h`` carries about this noise over ``h``.

        A stiff model's residual is a sum of large terms, e.g. the reference coordinates that a model
        in displacement form adds back, which ``u`` does not show: at rest (``u = 0``) an estimate
        from ``|u|`` is zero, while the point-loaded cap at N = 800 has a noise of 2e-5 of its load
        vector along a random direction.  Along ``p`` alone a linear load has none (the internal
        terms cancel).
        """
        t = self.step(du, dp, 1e-10)
        try:
            f_plus = self.problem.checked_residual(self.u + t * du, self.p + t * dp)
            f_minus = self.problem.checked_residual(self.u - t * du, self.p - t * dp)
        except (NonFiniteError, FloatingPointError, ValueError):
            return 0.0
        linear = np.asarray(self.J @ du, dtype=float).ravel() + self.fp * dp
        return _norm(0.5 * (f_plus - f_minus) - t * linear)

    def step(self, du: np.ndarray, dp: float, rel: float) -> float:
        """Step along ``(du, dp)`` that moves the point by ``rel`` of its scales (inside the model's domain)."""
        size = max(float(np.max(np.abs(du), initial=0.0)) / self.U, abs(dp) / self.P)
        h = rel / size if size > 0 else rel
        for sign in (1.0, -1.0):
            h *= min(1.0, self.problem.max_step_fraction(self.u, self.p, sign * h * du, sign * h * dp))
        return h

    def residual_rate(self, du: np.ndarray, dp: float, rel: float) -> tuple[np.ndarray, float] | None:
        """Central difference of the residual along ``(du, dp)`` and its rounding-noise level.

        The step is halved while the residual is not finite at its ends (a model whose domain ends
        closer than its step filter says, e.g. a contact barrier touching at the start); None when
        no step of at least a thousandth of the one asked for is inside.
        """
        h = self.step(du, dp, rel)
        for _ in range(10):
            try:
                f_plus = self.problem.checked_residual(self.u + h * du, self.p + h * dp)
                f_minus = self.problem.checked_residual(self.u - h * du, self.p - h * dp)
                return (f_plus - f_minus) / (2.0 * h), self.floor / h
            except (NonFiniteError, FloatingPointError, ValueError):
                h *= 0.5
        return None

    def compare(self, du: np.ndarray, dp: float, predicted: np.ndarray,
                reference: float | None = None) -> tuple[float, np.ndarray]:
        """Smallest relative error of ``predicted`` against the residual's rate over the steps tried.

        ``reference`` is the size the error is relative to (default: the larger of the two vectors);
        a comparison whose sizes are below rounding noise measures nothing and counts as 0.
        """
        best, best_fd = math.inf, predicted
        f_noise = self.measured_noise(du, dp)
        for rel in FD_STEPS:
            rate = self.residual_rate(du, dp, rel)
            if rate is None:
                continue
            fd, noise = rate
            measured = f_noise / self.step(du, dp, rel)
            scale = reference if reference is not None else max(_norm(fd), _norm(predicted))
            err = 0.0 if scale <= noise * math.sqrt(max(fd.size, 1)) else _norm(fd - predicted) / scale
            # a step agrees, or it disagrees by more than twice its measured rounding noise, or its
            # noise could hide half the tolerance and it decides nothing
            allowance = 2.0 * measured / scale if scale > 0 else 0.0
            if err > FD_TOL and allowance > 0.5 * FD_TOL:
                continue
            err = err if err <= FD_TOL else err - allowance
            if err < best:
                best, best_fd = err, fd
            if best <= FD_TOL:
                break
        # no step inside the model's domain, or none above its noise: nothing measurable, which is
        # not a failure
        return (0.0 if best == math.inf else best), best_fd


def _norm(x: np.ndarray) -> float:
    return float(np.linalg.norm(x))


def _cos(a: np.ndarray, b: np.ndarray) -> float:
    na, nb = _norm(a), _norm(b)
    return float(np.dot(a, b) / (na * nb)) if na > 0 and nb > 0 else 1.0


def _result(name: str, err: float, tol: float, ok_text: str, fail_text: str) -> CheckResult:
    passed = err <= tol
    return CheckResult(name, float(err), tol, passed, ok_text if passed else fail_text)


def _jacobian_check(probe: _Probe, v: np.ndarray, name: str, where: str) -> CheckResult:
    Jv = np.asarray(probe.J @ v, dtype=float).ravel()
    err, fd = probe.compare(v, 0.0, Jv)
    if _cos(fd, Jv) < -0.99:
        why = f"the Jacobian has the wrong sign (J v is minus the finite difference of the residual {where})"
    elif where.startswith("along its soft"):
        why = (f"the Jacobian is wrong in its soft direction: J v differs from the finite difference of the "
               f"residual by {err:.1%} {where}, where an error changes the tangent and the folds most")
    else:
        why = f"the Jacobian differs from the finite difference of the residual by {err:.1%} {where}"
    return _result(name, err, FD_TOL, f"J v agrees with the residual {where}", why)


def _dfdp_check(probe: _Probe) -> CheckResult:
    fp = probe.fp
    err, fd = probe.compare(np.zeros_like(probe.u), 1.0, fp)
    if _cos(fd, fp) < -0.99:
        why = "df/dp has the wrong sign (it is minus the finite difference of the residual in p)"
    elif _cos(fd, fp) > 0.99 and _norm(fd) > 0:
        why = (f"df/dp is {_norm(fp) / _norm(fd):.4g} times the finite difference of the residual in p "
               "(a missing or extra factor)")
    else:
        why = f"df/dp differs from the finite difference of the residual in p by {err:.1%}"
    return _result("df/dp", err, FD_TOL, "df/dp agrees with the residual", why)


def _tangent_check(probe: _Probe, t_u: np.ndarray, t_p: float) -> CheckResult:
    """The residual must not change to first order along the tangent computed from ``J`` and ``df/dp``."""
    Jt = np.asarray(probe.J @ t_u, dtype=float).ravel()
    fpt = probe.fp * t_p
    predicted = Jt + fpt
    # relative to the rates that cancel along the tangent: a wrong fp or J leaves a fraction of them
    reference = max(_norm(Jt), _norm(fpt))
    err, _ = probe.compare(t_u, t_p, predicted, reference=reference)
    return _result("tangent", err, FD_TOL, "the residual stays zero to first order along the tangent",
                   f"the residual changes along the tangent computed from the Jacobian and df/dp by {err:.1%} of "
                   "the rates that should cancel: the Jacobian or df/dp disagrees with the residual")


def _energy_check(probe: _Probe, rng: np.random.Generator) -> CheckResult:
    """``dE/du . v`` by central differences of the energy against ``f . v``, away from equilibrium.

    At an equilibrium ``f = 0`` and the comparison would measure noise, so the point is first moved
    by 1 % of its scale in a random direction.
    """
    problem, U = probe.problem, probe.U
    z = rng.standard_normal(probe.u.size)
    shift = 0.01 * U * z / max(_norm(z) / math.sqrt(z.size), 1e-300)
    shift *= min(1.0, problem.max_step_fraction(probe.u, probe.p, shift, 0.0))
    u1 = probe.u + shift
    f1 = problem.residual(u1, probe.p)
    v = rng.standard_normal(u1.size)
    # the energy's rounding noise here, measured as for the residual (_Probe.measured_noise)
    tiny = 1e-10 * U / max(float(np.max(np.abs(v))), 1e-300)
    noise = abs(0.5 * (problem.energy(u1 + tiny * v, probe.p) - problem.energy(u1 - tiny * v, probe.p))
                - tiny * float(np.dot(f1, v)))
    best, ratio = math.inf, 1.0
    # (the random shift makes a stiff model's energy strongly curved: the point-loaded cap at N = 800
    # from rest agrees to 1.3 % at 1e-6 and to 4e-6 at 1e-8)
    for rel in (1e-4, 1e-6, 1e-8):
        h = rel * U / max(float(np.max(np.abs(v))), 1e-300)
        for sign in (1.0, -1.0):
            h *= min(1.0, problem.max_step_fraction(u1, probe.p, sign * h * v, 0.0))
        dE = (problem.energy(u1 + h * v, probe.p) - problem.energy(u1 - h * v, probe.p)) / (2.0 * h)
        fv = float(np.dot(f1, v))
        scale = max(abs(dE), abs(fv))
        # as for the residual (_Probe.compare): a step agrees, or disagrees beyond its noise, or
        # decides nothing
        err = 0.0 if scale == 0.0 else abs(dE - fv) / scale
        allowance = 2.0 * noise / h / scale if scale > 0 else 0.0
        if err > FD_TOL and allowance > 0.5 * FD_TOL:
            continue
        err = err if err <= FD_TOL else err - allowance
        if err < best:
            best, ratio = err, (fv / dE if dE != 0 else math.inf)
        if best <= FD_TOL:
            break
    if best == math.inf:  # every step below its noise: nothing measurable, which is not a failure
        best = 0.0
    if abs(ratio + 1.0) < 0.05:
        why = "the residual is minus the gradient of the energy (the energy or the residual has the wrong sign)"
    else:
        why = f"the residual is not the gradient of the energy (they differ by {best:.1%} along a random direction)"
    return _result("energy gradient", best, FD_TOL, "the residual is the gradient of the energy", why)


def _symmetry_check(probe: _Probe, rng: np.random.Generator) -> CheckResult:
    v, w = rng.standard_normal(probe.u.size), rng.standard_normal(probe.u.size)
    Jv, Jw = np.asarray(probe.J @ v).ravel(), np.asarray(probe.J @ w).ravel()
    scale = _norm(w) * _norm(Jv) + _norm(v) * _norm(Jw)
    err = 0.0 if scale == 0.0 else abs(float(np.dot(w, Jv) - np.dot(v, Jw))) / scale
    return _result("symmetry", err, SYMMETRY_TOL, "the Jacobian is symmetric",
                   f"the problem is declared symmetric but its Jacobian is not (w.Jv - v.Jw is {err:.1e} of their size)")


def _second_derivative_check(probe: _Probe, rng: np.random.Generator) -> CheckResult:
    """An overridden ``jacobian_directional_derivative`` against central differences of the Jacobian."""
    problem, u, p = probe.problem, probe.u, probe.p
    v, w = rng.standard_normal(u.size), rng.standard_normal(u.size)
    exact = np.asarray(problem.jacobian_directional_derivative(u, p, v) @ w, dtype=float).ravel()
    best = math.inf
    for rel in (1e-4, 1e-6):
        h = probe.step(v, 0.0, rel)
        fd = np.asarray((problem.jacobian(u + h * v, p) - problem.jacobian(u - h * v, p)) @ w, dtype=float).ravel() / (2 * h)
        scale = max(_norm(fd), _norm(exact))
        best = min(best, 0.0 if scale == 0.0 else _norm(fd - exact) / scale)
        if best <= FD_TOL:
            break
    return _result("jacobian_directional_derivative", best, FD_TOL,
                   "jacobian_directional_derivative agrees with the Jacobian",
                   f"jacobian_directional_derivative differs from the finite difference of the Jacobian by {best:.1%}")


def _random_direction(rng: np.random.Generator, n: int) -> np.ndarray:
    return rng.standard_normal(n)


def _soft_direction(F: Any, rng: np.random.Generator, n: int) -> np.ndarray | None:
    """Two inverse iterations from a random vector: mostly the eigenvector of the smallest eigenvalue."""
    if F is None:
        return None
    try:
        v = rng.standard_normal(n)
        for _ in range(2):
            v = np.asarray(F.solve(v), dtype=float)
            v /= max(float(np.max(np.abs(v))), 1e-300)
    except (SingularMatrixError, np.linalg.LinAlgError, ValueError):
        return None
    return v if np.isfinite(v).all() else None


def _prepare(problem: Problem, u, p: float) -> tuple[np.ndarray, float, Any, np.ndarray, Any, float, float]:
    u = np.asarray(u, dtype=float).ravel()
    p = float(p)
    J = problem.jacobian(u, p)
    fp = np.asarray(problem.dresidual_dp(u, p), dtype=float)
    try:
        F = problem.factorize(J)
    except (SingularMatrixError, np.linalg.LinAlgError, RuntimeError):
        F = None
    U, P = start_scales(u, p, fp, F, getattr(problem, "reference_scales", None))
    return u, p, J, fp, F, U, P


def check_problem(problem: Problem, u, p: float, *, n_directions: int = 3, seed: int = 0,
                  raise_on_failure: bool = False, scales: tuple[float, float] | None = None) -> CheckReport:
    """Compare a model's derivatives with finite differences of its residual (and energy) at ``(u, p)``.

    Parameters
    ----------
    problem : Problem
    u, p : the point (it need not be an equilibrium).
    n_directions : int
        Random directions the Jacobian is probed along (besides its soft direction); the cost is two
        residuals per direction, never ``n`` columns.
    seed : int
        Seed of the random directions (the report is reproducible).
    raise_on_failure : bool
        Raise :class:`ModelCheckError` when a check fails.
    scales : (float, float), optional
        The sizes ``(U, P)`` of the state and the parameter the probes are measured in (default:
        :func:`contin.path.scales.start_scales` of the point).

    Returns
    -------
    CheckReport
        Per check the measured relative error, the tolerance, pass or fail, and a sentence saying
        which derivative is wrong and how (e.g. "df/dp has the wrong sign").
    """
    u, p, J, fp, F, U, P = _prepare(problem, u, p)
    if scales is not None:
        U, P = (float(x) for x in scales)
    probe = _Probe(problem, u, p, J, fp, U, P)
    rng = np.random.default_rng(seed)
    report = CheckReport(problem.name, p)
    for k in range(n_directions):
        v = U * _random_direction(rng, u.size)
        report.results.append(_jacobian_check(probe, v, f"jacobian (random direction {k + 1})",
                                              "along a random direction"))
    soft = _soft_direction(F, rng, u.size)
    if soft is not None:
        report.results.append(_jacobian_check(probe, soft, "jacobian (soft direction)",
                                              "along its soft direction (smallest eigenvalue)"))
    report.results.append(_dfdp_check(probe))
    if F is not None:
        try:
            t_u = -np.asarray(F.solve(fp), dtype=float)
            report.results.append(_tangent_check(probe, t_u, 1.0))
        except (SingularMatrixError, np.linalg.LinAlgError, ValueError):
            pass
    optional = [(getattr(problem, "has_energy", False), _energy_check),
                (problem.symmetric, _symmetry_check),
                (type(problem).jacobian_directional_derivative is not Problem.jacobian_directional_derivative,
                 _second_derivative_check)]
    for wanted, check in optional:
        if wanted:
            try:
                report.results.append(check(probe, rng))
            except (NonFiniteError, FloatingPointError):
                pass  # the probe left the model's domain: this check measures nothing here
    return report.raise_if_failed() if raise_on_failure else report


def quick_check(problem: Problem, u: np.ndarray, p: float, J: Any, fp: np.ndarray, t_u: np.ndarray, t_p: float,
                U: float, P: float, seed: int = 0) -> CheckReport:
    """The cheap check :func:`contin.continuation` runs at its start: the tangent and one random direction.

    Costs four residuals and two products with the Jacobian already assembled at the start point.
    When a probe fails, :func:`check_problem` runs and its failures replace the probes' (they say
    which derivative is wrong).
    """
    probe = _Probe(problem, u, p, J, fp, U, P)
    rng = np.random.default_rng(seed)
    report = CheckReport(problem.name, p, [
        _tangent_check(probe, t_u, t_p),
        _jacobian_check(probe, U * _random_direction(rng, u.size), "jacobian", "along a random direction")])
    if report.ok:
        return report
    full = check_problem(problem, u, p, seed=seed)
    if full.ok:
        return report
    # the start's scales can be degenerate: an unloaded state that is zero up to roundoff measures
    # the probes in units of that roundoff; a wrong derivative is wrong in the user's units too
    if check_problem(problem, u, p, seed=seed, scales=(1.0, 1.0)).ok:
        return CheckReport(problem.name, p)
    return full
