"""Benchmark: energy, gradient and Hessian assembly of the discrete shell (the model's hot path).

Run ``python -m studies.bench_shell_assembly [--N 200 2000 20000] [--repeat 7]
[--kappa11-length current|reference] [--json PATH]``.

What is measured (wall time per call, one process, BLAS single-threaded): for every ``N`` a
:class:`contin_models.shell.ShellEnergy` (default scene: ``R = 1``, ``E = 1e6``, ``nu = 0.5``,
``h = 0.02``, ``phi_hat = 0.8``, ``kappa11_length`` as given, default ``"current"``) is evaluated at
a deformed full state (the reference state plus a random perturbation of 1e-3 times the edge
length, plus a pole indentation of ``0.05 R`` spread smoothly over the cap), and

* ``energy``, ``gradient``, ``hessian``: :meth:`ShellEnergy.energy` / ``gradient`` / ``hessian``;
* ``e+g+H``: the sum of the three medians;
* ``residual``, ``jacobian``: :meth:`ShellPointLoad.residual` / ``jacobian`` (displacement control,
  mirror pole), i.e. what the continuation engine calls, with the pole element and the extraction
  of the free dofs.  The problem caches its last gradient and last few Hessians: the benchmark
  cycles through :data:`N_STATES` states so that every call recomputes them.

Each figure is the median over ``--repeat`` repeats of the mean over a timeit-style loop (the loop
count chosen by :meth:`timeit.Timer.autorange`, i.e. at least 0.2 s per repeat).  The table also
gives the time per node, which is constant when the cost is linear in ``N``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import timeit  # noqa: E402

import numpy as np  # noqa: E402

from contin_models.shell import ShellEnergy, ShellPointLoad, spherical_cap  # noqa: E402
from studies._common import write_text  # noqa: E402

SCENE = dict(R=1.0, E=1e6, nu=0.5, h=0.02, phi_hat=0.8)
QUANTITIES = ("energy", "gradient", "hessian", "e+g+H", "residual", "jacobian")
N_STATES = 7
"""States cycled through for the ShellPointLoad calls (more than its caches hold)."""


def deformed_state(cap, seed: int = 0) -> np.ndarray:
    """A smooth indentation of the pole plus a small random perturbation (full 2N state)."""
    rng = np.random.default_rng(seed)
    x = cap.x
    t = np.linspace(0.0, 1.0, cap.N)
    x[1::2] -= 0.05 * cap.R * t**2  # pushes the pole down by 0.05 R, the base not at all
    x += 1e-3 * float(cap.edge_length.min()) * rng.uniform(-1.0, 1.0, x.size)
    return x


def time_call(fn, repeat: int) -> float:
    """Median over ``repeat`` repeats of the per-call time (s), loop count from autorange."""
    timer = timeit.Timer(fn)
    number, _ = timer.autorange()
    return statistics.median(t / number for t in timer.repeat(repeat=repeat, number=number))


def measure(N: int, repeat: int, kappa11_length: str = "current") -> dict[str, float]:
    """Per-call medians (s) of every quantity of :data:`QUANTITIES` at ``N`` nodes."""
    cap = spherical_cap(SCENE["R"], SCENE["phi_hat"], N)
    s = ShellEnergy(cap, SCENE["E"], SCENE["h"], SCENE["nu"], kappa11_length=kappa11_length)
    x = deformed_state(cap)
    out = {
        "energy": time_call(lambda: s.energy(x), repeat),
        "gradient": time_call(lambda: s.gradient(x), repeat),
        "hessian": time_call(lambda: s.hessian(x), repeat),
    }
    out["e+g+H"] = out["energy"] + out["gradient"] + out["hessian"]

    P = ShellPointLoad(N=N, control="displacement", kappa11_length=kappa11_length, pole="mirror", **SCENE)
    p = 0.05 * P.R
    states = [P.unknowns(deformed_state(cap, seed)) for seed in range(1, N_STATES + 1)]

    def cycling(method):
        k = [0]

        def call():
            k[0] = (k[0] + 1) % N_STATES
            return method(states[k[0]], p)
        return call

    out["residual"] = time_call(cycling(P.residual), repeat)
    out["jacobian"] = time_call(cycling(P.jacobian), repeat)
    return out


def table(results: dict[int, dict[str, float]]) -> str:
    """Plain-text table: per-call median (ms) and per node (us / node) for every N."""
    lines = [f"{'N':>7}  {'quantity':<9} {'median':>11} {'per node':>13}"]
    for N, res in results.items():
        for q in QUANTITIES:
            lines.append(f"{N:>7}  {q:<9} {res[q] * 1e3:>8.4f} ms {res[q] / N * 1e6:>8.4f} us/N")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m studies.bench_shell_assembly",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--N", type=int, nargs="+", default=[200, 2000, 20000], help="numbers of nodes")
    parser.add_argument("--repeat", type=int, default=7, help="repeats per figure (median)")
    parser.add_argument("--kappa11-length", choices=("current", "reference"), default="current")
    parser.add_argument("--json", type=str, default=None, help="also write the results here")
    args = parser.parse_args(argv)

    results = {N: measure(N, args.repeat, args.kappa11_length) for N in args.N}
    print(f"shell assembly, kappa11_length={args.kappa11_length!r}, median of {args.repeat} repeats "
          f"(OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')})")
    print(table(results))
    if args.json:
        payload = {
            "scene": SCENE, "kappa11_length": args.kappa11_length, "repeat": args.repeat,
            "unit": "seconds per call (median)",
            "python": sys.version.split()[0], "numpy": np.__version__, "machine": platform.machine(),
            "results": {str(N): res for N, res in results.items()},
        }
        write_text(args.json, json.dumps(payload, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    from studies._common import run_study

    raise SystemExit(run_study(main))
