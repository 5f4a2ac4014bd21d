"""Figures (issue 18): one style, smooth branches from stored tangents, a legend of what is drawn, PNG and PDF."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import contin
from contin import cli
from contin.diagram import hermite_piece, smooth_path, stability_pieces

PNG, PDF = b"\x89PNG\r\n\x1a\n", b"%PDF-"


def test_the_hermite_piece_meets_both_ends_with_their_tangents() -> None:
    p0, p1, m0, m1 = np.array([0.3, -1.0]), np.array([2.0, 0.5]), np.array([1.5, 4.0]), np.array([-2.0, 0.7])
    np.testing.assert_allclose(hermite_piece(p0, p1, m0, m1, [0.0, 1.0]), [p0, p1], atol=1e-15)
    h = 1e-6
    d0 = (hermite_piece(p0, p1, m0, m1, h) - hermite_piece(p0, p1, m0, m1, 0.0))[0] / h
    d1 = (hermite_piece(p0, p1, m0, m1, 1.0) - hermite_piece(p0, p1, m0, m1, 1.0 - h))[0] / h
    np.testing.assert_allclose(d0, m0, rtol=1e-5)
    np.testing.assert_allclose(d1, m1, rtol=1e-5)


def test_a_circle_sampled_coarsely_is_drawn_round() -> None:
    """Eight points of the unit circle with their tangents: the drawn pieces stay within 1e-3 of the circle
    (the chords of the same points are 0.08 inside it), and every stored point is on the line."""
    s = np.linspace(0.0, 2 * np.pi, 9)
    X, Y = smooth_path(np.cos(s), np.sin(s), -np.sin(s), np.cos(s), s, samples=16)
    assert X.size == 9 + 8 * 15
    assert np.max(np.abs(np.hypot(X, Y) - 1.0)) < 2e-3
    assert np.max(np.abs(np.hypot(*smooth_path(np.cos(s), np.sin(s), None, None, s)) - 1.0)) < 1e-15
    for x, y in zip(np.cos(s), np.sin(s)):
        assert np.min(np.hypot(X - x, Y - y)) < 1e-15


def test_missing_or_backward_tangents_give_straight_pieces() -> None:
    x, y, s = np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, 0.0]), np.array([0.0, 1.5, 3.0])
    dx = np.array([0.7, 0.7, math.nan])
    dy = np.array([0.7, 0.0, -0.7])
    X, Y = smooth_path(x, y, dx, dy, s, samples=4)
    assert X.size == 3 + 3  # the first piece curved, the second (no tangent at its end) straight
    back = smooth_path(x, y, -np.abs(dx), dy, s, samples=4)[0]
    assert back.size == 3  # tangents pointing against the path are not trusted


def _truss_branch() -> contin.Branch:
    from contin_models.benchmarks.truss import VonMisesTruss

    return contin.continuation(VonMisesTruss(1.0, 0.5, 1.0), [0.0, 0.5], 0.0, ds=0.02, ds_max=0.05, stability=True,
                               stop_at=("fold",))


def test_the_legend_names_only_what_is_drawn() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    br = _truss_branch()  # stable up to its fold, where it stops: no unstable part, no branch point
    ax = Figure().subplots()
    contin.plot_branches(br, x="p", y="y", ax=ax, stability="stability", labels=["only one"])
    names = [t.get_text() for t in ax.get_legend().get_texts()]
    assert names == ["stable", "fold in $P$"]  # one branch: no entry of its own; no "unstable"
    assert ax.get_legend().get_title().get_text() == "stability control"
    ax = Figure().subplots()
    contin.plot_branches(br, x="p", y="y", ax=ax, special_kinds=())
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["stable"]


def test_stored_tangents_make_the_branch_smooth_and_survive_saving(tmp_path: Path) -> None:
    from contin_models.shell import ShellPointLoad

    P = ShellPointLoad(N=30, phi_hat=0.8, control="displacement")
    br = contin.continuation(P, P.reference_unknowns(), 0.0, ds=0.05, ds_max=0.1, p_max=0.3, max_steps=40)
    assert set(br.tangents) == set(P.observables)
    np.testing.assert_allclose(br.tangent("w"), br.tangent_p)  # w is the parameter
    # dF/ds against the chords past the stiff first step: the stored tangent is the path's own
    F, s = br.observables["F"][1:], br.s[1:]
    mid = 0.5 * (br.tangent("F")[2:] + br.tangent("F")[1:-1])
    np.testing.assert_allclose(np.diff(F) / np.diff(s), mid, rtol=0.05, atol=0.05 * np.max(np.abs(mid)))
    br.save(tmp_path / "b.npz")
    back = contin.Branch.load(tmp_path / "b.npz")
    np.testing.assert_array_equal(back.tangents["F"], br.tangents["F"])


def test_trace_writes_png_and_pdf_and_plot_draws_them_smooth_again(tmp_path: Path, capsys) -> None:
    out = tmp_path / "run"
    code = cli.main(["trace", "-q", "--set", "shell.N=40", "--set", "shell.phi_hat=0.8", "--set",
                     "continuation.ds_max=0.05", "--out", str(out)])
    assert code == 0
    for stem in ("diagram", "shapes"):
        assert (out / f"{stem}.png").read_bytes()[:8] == PNG and (out / f"{stem}.pdf").read_bytes()[:5] == PDF
    header = (out / "branch.csv").read_text().splitlines()[0].split(",")
    assert {"tangent_p", "tangent_F", "tangent_w"} <= set(header)
    from contin.saved import load_run

    run = load_run(out)
    assert "tangent_F" not in run.branches[0].observables
    assert np.isfinite(run.branches[0].tangent("F")).all() and run.plot_options["scale"]["w"] == pytest.approx(1.0)
    assert "N = 40" in run.plot_options["title"]
    capsys.readouterr()
    assert cli.main(["plot", str(out), str(out), "--out", str(tmp_path / "both.pdf")]) == 0
    assert (tmp_path / "both.pdf").read_bytes()[:5] == PDF and (tmp_path / "both.png").read_bytes()[:8] == PNG


def test_the_style_saves_both_formats_and_leaves_the_global_rcparams_alone(tmp_path: Path) -> None:
    import matplotlib

    from contin import style

    before = dict(matplotlib.rcParams)
    with style.context():
        fig, ax = style.figure()
        ax.plot([0, 1], [0, 1])
    written = style.save(fig, tmp_path / "f.png")
    assert sorted(p.name for p in written) == ["f.pdf", "f.png"]
    assert (tmp_path / "f.pdf").read_bytes()[:5] == PDF
    assert dict(matplotlib.rcParams) == before


def _flat_cap_shapes(with_mode: bool) -> dict[str, np.ndarray]:
    """Arrays of :func:`contin_models.shell_scene.deformed.shell_shapes` for a flat cap (the shapes figure's
    hardest case: a cross-section much wider than tall) with four special points and a located mode."""
    t = np.linspace(0.0, 1.0, 60)
    r0, z0 = 0.75 * (1.0 - t), 0.72 + 0.28 * np.sqrt(1.0 - (0.75 * (1.0 - t)) ** 2 / 0.75 ** 2)
    rows = [0.85, 0.6, 0.4, 0.2]
    out = {"special_kind": np.array(["fold", "bifurcation", "fold", "fold"]),
           "special_label": np.array(["max(F)", "bifurcation(n)", "fold", "min(F)"]),
           "special_p": np.array([0.289, 0.323, 0.402, 0.26]),
           "special_r": np.array([r0] * 4), "special_z": np.array([0.72 + f * (z0 - 0.72) for f in rows]),
           "reference_r": r0, "reference_z": z0}
    if with_mode:
        a = np.exp(-((t - 0.97) / 0.02) ** 2)
        out.update(mode_record=np.array([1]), mode_n=np.array([1]), mode_a=a[None], mode_b=0 * a[None],
                   mode_c=0 * a[None])
    return out


@pytest.mark.parametrize("with_mode", [False, True])
def test_the_shapes_figure_keeps_its_texts_inside_and_apart(with_mode: bool) -> None:
    """Every title, axis label and legend of the shapes figure lies inside the figure, and no legend lies
    on an axis label or title (a long panel title once ran off the figure, and a legend anchored under
    a flat cross-section sat on its r/L)."""
    from contin import style
    from contin_models.shell_scene.deformed import draw_shapes

    with style.context():
        fig, _ = style.figure(nrows=0)
        fig.suptitle("point load")
        draw_shapes(fig, _flat_cap_shapes(with_mode), 1.0, "w")
        fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    page = fig.bbox
    axes = [ax for ax in fig.axes if ax.axison]
    legends = [leg for ax in fig.axes if (leg := ax.get_legend()) is not None]
    texts = [fig._suptitle] + [t for ax in axes for t in (ax.title, ax.xaxis.label, ax.yaxis.label)]
    assert len(axes) == (2 if with_mode else 1) and len(legends) == len(axes)
    for artist in texts + legends:
        box = artist.get_window_extent(renderer)
        assert page.x0 - 0.5 <= box.x0 and box.x1 <= page.x1 + 0.5, artist
        assert page.y0 - 0.5 <= box.y0 and box.y1 <= page.y1 + 0.5, artist
    for leg in legends:
        for t in texts:
            assert not leg.get_window_extent(renderer).overlaps(t.get_window_extent(renderer)), t.get_text()


def test_the_first_bifurcation_names_its_mode_in_the_legend_not_on_the_axes() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    br = _truss_branch()
    for k, p in enumerate((0.2, 0.3)):
        br.special_points.append(contin.SpecialPoint("bifurcation", p, br.u[0].copy(), {"y": 0.1 * k}, located=True,
                                                     info={"family": "n", "key": 3 + k}))
    ax = Figure().subplots()
    contin.plot_branches(br, x="p", y="y", ax=ax, stability="stability")
    names = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "bifurcation into another mode (first: $n = 3$)" in names
    assert not ax.texts  # no label beside a marker


def test_legend_symbols_name_the_quantity_that_folds() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    contin.plot_branches(_truss_branch(), x="p", y="y", ax=ax, stability="stability", symbols={"P": r"$\Pi$"})
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["stable", r"fold in $\Pi$"]


def test_the_shapes_are_labelled_in_the_diagram_units_and_extrema_as_limit_points() -> None:
    """A path in ``w`` drawn as ``w/R`` (scale 1/2 here): the shapes' labels give ``w/R``, and ``max(p)``,
    an extremum of the pressure, is a limit point of ``p`` whatever the model calls its load."""
    from contin import style
    from contin_models.shell_scene.deformed import shapes_drawer

    shapes = _flat_cap_shapes(False)
    shapes["special_label"] = np.array(["max(p)", "", "", "min(F)"])
    shapes["special_kind"] = np.array(["fold"] * 4)
    shapes["special_p"] = np.array([0.4, 0.2, 0.6, 1.0])
    draw = shapes_drawer(shapes, 1.0, "w", {"axis_labels": {"w": "$w/R$"}, "scale": {"w": 0.5}})
    with style.context():
        fig, _ = style.figure(nrows=0)
        draw(fig)
    names = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert names == ["reference", "limit point, max $p$ at $w/R$ = 0.2", "fold at $w/R$ = 0.1",
                     "fold at $w/R$ = 0.3", "limit point, min $F$ at $w/R$ = 0.5"]


def test_stability_runs_meet_at_the_located_point_on_the_cubic() -> None:
    """Eight pieces of the unit circle, stable up to point 3 and unstable from point 4: with a located point a
    quarter of the way along piece 3, the solid run ends and the dashed one starts there, on the cubic (on
    the circle to 2e-3); without it they meet at point 4, as before any point is located."""
    s = np.linspace(0.0, 2 * np.pi, 9)
    x, y, dx, dy = np.cos(s), np.sin(s), -np.sin(s), np.cos(s)
    stable = [True] * 4 + [False] * 5
    cut = s[3] + 0.25 * (s[4] - s[3])
    (X0, Y0, st0), (X1, Y1, st1) = stability_pieces(x, y, dx, dy, s, stable, [cut, s[6] + 0.1])
    assert (st0, st1) == (True, False)
    assert (X0[-1], Y0[-1]) == (X1[0], Y1[0])
    assert abs(np.hypot(X0[-1], Y0[-1]) - 1.0) < 2e-3 and abs(np.arctan2(Y0[-1], X0[-1]) % (2 * np.pi) - cut) < 1e-2
    # every stored point drawn once, in the run of its own stability; the whole path as smooth_path draws it
    for k in range(9):
        where = [np.any((X == x[k]) & (Y == y[k])) for X, Y in ((X0, Y0), (X1, Y1))]
        assert where == [k <= 3, k >= 4]
    whole = smooth_path(x, y, dx, dy, s)
    assert np.max(np.abs(np.hypot(np.concatenate([X0, X1]), np.concatenate([Y0, Y1])) - 1.0)) < 2e-3
    assert X0.size + X1.size == whole[0].size + 1  # the split piece as finely sampled, its cut sample in both runs
    (A0, B0, _), (A1, B1, _) = stability_pieces(x, y, dx, dy, s, stable)
    assert (A0[-1], B0[-1]) == (A1[0], B1[0]) == (x[4], y[4])
    np.testing.assert_array_equal(np.concatenate([A0, A1[1:]]), whole[0])


def test_stability_runs_leave_no_lone_point_and_unknown_is_one_run() -> None:
    s = np.linspace(0.0, 1.0, 5)
    x, y = s, s**2
    pieces = stability_pieces(x, y, None, None, s, [True] * 4 + [False])
    assert len(pieces) == 1 and pieces[0][2] is True and pieces[0][0].size == 5
    (X, Y, st), = stability_pieces(x, y, None, None, s, None)
    assert st is None and X.size == 5
    # straight pieces (no tangents) are cut on the chord
    (X0, Y0, _), (X1, Y1, _) = stability_pieces(x, y, None, None, s, [True, True, False, False, False], [0.3])
    assert (X0[-1], Y0[-1]) == pytest.approx((0.3, 0.0625 + 0.2 * (0.25 - 0.0625)))
