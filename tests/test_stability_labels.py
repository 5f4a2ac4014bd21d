"""Stability labels are engine data (issue 14, A2): every fold, branch point and extremum event records
its stability on either side under every label; ``Branch.columns`` gives ``stable_<label>`` and
``n_negative_<label>``; an extremum can declare what folds there; ``plot_branches`` styles by a label;
nested operators are declared once (``LeadingBlock``) and counted from one factorization."""

from __future__ import annotations

import numpy as np
import pytest

import contin
from contin import Branch, LeadingBlock, Problem, continuation, extremum
from contin_models.benchmarks.truss import TrussDisplacementControl

A, B, K = 1.0, 0.5, 1.0


class LabelledTruss(TrussDisplacementControl):
    """The displacement-controlled truss with both stability notions: with ``y`` prescribed
    (``"displacement"``: the ``x`` stiffness) and with the load ``P`` prescribed (``"force"``: the
    whole Hessian in ``(x, y)``, of which the displacement operator is the leading block)."""

    def __init__(self, nested: bool = True) -> None:
        super().__init__(A, B, K)
        force = lambda u, y: self.truss.jacobian(np.array([u[0], y]), 0.0)  # noqa: E731
        self._stability_operators = {
            "displacement": LeadingBlock("force", 1) if nested else (lambda u, y: force(u, y)[:1, :1]),
            "force": force}


def _trace(nested: bool = True, n_eigs: int = 0, **kw) -> Branch:
    P = LabelledTruss(nested)
    return continuation(P, [0.0], B, ds=0.02, ds_max=0.05, direction=-1, p_min=-B, stability=True,
                        n_eigs=n_eigs, events=[extremum("P", "max", folds="P", stability_label="force"),
                                               extremum("P", "min")], **kw)


@pytest.fixture(scope="module")
def branch() -> Branch:
    return _trace()


def test_extremum_declares_the_fold_and_its_stability(branch: Branch) -> None:
    (pmax,) = branch.events("max(P)")
    assert pmax.located and pmax.info["folds"] == "P" and pmax.info["extremum_of"] == "P"
    assert pmax.info["stability_label"] == "force"
    # a maximum of the reaction is the limit load: stable before, one unstable direction after, under force
    assert pmax.stability_under() == {"n_negative_before": 0, "stable_before": True,
                                      "n_negative_after": 1, "stable_after": False}
    assert pmax.info["stable_before"] is True and pmax.info["stable_after"] is False
    assert pmax.info["stability"]["displacement"]["stable_before"] is True
    assert pmax.info["stability"]["displacement"]["stable_after"] is True
    # without a declaration the event carries the per-label data but no flat keys
    (pmin,) = branch.events("min(P)")
    assert pmin.info["stability"]["force"] == {"n_negative_before": 1, "stable_before": False,
                                               "n_negative_after": 0, "stable_after": True}
    assert "folds" not in pmin.info and "stable_before" not in pmin.info


def test_stability_on_either_side_matches_the_stored_points(branch: Branch) -> None:
    for spt in branch.special_points:
        for label, entry in spt.info["stability"].items():
            nneg = branch.n_negative_under(label)
            assert entry["n_negative_before"] == nneg[spt.index]
            assert entry["n_negative_after"] == nneg[spt.index + 1]


def test_columns(branch: Branch) -> None:
    cols = branch.columns()
    assert list(cols) == ["p", "s", "P", "residual", "newton_iterations", "stable_displacement",
                          "n_negative_displacement", "stable_force", "n_negative_force"]
    assert all(len(v) == len(branch) for v in cols.values())
    np.testing.assert_array_equal(cols["n_negative_force"], branch.stability_by["force"][0])
    np.testing.assert_array_equal(cols["stable_force"], (branch.stability_by["force"][0] == 0).astype(int))
    assert set(cols["stable_displacement"]) == {1} and set(cols["n_negative_force"]) == {0, 1}
    # the old names keep working
    np.testing.assert_array_equal(branch.n_negative, cols["n_negative_displacement"])
    np.testing.assert_array_equal(branch.stable_under("force"), cols["stable_force"] == 1)


