"""The README's Python examples run as printed (in a scratch directory, figures off screen)."""

import contextlib
import io
import math
import re
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

README = Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)


def test_the_readme_has_examples():
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_a_readme_example_runs(index, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(BLOCKS[index], f"README.md python block {index + 1}", "exec"), {"__name__": "__readme__"})
    if "contin.EnergyProblem" in BLOCKS[index]:
        limit, landing = (float(x) for x in out.getvalue().split())
        # closed form of the symmetric path (models/benchmarks/truss.py): limit points at L^3 = L0 s^2
        span, rise = 1.0, 0.001
        L0 = math.hypot(span, rise)
        L = (L0 * span ** 2) ** (1 / 3)
        assert limit == pytest.approx(2 / L0 * math.sqrt(L ** 2 - span ** 2) * (L0 / L - 1), rel=1e-8)
        assert landing == pytest.approx(-2 / math.sqrt(3), rel=1e-5)
