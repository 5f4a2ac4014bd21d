"""Save/load round trip, corrupt files, plotting conventions."""

import numpy as np
import pytest

from contin import Branch, BranchFileError, continuation, plot_branches
from contin_models.benchmarks.truss import VonMisesTruss


@pytest.fixture(scope="module")
def branch():
    return continuation(VonMisesTruss(), [0.0, 0.5], 0.0, ds=0.02, ds_max=0.05, stability=True,
                        bounds={"y": (-0.8, None)})


def test_save_load_identical(tmp_path, branch):
    path = branch.save(tmp_path / "truss.npz")
    back = Branch.load(path)
    for name in ("p", "u", "s", "tangent_p", "residual", "newton_iterations", "n_negative", "eigenvalues"):
        np.testing.assert_array_equal(getattr(back, name), getattr(branch, name))
    assert back.observables.keys() == branch.observables.keys()
    for k in branch.observables:
        np.testing.assert_array_equal(back.observables[k], branch.observables[k])
    assert len(back.special_points) == len(branch.special_points)
    for a, b in zip(back.special_points, branch.special_points):
        assert a.header() == b.header()
        np.testing.assert_array_equal(a.u, b.u)
    assert (back.status, back.message) == (branch.status, branch.message)
    assert not list(tmp_path.glob(".*tmp"))  # the temporary file was moved into place


def test_corrupt_files_raise_clear_errors(tmp_path, branch):
    path = branch.save(tmp_path / "b.npz")
    data = path.read_bytes()
    (tmp_path / "trunc.npz").write_bytes(data[: len(data) // 2])
    (tmp_path / "junk.npz").write_bytes(b"not a zip at all")
    for name in ("trunc.npz", "junk.npz", "missing.npz"):
        with pytest.raises(BranchFileError, match=name):
            Branch.load(tmp_path / name)


def test_plot_stable_solid_unstable_dashed(branch):
    import matplotlib

    matplotlib.use("Agg")
    ax = plot_branches(branch, x="deflection", y="p")
    styles = {line.get_linestyle() for line in ax.get_lines() if len(line.get_xdata()) > 1}
    assert styles == {"-", "--"}
    n_markers = sum(1 for line in ax.get_lines() if len(line.get_xdata()) == 1)
    assert n_markers == len(branch.folds()) == 2