def test_saved_and_loaded_with_the_stability_records(tmp_path, branch: Branch) -> None:
    back = Branch.load(branch.save(tmp_path / "b.npz"))
    for a, b in zip(back.special_points, branch.special_points):
        assert a.info["stability"] == b.info["stability"]
    assert list(back.columns()) == list(branch.columns())


def test_nested_operators_counted_like_separate_ones(branch: Branch) -> None:
    separate = _trace(nested=False)
    eigs = _trace(n_eigs=1)  # counted by eigenvalues, the blocks sliced from the enclosing operator
    for other in (separate, eigs):
        assert len(other) == len(branch)
        for label in ("displacement", "force"):
            np.testing.assert_array_equal(other.n_negative_under(label), branch.n_negative_under(label))
    P = LabelledTruss()
    u, y = np.array([0.0]), 0.3
    ops = P.stability_operators(u, y)
    np.testing.assert_array_equal(ops["displacement"], ops["force"][:1, :1])
    assert {k: v.n_negative for k, v in P.stability(u, y).items()} == \
        {k: v.n_negative for k, v in P.stability(u, y, n_eigs=2).items()}


def test_leading_block_must_name_a_declared_operator() -> None:
    with pytest.raises(ValueError, match="LeadingBlock"):
        Problem(residual=lambda u, p: u, stability_operators={"a": LeadingBlock("b", 1)})


def test_fold_ending_the_branch_has_only_the_side_it_came_from() -> None:
    from contin_models.benchmarks.truss import VonMisesTruss

    tr = VonMisesTruss(A, B, K)
    br = continuation(tr, [0.0, B], 0.0, ds=0.02, ds_max=0.05, stability=True, n_eigs=0, stop_at=("fold",))
    fold = br.special_points[-1]
    assert fold.kind == "fold" and fold.info["ends_branch"] and fold.info["folds"] == "P"
    assert fold.info["stability"] == {"stability": {"n_negative_before": 0, "stable_before": True}}


def test_plot_branches_styles_by_the_label(branch: Branch) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def styles(label):
        _, ax = plt.subplots()
        contin.plot_branches(branch, x="p", y="P", stability=label, special_kinds=())
        lines = [ln.get_linestyle() for ln in plt.gca().lines]
        plt.close("all")
        return lines

    assert styles("displacement") == ["-"]  # stable all along under displacement control
    assert styles("force") == ["-", "--", "-"]  # unstable between the limit loads under force control
    assert styles(None) == ["-"]  # the primary label


def test_the_shell_declares_its_nested_operators() -> None:
    """The point-loaded shell declares its displacement Hessian as the leading block of its force Hessian
    (and overrides nothing): the engine's one-factorization counts equal each operator's own."""
    from contin.numerics.stability import stability_info
    from contin_models.shell import ShellPointLoad

    P = ShellPointLoad(N=40, phi_hat=0.8, control="displacement")
    assert not hasattr(P, "stability_counts")  # one way to declare: the operators, nothing to override
    br = continuation(P, P.reference_unknowns(), 0.0, ds=0.02, ds_max=0.05, p_max=0.45, max_steps=200)
    seen = set()
    for u, w in zip(br.u[::3], br.p[::3]):
        declared = {label: info.n_negative for label, info in P.stability(u, w).items()}
        each = {label: stability_info(op, 0).n_negative for label, op in P.stability_operators(u, w).items()}
        assert declared == each
        assert list(declared) == ["displacement", "force"]
        seen.add(declared["displacement"])
    assert len(seen) >= 2


def test_records_read_the_engine_stability(branch: Branch) -> None:
    """``special_point_records`` records a declared extremum as a limit point of what folds there, with
    its stability under the declared label, and adds a model's own fields."""
    from contin.app.scene import special_point_records

    records = special_point_records([branch], parameter_name="y", fields=lambda spt: {"index": spt.index})
    by_label = {rec["label"]: rec for rec in records}
    pmax, pmin = by_label["max(P)"], by_label["min(P)"]
    assert (pmax["kind"], pmax["parameter"]) == ("fold", "P")
    assert (pmax["stable_before"], pmax["stable_after"]) == (True, False)  # under "force"
    assert (pmin["kind"], pmin["parameter"]) == ("event", "y") and "stable_before" not in pmin
    assert [rec["index"] for rec in records] == [spt.index for spt in branch.special_points]


