"""Issue 18: the help and a refused scene import no numpy, scipy or matplotlib; status lines and tables fit
100 columns.

The start-up paths run in fresh processes (the imports of this test process say nothing); no test here is
timed (``studies/bench_startup.py`` measures the times).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from contin.app import cli
from contin.results.io import LINE_WIDTH, status_text

ROOT = Path(__file__).resolve().parents[1]

#: Run ``contin ARGS`` in a fresh process; print, as the last line on stderr, the exit status and the heavy
#: packages then imported.
CHILD = r"""
import json, sys
from contin.launch import main
code = main(sys.argv[1:])
heavy = sorted({m.split(".")[0] for m in sys.modules} & {"numpy", "scipy", "matplotlib", "networkx"})
print("\n" + json.dumps({"code": code, "heavy": heavy}), file=sys.stderr)
"""


def _fresh(*args: str) -> tuple[dict, str, str]:
    proc = subprocess.run([sys.executable, "-c", CHILD, *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    err_lines = proc.stderr.rstrip("\n").splitlines()
    return json.loads(err_lines[-1]), proc.stdout, "\n".join(err_lines[:-1])


@pytest.mark.parametrize("args, code", [
    (["--help"], 0),
    (["trace", "--help"], 0),
    (["classify", "--help"], 0),
    (["models"], 0),
    (["trace", "--set", "shell.phi_hat=-1"], 2),  # out of range
    (["trace", "--set", "nosuch.key=1"], 2),  # unknown section
    (["trace", "--set", "shell.N=abc"], 2),  # wrong type
    (["trace", "--model", "nosuch"], 2),  # unknown model
])
def test_help_and_refused_input_import_nothing_heavy(args: list[str], code: int, tmp_path: Path) -> None:
    if args[0] == "trace" and "--help" not in args:
        args = [*args, "--out", str(tmp_path / "out")]
    result, out, err = _fresh(*args)
    assert result["code"] == code, err
    assert result["heavy"] == [], f"contin {' '.join(args)} imported {result['heavy']}"
    if code == 2:
        assert err.startswith("contin: error: ") and not (tmp_path / "out").exists()
    else:
        assert out


def test_a_trace_with_its_figures_imports_no_scipy_it_does_not_use(tmp_path: Path) -> None:
    """A default-control trace with its figures never factorizes sparse matrices by LU, never runs ARPACK and
    needs no graph ordering: scipy.sparse.linalg and scipy.sparse.csgraph stay unimported (they were
    imported by the engine's modules on load); and it writes its figures as PNG only."""
    child = CHILD.replace('{"numpy", "scipy", "matplotlib", "networkx"}',
                          '{"scipy.sparse.linalg", "scipy.sparse.csgraph", "matplotlib"}').replace(
        "m.split(\".\")[0]", "\".\".join(m.split(\".\")[:3])")
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-c", child, "trace", "-q", "--set", "shell.N=40", "--out", str(out)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    result = json.loads(proc.stderr.strip().splitlines()[-1])
    assert result["code"] == 0, proc.stderr
    assert result["heavy"] == ["matplotlib"]  # the figures were drawn, with nothing else of the list
    assert sorted(p.name for p in out.glob("*.p*g")) == ["diagram.png", "shapes.png"] and not list(out.glob("*.pdf"))


def test_the_check_sees_a_heavy_import() -> None:
    # the test above can fail: a child that imports numpy is reported
    proc = subprocess.run([sys.executable, "-c", CHILD.replace("code = main", "import numpy; code = main"), "--help"],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert json.loads(proc.stderr.strip().splitlines()[-1])["heavy"] == ["numpy"]


# ---- terminal output: status lines wrap, tables fit, no "-0" -------------------------------------------------
def test_status_lines_wrap_at_100_columns_and_join_back() -> None:
    text = ("status: ok - path: stopped at p_max (w = 0.5935522091); classification: bistable (F_max = 49.8601 at "
            "w = 0.28904, F_min = -51.4035 at w = 0.310124; normalized F_max R/(2 pi D) = 8.92742 at w/R = 0.28904, "
            "F_min R/(2 pi D) = -9.20377 at w/R = 0.310124) /a/path/that/is/long/and/must/not/be/broken.json")
    lines = status_text(text).splitlines()
    assert LINE_WIDTH == 100 and len(lines) > 1 and all(len(line) <= 100 for line in lines)
    assert all(line.startswith("  ") for line in lines[1:])
    assert " ".join(" ".join(lines).split()) == text
    assert "/a/path/that/is/long/and/must/not/be/broken.json" in lines[-1]
    assert status_text("short") == "short"


@pytest.mark.parametrize("text, shown", [
    ("F = -0 at w = -0.000", "F = 0 at w = 0.000"),
    ("F = -0.0e+00, (-0)", "F = 0.0e+00, (0)"),
    ("F = -0.5, tol 1e-0, x-0, -0.001", "F = -0.5, tol 1e-0, x-0, -0.001"),  # no negative zeros here
])
def test_status_lines_print_no_negative_zero(text: str, shown: str) -> None:
    assert status_text(text) == shown


def _wide_rows() -> list[dict]:
    return [{"kind": "fold", "label": "max(F)", "w": 0.28904045, "F": 49.860097 * k, "w/R": 0.28904045,
             "F_norm": -1.1378631e-10, "residual": 2.5e-08, "located": "yes",
             "stability": "stable -> unstable (displacement)"} for k in (1, -1)]


def test_a_wide_table_leaves_out_its_least_important_columns_and_says_so() -> None:
    rows = _wide_rows()
    whole = cli.format_table(rows, title="special points:")
    assert max(len(line) for line in whole.splitlines()) > 100  # without a width: every column
    optional = cli._optional_columns(rows)
    assert optional == ["residual", "located", "F_norm", "w/R", "F"]  # the parameter w always stays
    fitted = cli.format_table(rows, title="special points:", width=100, optional=optional,
                              elsewhere="summary.json has every column")
    lines = fitted.splitlines()
    assert all(len(line) <= 100 for line in lines)
    header = lines[1].split()
    assert header[:4] == ["kind", "label", "w", "F"] and header[-1] == "stability"
    assert "residual" not in header and "located" not in header
    left_out = [k for k in ("residual", "located", "F_norm", "w/R") if k not in header]
    assert lines[-1] == f"(not shown: {', '.join(left_out)}, to fit 100 columns; summary.json has every column)"
    # a table that fits is left whole, with no note
    narrow = cli.format_table(rows[:1], width=200, optional=optional)
    assert "residual" in narrow and "not shown" not in narrow


def test_a_long_failure_is_cut_short_to_fit() -> None:
    rows = [{"shell.h": 0.01, "class": "failed", "time_s": "1.00", "failure": "run failed: " + "x " * 80},
            {"shell.h": 0.02, "class": "bistable", "time_s": "1.00", "failure": ""}]
    lines = cli.format_table(rows, width=100, optional=["time_s"], abbreviate="failure",
                             elsewhere="'s.csv' has every column").splitlines()
    assert all(len(line) <= 100 for line in lines)
    assert lines[1].endswith("...") and "time_s" not in lines[0]
    assert lines[-1] == "(not shown: time_s; failure cut short, to fit 100 columns; 's.csv' has every column)"
