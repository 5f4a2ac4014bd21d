"""Studies behave like the command line (issue 14, B4): Ctrl-C exits 130 quietly, an output directory that
cannot be written exits 2 with one paragraph, and no empty directory the study made is left behind."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from studies import _common
from studies._common import output_dir, run_study, write_json

ROOT = Path(__file__).resolve().parents[1]
#: The processes import this tree first (and whatever the test run's own path adds).
ENV = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p)}


def test_an_interrupted_study_exits_130_and_removes_the_directory_it_made(tmp_path: Path,
                                                                           capsys: pytest.CaptureFixture) -> None:
    def main(argv: list[str]) -> int:
        output_dir(tmp_path / "new" / "out")
        raise KeyboardInterrupt

    assert run_study(main, []) == 130
    err = capsys.readouterr().err
    assert err.endswith("interrupted\n") and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_a_study_keeps_what_it_wrote_and_what_was_there(tmp_path: Path) -> None:
    (tmp_path / "old").mkdir()

    def main(argv: list[str]) -> int:
        write_json(output_dir(tmp_path / "new") / "summary.json", {"a": 1})
        output_dir(tmp_path / "old")
        return 0

    assert run_study(main, []) == 0
    assert (tmp_path / "new" / "summary.json").exists() and (tmp_path / "old").is_dir()
    assert not _common._MADE


def test_an_output_directory_that_cannot_be_made_exits_2(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    (tmp_path / "file").write_text("")

    def main(argv: list[str]) -> int:
        output_dir(tmp_path / "file" / "out")
        return 0

    with pytest.raises(SystemExit) as exc:
        run_study(main, [])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("error: cannot create the output directory") and err.count("\n") == 1


#: A study as the real ones are built (its __main__ block runs it through run_study), that makes its
#: output directory, says so, and then works until it is interrupted.
_STUDY = """
import sys, time
from studies._common import output_dir, run_study


def main():
    output_dir(sys.argv[1])
    print("ready", flush=True)
    time.sleep(120)


if __name__ == "__main__":
    raise SystemExit(run_study(main))
"""


def test_ctrl_c_in_a_study_process(tmp_path: Path) -> None:
    out = tmp_path / "run" / "out"
    script = tmp_path / "study.py"
    script.write_text(_STUDY)
    proc = subprocess.Popen([sys.executable, str(script), str(out)], cwd=ROOT, env=ENV, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None and proc.stdout.readline() == "ready\n"
        assert out.is_dir()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and "Traceback" not in err
    assert err == "study.py: interrupted\n"
    assert not (tmp_path / "run").exists()


def test_an_unwritable_study_output_exits_2(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    proc = subprocess.run([sys.executable, "-m", "studies.pole_strain", "--out", str(tmp_path / "file" / "out")],
                          cwd=ROOT, env=ENV, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 2 and proc.stdout == "" and "Traceback" not in proc.stderr
    assert proc.stderr.startswith("error: cannot create the output directory") and proc.stderr.count("\n") == 1


def test_clearest_offset_puts_a_label_where_nothing_is_drawn() -> None:
    """A line through the point from lower left to upper right, and one label already to the lower right:
    of the four corners the label goes to the upper left, the one farthest from both."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from studies._common import clearest_offset

    ax = Figure(figsize=(4, 4)).subplots()
    ax.plot([0.0, 1.0], [0.0, 1.0])
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(0.0, 1.0)
    ax.figure.canvas.draw()
    offsets = [(10, 10), (10, -10), (-10, 10), (-10, -10)]
    placed = [ax.transData.transform((0.5, 0.5)) + np.array([10.0, -10.0]) * ax.figure.dpi / 72.0]
    best, place = clearest_offset(ax, (0.5, 0.5), offsets, placed)
    assert best == 2
    np.testing.assert_allclose(place, ax.transData.transform((0.5, 0.5)) + np.array([-10.0, 10.0]) * ax.figure.dpi / 72.0)
    # near the axes' edge the corner outside is never chosen, however empty it is
    assert clearest_offset(ax, (0.02, 0.6), offsets)[0] in (0, 1)