def test_special_point_table_columns_from_the_record_fields(branch: Branch) -> None:
    """``special_point_table(columns=...)`` shows chosen record fields (which quantity folds, a model's own
    fields) in place of the parameter and observables; a limit point's stability carries its control,
    a jump's row its landing's ``stable``."""
    from contin.app.scene import special_point_records, special_point_table

    records = special_point_records([branch], parameter_name="y",
                                    fields=lambda spt: {"stability_control": spt.info.get("stability_label")})
    records.append({"kind": "jump", "jump": 0, "label": "jump_to", "parameter": "P", "p": 0.1, "residual": 1e-9,
                    "located": True, "stable": True, "stable_after": True, "observables": {"P": 0.1}})
    rows = special_point_table(records, "y", branch_labels=["path"],
                               columns={"folds_in": "parameter", "load": "P", "missing": "nothing"})
    assert list(rows[0]) == ["on", "kind", "label", "folds_in", "load", "missing", "residual", "located", "stability"]
    by_label = {row["label"]: row for row in rows}
    pmax = by_label["max(P)"]
    assert (pmax["on"], pmax["kind"], pmax["folds_in"]) == ("path", "fold", "P")
    assert pmax["load"] == branch.events("max(P)")[0].observables["P"] and pmax["missing"] is None
    assert pmax["stability"] == "stable -> unstable (force)"
    assert by_label["min(P)"]["stability"] == ""  # an undeclared event: no stability of its own
    assert by_label["jump_to"]["on"] == "jump 0" and by_label["jump_to"]["stability"] == "stable"
    # without columns: the parameter and every observable, as before
    plain = special_point_table(records[:1], "y")
    assert list(plain[0]) == ["kind", "label", "y", "P", "residual", "located", "stability"]


def test_plot_marks_folds_by_the_quantity_that_folds(branch: Branch) -> None:
    """A fold in the quantity on the x axis is an open circle, a fold in another quantity (a limit point,
    declared by an extremum or the parameter of a force-controlled branch) a filled triangle."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from contin_models.benchmarks.truss import VonMisesTruss

    def marks(br: Branch, x: str, y: str, **kw) -> dict[str, tuple[str, str]]:
        _, ax = plt.subplots()
        contin.plot_branches(br, x=x, y=y, ax=ax, **kw)
        out = {ln.get_label(): (ln.get_marker(), str(ln.get_markerfacecolor())) for ln in ax.lines
               if ln.get_marker() not in ("None", None) and not ln.get_label().startswith("_")}
        labels = (ax.get_xlabel(), ax.get_ylabel())
        plt.close("all")
        return out, labels

    found, axes = marks(branch, "p", "P", axis_labels={"P": "reaction"})
    assert found["limit point in $P$"] == ("^", "k") and found["event"][0] == "d"
    assert axes == ("y", "P (reaction)")  # the parameter by its name
    force = continuation(VonMisesTruss(A, B, K), [0.0, B], 0.0, ds=0.02, ds_max=0.05, stability=True,
                         stop_at=("fold",))
    assert marks(force, "p", "y")[0] == {"fold in $P$": ("o", "w")}  # the path turns back in P
    assert marks(force, "y", "p")[0] == {"limit point in $P$": ("^", "k")}  # P on the y axis: its maximum


def test_trace_result_draws_by_its_stability_label(branch: Branch) -> None:
    """``TraceResult.draw``: the default diagram styled by the result's stability label, with its options."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contin.app.scene import TraceResult

    def draw(label: str | None) -> tuple[list[str], list[str]]:
        res = TraceResult.from_branches([branch], x="y", y="P", labels=["path"])
        res.stability = label
        res.plot_options = {"note": "a note", "zero_line": True}
        _, ax = plt.subplots()
        res.draw(ax)
        styles = [ln.get_linestyle() for ln in ax.lines if ln.get_marker() in ("None", None)]
        texts = [ax.get_title()]
        plt.close("all")
        return styles, texts

    styles, texts = draw("force")
    assert styles[:3] == ["-", "--", "-"] and texts == ["a note"]  # the note stands under the title
    assert draw("displacement")[0][0] == "-" and "--" not in draw("displacement")[0]


