"""Run the 1-D Bratu benchmark on peer continuation packages.

This module is benchmark-only glue: it drives two *peer* packages on the same
problem that ``contin`` solves, so that the three can be compared side by
side.  Neither peer is a dependency of ``contin``; each adapter imports its
peer lazily and reports ``available=False`` (never raises) when the peer is
missing or fails.

Problem
-------
1-D Bratu, ``u'' + lam * exp(u) = 0`` on ``(0, 1)``, ``u(0) = u(1) = 0``,
second-order central differences on ``n`` interior points,
``h = 1 / (n + 1)``::

    (u[i-1] - 2 u[i] + u[i+1]) / h**2 + lam * exp(u[i]) = 0.

Each adapter traces the branch from ``lam = 0, u = 0`` through the fold
(limit point, ``lam ~ 3.5138``) onto the upper branch until
``max(u) >= 4`` and locates the fold value of ``lam`` with the peer's own
machinery.

Peers
-----
``bice``
    PyPI ``bice`` (pure Python, scipy sparse linear algebra).  See
    :func:`run_bice`.
``AUTO-07p``
    Driven through PyPI ``bifpy``, which compiles a vendored AUTO-07p at
    install time (needs ``gfortran``).  See :func:`run_auto`.

Both adapters use the same step-size scale: both peers measure arclength in
the plain Euclidean norm of ``(u, lam)``, which grows like ``sqrt(n)``, so
the initial step is ``0.3 * sqrt(n)`` and the maximum step ``2 * sqrt(n)``
(i.e. about 0.3 and 2 in root-mean-square units of ``u``).

Results
-------
Each adapter returns a dict with ``available`` (bool), ``reason`` (str, empty
on success), ``time_s`` (float, wall time of the run), ``cpu_s``, ``steps``
(int), ``fold_lam`` (float), ``settings`` (str, the peer's settings in
words), ``final_lam``, ``final_max_u`` and ``version``; what ``time_s``,
``cpu_s`` and ``steps`` count is the peer's own (see each adapter).  It never
raises: a missing package or any failure inside the run gives
``available=False`` and the reason (:func:`_unavailable`).

Command line
------------
``python studies/peers.py --n 200 2000 --repeat 3 --peer bice auto`` prints
the median wall time of ``--repeat`` runs for each peer and size (it sets
``OPENBLAS_NUM_THREADS=1`` etc. unless already set, so that the runs are
single-threaded; set it yourself before importing numpy when calling the
functions from your own script).
"""

from __future__ import annotations

import math
import time
from typing import Any

#: The trace stops at the first point with ``max(u) >= MAX_U_TARGET``.
MAX_U_TARGET = 4.0


def _unavailable(reason: str, settings: str = "") -> dict[str, Any]:
    """Build the result dictionary of a peer that could not run.

    Parameters
    ----------
    reason : str
        Why the peer is unavailable or failed.
    settings : str, optional
        The settings that were attempted, if any.

    Returns
    -------
    dict
        ``available=False`` with ``reason``; numeric fields are NaN / 0.
    """
    return {
        "available": False,
        "reason": reason,
        "time_s": float("nan"),
        "steps": 0,
        "fold_lam": float("nan"),
        "settings": settings,
    }


def _as_size(n: Any) -> int | None:
    """Return ``n`` as a positive ``int``, or ``None`` if it is not one.

    Parameters
    ----------
    n : Any
        Candidate grid size (``int`` or any integer type, e.g. numpy's).

    Returns
    -------
    int or None
        The size, or ``None`` for non-integers, booleans and ``n < 1``.
    """
    import operator

    if isinstance(n, bool):
        return None
    try:
        size = operator.index(n)
    except TypeError:
        return None
    return size if size >= 1 else None


