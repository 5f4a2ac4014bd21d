"""No number of the shell's views moves while their code is rearranged.

``tests/data/shell_views.npz`` holds, at one deformed state per case, the traced energy, gradient and
Hessian, the harmonic blocks of several wave numbers (with pressure, by the generated kernels and by the
jets, the direct projection), the enclosed volume and a ring mesh's block, as the code computed them
before the shell's modules were rearranged (:mod:`tests.regression.capture_shell_views`).  With the numpy
kernels the arithmetic is the same operations in the same order, so what is assembled element by element
must keep its bits (sums and matrix products, which a CPU's BLAS or SIMD kernels may block differently,
to 1e-15 of each array's largest entry); with the C kernels (which may round differently in the last
bits) everything the same to 1e-13.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from tests.regression.capture_shell_views import DATA, differences, shell_views

ROOT = Path(__file__).resolve().parents[1]
#: the recorded quantities that must keep their bits (the rest: within 1e-15 of their largest entry)
EXACT = ("gradient", "hessian/data", "hessian/indices", "hessian/indptr", "volume_gradient", "volume_hessian/data",
         "volume_hessian/indices", "volume_hessian/indptr", "full_2_reference/indices", "full_2_reference/indptr")


def test_views_equal_the_recorded_ones_bit_for_bit_with_the_numpy_kernels() -> None:
    # assembled element by element (correctly rounded operations, np.add.at in a fixed order): the same
    # bits on any CPU; sums and matrix products may be blocked differently by the CPU's BLAS or SIMD
    # kernels, so those are held to a few units in the last place
    code = ("import sys, numpy as np\n"
            "from tests.regression.capture_shell_views import DATA, differences, shell_views\n"
            f"EXACT = {EXACT!r}\n"
            "views, ref = shell_views(), dict(np.load(DATA))\n"
            "exact = lambda d: {k: v for k, v in d.items() if k.split('/', 1)[1] in EXACT}\n"
            "rest = lambda d: {k: v for k, v in d.items() if k.split('/', 1)[1] not in EXACT}\n"
            "diff = differences(exact(views), exact(ref)) + differences(rest(views), rest(ref), rtol=1e-15)\n"
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