def test_branch_columns_take_the_named_stability_columns(branch: Branch) -> None:
    from contin.app.scene import branch_columns

    plain = branch_columns([branch, branch])
    assert list(plain)[-2:] == ["stable", "n_negative"]
    named = branch_columns([branch, branch], {"stable_force": "stable_force",
                                              "n_negative": "n_negative_displacement"})
    assert list(named) == [k for k in plain if k not in ("stable", "n_negative")] + ["stable_force", "n_negative"]
    np.testing.assert_array_equal(named["stable_force"], np.tile(branch.columns()["stable_force"], 2))
    np.testing.assert_array_equal(named["n_negative"], np.tile(branch.n_negative_under("displacement"), 2))
    assert "stable_x" not in branch_columns([branch], {"stable_x": "stable_nothing"})


def _banded_saddle(n: int, shift: float) -> np.ndarray:
    """A symmetric tridiagonal matrix with eigenvalues spread around ``-shift``, bordered by a full row."""
    rng = np.random.default_rng(7)
    H = np.diag(np.linspace(1.0, 4.0, n)) - shift * np.eye(n)
    H += np.diag(np.full(n - 1, 0.3), 1) + np.diag(np.full(n - 1, 0.3), -1)
    H[-1, :] = H[:, -1] = rng.standard_normal(n)
    H[-1, -1] = 0.5
    return H


def _negative(A: np.ndarray) -> int:
    return int(np.count_nonzero(np.linalg.eigvalsh(A) < 0))


@pytest.mark.parametrize("shift", [0.0, 1.5, 2.5])
def test_nested_inertias_by_ldlt_and_by_schur_complement(monkeypatch, shift: float) -> None:
    """Both ways of :func:`contin.numerics.stability.nested_inertias` count like eigenvalues: one ``L D L^T``, and,
    when that cannot be trusted, the leading block's count plus the Schur complement's (Sylvester)."""
    import scipy.sparse as sp

    import contin.numerics.stability as stability

    H = _banded_saddle(120, shift)
    m = H.shape[0] - 1
    expected = (_negative(H[:m, :m]), _negative(H))
    assert stability.nested_inertias(sp.csr_matrix(H), m) == expected
    monkeypatch.setattr(stability, "leading_inertias", lambda H, sizes: None)
    assert stability.nested_inertias(sp.csr_matrix(H), m) == expected
    # a border of two rows: the Schur complement is 2 x 2
    assert stability.nested_inertias(sp.csr_matrix(H), m - 1) == (_negative(H[:m - 1, :m - 1]), _negative(H))


def test_leading_block_counted_from_the_end_and_by_schur_when_ldlt_fails(monkeypatch) -> None:
    """``LeadingBlock(of, -1)``: the operator without its last row and column; the engine counts it with
    its enclosing operator, by the Schur complement when the pivot-free factorization is refused."""
    import contin.numerics.stability as stability

    H = _banded_saddle(80, 2.5)
    P = Problem(residual=lambda u, p: u, stability_operators={"inner": LeadingBlock("outer", -1),
                                                               "outer": lambda u, p: H})
    u = np.zeros(80)
    np.testing.assert_array_equal(P.stability_operators(u, 0.0)["inner"], H[:79, :79])
    expected = {"inner": _negative(H[:79, :79]), "outer": _negative(H)}
    assert {k: v.n_negative for k, v in P.stability(u, 0.0).items()} == expected
    assert list(P.stability(u, 0.0)) == ["inner", "outer"]
    monkeypatch.setattr(stability, "leading_inertias", lambda H, sizes: None)
    assert {k: v.n_negative for k, v in P.stability(u, 0.0).items()} == expected
