"""Executors (:mod:`contin.app.executors`): serial, local processes and Dask give the same results.

The serial and process executors are checked on a toy function (numerics, an initializer, an exception,
a worker that dies) and on a small shell sweep through ``contin classify``; the Dask executor the same
way on a local cluster on 127.0.0.1, in tests that are skipped when ``distributed`` is not installed (it
is the optional extra ``dask``, not a test dependency; ``.ci/run`` installs it and makes them required).
"""

from __future__ import annotations

import csv
import multiprocessing
import os
import signal
import subprocess
import sys
import time
from contextlib import closing, contextmanager
from pathlib import Path

import numpy as np
import pytest

from contin.app import cli, executors
from contin.app.executors import (DaskExecutor, ExecutorError, ProcessExecutor, SerialExecutor, WorkerDied,
                              make_executor)

SWEEP = ["classify", "--set", "shell.N=40", "--sweep", "shell.phi_hat=0.8,1.0,1.2,1.3"]
CLASSES = ["bistable", "bistable", "monostable", "monotonous"]


# ---- toy tasks (module level: worker processes import this module to unpickle them) ------------------------
_OFFSET = [0.0]


def _set_offset(value: float) -> None:
    _OFFSET[0] = value


def _failing_init() -> None:
    raise RuntimeError("the model cannot be loaded here")


def _task(item: tuple) -> object:
    kind, x = item
    if kind == "value":  # some floating-point work whose last bits depend on every operation
        rng = np.random.default_rng(x)
        a = rng.standard_normal((30, 30)) + 30 * np.eye(30)
        sol = np.linalg.solve(a, rng.standard_normal(30))
        return x, float(sol @ sol), float(np.linalg.eigvalsh(a + a.T).max())
    if kind == "offset":
        return x + _OFFSET[0]
    if kind == "raise":
        raise ValueError(f"bad item {x}")
    if kind == "sleep":
        time.sleep(x)
        return x
    if kind == "die":
        os._exit(3)  # as a crash in compiled code or the OOM killer
    raise AssertionError(kind)


@contextmanager
def deadline(seconds: int):
    """Fail (instead of hanging) when the block takes longer than ``seconds``."""
    def expired(signum, frame):
        raise TimeoutError(f"still running after {seconds} s")

    old = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


@pytest.fixture(scope="module")
def pool():
    with ProcessExecutor(2) as ex:
        yield ex


