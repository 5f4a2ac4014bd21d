"""User events: crossings located to 1e-12 in the observable, directions, terminal events, bounds."""

import numpy as np
import pytest

from contin import continuation, crossing, extremum
from contin_models.benchmarks.bratu import Bratu
from contin_models.benchmarks.truss import VonMisesTruss


def test_crossing_located_to_1e_12_in_the_observable():
    pb = Bratu(200)
    br = continuation(pb, np.zeros(200), 0.0, ds=0.1, ds_max=1.0, bounds={"max_u": (None, 3.0)},
                      events=[crossing("max_u", 1.0), crossing("u_mid", 2.0), crossing("p", 2.5)])
    hits = br.events()
    assert sorted(e.label for e in hits) == ["max_u=1", "p=2.5", "p=2.5", "u_mid=2"]
    assert [e.s for e in hits] == sorted(e.s for e in hits)  # reported in path order
    for e in hits:
        assert e.located
        name, value = e.label.split("=")
        obs = e.p if name == "p" else pb.observables[name](e.u, e.p)
        assert abs(obs - float(value)) <= 1e-12
        assert np.max(np.abs(pb.residual(e.u, e.p))) <= br.meta["abs_tol"]


def test_direction_filters_and_terminal_event():
    pb = Bratu(100)
    kw = dict(ds=0.1, ds_max=1.0, bounds={"max_u": (None, 3.0)})
    up = continuation(pb, np.zeros(100), 0.0, events=[crossing("p", 2.5, direction=+1)], **kw)
    down = continuation(pb, np.zeros(100), 0.0, events=[crossing("p", 2.5, direction=-1)], **kw)
    assert len(up.events()) == 1 and up.events()[0].observables["max_u"] < 1.0
    assert len(down.events()) == 1 and down.events()[0].observables["max_u"] > 1.0
    stop = continuation(pb, np.zeros(100), 0.0, events=[crossing("max_u", 2.0, terminal=True)], **kw)
    assert stop.status == "event"
    assert stop.observables["max_u"][-1] == pytest.approx(2.0, abs=1e-12)
    assert stop.special_points[-1].kind == "event"


def test_extremum_of_an_observable_along_a_closed_form_path():
    tr = VonMisesTruss()
    # P(y) = 2 y (L0 / L - 1): the deflection b - y is extremal where y is, i.e. at the folds of P
    br = continuation(tr, [0.0, 0.5], 0.0, ds=0.02, ds_max=0.05, bounds={"y": (-0.8, None)},
                      events=[extremum("p", "max"), extremum("p", "min")])
    mx, mn = br.events("max(p)"), br.events("min(p)")
    assert len(mx) == 1 and len(mn) == 1
    folds = br.folds()
    assert mx[0].p == pytest.approx(folds[0].p, rel=1e-12)
    assert mn[0].p == pytest.approx(folds[1].p, rel=1e-12)


def test_parameter_bounds_end_exactly():
    tr = VonMisesTruss()
    # the weights of before the start-point calibration: under them Brent's bracket (locate_tol)
    # happens to end on the bound to 1e-14; under the calibrated ones it ends within locate_tol
    br = continuation(tr, [0.0, 0.5], 0.0, ds=0.02, ds_max=0.05, p_max=0.03, state_weight=1.0, param_weight=1.0)
    assert br.status == "bound" and br.p[-1] == pytest.approx(0.03, abs=1e-14)


def test_unknown_observable_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown observable 'nope'"):
        continuation(VonMisesTruss(), [0.0, 0.5], 0.0, events=[crossing("nope", 1.0)])


def test_only_an_extremum_declares_a_fold():
    import contin

    ev = contin.extremum("F", "max", folds="F", stability_label="force")
    assert (ev.kind, ev.folds, ev.stability_label, ev.direction) == ("extremum", "F", "force", -1)
    with pytest.raises(ValueError, match="extremum events only"):
        contin.Event("F", 1.0, folds="F")
