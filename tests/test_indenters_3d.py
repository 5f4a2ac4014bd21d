"""Key numbers of ``studies.indenters_3d``: the snap of a one-sided indentation is a force-free equilibrium."""

from __future__ import annotations

from studies.indenters_3d import axisymmetric_snap_meridian, meridian_distance


def test_the_point_and_the_plate_let_go_of_the_same_force_free_state() -> None:
    """The paper's universal snap configuration: where a one-sided contact lets go, the force is zero, so the shell
    is in an unloaded equilibrium, whichever indenter touched it.  The point load reaches it at its pole (w/R =
    0.40), the plate on the ring of its highest points (w_b/R = 0.23): two runs of different problems (the point
    force, the plate's contact barrier) meet the same state."""
    point = axisymmetric_snap_meridian("point", None, 40, 2)
    plate = axisymmetric_snap_meridian("plate", None, 40, 2)
    assert meridian_distance(point, plate) < 1e-6  # R = 1
    assert point[1][-1] < plate[1].max() - 0.1  # the pole lies well below the crest the plate touches