def run_cli(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def csv_rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def without_wall_time(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    return [{k: v for k, v in r.items() if k != "wall_time_s"} for r in rows]


@pytest.fixture(scope="module")
def serial_sweep(tmp_path_factory) -> list[dict[str, str]]:
    """The small shell sweep, classified in this process by ``contin classify --workers 1``."""
    path = tmp_path_factory.mktemp("serial") / "serial.csv"
    assert cli.main([*SWEEP, "-q", "--workers", "1", "--csv", str(path)]) == 0
    rows = csv_rows(path)
    assert [r["label"] for r in rows] == CLASSES and all(float(r["wall_time_s"]) > 0 for r in rows)
    return rows


# ---- choosing an executor ---------------------------------------------------------------------------------
def test_make_executor_picks_by_the_options():
    assert isinstance(make_executor(1), SerialExecutor) and make_executor(1).in_process
    with make_executor(3) as ex:
        assert isinstance(ex, ProcessExecutor) and ex.name == "process" and ex.workers == 3 and not ex.in_process
    with make_executor() as ex:  # one per CPU; serial on a single CPU
        assert ex.workers == executors.default_workers()
        assert ex.name == ("serial" if ex.workers == 1 else "process")
    for bad in (0, -2, 1.5, True):
        with pytest.raises(ExecutorError, match="workers must be an integer >= 1"):
            make_executor(bad)
    with pytest.raises(ExecutorError, match="not both"):
        make_executor(2, "tcp://127.0.0.1:8786")


def test_without_dask_a_scheduler_names_the_extra(monkeypatch, tmp_path, capsys):
    """Whether or not dask is installed here: made unimportable, the error names the optional extra."""
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    with pytest.raises(ExecutorError) as info:
        make_executor(scheduler="tcp://127.0.0.1:8786")
    assert "pip install 'contin[dask]'" in str(info.value) and "tcp://127.0.0.1:8786" in str(info.value)
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, *SWEEP, "--scheduler", "tcp://127.0.0.1:8786")
    assert code == 2 and out == "" and "Traceback" not in err
    last = err.splitlines()[-1]
    assert last.startswith("contin: error: --scheduler") and "pip install 'contin[dask]'" in last
    assert list(tmp_path.iterdir()) == []  # refused before the CSV is touched


@pytest.mark.parametrize("args, needles", [
    ([*SWEEP, "--workers", "2", "--scheduler", "tcp://127.0.0.1:8786"], ["--workers 2", "--scheduler", "exclude"]),
    (["classify", "--scheduler", "tcp://127.0.0.1:8786"], ["--scheduler applies only to a sweep"]),
    ([*SWEEP, "--scheduler", " "], ["--scheduler needs the address"]),
])
def test_cli_bad_executor_options_exit_2(tmp_path, capsys, monkeypatch, args, needles):
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli(capsys, *args)
    assert code == 2 and out == "" and err.startswith("contin: error:") and err.count("\n") == 1
    for needle in needles:
        assert needle in err
    assert list(tmp_path.iterdir()) == []


# ---- the same results ---------------------------------------------------------------------------------------
def test_serial_and_process_give_identical_results_on_a_toy_function(pool):
    items = [("value", seed) for seed in range(7)]
    serial = dict(SerialExecutor().map_unordered(_task, items))
    with deadline(120):
        parallel = dict(pool.map_unordered(_task, items))
        ordered = pool.map(_task, items)
    assert sorted(serial) == sorted(parallel) == list(range(7))
    assert [serial[i] for i in range(7)] == [parallel[i] for i in range(7)] == ordered  # bit for bit
    assert [r[0] for r in ordered] == list(range(7))


def test_the_initializer_runs_in_each_worker(pool):
    items = [("offset", float(x)) for x in range(5)]
    with deadline(120):
        got = pool.map(_task, items, initializer=_set_offset, initargs=(0.5,))
    assert got == [0.5, 1.5, 2.5, 3.5, 4.5]
    assert _OFFSET[0] == 0.0  # it ran in the workers, not here
    try:
        assert SerialExecutor().map(_task, items, initializer=_set_offset, initargs=(0.5,)) == got
    finally:
        _OFFSET[0] = 0.0


def test_the_sweep_gives_identical_rows_on_local_processes(serial_sweep, tmp_path, capsys):
    path = tmp_path / "process.csv"
    with deadline(120):
        code, _, err = run_cli(capsys, *SWEEP, "--workers", "2", "--csv", str(path))
    assert code == 0, err
    assert "classifying 4 of 4 combinations on 2 worker processes" in err
    rows = csv_rows(path)
    assert list(rows[0]) == list(serial_sweep[0])  # the same columns, in the same order
    assert without_wall_time(rows) == without_wall_time(serial_sweep)  # every number, character for character


# ---- failures -----------------------------------------------------------------------------------------------
def _children_gone(before: set[int], within: float = 15.0) -> bool:
    """Whether every child process started since ``before`` has ended within ``within`` seconds.

    A stopped worker may take a moment to be reaped on a loaded machine; one still running the
    60 s task would outlive the wait.
    """
    t_end = time.perf_counter() + within
    while time.perf_counter() < t_end:
        if {p.pid for p in multiprocessing.active_children()} <= before:
            return True
        time.sleep(0.1)
    return False


def test_an_exception_in_a_task_is_raised_with_its_type_and_stops_the_rest():
    items = [("sleep", 60), ("raise", 3), ("value", 1)]
    with pytest.raises(ValueError, match="bad item 3"):
        list(SerialExecutor().map_unordered(_task, items[1:]))
    before = {p.pid for p in multiprocessing.active_children()}
    ex = ProcessExecutor(2)
    t0 = time.perf_counter()
    with deadline(50), pytest.raises(ValueError, match="bad item 3"):
        for _ in ex.map_unordered(_task, items):
            pass
    assert time.perf_counter() - t0 < 40  # the 60 s task was not waited for
    # its worker was stopped with the pool
    assert _children_gone(before), {p.pid for p in multiprocessing.active_children()} - before
    ex.close()


def test_an_initializer_that_fails_fails_the_tasks():
    with deadline(120), ProcessExecutor(2) as ex, pytest.raises(RuntimeError, match="cannot be loaded here"):
        ex.map(_task, [("offset", 1.0), ("offset", 2.0)], initializer=_failing_init)


def test_a_worker_that_dies_yields_worker_died_for_its_task_only(pool):
    items = [("value", 1), ("die", 0), ("value", 2), ("value", 3), ("value", 4)]
    with deadline(120):
        got = dict(pool.map_unordered(_task, items))
    assert sorted(got) == [0, 1, 2, 3, 4]
    assert isinstance(got[1], WorkerDied) and "worker process died" in got[1].message
    assert [got[i] for i in (0, 2, 3, 4)] == [_task(items[i]) for i in (0, 2, 3, 4)]
    with deadline(120), pytest.raises(WorkerDied):
        pool.map(_task, [("value", 5), ("die", 0)])
    with deadline(120):  # and the executor goes on working
        assert pool.map(_task, [("value", 6)]) == [_task(("value", 6))]


def test_closing_the_generator_early_stops_the_workers():
    before = {p.pid for p in multiprocessing.active_children()}
    ex = ProcessExecutor(2)
    t0 = time.perf_counter()
    with deadline(50):
        with closing(ex.map_unordered(_task, [("value", 1), ("sleep", 60), ("sleep", 60)])) as results:
            first = next(results)
    assert first[0] in (0, 1, 2) and time.perf_counter() - t0 < 40
    assert _children_gone(before), {p.pid for p in multiprocessing.active_children()} - before
    ex.close()


# ---- one BLAS thread ------------------------------------------------------------------------------------------
_REPORT_THREADS = """
import contextlib, io, os, sys
sys.argv = ["contin", "--help"]
from contin.launch import main
with contextlib.redirect_stdout(io.StringIO()):
    status = main()
print(status, *(os.environ.get(var, "unset") for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")))
"""


@pytest.mark.parametrize("given, expected", [({}, "0 1 1 1"), ({"OPENBLAS_NUM_THREADS": "2"}, "0 2 1 1")])
def test_the_command_runs_blas_on_one_thread_unless_told_otherwise(given, expected):
    """OpenBLAS's threaded inner products on state vectors beyond ten thousand entries cost a trace of a shell
    of 6400 nodes six times its time on a busy 2-core machine: the command sets one thread before numpy loads."""
    env = {k: v for k, v in os.environ.items() if not k.endswith(("_NUM_THREADS", "_MAXIMUM_THREADS"))} | given
    done = subprocess.run([sys.executable, "-c", _REPORT_THREADS], env=env, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[-2] == expected


# ---- Dask (an optional extra: skipped without it) -------------------------------------------------------------
@pytest.fixture(scope="module")
def cluster():
    """A local Dask cluster on 127.0.0.1 with two single-thread worker processes, for the whole module.

    Skipped when ``distributed`` is not installed, unless ``CONTIN_TEST_DASK=required`` (as ``.ci/run``
    sets it): then its absence is a failure.
    """
    if os.environ.get("CONTIN_TEST_DASK") == "required":
        import distributed
    else:
        distributed = pytest.importorskip("distributed")
    import dask

    # one failure makes a task "killed": the dead-worker test does not wait for four restarts
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with distributed.LocalCluster(host="127.0.0.1", n_workers=2, processes=True, threads_per_worker=1,
                                      dashboard_address=None) as local:
            yield local


def test_dask_sweep_gives_the_same_rows_as_serial(cluster, serial_sweep, tmp_path, capsys):
    path = tmp_path / "dask.csv"
    code, _, err = run_cli(capsys, *SWEEP, "--csv", str(path), "--scheduler", cluster.scheduler_address)
    assert code == 0, err
    # the progress lines are wrapped to the terminal's width: joined again on whitespace
    assert f"on the Dask cluster at {cluster.scheduler_address} (2 worker threads)" in " ".join(err.split())
    rows = csv_rows(path)
    assert [r["label"] for r in rows] == CLASSES
    assert list(rows[0]) == list(serial_sweep[0])
    assert without_wall_time(rows) == without_wall_time(serial_sweep)


def test_dask_executor_on_toy_tasks(cluster, pool):
    items = [("value", seed) for seed in range(5)]
    with DaskExecutor(cluster.scheduler_address) as ex:
        assert ex.name == "dask" and ex.workers == 2 and not ex.in_process
        assert ex.map(_task, items) == SerialExecutor().map(_task, items)
        got = ex.map(_task, [("offset", 1.0), ("offset", 2.0)], initializer=_set_offset, initargs=(0.25,))
        assert got == [1.25, 2.25] and _OFFSET[0] == 0.0
        with pytest.raises(ValueError, match="bad item 7"):
            ex.map(_task, [("value", 1), ("raise", 7)])
        died = dict(ex.map_unordered(_task, [("value", 1), ("die", 0)]))
        assert isinstance(died[1], WorkerDied) and died[0] == _task(("value", 1))


def test_dask_unreachable_scheduler_exits_2(cluster, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(executors, "DEFAULT_CONNECT_TIMEOUT", 0.5)
    import socket

    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    for address, needle in ((f"tcp://127.0.0.1:{port}", "cannot reach the Dask scheduler"),
                            ("tcp://", "is not the address of a Dask scheduler")):
        code, out, err = run_cli(capsys, *SWEEP, "--scheduler", address)
        assert code == 2 and out == "" and "Traceback" not in err, err
        last = err.splitlines()[-1]
        assert last.startswith("contin: error: --scheduler") and needle in last
    assert list(tmp_path.iterdir()) == []
