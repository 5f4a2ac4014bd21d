"""Phase boundaries traced by fold continuation (issue 5) against the classification itself.

* The bistable/monostable boundary at ``h/R = 0.02``, located as an event on the traced curve (the
  fold of the unloaded cap continued in ``phi_hat``, force-control machinery), agrees to 1e-4 in
  ``phi_hat`` with a bisection on ``contin classify``'s class (the displacement-controlled path and its
  ``F < 0`` test): two independent routes to the same number on the same mesh.
* The monostable/monotonous boundary (the cusp curve) at ``h/R = 0.02`` lies between a cap the
  classifier calls monostable and one it calls monotonous, ``1e-3`` in ``phi_hat`` either side.
* At the located cusp of that curve, ``F_max - F_min`` vanishes like the 3/2 power of the distance in
  the second parameter (here ``phi_hat`` at fixed ``h/R``), the cusp normal form.  (The same law in
  ``h`` at fixed ``phi_hat`` is in ``tests/test_twopar.py``.)
* ``python -m studies.phase_diagram`` runs end to end in its fast mode and writes what it promises.
  The default run gives the study the boundaries traced once here (the same call at the same ``N``)
  and classifies only the shallow half of its grid (``phi_hat > 1``: every class, both boundaries); the
  whole fast grid, whose deep thin caps cost four fifths of its time, runs under ``-m slow``.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import contin
from contin.app.scene import load_scene
from contin_models.shell import boundaries as B
from contin_models.shell_scene import SHELL_SCHEMA, classify_scene
from studies import phase_diagram
from tests.cusp_check import assert_three_halves_law

N = 60
H_MARK = 0.02


def _class(phi: float, h: float = H_MARK) -> str:
    scene = load_scene(SHELL_SCHEMA, None, [f"shell.N={N}", f"shell.phi_hat={phi!r}", f"shell.h={h!r}"])
    c = classify_scene(scene)
    assert c.success, c.failure
    return c.label


@pytest.fixture(scope="module")
def curves():
    # both boundaries over the phase diagram's phi_hat range with h/R = H_MARK located as "h_mark":
    # the study's own call, traced once for this module (and handed to the study's run below)
    return phase_diagram.trace_boundaries(N, H_MARK)


def _phi_mark(curve) -> float:
    (hit,) = [e for br in curve.branches for e in br.events("h_mark")]
    return float(hit.p)


@pytest.mark.slow
def test_bistable_boundary_agrees_with_bisection_on_the_classification(curves):
    lo, hi = 1.0, 1.2
    assert _class(lo) == "bistable" and _class(hi) == "monostable"
    while hi - lo > 2e-5:
        mid = 0.5 * (lo + hi)
        if _class(mid) == "bistable":
            lo = mid
        else:
            hi = mid
    phi_traced = _phi_mark(curves["bistable"])
    assert abs(phi_traced - 0.5 * (lo + hi)) < 1e-4
    # and the traced point is the unloaded cap's fold: F = 0 there, to the boundary's own tolerance
    assert np.all(curves["bistable"].F_norm == 0.0)


@pytest.mark.slow
def test_monotonous_boundary_separates_the_classes(curves):
    phi_c = _phi_mark(curves["monotonous"])
    assert _class(phi_c - 1e-3) == "monostable"
    assert _class(phi_c + 1e-3) == "monotonous"


@pytest.mark.slow
def test_cusp_three_halves_law_in_phi(curves):
    """At h/R = 0.02 the folds F_max, F_min of the force path merge at phi_c: their gap ~ (phi_c - phi)^(3/2)."""
    phi_c = _phi_mark(curves["monotonous"])
    s = math.log(H_MARK)
    phi0 = phi_c - 0.02
    P = B.thickness_member(phi0, s, N)
    f_max = B.force_folds(P, 1)[0]
    fc = contin.FoldCurveProblem(lambda phi: B.thickness_member(phi, s, N), f_max, phi0, q_name="phi_hat",
                                 p_scale=10 * 2 * math.pi * P.D, q_step=1e-4)
    distances = (1e-4, 2e-4, 4e-4, 8e-4)
    events = [contin.crossing("phi_hat", phi_c - d, name=f"d={d:g}") for d in distances]
    br = contin.continuation(fc, fc.start, phi0, ds=0.002, ds_max=0.005, stability=False, max_steps=400,
                             p_min=phi0 - 0.01, p_max=phi_c + 0.01, events=events)
    (cusp,) = [s_ for s_ in br.special_points if s_.kind == "fold"]
    assert cusp.p == pytest.approx(phi_c, abs=1e-5)  # the cusp curve and this fold curve meet there
    assert_three_halves_law(fc, br, distances)


def _check_study_outputs(out) -> dict:
    for name in ("phase_diagram.png", "phase_diagram.pdf", "boundaries.csv", "grid.csv", "summary.json"):
        assert (out / name).stat().st_size > 0
    s = json.loads((out / "summary.json").read_text())
    for kind in ("bistable", "monotonous"):
        assert set(s["lambda_d"][kind]) == {"value", "stderr"}
        assert s["lambda_d"][kind]["stderr"] > 0
    assert s["eq41_form"] in ("squared", "literal")
    assert set(s["phi_c_at_h_0.02"]) == {"bistable", "monotonous"}
    assert s["agreement"]["consistent"] and s["agreement"]["agree"] > 0.9 * s["agreement"]["cells"]
    # the fitted lambda_d is the depth parameter at the located boundary crossing, to the scatter of
    # lambda along the curve (about 1 % over the fitted range): an independent read of the same curve
    for kind in ("bistable", "monotonous"):
        lam_mark = B.depth_parameter(s["phi_c_at_h_0.02"][kind], H_MARK)
        assert lam_mark == pytest.approx(s["lambda_d"][kind]["value"], rel=0.02)
    return s


@pytest.mark.slow
def test_phase_diagram_study_runs_in_fast_mode(tmp_path, curves, monkeypatch):
    """The study's main in fast mode, with its boundaries traced once (``curves``) and the shallow grid."""
    real_grid = phase_diagram.classify_grid

    def traced(n: int, h_mark: float = H_MARK):
        assert (n, h_mark) == (N, H_MARK)  # the fast mode's call: the module's curves are its result
        return curves

    def shallow_grid(n, phis, hs, *args, **kwargs):
        return real_grid(n, [p for p in phis if p > 1.0], hs, *args, **kwargs)

    monkeypatch.setattr(phase_diagram, "trace_boundaries", traced)
    monkeypatch.setattr(phase_diagram, "classify_grid", shallow_grid)
    # in this process: the sweep's worker processes are covered by the slow run and tests/test_executors.py
    assert phase_diagram.main(["--out", str(tmp_path), "-q", "--workers", "1"]) == 0
    s = _check_study_outputs(tmp_path)
    assert s["agreement"]["cells"] == 5 * 7  # five columns of the 10 x 7 grid have phi_hat > 1
    # the shallow columns hold every class, so both boundaries are crossed by the grid and fitted from it
    assert set(s["routes"]["grid"]) == {"bistable", "monotonous"}


