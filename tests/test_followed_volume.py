"""The path a shell really takes under a prescribed volume: the views under volume control, the snap on the constraint."""

import dataclasses

import numpy as np
import pytest

import contin
from contin.app.scene import load_scene
from contin_models.shell.constrained_snap import jump_on_constraint
from contin_models.shell.followed import follow_path
from contin_models.shell.lift import VolumeView, follow_waves
from contin_models.shell_scene.build import build, pressure_settings, traced_structure, travel
from contin_models.shell_scene.pressure import volume_problem, volume_settings
from contin_models.shell_scene.schema import SHELL_SCHEMA

STOPS = ("fold", "branch_point", "bifurcation")


def _scene(N: int, harmonics: bool = True) -> dict:
    """The clamped default cap under a prescribed volume (view.harmonics = 2)."""
    return load_scene(SHELL_SCHEMA, None, ["load.kind=pressure", "load.control=displacement", "shell.boundary=clamped",
                                           f"shell.N={N}", f"stability.harmonics={str(harmonics).lower()}",
                                           "view.harmonics=2"])


def _volume(scene: dict):
    """The traced model under the prescribed volume, its settings and its unloaded start, as the scene builds them."""
    b = build(scene)
    source = volume_problem(b.problem, travel(scene))
    U0, q0 = source.from_load_state(b.u0, b.p0)
    return b, source, volume_settings(scene, source), U0, q0


def _equilibrium_under_pressure(view: VolumeView, U: np.ndarray, dV: float) -> tuple[float, float]:
    """The residual of the pressure-controlled view at a volume-controlled state's pressure (relative to its scale),
    and how far its volume change is from ``dV`` (relative): both without the volume-controlled problem."""
    base = view.base
    x, p = view.split(U)
    c = base.full_state(x, p)
    residual = float(np.max(np.abs(base.residual(x, p)))) / base.residual_scale
    volume_change = base.view.volume(base.c_ref) - base.view.volume(c)
    return residual, abs(volume_change - dV) / abs(dV)


def test_the_path_under_a_prescribed_volume_leaves_where_the_pressure_controlled_blocks_bifurcate() -> None:
    scene = _scene(30)
    # the pressure-controlled trace of the same cap, its harmonic blocks watched: the first bifurcation into waves
    b = build(scene)
    st = dataclasses.replace(pressure_settings(scene, b.problem), stop_at=("bifurcation",))
    pressure_path = contin.continuation(b.problem, b.u0, b.p0, st)
    under_pressure = pressure_path.special_points[-1]
    assert under_pressure.kind == "bifurcation" and under_pressure.info["family"] == "n"

    _, source, settings, U0, q0 = _volume(scene)
    fp = follow_path(source, U0, q0, settings, structure=traced_structure(scene, b.problem), label="volume", K=2,
                     p_end=float(settings.p_max), max_pieces=1)
    first = fp.pieces[0]
    stop = first.branch.special_points[-1]
    # the same state as the pressure-controlled trace's bifurcation: the same wave number, pressure and deflection
    assert first.end == "bifurcation" and stop.info["key"] == under_pressure.info["key"]
    assert stop.observables["p"] == pytest.approx(under_pressure.p, rel=1e-6)
    assert stop.observables["w"] == pytest.approx(under_pressure.observables["w"], rel=1e-6)
    # every stored point before it is stable under the prescribed volume (the located point is singular)
    assert np.all(np.asarray(first.branch.n_negative_under("volume"))[:-1] == 0)

    # onto the n-wave branch in the D_n view under the prescribed volume, as the path does
    probe = dataclasses.replace(settings, max_steps=4, stability=True)
    waves = follow_waves(source, stop, 2, structure=traced_structure(scene, b.problem), settings=probe,
                         every_mode=True)
    view = waves.problem
    assert isinstance(view, VolumeView) and view.basis.n == int(stop.info["key"])
    assert abs(waves.branch_point.info["moved_p"]) < 1e-9 * stop.p
    assert len(waves.branch) >= 2
    for U, dV in zip(waves.branch.u, waves.branch.p):
        residual, volume_error = _equilibrium_under_pressure(view, np.asarray(U), float(dV))
        assert residual < 1e-8 and volume_error < 1e-10
    # its waves turn back in the volume as they do in the pressure: a subcritical branch, which the path snaps from
    assert waves.branch.p[-1] < stop.p and waves.branch.observables["p"][-1] < stop.observables["p"]


