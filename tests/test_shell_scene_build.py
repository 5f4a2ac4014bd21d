"""The shell scene's public builders (contin_models.shell_scene.build): scene -> problem, settings, start."""

from __future__ import annotations

import math

import numpy as np
import pytest

import contin
from contin.app.scene import load_scene
from contin_models.contact import Plate, Sphere
from contin_models.contact.indentation import ShellIndentation
from contin_models.shell import ShellPointLoad
from contin_models.shell_scene import SHELL_SCHEMA, build, contact_settings, end_of_path, point_problem, point_settings


def _scene(*overrides: str) -> dict:
    return load_scene(SHELL_SCHEMA, None, ["shell.N=30", *overrides])


def test_point_scene_builds_the_point_load_under_its_control() -> None:
    b = build(_scene())
    assert isinstance(b.problem, ShellPointLoad) and b.problem.control == "displacement" and b.p0 == 0.0
    np.testing.assert_array_equal(b.u0, b.problem.reference_unknowns())
    assert b.w_end == pytest.approx(2 * (1 - math.sin(0.8)) * 1.05)
    assert b.settings.stability and b.settings.ds <= b.settings.ds_max <= 0.1
    forced = build(_scene("load.control=force"))
    assert forced.problem.parameter_name == "F" and forced.settings.param_weight < forced.settings.state_weight
    # the pieces agree with the whole
    assert point_settings(_scene(), point_problem(_scene())) == b.settings


def test_indenter_scenes_build_the_contact_problem() -> None:
    sphere = build(_scene("load.kind=sphere", "load.radius=0.3"))
    assert isinstance(sphere.problem, ShellIndentation) and isinstance(sphere.problem.indenter, Sphere)
    assert sphere.problem.indenter.radius == 0.3 and sphere.p0 == 0.0
    plate = build(_scene("load.kind=plate", "load.control=force"))
    assert isinstance(plate.problem.indenter, Plate)  # force control starts from displacement control
    st, w_end = contact_settings(_scene("load.kind=plate"))
    assert w_end == end_of_path(_scene()) and st == plate.settings
    assert st.ds == pytest.approx(0.25 * min(0.02, st.ds_max))  # the first contact is a corner: a quarter step


def test_a_built_scene_traces() -> None:
    b = build(_scene("shell.phi_hat=1.2"))
    br = contin.continuation(b.problem, b.u0, b.p0, b.settings, p_max=b.w_end)
    assert br.status == "bound" and br.p[-1] == pytest.approx(b.w_end)
