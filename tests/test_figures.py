"""Figures (issue 18): one style, smooth branches from stored tangents, a legend of what is drawn, PNG and PDF."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import contin
from contin.app import cli
from contin.plot.branches import hermite_piece, smooth_path, stability_pieces

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


def test_trace_writes_png_and_plot_draws_it_smooth_again(tmp_path: Path, capsys) -> None:
    out = tmp_path / "run"
    code = cli.main(["trace", "-q", "--set", "shell.N=40", "--set", "shell.phi_hat=0.8", "--set",
                     "continuation.ds_max=0.05", "--out", str(out)])
    assert code == 0
    for stem in ("diagram", "shapes"):
        assert (out / f"{stem}.png").read_bytes()[:8] == PNG
    header = (out / "branch.csv").read_text().splitlines()[0].split(",")
    assert {"tangent_p", "tangent_F", "tangent_w"} <= set(header)
    from contin.app.saved import load_run

    run = load_run(out)
    assert "tangent_F" not in run.branches[0].observables
    assert np.isfinite(run.branches[0].tangent("F")).all() and run.plot_options["scale"]["w"] == pytest.approx(1.0)
    assert "N = 40" in run.plot_options["title"]
    capsys.readouterr()
    assert cli.main(["plot", str(out), str(out), "--out", str(tmp_path / "both.pdf")]) == 0
    assert (tmp_path / "both.pdf").read_bytes()[:5] == PDF and not (tmp_path / "both.png").exists()


def test_the_style_saves_both_formats_and_leaves_the_global_rcparams_alone(tmp_path: Path) -> None:
    import matplotlib

    from contin.plot import style

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
    from contin.plot import style
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
    names = [" ".join(t.get_text().split("\n")) for t in ax.get_legend().get_texts()]  # long texts are broken
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
    from contin.plot import style
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


# ---- issue 32: figures for every scene ---------------------------------------------------------------------
def _trace(tmp_path: Path, name: str, *settings: str, capsys=None) -> Path:
    """A small run of the shell (N = 40) into ``tmp_path/name``; ``settings``: ``key=value`` pairs."""
    out = tmp_path / name
    args = ["trace", "-q", "--set", "shell.N=40"] + [a for kv in settings for a in ("--set", kv)] + ["--out", str(out)]
    assert cli.main(args) == 0
    if capsys is not None:
        capsys.readouterr()
    return out


@pytest.mark.slow
def test_trace_writes_pdf_only_when_asked_by_flag_or_key(tmp_path: Path, capsys) -> None:
    """PNG by default; ``--pdf`` or ``output.pdf = true`` add the PDFs; a rerun without them removes the PDFs
    the earlier run left (they would show another run than the summary beside them)."""
    out = _trace(tmp_path, "run", capsys=capsys)
    assert {p.name for p in out.iterdir() if p.suffix in (".png", ".pdf")} == {"diagram.png", "shapes.png"}
    assert cli.main(["trace", "-q", "--set", "shell.N=40", "--pdf", "--out", str(out)]) == 0
    assert (out / "diagram.pdf").read_bytes()[:5] == PDF and (out / "shapes.pdf").read_bytes()[:5] == PDF
    _trace(tmp_path, "run", capsys=capsys)
    assert not (out / "diagram.pdf").exists() and not (out / "shapes.pdf").exists()
    keyed = _trace(tmp_path, "keyed", "output.pdf=true", capsys=capsys)
    assert (keyed / "diagram.pdf").read_bytes()[:5] == PDF and (keyed / "diagram.png").read_bytes()[:8] == PNG


def test_plot_writes_the_format_its_file_names_and_pdf_on_request(tmp_path: Path, capsys) -> None:
    out = _trace(tmp_path, "run", capsys=capsys)
    assert cli.main(["plot", str(out), "-o", str(tmp_path / "x.png")]) == 0
    assert (tmp_path / "x.png").read_bytes()[:8] == PNG and not (tmp_path / "x.pdf").exists()
    assert cli.main(["plot", str(out), "-o", str(tmp_path / "y.png"), "--pdf"]) == 0
    assert (tmp_path / "y.pdf").read_bytes()[:5] == PDF and (tmp_path / "y.png").read_bytes()[:8] == PNG
    assert cli.main(["plot", str(out), "-o", str(tmp_path / "z.pdf")]) == 0
    assert (tmp_path / "z.pdf").read_bytes()[:5] == PDF and not (tmp_path / "z.png").exists()


@pytest.mark.parametrize("scene, folds_in", [
    (["load.kind=ring", "shell.boundary=clamped"], "w"),  # eight folds in w under a stiffening that reaches 16000
    (["load.kind=pressure", "shell.boundary=clamped"], "dV"),  # the snap at dV/V0 = 0.05 of a path to 2.1
])
def test_the_snaps_get_a_detail_when_the_stiffening_sets_the_axes(tmp_path: Path, capsys, monkeypatch, scene,
                                                                   folds_in) -> None:
    """The diagram of a scene whose path after eversion reaches far beyond its snaps has an Axes on which the
    folds under its control lie inside the limits with margin and span a sizeable part of both ranges; the
    whole path stays drawn (above, the detail's box marked on it)."""
    from tests.figure_check import CapturedFigures, marker_points, inside_with_margin, span_fraction

    captured = CapturedFigures().install(monkeypatch)
    out = _trace(tmp_path, "run", *scene, capsys=capsys)
    import json

    summary = json.loads((out / "summary.json").read_text())
    assert sum(r["kind"] == "fold" and r["parameter"] == folds_in for r in summary["special_points"]) >= 2
    diagram = captured.figures[0]
    best = max(diagram.axes, key=lambda ax: min(span_fraction(ax, marker_points(ax, "o"))))
    circles = marker_points(best, "o")  # the folds in the quantity on the x axis
    assert len(circles) >= 2 and inside_with_margin(best, circles, 0.03)
    assert min(span_fraction(best, circles)) > 0.25
    whole = max(diagram.axes, key=lambda ax: ax.get_ylim()[1])
    top = max(float(np.nanmax(ln.get_ydata())) for ln in whole.lines if len(ln.get_ydata()) > 1)
    assert whole.get_ylim()[1] >= top  # the path to its end is still shown


def test_limits_around_the_snaps_say_where_the_path_goes_off_the_axes() -> None:
    """A path whose last branch stiffens straight up to 100 after snaps at 12 and 16 (the plate under a dead
    load): one panel, limited to the snaps (both arrows on it), with the value the path reaches written at
    its edge."""
    from types import SimpleNamespace

    from contin.app.figures import trace_figure
    from contin.app.scene import TraceResult
    from tests.figure_check import arrows

    def branch(w: np.ndarray, F: np.ndarray, folds: list[int]) -> contin.Branch:
        n = w.size
        spts = [contin.SpecialPoint("fold", float(F[i]), np.zeros(0), {"w": float(w[i]), "F": float(F[i])},
                                    located=True, index=i, info={"folds": "F"}) for i in folds]
        return contin.Branch(p=F, u=np.zeros((n, 0)), s=np.arange(n, dtype=float), observables={"w": w, "F": F},
                             special_points=spts, meta={"parameter_name": "F"}, tangent_p=np.full(n, np.nan),
                             residual=np.zeros(n), newton_iterations=np.zeros(n, dtype=int))

    t = np.linspace(0.0, 1.0, 30)
    branches = [branch(0.06 * t, 12.0 * t, [29]), branch(0.07 + 0.06 * t, 12.0 + 4.0 * np.sin(0.5 * np.pi * t), [29]),
                branch(0.28 + 0.001 * t, 16.0 + 84.0 * t, [])]
    result = TraceResult(branches=branches, jumps=[SimpleNamespace(p=12.0), SimpleNamespace(p=16.0)], x="w", y="F",
                         parameter_name="F", labels=["loading", "after snap 1", "after snap 2"],
                         jump_observables=[({"w": 0.06, "F": 12.0}, {"w": 0.07, "F": 12.0}),
                                           ({"w": 0.13, "F": 16.0}, {"w": 0.28, "F": 16.0})])
    fig = trace_figure("plate", result)
    ax = fig.axes[0]
    assert len(fig.axes) == 1 and 16.0 < ax.get_ylim()[1] < 25.0
    assert len(arrows(ax)) == 2  # both snaps
    assert any("100" in t.get_text() for t in ax.texts)


def test_plot_of_other_quantities_names_them_and_marks_folds_in_w_as_folds(tmp_path: Path, capsys) -> None:
    """The README's ``contin plot OUT -x w_over_R -y F_norm``: the axes read w/R and F R/2 pi D, and a fold in
    w is a fold in w/R (an open circle), not a limit point beside the limit points in F."""
    from contin.app.saved import load_run
    from tests.figure_check import legend_texts

    run = load_run(_trace(tmp_path, "run", capsys=capsys))
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    contin.plot_branches(run.branches, x="w_over_R", y="F_norm", ax=ax, stability=run.stability, **run.plot_options)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("$w/R$", r"$F R / 2\pi D$")
    names = legend_texts(ax)
    assert "fold in $w$" in names and "limit point in $w$" not in names
    assert len(names) == len(set(names))


def _overlay_runs(tmp_path: Path, capsys) -> list[Path]:
    """Three point-load runs of one model that differ in several keys, two of them in keys no title shows."""
    return [_trace(tmp_path, "a", capsys=capsys),
            _trace(tmp_path, "b", "load.control=force", "shell.h=0.015", "shell.phi_hat=0.7", capsys=capsys),
            _trace(tmp_path, "c", "shell.nu=0.3", "continuation.ds_max=0.05", capsys=capsys)]


@pytest.mark.slow
def test_an_overlay_keeps_its_axes_wide_and_its_title_inside(tmp_path: Path, capsys, monkeypatch) -> None:
    """Legend labels long enough to squeeze the axes to 40 % of the figure and push the title off its edge
    are broken into lines: the axes keep more than half the width and every text stays on the figure."""
    from tests.figure_check import CapturedFigures

    runs = _overlay_runs(tmp_path, capsys)
    captured = CapturedFigures().install(monkeypatch)
    assert cli.main(["plot", *map(str, runs), "-o", str(tmp_path / "o.png")]) == 0
    fig = captured.figures[0]
    from contin.plot import style

    fig.set_dpi(style.DPI)  # measured as written
    fig.canvas.draw()
    ax = fig.axes[0]
    assert ax.get_position().width > 0.5
    page = fig.bbox
    for artist in (ax.title, ax.get_legend()):
        box = artist.get_window_extent(fig.canvas.get_renderer())
        assert page.x0 - 0.5 <= box.x0 and box.x1 <= page.x1 + 0.5, artist


def test_a_force_and_a_displacement_run_overlaid_keep_their_controls_and_the_snap(tmp_path: Path, capsys,
                                                                                  monkeypatch) -> None:
    """Overlaid, the dead load's run keeps its snap arrow, and the legend does not call both runs
    displacement-controlled."""
    from tests.figure_check import CapturedFigures, arrows, legend_texts

    runs = [_trace(tmp_path, "d", capsys=capsys), _trace(tmp_path, "f", "load.control=force", capsys=capsys)]
    captured = CapturedFigures().install(monkeypatch)
    assert cli.main(["plot", *map(str, runs), "-o", str(tmp_path / "o.png")]) == 0
    ax = captured.figures[0].axes[0]
    assert len(arrows(ax)) >= 1
    assert ax.get_legend().get_title().get_text() != "displacement control"
    assert {"displacement control", "force control"} <= set(legend_texts(ax))


def test_overlay_labels_name_what_differs_in_the_scenes_titles() -> None:
    """A plate's entry names no sphere radius (the plate has none); the runs are told apart by their titles."""
    from contin.app.saved import SavedRun, overlay_labels
    from contin_models.shell_scene import SHELL_SCENE
    from contin_models.shell_scene.labels import scene_title
    from contin.app.scene import load_scene

    runs = []
    for name, sets in (("pt", []), ("sph", ["load.kind=sphere", "load.radius=0.3"]), ("pl", ["load.kind=plate"])):
        scene = load_scene(SHELL_SCENE.schema, None, sets)
        runs.append(SavedRun(path=Path(name), summary={"model": "shell", "scene": scene}, branches=[],
                             plot_options={"title": scene_title(scene)}, stability="displacement"))
    title, labels = overlay_labels(runs)
    assert labels == ["point load", "rigid sphere, $r_s/R = 0.3$", "rigid plate"]
    assert not any("radius" in label for label in labels)
    assert title.startswith("shell: ") and r"$h/R = 0.02$" in title


@pytest.mark.parametrize("scene, label", [
    (["load.kind=pressure", "shell.boundary=clamped", "load.control=force"], "$p/p_c$"),
    (["load.kind=ring", "shell.boundary=clamped"], "$w/R$"),
])
def test_the_shapes_are_labelled_as_the_diagram_with_the_length_named_and_the_load_drawn(
        tmp_path: Path, capsys, monkeypatch, scene, label) -> None:
    """The shapes of a pressure run say p/p_c (the diagram's axis) where they said p = 219; the cross-sections
    are in r/R, z/R (never an undefined L); a ring load is drawn as arrows on each shape."""
    from tests.figure_check import CapturedFigures, legend_texts

    captured = CapturedFigures().install(monkeypatch)
    _trace(tmp_path, "run", *scene, capsys=capsys)
    shapes = captured.figures[1]
    ax = shapes.axes[0]
    names = legend_texts(ax)
    drawn = [n for n in names if n.startswith(("fold", "limit point"))]
    assert drawn and all(f" at {label} = " in n for n in drawn)
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("$r / R$", "$z / R$")
    if "load.kind=ring" in scene:  # an arrow's head at the ring's node on each side of the axis, on every shape
        heads = [xy for ln in ax.lines if ln.get_marker() in ("v", "^") for xy in ln.get_xydata()]
        assert len(heads) == 2 * len(drawn) and "ring load" in names
        assert sorted(round(float(x), 9) for x, _ in heads) == sorted(round(-float(x), 9) for x, _ in heads)


def test_the_shapes_draw_the_sphere_where_it_stands(tmp_path: Path, capsys, monkeypatch) -> None:
    """Each cross-section of a sphere indentation shows the rigid sphere where it stands: its lowest point on
    the pole at the release fold, where the sphere still touches it."""
    from tests.figure_check import CapturedFigures, legend_texts

    captured = CapturedFigures().install(monkeypatch)
    out = _trace(tmp_path, "run", "load.kind=sphere", capsys=capsys)
    ax = captured.figures[1].axes[0]
    shapes = np.load(out / "shapes.npz")
    folds = [k for k, kind in enumerate(shapes["special_kind"]) if kind == "fold"]
    drawn = [n for n in legend_texts(ax) if n.startswith("fold")]
    assert folds and len(drawn) == len(folds)
    # the reference, each shape and, thin, the sphere of each shape
    thin = [ln for ln in ax.lines if len(ln.get_xydata()) > 2 and ln.get_linewidth() < 0.9]
    assert len(thin) == len(folds)
    for line, k in zip(thin, folds):
        assert float(np.nanmin(line.get_ydata())) == pytest.approx(shapes["special_z"][k][-1], abs=2e-3)


def test_the_shapes_draw_the_plate_where_it_stands() -> None:
    from contin.plot import style
    from contin_models.shell_scene.deformed import LoadSketch, draw_shapes

    shapes = _flat_cap_shapes(False)
    pole = shapes["special_z"][:, -1]
    shapes["special_indenter"] = pole
    with style.context():
        fig, _ = style.figure(nrows=0)
        draw_shapes(fig, shapes, 1.0, "w_b", "$w_b/R$", 1.0, load=LoadSketch("plate"))
    ax = fig.axes[0]
    plates = [ln for ln in ax.lines if len(ln.get_xydata()) == 2 and np.ptp(ln.get_ydata()) == 0.0]
    assert sorted(float(ln.get_ydata()[0]) for ln in plates) == sorted(pole)
    assert "rigid plate, in each shape's colour" in [t.get_text() for t in ax.get_legend().get_texts()]


def test_plot_branches_is_put_together_from_short_reusable_pieces() -> None:
    """Drawing a branch, its special points and the legend are functions of their own, each usable alone: with
    them a diagram is drawn as plot_branches draws it; plot_branches itself is short."""
    import inspect

    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from contin.plot.branches import (add_legend, draw_branch, draw_jumps, legend_entries, mark_special_points,
                                      plot_branches)

    br = _truss_branch()
    ax = Figure().subplots()
    contin.plot_branches(br, x="p", y="y", ax=ax, stability="stability")
    by_pieces = Figure().subplots()
    drawn = draw_branch(by_pieces, br, "p", "y", color="C0", stability="stability")
    points = mark_special_points(by_pieces, br, "p", "y")
    add_legend(by_pieces, legend_entries([], drawn, points, snaps=False), title="stability control")
    for a, b in zip(ax.lines, by_pieces.lines):
        np.testing.assert_array_equal(a.get_xydata(), b.get_xydata())
    assert [t.get_text() for t in ax.get_legend().get_texts()] == \
        [t.get_text() for t in by_pieces.get_legend().get_texts()]
    for piece in (plot_branches, draw_branch, mark_special_points, add_legend, legend_entries, draw_jumps):
        source = inspect.getsource(piece)
        body = source[source.index('"""', source.index('"""') + 3) + 3:]  # after the docstring
        assert len([ln for ln in body.splitlines() if ln.strip()]) <= 45, piece.__name__


def test_an_event_at_a_fold_and_a_snap_that_moves_nothing_on_the_axes_make_no_blob() -> None:
    """Where a sphere releases the shell, the F -> 0 event, the release fold and the snap at zero force fall
    on one point: the fold is marked once, with no diamond in it and no arrow of zero length."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from tests.figure_check import arrows

    br = _truss_branch()
    fold = next(s for s in br.special_points if s.kind == "fold")
    br.special_points.append(contin.SpecialPoint("event", fold.p, fold.u.copy(), dict(fold.observables), located=True,
                                                 label="F -> 0", index=fold.index))
    at = dict(fold.observables)
    ax = Figure().subplots()
    from types import SimpleNamespace

    contin.plot_branches(br, x="p", y="y", ax=ax, jumps=[(SimpleNamespace(p=fold.p), at, dict(at, y=at["y"] - 1e-9))])
    assert not [ln for ln in ax.lines if ln.get_marker() == "d"]
    assert len([ln for ln in ax.lines if ln.get_marker() == "o"]) == 1
    assert not arrows(ax)


def test_a_saved_run_whose_parameter_has_its_own_column_is_drawn_against_it(tmp_path: Path) -> None:
    """A volume-controlled run saves the volume change dV as its parameter's column and the pressure as "p":
    read back, the path's parameter is dV (``contin plot`` drew ΔV/V0 up to 10000 from the pressure)."""
    from contin.app.saved import load_run
    from tests.figure_check import write_saved_run

    dV, pressure = np.array([0.0, 0.01, 0.02]), np.array([0.0, 400.0, 300.0])
    summary = {"model": "shell", "parameter": "dV", "diagram": {"x": "dV", "y": "p_over_p_c"},
               "special_points": [{"kind": "fold", "parameter": "dV", "branch": 0, "p": 400.0,
                                   "observables": {"dV": 0.01, "p": 400.0, "p_over_p_c": 0.8}}]}
    out = write_saved_run(tmp_path / "vol", summary, {"branch": [0, 0, 0], "p": pressure, "dV": dV,
                                                       "p_over_p_c": pressure / 500.0, "s": [0.0, 1.0, 2.0]})
    br = load_run(out).branches[0]
    np.testing.assert_array_equal(br.p, dV)
    assert br.special_points[0].p == 0.01


def test_an_overlay_limited_to_one_runs_snaps_keeps_every_other_run_whole() -> None:
    """Overlaid with a run whose last branch rises to 100 after its snaps, a run whose whole path shows its
    snaps (the point load, down to F = -11) is not cut off by the limits chosen for the other."""
    from contin.plot.framing import Frame, combine

    whole_run = Frame(region=((0.0, 0.4), (-6.0, 11.6)), whole=((0.0, 0.6), (-11.2, 12.3)), farthest={})
    stiff_run = Frame(region=((0.0, 0.28), (0.0, 16.4)), whole=((0.0, 0.28), (0.0, 100.0)), farthest={})
    assert whole_run.layout is None and stiff_run.layout == "limits"
    both = combine([whole_run, stiff_run])
    assert both.layout == "limits"
    (x0, x1), (y0, y1) = both.detail
    assert y0 < -11.2 and 16.4 < y1 < 100.0 and x0 < 0.0 and x1 > 0.6


@pytest.mark.parametrize("scene", [[], ["load.kind=ring", "shell.boundary=clamped"]])
def test_the_written_figures_keep_every_text_inside_and_clear_of_the_panels(tmp_path: Path, capsys, monkeypatch,
                                                                            scene) -> None:
    """The diagram (one panel, or two with the snaps' detail) and the shapes figure, as written: titles, axis
    labels, tick labels and legends lie on the figure, no legend or text of one panel lies on another panel,
    and the panels keep most of the figure (their layout measures the texts once, as the constrained
    layout did)."""
    from contin.plot import style
    from tests.figure_check import CapturedFigures

    captured = CapturedFigures().install(monkeypatch)
    _trace(tmp_path, "run", *scene, capsys=capsys)
    for fig in captured.figures:
        fig.set_dpi(style.DPI)
        with style.context():
            fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        page = fig.bbox.padded(0.5)
        panels = [ax for ax in fig.axes if ax.axison]
        # (box, the panel it belongs to or None for the figure's own texts and the legends)
        boxes = [(t.get_window_extent(renderer), None) for t in fig.texts if t.get_text()]
        for ax in panels:
            boxes += [(t.get_window_extent(renderer), ax) for t in (ax.title, ax.xaxis.label, ax.yaxis.label)
                      if t.get_text()]
            boxes += [(axis.get_tightbbox(renderer), ax) for axis in (ax.xaxis, ax.yaxis)]  # tick labels drawn
            if ax.get_legend() is not None:
                boxes.append((ax.get_legend().get_window_extent(renderer), None))
        for box, _ in boxes:
            assert page.x0 <= box.x0 and box.x1 <= page.x1 and page.y0 <= box.y0 and box.y1 <= page.y1, box
        for ax in panels:
            inner = ax.get_window_extent(renderer).shrunk(0.98, 0.98)
            for box, owner in boxes:
                if owner is not ax:
                    assert not inner.overlaps(box), (ax, box)
        assert panels[0].get_position().width > 0.5


def test_a_snap_that_ends_the_path_is_drawn_to_its_landing() -> None:
    """A sweep that ends at a landing (a plate snapping onto the base ring) has no branch there: the axes
    must still reach the landing, or matplotlib drops the arrow that points off them."""
    import matplotlib

    matplotlib.use("Agg")
    from types import SimpleNamespace

    from matplotlib.figure import Figure

    from tests.figure_check import arrows

    br = _truss_branch()
    fold = next(s for s in br.special_points if s.kind == "fold")
    at = dict(fold.observables)
    landing = dict(at, y=-1.5)  # far below the loading branch, which stays above y = 0
    ax = Figure().subplots()
    contin.plot_branches(br, x="p", y="y", ax=ax, jumps=[(SimpleNamespace(p=fold.p), at, landing)])
    assert len(arrows(ax)) == 1
    assert ax.get_ylim()[0] <= -1.5 < at["y"] <= ax.get_ylim()[1]


def test_a_legend_of_many_branches_names_the_first_and_counts_the_rest() -> None:
    """A force-controlled trace through forty small snaps (a contact ring moving node by node) would list a
    legend taller than the figure."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from contin.plot.branches import MAX_BRANCH_ENTRIES

    br = _truss_branch()
    n = MAX_BRANCH_ENTRIES + 12
    ax = Figure().subplots()
    contin.plot_branches([br] * n, x="p", y="y", ax=ax, labels=[f"branch {k}" for k in range(n)])
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts[:MAX_BRANCH_ENTRIES - 1] == [f"branch {k}" for k in range(MAX_BRANCH_ENTRIES - 1)]
    assert texts[MAX_BRANCH_ENTRIES - 1] == f"and {n - MAX_BRANCH_ENTRIES + 1} more branches"
    assert "branch 8" not in texts
