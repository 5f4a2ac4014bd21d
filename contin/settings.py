"""Options of the continuation engine: :class:`Settings` and the checks on their ranges."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import Any

__all__ = ["Settings", "SettingsError", "ROUNDOFF_FLOOR", "resolve_settings"]

#: Smallest relative tolerance ``tol`` and ``xtol`` accepted.  A residual component is a sum of a
#: few tens of terms of size ``residual_scale`` (the element contributions meeting at a node), each
#: rounded to a relative ``eps`` = 2.2e-16, so a converged residual is only known to about
#: ``n_terms * eps * residual_scale``, i.e. 1e-15 to 1e-14 of the scale; a Newton update of a
#: converged point is likewise rounding noise of that relative size.  A tolerance below 1e-14 asks for
#: digits below that noise: the corrector would iterate on noise and fail at the first point.
ROUNDOFF_FLOOR = 1e-14


class SettingsError(ValueError):
    """A continuation setting out of its range; the message names the field and the allowed range."""


@dataclass
class Settings:
    """Options of :func:`continuation` (every field can also be passed as a keyword).

    Attributes
    ----------
    ds, ds_min, ds_max : float
        Initial, minimum and maximum step in the weighted arclength norm.
    max_steps : int
        Maximum number of accepted steps; the run stops there with status ``"max_steps"``.  0 corrects the
        start point and records it with its stability alone.
    stall_steps : int
        0 (the default): off.  Otherwise the run also stops, with status ``"stalled"``, once this
        many accepted steps in a row brought no progress: no special point found (a fold, a branch
        point, an event) and no bound (``p_min``, ``p_max``, ``bounds``) approached closer than
        before.  A path that winds through many folds on its way to a bound keeps finding them; one
        that runs away from every bound without a feature does not.  With it, ``max_steps`` is the
        hard cap of a path that keeps progressing.
    direction : int
        +1 to start with increasing parameter, -1 decreasing.
    p_min, p_max : float
        Parameter bounds; the run stops exactly on a bound (located like an event).
    bounds : dict
        Observable bounds ``{name: (low, high)}`` (either may be None); the run stops exactly on them.
    tol : float
        Relative residual tolerance: a stored point has ``max|f| <= tol * problem.residual_scale``.
        At least :data:`ROUNDOFF_FLOOR`.
    xtol : float
        Newton-update tolerance: a point is accepted only once its estimated error (the last
        corrector update, times the observed contraction rate once there is one) is below
        ``xtol * (1 + ||X||)`` in the arclength norm.  Both tests must hold: in ill-conditioned
        discretizations a small residual alone does not pin the solution down.
    max_newton : int
        Corrector iterations before a step is declared failed.
    fast_newton : int
        The step grows when the corrector needed at most this many iterations.
    target_contraction : float
        Step-size control by the corrector's first contraction rate ``theta = |dX_2| / |dX_1|``:
        the next step is scaled by ``sqrt(target_contraction / theta)`` (within ``shrink`` and
        ``grow``), since ``theta`` grows like the step for a Newton corrector.  Steps that sit at
        the rate where the corrector starts to fail are avoided instead of repeatedly retried.
    grow, shrink : float
        Step-size factors after an easy step and after a failed one.
    state_weight, param_weight : float or None
        Weights of the state (RMS) and parameter parts of the arclength norm.  None (the default)
        chooses them from the start point as ``1 / U`` and ``1 / P``, the state and parameter scales
        of :func:`contin.path.scales.start_scales`: the steps are then fractions of the problem's own
        sizes, and the same model in other units takes the same steps.  A problem that gives its
        own ``residual_scale`` is taken to be in its own units: open weights are then 1.
    check_model : bool
        Before stepping, probe the residual along the first tangent and one random direction and
        compare with the Jacobian and ``df/dp`` (:func:`contin.modelkit.check.quick_check`); a model whose
        derivatives disagree with its residual stops the run with status ``"failed"``.
    max_correction : float
        Guard against branch jumping: the corrector may move at most this multiple of the step away
        from the predicted point.
    max_contraction : float
        Guard against branch jumping: from the second corrector iteration on, each Newton update
        must be at most this fraction of the previous one; a slowly contracting corrector started
        between branches and may end on the wrong one, so the step is retried smaller.
    max_chord_rate : float
        After the corrector's first (Newton) update, later updates reuse its linearization (chord
        updates: one solve and no new Jacobian) while each shrinks the update by at least this
        factor; a slower one is replaced by a Newton update from a new linearization.  0 gives
        Newton's method throughout.
    min_tangent_cos : float
        Guard against branch jumping: consecutive unit tangents must have at least this cosine.
    target_angle : float
        Curvature control: the next step is scaled so that the tangent turns by about this angle
        (radians) per step, keeping the predictor error small compared with the local curvature.
    detect_folds, detect_branch_points, locate : bool
        Which test functions run, and whether special points are located (else only bracketed).
    stability : bool
        Compute the stability operator's inertia and smallest eigenvalues at every point.
    watch_index : bool
        For a symmetric problem, count the Morse index of its primary stability operator at every
        accepted point (one pivot-free factorization, shared with ``stability``) and explain each change
        by the folds and branch points found on the step; a change they do not explain is bisected and
        located: a multiple branch point (reported with its multiplicity and kernel), a point the sign
        tests missed, or a step that jumped to another branch (rejected).  Off, a double branch point
        of a symmetric structure passes unseen.
    n_eigs : int
        Number of smallest eigenvalues stored per point.  0 stores only the Morse index, which for
        a sparse (banded) operator costs one pivot-free factorization per point, O(n), instead of
        a banded eigensolve: O(n^2 b) by LAPACK, or for a large band (``n^2 b`` above
        ``contin.numerics.stability.SHIFT_INVERT_WORK``) Lanczos in shift-invert mode, a few O(n b^2)
        factorizations.
    locate_tol : float
        Relative tolerance of the arclength root-finding that locates events and branch points.
    store_states : bool
        Keep every state vector (False keeps only the special points' states and the last one).
    stop_at : tuple of str
        Special point kinds (``"fold"``, ``"branch_point"``) that end the run; the run then ends
        exactly on the first located one (e.g. load until the structure snaps).
    progress : bool
        Print a progress line every ``progress_every`` steps to stderr.
    """

    ds: float = 0.02
    ds_min: float = 1e-9
    ds_max: float = 0.2
    max_steps: int = 1000
    stall_steps: int = 0
    direction: int = 1
    p_min: float = -math.inf
    p_max: float = math.inf
    bounds: dict[str, tuple[float | None, float | None]] = field(default_factory=dict)
    tol: float = 1e-10
    xtol: float = 1e-10
    max_newton: int = 10
    fast_newton: int = 4
    target_contraction: float = 0.1
    grow: float = 1.5
    shrink: float = 0.5
    state_weight: float | None = None
    param_weight: float | None = None
    max_correction: float = 0.5
    max_contraction: float = 0.5
    max_chord_rate: float = 0.0
    min_tangent_cos: float = 0.9
    target_angle: float = 0.15
    detect_folds: bool = True
    detect_branch_points: bool = True
    locate: bool = True
    stability: bool = False
    watch_index: bool = True
    n_eigs: int = 3
    locate_tol: float = 1e-10
    store_states: bool = True
    stop_at: tuple[str, ...] = ()
    progress: bool = False
    progress_every: int = 25
    check_model: bool = True

    def validate(self) -> None:
        """Raise :class:`SettingsError` (a ``ValueError``) naming the field and its range if one is out of range."""
        def need(cond: bool, name: str, rule: str) -> None:
            if not cond:
                raise SettingsError(f"continuation setting {name!r} = {getattr(self, name)!r} is invalid: {rule}")
        need(self.ds_min > 0, "ds_min", "must be > 0")
        need(self.ds_max >= self.ds_min, "ds_max", "must be >= ds_min")
        need(self.ds_min <= self.ds <= self.ds_max, "ds", "must lie in [ds_min, ds_max]")
        need(self.max_steps >= 0, "max_steps", "must be >= 0 (0: the start point alone)")
        need(self.stall_steps >= 0, "stall_steps", "must be >= 0 (0: off)")
        need(self.direction in (-1, 1), "direction", "must be +1 or -1")
        need(self.p_min < self.p_max, "p_min", "must be < p_max")
        floor = f"must be >= {ROUNDOFF_FLOOR:g} (the roundoff floor of a relative tolerance) and < 1"
        need(ROUNDOFF_FLOOR <= self.tol < 1, "tol", floor)
        need(ROUNDOFF_FLOOR <= self.xtol < 1, "xtol", floor)
        need(self.max_newton >= 1, "max_newton", "must be >= 1")
        need(self.grow >= 1, "grow", "must be >= 1")
        need(0 < self.shrink < 1, "shrink", "must lie in (0, 1)")
        w_u, w_p = (1.0 if w is None else w for w in (self.state_weight, self.param_weight))
        need(w_u >= 0 and w_p >= 0 and w_u + w_p > 0, "state_weight", "weights must be None or >= 0, and not both 0")
        need(0 < self.max_correction, "max_correction", "must be > 0")
        need(-1 <= self.min_tangent_cos < 1, "min_tangent_cos", "must lie in [-1, 1)")
        need(0 < self.max_contraction < 1, "max_contraction", "must lie in (0, 1)")
        need(0 <= self.max_chord_rate < 1, "max_chord_rate", "must lie in [0, 1)")
        need(0 < self.target_contraction <= self.max_contraction, "target_contraction",
             "must lie in (0, max_contraction]")
        need(0 < self.target_angle < math.pi / 2, "target_angle", "must lie in (0, pi/2)")
        need(self.n_eigs >= 0, "n_eigs", "must be >= 0")


def resolve_settings(settings: Settings | None, overrides: dict[str, Any]) -> Settings:
    """``settings`` (default: :class:`Settings`) with keyword ``overrides`` applied, validated.

    Raises
    ------
    TypeError
        An override that is not a field of :class:`Settings`.
    SettingsError
        A setting out of range (:meth:`Settings.validate`).
    """
    unknown = set(overrides) - {f.name for f in fields(Settings)}
    if unknown:
        raise TypeError(f"unknown continuation option(s): {', '.join(sorted(unknown))}")
    st = replace(settings or Settings(), **overrides)
    st.validate()
    return st