def test_a_snap_at_a_prescribed_volume_lands_on_the_traced_path_at_that_volume() -> None:
    scene = _scene(30, harmonics=False)
    _, source, settings, U0, q0 = _volume(scene)
    path = contin.continuation(source, U0, q0, dataclasses.replace(settings, stop_at=("fold",)))
    fold = path.special_points[-1]
    assert fold.kind == "fold" and fold.info.get("parameter", "dV") in ("dV", None)
    q = fold.p * (1.0 + 1e-6)
    jr = jump_on_constraint(source, fold.u, q)
    assert jr.success and jr.n_negative == 0 and jr.energy_to < jr.energy_from
    # independently of the descent: an equilibrium under the pressure it ends at, with the prescribed volume change
    x, p = source.split(jr.u_to)
    base = source.base
    assert float(np.max(np.abs(base.residual(x, p)))) < 1e-8 * base.residual_scale
    assert -float(base.conjugate_force(x, p)) == pytest.approx(q, rel=1e-10)
    # and the traced path, followed on past the fold, comes back through this volume at a stable state there
    on = contin.continuation(source, U0, q0, dataclasses.replace(settings, stop_at=()))
    dV, w = np.asarray(on.p), np.asarray(on.observables["w"])
    stable = np.asarray(on.n_negative_under("volume")) == 0
    i_fold = int(np.argmin(np.abs(dV - fold.p)))
    later = [i for i in range(i_fold + 1, len(on) - 1)
             if (dV[i] - q) * (dV[i + 1] - q) <= 0.0 and stable[i] and stable[i + 1]]
    assert later
    i = later[0]
    w_path = w[i] + (w[i + 1] - w[i]) * (q - dV[i]) / (dV[i + 1] - dV[i])
    w_landed = float(source.evaluate_observables(jr.u_to, q)["w"])
    assert w_landed == pytest.approx(w_path, rel=1e-2)


@pytest.mark.slow
def test_the_followed_path_under_a_prescribed_volume_reaches_eversion_on_stable_states() -> None:
    scene = _scene(40)
    b, source, settings, U0, q0 = _volume(scene)
    fp = follow_path(source, U0, q0, settings, structure=traced_structure(scene, b.problem), label="volume", K=2,
                     p_end=float(settings.p_max), end=("w", float(settings.bounds["w"][1])))
    assert fp.success, fp.message
    # it snaps at the five-wave bifurcation, off the axisymmetric path, and comes back to it before eversion
    assert fp.snaps and fp.pieces[0].end == "bifurcation" and fp.pieces[1].symmetry != "O(2)"
    assert fp.pieces[-1].symmetry == "O(2)"
    for piece in fp.pieces:
        br = piece.branch
        located = piece.end in STOPS
        counts = np.asarray(br.n_negative_under("volume"))
        assert np.all(counts[: len(br) - (1 if located else 0)] == 0)
        if isinstance(piece.problem, VolumeView):
            for U, dV in zip(br.u[::5], br.p[::5]):
                residual, volume_error = _equilibrium_under_pressure(piece.problem, np.asarray(U), float(dV))
                assert residual < 1e-8 and volume_error < 1e-10
    for snap in fp.snaps:  # a snap keeps the volume: it lands at the volume just past the point it leaves
        before, after = fp.pieces[snap.from_piece].branch, fp.pieces[snap.to_piece].branch
        assert after.p[0] == pytest.approx(snap.p, rel=1e-12)
        assert snap.p == pytest.approx(before.p[-1], rel=1e-5)