@pytest.mark.slow
def test_phase_diagram_study_runs_in_fast_mode_whole_grid(tmp_path):
    """The same, unpatched: the study traces its own boundaries and classifies the whole 10 x 7 grid."""
    assert phase_diagram.main(["--out", str(tmp_path), "-q"]) == 0
    s = _check_study_outputs(tmp_path)
    assert s["agreement"]["cells"] == 10 * 7


def test_bistable_boundary_builds_only_the_members_it_evaluates(monkeypatch):
    """The fold curve makes the thickness family anew at every phi_hat it visits; each family builds the
    members it evaluates (the state and its finite-difference neighbours in ln h and phi_hat), and takes
    its names and settings from one shared member instead of building one more at its start for them."""
    built, evaluated = [], set()
    member = B.thickness_member

    def counted(*args, **kwargs):
        built.append(member(*args, **kwargs))
        return built[-1]

    for name in ("residual", "jacobian", "dresidual_dp"):
        def marked(self, u, p, _real=getattr(B.DisplacementForm, name)):
            evaluated.add(id(self))
            return _real(self, u, p)

        monkeypatch.setattr(B.DisplacementForm, name, marked)

    def observable(self, fun):  # an observable read counts as a use too
        return lambda u, p: (evaluated.add(id(self)), fun(u + self.origin, p))[1]

    monkeypatch.setattr(B.DisplacementForm, "_wrap", observable)
    monkeypatch.setattr(B, "thickness_member", counted)
    curve = B.bistable_boundary(N, phi_range=(0.97, 1.03))
    assert curve.phi_hat[0] == pytest.approx(0.97) and curve.phi_hat[-1] == pytest.approx(1.03)
    unused = [P for P in built if id(P) not in evaluated]
    assert len(built) > 50 and len(unused) <= 1, (len(built), len(unused))  # at most the shared one
