"""User events: an observable crossing a value, or an extremum of an observable along the branch.

Modelled on ``scipy.integrate.solve_ivp`` events: plain data with a ``direction`` and a ``terminal``
flag.  Events are located on the branch to the precision of the corrector (a root of the event
function on the curve, not an interpolation between stored points).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["Event", "crossing", "extremum"]


@dataclass
class Event:
    """An event to detect and locate during continuation.

    Attributes
    ----------
    observable : str or callable
        Name of an observable of the problem, the parameter name / ``"p"``, or a callable ``(u, p)``.
    value : float
        Crossing value (ignored for extrema).
    direction : int
        ``+1``: only when the test function increases along the path; ``-1``: only when it
        decreases; ``0``: both.  For an extremum the test function is the derivative of the
        observable along the path, so ``-1`` selects maxima and ``+1`` minima.
    terminal : bool
        Stop the continuation at this event.
    name : str
        Label of the resulting special points.
    kind : {"crossing", "extremum"}
        What the event tests.
    folds : str, optional
        For an extremum: the quantity that has a limit point (fold) there when it is the load, e.g.
        ``"F"`` for an extremum of the force along a displacement-controlled path, which is a limit
        point of the force-controlled problem.  Recorded as ``info["folds"]`` of the special point.
    stability_label : str, optional
        For an extremum that is a fold: the stability label (of the problem's stability operators)
        under which it is one (e.g. ``"force"``).  The special point's ``stable_before`` /
        ``stable_after`` / ``n_negative_before`` / ``n_negative_after`` are then given under this
        label (``info["stability"]`` has them under every label).
    """

    observable: str | Callable[[np.ndarray, float], float]
    value: float = 0.0
    direction: int = 0
    terminal: bool = False
    name: str | None = None
    kind: str = "crossing"
    folds: str | None = None
    stability_label: str | None = None

    def __post_init__(self) -> None:
        if self.kind not in ("crossing", "extremum"):
            raise ValueError(f"Event.kind must be 'crossing' or 'extremum', got {self.kind!r}")
        if self.kind != "extremum" and (self.folds is not None or self.stability_label is not None):
            raise ValueError("Event.folds and Event.stability_label apply to extremum events only")
        if self.direction not in (-1, 0, 1):
            raise ValueError(f"Event.direction must be -1, 0 or +1, got {self.direction!r}")
        if self.name is None:
            obs = self.observable if isinstance(self.observable, str) else getattr(self.observable, "__name__", "g")
            self.name = f"{obs}={self.value:g}" if self.kind == "crossing" else f"extremum({obs})"

    def triggered(self, before: float, after: float) -> bool:
        """Whether the test function changed sign between two consecutive points."""
        if not (np.isfinite(before) and np.isfinite(after)):
            return False
        if before == 0.0:
            return False  # a zero at a stored point was reported when it was reached
        if (before < 0) == (after < 0) and after != 0.0:
            return False
        rising = after > before
        return self.direction == 0 or (self.direction > 0) == rising


def crossing(observable, value: float, direction: int = 0, terminal: bool = False,
             name: str | None = None) -> Event:
    """Event: ``observable`` crosses ``value`` (with an optional direction)."""
    return Event(observable, float(value), direction, terminal, name, "crossing")


def extremum(observable, which: str = "any", terminal: bool = False, name: str | None = None, *,
             folds: str | None = None, stability_label: str | None = None) -> Event:
    """Event: ``observable`` has a local extremum along the branch (``which`` = max, min or any).

    ``folds`` names the quantity that has a limit point there (``extremum("F", folds="F",
    stability_label="force")``: a force extremum along a displacement-controlled path is a limit
    load); see :class:`Event`.
    """
    direction = {"any": 0, "max": -1, "min": +1}.get(which)
    if direction is None:
        raise ValueError(f"extremum(which=...) must be 'any', 'max' or 'min', got {which!r}")
    obs_name = observable if isinstance(observable, str) else getattr(observable, "__name__", "g")
    if name is None:
        name = f"{which}({obs_name})" if which != "any" else f"extremum({obs_name})"
    return Event(observable, 0.0, direction, terminal, name, "extremum", folds, stability_label)
