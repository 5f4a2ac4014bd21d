"""The one atomic-write helper and the output directory of :mod:`contin.results.io` (issue 14, A5 and B4)."""

from __future__ import annotations

import ast
import math
import os
import stat
from pathlib import Path

import numpy as np
import pytest

import contin
from contin.results.io import OutputDirectory, OutputError, atomic_write, json_ready, output_directory

ROOT = Path(__file__).resolve().parents[1]


def test_a_group_is_all_or_nothing(tmp_path: Path) -> None:
    (tmp_path / "a.txt").write_text("old a")

    def broken(fh: object) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write([(tmp_path / "a.txt", lambda fh: fh.write("new a")), (tmp_path / "b.bin", broken, True)])
    assert (tmp_path / "a.txt").read_text() == "old a"  # not replaced: the group did not complete
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]  # and no temporary file is left

    written = atomic_write([(tmp_path / "a.txt", lambda fh: fh.write("new a")),
                            (tmp_path / "b.bin", lambda fh: fh.write(b"\x00\x01"), True)])
    assert written == [tmp_path / "a.txt", tmp_path / "b.bin"]
    assert (tmp_path / "a.txt").read_text() == "new a" and (tmp_path / "b.bin").read_bytes() == b"\x00\x01"


def test_permissions_are_a_new_files_or_kept(tmp_path: Path) -> None:
    path = tmp_path / "f.csv"
    atomic_write([(path, lambda fh: fh.write("x"))])
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o666 & ~umask
    path.chmod(0o600)
    atomic_write([(path, lambda fh: fh.write("y"))], keep_mode=True)
    assert stat.S_IMODE(path.stat().st_mode) == 0o600 and path.read_text() == "y"


def test_a_branch_saves_through_the_helper(tmp_path: Path) -> None:
    br = contin.Branch(p=np.array([0.0, 1.0]), u=np.zeros((2, 1)), s=np.array([0.0, 1.0]), tangent_p=np.ones(2),
                       residual=np.zeros(2), newton_iterations=np.zeros(2, dtype=int), status="bound", message="m")
    path = br.save(tmp_path / "sub" / "b")
    assert path == tmp_path / "sub" / "b.npz" and [p.name for p in path.parent.iterdir()] == ["b.npz"]
    assert contin.Branch.load(path).status == "bound"


@pytest.mark.slow
def test_one_atomic_write_in_the_tree() -> None:
    # mkstemp + os.replace is the atomic write: it lives in contin/results/io.py only
    found = []
    for folder in ("contin", "models", "studies"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            tree = ast.parse(path.read_text())
            calls = {node.func.attr for node in ast.walk(tree)
                     if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)}
            if {"mkstemp", "replace"} <= calls:
                found.append(str(path.relative_to(ROOT)))
    assert found == ["contin/results/io.py"]


def test_json_ready() -> None:
    doc = {"a": np.float32(1.5), "b": [np.int64(2), np.bool_(True)], "c": (np.inf, -np.nan), 4: np.zeros(2)}
    assert json_ready(doc) == {"a": 1.5, "b": [2, True], "c": [None, None], "4": [0.0, 0.0]}


def test_json_ready_keeps_nan_and_infinity_for_a_bundle_header() -> None:
    kept = json_ready({"c": (np.inf, np.float64("nan")), "a": np.array([1.0, -np.inf]), "n": np.int32(3)},
                      keep_nonfinite=True)
    assert kept["c"][0] == math.inf and math.isnan(kept["c"][1]) and kept["a"] == [1.0, -math.inf]
    assert [type(v) for v in (*kept["c"], *kept["a"], kept["n"])] == [float] * 4 + [int]


def test_an_output_directory_removes_only_what_it_made(tmp_path: Path) -> None:
    with output_directory(tmp_path / "a" / "b" / "c"):
        pass
    assert list(tmp_path.iterdir()) == []
    with output_directory(tmp_path / "a" / "b") as out:
        (out / "kept.txt").write_text("")
    assert (tmp_path / "a" / "b" / "kept.txt").exists()
    made = OutputDirectory(tmp_path / "a" / "x" / "y")
    (tmp_path / "a" / "x" / "other").write_text("")  # someone wrote beside it: the parent stays
    made.remove_if_empty()
    assert sorted(p.name for p in (tmp_path / "a" / "x").iterdir()) == ["other"]


def test_output_directory_errors(tmp_path: Path) -> None:
    (tmp_path / "f").write_text("")
    with pytest.raises(OutputError, match="exists and is not a directory"):
        OutputDirectory(tmp_path / "f")
    with pytest.raises(OutputError, match="cannot create the output directory"):
        OutputDirectory(tmp_path / "f" / "sub")
    (tmp_path / "summary.json").mkdir()
    with pytest.raises(OutputError, match="summary.json is a directory there"):
        OutputDirectory(tmp_path, reserved=("summary.json", "branch.csv"))
    with pytest.raises(OutputError, match="name is empty"):
        OutputDirectory("")