def _step_sizes(n: int) -> tuple[float, float]:
    """Return the initial and maximum arclength step used for size ``n``.

    Parameters
    ----------
    n : int
        Number of interior grid points.

    Returns
    -------
    tuple of float
        ``(ds0, ds_max) = (0.3 * sqrt(n), 2 * sqrt(n))``.
    """
    root = math.sqrt(n)
    return 0.3 * root, 2.0 * root


def run_bice(n: int) -> dict[str, Any]:
    """Trace the discrete Bratu branch with ``bice`` and locate the fold.

    The problem is a ``bice.Equation`` with the finite-difference residual and
    its exact sparse (tridiagonal) Jacobian.  ``bice``'s
    ``PseudoArclengthContinuation`` stepper follows the branch; after every
    step the three eigenvalues of the Jacobian nearest zero are computed
    (ARPACK shift-invert, ``bice``'s default eigensolver), and the step where
    the number of positive eigenvalues changes is refined with
    ``Problem.locate_bifurcation`` (bisection on the critical eigenvalue).
    The state is restored afterwards, as ``bice`` does itself with
    ``settings.always_locate_bifurcations``.

    Parameters
    ----------
    n : int
        Number of interior grid points (the size of the ``bice.Equation``).

    Returns
    -------
    dict
        The fields of the module's *Results*: ``time_s`` is this one run
        (problem set-up, trace and fold location; excludes importing
        ``bice``/numpy/scipy), ``cpu_s`` the process CPU time of the same
        interval, ``steps`` the calls to ``Problem.continuation_step`` (the
        bisection sub-steps of the fold location are reported separately in
        ``locate_steps``); plus ``fold_converged`` (bool, whether
        ``locate_bifurcation`` reported convergence) and ``locate_steps``.
    """
    n = _as_size(n)
    if n is None:
        return _unavailable("n must be a positive integer")
    ds0, ds_max = _step_sizes(n)
    newton_tol = 1e-10
    neigs = 3
    locate_tol = 1e-5
    max_steps = 1000
    settings = (
        f"PseudoArclengthContinuation: ds={ds0:.4g} (0.3*sqrt(n)), ds_max={ds_max:.4g} "
        f"(2*sqrt(n)), ds_min=1e-9 (default), convergence_tolerance={newton_tol:g} "
        "(||Newton update||_2 of the bordered system), max_newton_iterations=30, "
        "ndesired_newton_steps=3 (default step control), fd_epsilon=1e-6 for dF/dlam "
        "(F is linear in lam); exact sparse Jacobian, spsolve; "
        f"neigs={neigs} (ARPACK shift-invert at 0, eigensolver tol 1e-8); fold refined with "
        f"locate_bifurcation(tolerance={locate_tol:g}) (bisection, default tolerance); "
        f"stop at max(u) >= {MAX_U_TARGET:g}"
    )
    try:
        import contextlib
        import io
        from importlib import metadata

        import numpy as np
        import scipy.sparse as sp
        from bice import Equation, Problem
    except Exception as exc:  # ImportError, or a broken install
        return _unavailable(f"cannot import bice: {type(exc).__name__}: {exc}", settings)

    try:
        version = metadata.version("bice")
    except Exception:
        version = "unknown"

    class _BratuEquation(Equation):
        """Finite-difference Bratu residual for ``bice``."""

        def __init__(self, size: int) -> None:
            super().__init__(shape=(size,))
            inv_h2 = float(size + 1) ** 2
            off = np.full(size - 1, inv_h2)
            self.laplacian = sp.diags(
                [off, np.full(size, -2.0 * inv_h2), off], [-1, 0, 1], format="csr"
            )
            self.lam = 0.0

        def rhs(self, u):
            return self.laplacian @ u + self.lam * np.exp(u)

        def jacobian(self, u):
            return (self.laplacian + sp.diags(self.lam * np.exp(u))).tocsr()

    class _BratuProblem(Problem):
        """``bice`` problem with ``lam`` as the continuation parameter."""

        def __init__(self, size: int) -> None:
            super().__init__()
            self.bratu = _BratuEquation(size)
            self.add_equation(self.bratu)
            self.continuation_parameter = (self.bratu, "lam")

    log = io.StringIO()  # bice prints warnings/retries to stdout
    try:
        with contextlib.redirect_stdout(log):
            start = time.perf_counter()
            cpu_start = time.process_time()
            problem = _BratuProblem(n)
            stepper = problem.continuation_stepper
            stepper.ds = ds0
            stepper.ds_max = ds_max
            stepper.convergence_tolerance = newton_tol
            stepper.fd_epsilon = 1e-6
            problem.settings.neigs = neigs
            problem.settings.always_locate_bifurcations = False
            steps = 0
            locate_steps = 0
            fold_lam = float("nan")
            fold_converged = False
            while float(np.max(problem.u)) < MAX_U_TARGET and steps < max_steps:
                problem.continuation_step()
                steps += 1
                point = problem.bifurcation_diagram.current_solution()
                if math.isnan(fold_lam) and point.is_bifurcation():
                    u_keep = problem.u.copy()
                    lam_keep = problem.get_continuation_parameter()
                    counter = _CountingStep(stepper)
                    try:
                        fold_converged = bool(problem.locate_bifurcation(tolerance=locate_tol))
                    finally:
                        counter.restore()
                    locate_steps = counter.calls
                    fold_lam = problem.get_continuation_parameter()
                    problem.u = u_keep
                    problem.set_continuation_parameter(lam_keep)
            elapsed = time.perf_counter() - start
            cpu = time.process_time() - cpu_start
    except Exception as exc:
        return _unavailable(f"bice failed: {type(exc).__name__}: {exc}", settings)

    final_max_u = float(np.max(problem.u))
    if final_max_u < MAX_U_TARGET:
        return _unavailable(
            f"bice stopped after {steps} steps at max(u)={final_max_u:.4g} < {MAX_U_TARGET:g}",
            settings,
        )
    if math.isnan(fold_lam):
        return _unavailable("bice detected no fold (no eigenvalue crossed zero)", settings)
    return {
        "available": True,
        "reason": "",
        "time_s": elapsed,
        "cpu_s": cpu,
        "steps": steps,
        "fold_lam": float(fold_lam),
        "settings": settings,
        "fold_converged": fold_converged,
        "locate_steps": locate_steps,
        "final_lam": problem.get_continuation_parameter(),
        "final_max_u": final_max_u,
        "version": version,
    }


