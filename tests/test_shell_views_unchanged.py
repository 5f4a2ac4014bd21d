"""No number of the shell's views moves while their code is rearranged.

``tests/data/shell_views.npz`` holds, at one deformed state per case, the traced energy, gradient and
Hessian, the harmonic blocks of several wave numbers (with pressure, by the generated kernels and by the
jets, the direct projection), the enclosed volume and a ring mesh's block, as the code computed them
before the shell's modules were rearranged (:mod:`tests.regression.capture_shell_views`).  With the numpy
kernels the arithmetic is the same operations in the same order, so every number must be the same bits;
with the C kernels (which may round differently in the last bits) the same to 1e-13 of each array's
largest entry.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from tests.regression.capture_shell_views import DATA, differences, shell_views

ROOT = Path(__file__).resolve().parents[1]


def test_views_equal_the_recorded_ones_bit_for_bit_with_the_numpy_kernels() -> None:
    code = ("import sys, numpy as np\n"
            "from tests.regression.capture_shell_views import DATA, differences, shell_views\n"
            "diff = differences(shell_views(), np.load(DATA))\n"
            "print('\\n'.join(diff) or 'same')\n")
    env = dict(os.environ, CONTIN_COMPILED="0")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "same", out.stdout


def test_views_equal_the_recorded_ones_to_roundoff_in_process() -> None:
    diff = differences(shell_views(), np.load(DATA), rtol=1e-13)
    assert not diff, "\n".join(diff)


def test_the_comparison_sees_one_changed_bit() -> None:
    """The guard is not blind: one entry moved by one ulp, or one array missing, is reported."""
    reference = dict(np.load(DATA))
    views = dict(reference)
    key = "paper_mirror/hessian/data"
    views[key] = reference[key].copy()
    views[key][7] = np.nextafter(views[key][7], np.inf)
    assert differences(views, reference) == [f"{key}: 1 of {reference[key].size} entries differ"]
    assert differences(views, reference, rtol=1e-13) == []
    del views["clamped/band_7"]
    assert differences(views, reference, rtol=1e-13) == ["clamped/band_7: missing"]
