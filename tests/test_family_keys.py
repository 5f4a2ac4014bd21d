"""A watched operator family whose keys are not numbers (a Bloch class ``(j, parity)``) gives its CSV columns."""

import numpy as np
import contin
from contin.app.scene import branch_columns


class Twin(contin.Problem):
    """One unknown at rest and two watched modes keyed by tuples, of eigenvalues ``1 - p`` and ``2 - p``."""

    def __init__(self):
        fam = contin.OperatorFamily("pair", ((1, "even"), (1, "odd")),
                                    lambda k, u, p: np.array([[(1.0 if k[1] == "even" else 2.0) - p]]))
        super().__init__(symmetric=True, operator_families=(fam,))

    def residual(self, u, p):
        return u.copy()

    def jacobian(self, u, p):
        return np.eye(1)


def test_a_family_with_tuple_keys_gives_its_csv_columns():
    br = contin.continuation(Twin(), np.zeros(1), 0.0, p_max=1.5, ds=0.1, ds_max=0.1, stability=True)
    cols = branch_columns([br])
    crit = cols["critical_pair"]
    assert crit[-1] == "1 even" and cols["n_negative_pair"][-1] == 1


def test_its_csv_column_is_written_as_text(tmp_path):
    from contin.app.cli import write_outputs
    from contin.app.scene import TraceResult

    br = contin.continuation(Twin(), np.zeros(1), 0.0, p_max=1.5, ds=0.1, ds_max=0.1, stability=True)
    result = TraceResult(branches=[br], csv_columns=branch_columns([br]))
    write_outputs(tmp_path, "twin", {"output": {"figure": False}}, result, 0.0)
    lines = (tmp_path / "branch.csv").read_text().splitlines()
    column = lines[0].split(",").index("critical_pair")
    assert lines[-1].split(",")[column] == "1 even"