class _CountingStep:
    """Count calls of a continuation stepper's ``step`` method.

    Parameters
    ----------
    stepper : object
        An object with a ``step`` method; it is wrapped until
        :meth:`restore` is called.
    """

    def __init__(self, stepper: Any) -> None:
        self.stepper = stepper
        self.calls = 0
        inner = stepper.step

        def counted(*args: Any, **kwargs: Any) -> Any:
            self.calls += 1
            return inner(*args, **kwargs)

        stepper.step = counted

    def restore(self) -> None:
        """Remove the wrapper and restore the stepper's own ``step``."""
        try:
            del self.stepper.step
        except AttributeError:
            pass


def run_auto(n: int) -> dict[str, Any]:
    """Trace the discrete Bratu branch with AUTO-07p (via ``bifpy``).

    The finite-difference system is posed as an AUTO algebraic problem
    (``IPS=0``, ``NDIM=n``) with the exact Jacobian supplied (``JAC=1``,
    dense, as AUTO's algebraic solver requires).  Fold detection is AUTO's
    own (``ILP=1``: sign change of the ``lam`` component of the tangent,
    refined by its secant/Mueller iteration).  A ``PVLS`` callback stores
    ``max(u)`` in ``PAR(2)`` and ``UZSTOP`` ends the run exactly at
    ``max(u) = 4``.  AUTO's output files are written inside a
    :class:`tempfile.TemporaryDirectory` that is removed afterwards.

    Parameters
    ----------
    n : int
        Number of interior grid points (AUTO's ``NDIM``).

    Returns
    -------
    dict
        The fields of the module's *Results*: ``time_s`` is this one
        ``bifpy.auto.run`` call (forking the worker, the AUTO run with its
        Python callbacks, and parsing ``fort.7``/``fort.8``; excludes
        importing ``bifpy`` and compiling AUTO, which happens once at
        ``pip install`` time), ``cpu_s`` the user CPU time of bifpy's worker
        process, ``steps`` the continuation points after the starting point,
        i.e. AUTO's final ``PT`` minus one (includes the ``LP`` and final
        ``UZ`` points, excludes the secant iterations that locate them), and
        ``fold_lam`` as written by AUTO (11 significant digits).

    Notes
    -----
    A missing compiled library is one more way to ``available=False``.  AUTO's algebraic
    solver factors the dense ``(n+1) x (n+1)`` bordered Jacobian by Gauss
    elimination with complete pivoting at every Newton iteration, so the
    cost grows like ``n**3``: expect tens of minutes for ``n = 2000``.
    """
    n = _as_size(n)
    if n is None:
        return _unavailable("n must be a positive integer")
    ds0, ds_max = _step_sizes(n)
    eps = 1e-10
    settings_text = (
        f"IPS=0 (algebraic), NDIM={n}, ICP=[1], JAC=1 (exact dense Jacobian), "
        f"DS={ds0:.4g} (0.3*sqrt(n)), DSMIN=1e-6, DSMAX={ds_max:.4g} (2*sqrt(n)), IADS=1, "
        f"EPSL=EPSU={eps:g} (relative Newton tolerances), EPSS=1e-8, ITNW=7, ITMX=9, "
        "ILP=1 (fold detection), ISP=0, IID=0, NMX=1000; "
        f"PVLS: PAR(2)=max(u), UZSTOP PAR(2)={MAX_U_TARGET:g}"
    )
    try:
        import resource
        import tempfile
        from importlib import metadata

        import numpy as np
        from bifpy import auto
    except Exception as exc:  # ImportError, missing libbifpy, ...
        return _unavailable(f"cannot import bifpy.auto: {type(exc).__name__}: {exc}", settings_text)

    try:
        version = f"bifpy {metadata.version('bifpy')} (AUTO-07p vendored)"
    except Exception:
        version = "unknown"

    inv_h2 = float(n + 1) ** 2
    diag_idx = np.arange(n)

    def func(state, parameters):
        lam = parameters[0]
        residual = -2.0 * state
        residual[1:] += state[:-1]
        residual[:-1] += state[1:]
        return inv_h2 * residual + lam * np.exp(state)

    def jac(state, parameters):
        growth = np.exp(state)
        d_state = np.zeros((n, n))
        d_state[diag_idx, diag_idx] = -2.0 * inv_h2 + parameters[0] * growth
        d_state[diag_idx[1:], diag_idx[:-1]] = inv_h2
        d_state[diag_idx[:-1], diag_idx[1:]] = inv_h2
        return d_state, growth.reshape(n, 1)

    def stpnt(state, parameters, normalized_time):
        state[:] = 0.0
        parameters[0] = 0.0
        parameters[1] = 0.0

    def pvls(state, parameters, extras):
        parameters[1] = float(np.max(state))

    settings = dict(
        ips=auto.IPS_ALGEBRAIC_SYSTEM,
        ndim=n,
        npar=2,
        nmx=1000,
        npr=0,
        ilp=1,
        isp=0,
        iads=1,
        itmx=9,
        itnw=7,
        nwtn=3,
        jac=1,
        iid=0,
        ds=ds0,
        dsmin=1e-6,
        dsmax=ds_max,
        rl0=-1.0,
        rl1=10.0,
        a0=-1e300,
        a1=1e300,
        epsl=eps,
        epsu=eps,
        epss=1e-8,
    )

    saved_tempdir = tempfile.tempdir
    try:
        with tempfile.TemporaryDirectory(prefix="contin-auto-") as workdir:
            # bifpy creates its own AUTO working directory with
            # tempfile.mkdtemp(); point that at our TemporaryDirectory so
            # nothing (not even a failed run's fort.* files) is left behind.
            tempfile.tempdir = workdir
            try:
                cpu_start = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
                start = time.perf_counter()
                result = auto.run(
                    func, stpnt, settings, icu=[1], pvls=pvls, jac=jac, uzstop={2: MAX_U_TARGET}
                )
                elapsed = time.perf_counter() - start
                cpu = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - cpu_start
            finally:
                tempfile.tempdir = saved_tempdir
    except Exception as exc:
        message = str(exc).strip().splitlines()
        head = message[0] if message else ""
        return _unavailable(f"AUTO-07p (bifpy) failed: {type(exc).__name__}: {head}", settings_text)

    try:
        points = [p for branch in result.branches for p in branch.points]
        folds = [p for p in points if p.point_type == auto.PointType.FOLD]
        last = points[-1]
        final_lam = float(last.parameters[0])
        final_max_u = float(last.all_parameters[1]) if last.all_parameters is not None else float("nan")
    except Exception as exc:
        return _unavailable(f"could not read bifpy result: {type(exc).__name__}: {exc}", settings_text)
    if not folds:
        return _unavailable("AUTO-07p reported no fold (LP) point", settings_text)
    if not final_max_u >= MAX_U_TARGET - 1e-6:
        return _unavailable(
            f"AUTO-07p stopped at max(u)={final_max_u:.4g} before reaching {MAX_U_TARGET:g}",
            settings_text,
        )
    return {
        "available": True,
        "reason": "",
        "time_s": elapsed,
        "cpu_s": cpu,
        "steps": int(last.point_number) - 1,
        "fold_lam": float(folds[0].parameters[0]),
        "settings": settings_text,
        "final_lam": final_lam,
        "final_max_u": final_max_u,
        "version": version,
    }


