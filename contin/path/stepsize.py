"""Step-size control of pseudo-arclength continuation: :class:`StepController`.

After an accepted step the next one is scaled by the corrector's effort and by the curvature:

* contraction rate: with a known first contraction rate ``theta`` (and a corrector that did not
  need nearly all its iterations) the step is scaled by ``sqrt(target_contraction / theta)``
  within ``[shrink, grow]``, since ``theta`` grows like the step for a Newton corrector;
* otherwise Newton effort: grow after at most ``fast_newton`` iterations, shrink after at least
  ``max_newton - 2``;
* curvature: when the tangent turned by more than ``target_angle`` the step shrinks so that it
  would turn by about that angle.

A rejected step (corrector failure or a guard against branch jumping) halves the step (``shrink``)
and is counted by reason; the run stops when the step would fall below ``ds_min``.  ``retries``
counts the rejections since the last accepted step (a guard that may fire on a genuine feature of
the curve gives up after a few).
"""

from __future__ import annotations

import math
import re

from ..settings import Settings

__all__ = ["StepController"]

_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


class StepController:
    """The current step size and the rules that change it.

    Parameters
    ----------
    settings : Settings

    Attributes
    ----------
    ds : float
        Step for the next attempt.
    rejections : dict of str to int
        Rejected attempts by reason (the failure message up to its first detail).
    """

    def __init__(self, settings: Settings) -> None:
        self.settings = settings
        self.ds = settings.ds
        self.rejections: dict[str, int] = {}
        self.retries = 0

    def reject(self, reason: Exception | str) -> bool:
        """Count a rejected step and shrink; False when the step would fall below ``ds_min``."""
        # the reason without its details and numbers, so that like rejections count together
        key = _NUMBER.sub("#", str(reason).split(" (")[0].split(";")[0])
        self.rejections[key] = self.rejections.get(key, 0) + 1
        self.retries += 1
        if self.ds * self.settings.shrink < self.settings.ds_min:
            return False
        self.ds *= self.settings.shrink
        return True

    def accept(self, iterations: int, contraction: float | None, cos_turn: float) -> None:
        """Adapt the step after an accepted one.

        Parameters
        ----------
        iterations : corrector iterations of the step.
        contraction : its first contraction rate (None when unknown).
        cos_turn : cosine of the angle between the tangents at the two ends of the step.
        """
        st, ds = self.settings, self.ds
        self.retries = 0
        if contraction is not None and iterations <= st.max_newton - 3:
            factor = math.sqrt(st.target_contraction / contraction) if contraction > 0 else st.grow
            ds = min(max(ds * min(max(factor, st.shrink), st.grow), st.ds_min), st.ds_max)
        elif iterations <= st.fast_newton:
            ds = min(ds * st.grow, st.ds_max)
        elif iterations >= st.max_newton - 2:
            ds = max(ds * st.shrink, st.ds_min)
        angle = math.acos(min(1.0, max(-1.0, cos_turn)))
        if angle > st.target_angle:
            ds = max(ds * max(st.target_angle / angle, st.shrink), st.ds_min)
        self.ds = ds
