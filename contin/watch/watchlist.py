"""The test functions a run watches, built from its settings, its events and its problem's operator families.

The kinds are defined beside what they need: folds, branch points and events in
:mod:`contin.watch.testfunctions`, the stability of operator families in :mod:`contin.watch.modes` (which
builds on the protocol of the first).  Assembling the list is kept apart from both, so neither imports
the other's module for it.
"""

from __future__ import annotations

from collections.abc import Sequence

from ..path.curve import Curve
from .events import Event
from .modes import ModeTest
from .testfunctions import BranchPointTest, EventTest, FoldTest, KnownBranchPoints, TestFunction, bound_events

__all__ = ["test_functions"]


def test_functions(curve: Curve, events: Sequence[Event | KnownBranchPoints] = ()) -> list[TestFunction]:
    """Everything a branch watches, in the order special points found on one step are reported."""
    st = curve.settings
    tests: list[TestFunction] = []
    if st.detect_folds:
        tests.append(FoldTest(curve))
    known = [ev for ev in events if isinstance(ev, KnownBranchPoints)]
    events = [ev for ev in events if not isinstance(ev, KnownBranchPoints)]
    if st.detect_branch_points:
        tests.append(BranchPointTest(curve, known[0] if known else None))
    tests += [EventTest(curve, ev) for ev in events]
    tests += [EventTest(curve, ev, bound=True) for ev in bound_events(st)]
    families = getattr(curve.problem, "operator_families", ())
    if families and st.stability:
        tests += [ModeTest(curve, family) for family in families]
    return tests


# pytest would otherwise collect the name starting with "test" when a test module imports it
test_functions.__test__ = False