def _main(argv: list[str] | None = None) -> int:
    """Command-line entry point: print median timings per peer and size.

    Parameters
    ----------
    argv : list of str, optional
        Arguments (defaults to ``sys.argv[1:]``).

    Returns
    -------
    int
        Process exit status (0).
    """
    import argparse
    import json
    import statistics

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, nargs="+", default=[200, 2000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--peer", nargs="+", choices=["bice", "auto"], default=["bice", "auto"])
    parser.add_argument("--json", action="store_true", help="also print every run as JSON")
    args = parser.parse_args(argv)
    runners = {"bice": run_bice, "auto": run_auto}
    print(f"{'peer':6s} {'n':>6s} {'median_s':>10s} {'runs_s':>28s} {'steps':>6s} {'fold_lam':>20s}")
    for peer in args.peer:
        for n in args.n:
            runs = []
            for _ in range(args.repeat):
                runs.append(runners[peer](n))
                if args.json:
                    print(json.dumps(runs[-1]), flush=True)
            ok = [r for r in runs if r["available"]]
            if not ok:
                print(f"{peer:6s} {n:6d} unavailable: {runs[0]['reason']}")
                continue
            times = [r["time_s"] for r in ok]
            times_text = ",".join(f"{t:.3f}" for t in times)
            print(
                f"{peer:6s} {n:6d} {statistics.median(times):10.3f} {times_text:>28s} "
                f"{ok[0]['steps']:6d} {ok[0]['fold_lam']:20.13f}",
                flush=True,
            )
    return 0


if __name__ == "__main__":
    import os

    # Benchmark on one core: a multi-threaded OpenBLAS (numpy/scipy wheels)
    # slows bice's ARPACK calls badly when the other core is busy.  Must be
    # set before numpy is first imported.
    for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_var, "1")
    from studies._common import run_study

    raise SystemExit(run_study(_main))
