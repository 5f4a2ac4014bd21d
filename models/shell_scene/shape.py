"""The scene's reference shape: ``shell.geometry`` and ``[imperfection]`` -> a reference meridian.

Geometries (``docs/model.md#geometry``), each from its edge (node 0) to its pole on the axis:

``"sphere"`` (default)
    the spherical cap of radius ``shell.R`` whose edge is at ``shell.phi_hat`` from the equator (the
    paper's cap); length scale ``R``.
``"cone"``
    a cone of base radius ``shell.a`` and rise ``shell.H``; length scale ``a``.
``"plate"``
    a flat disc of radius ``shell.a``; length scale ``a``.
``"ellipse"``
    the cap of the spheroid with radial semi-axis ``shell.a`` and axial semi-axis ``shell.b`` from the
    parametric angle ``shell.t_edge`` (0: the equator) to the pole; length scale ``a^2 / b``, the
    radius of curvature at the pole.
``"torus"``
    a torispherical head: a toroidal knuckle of radius ``shell.knuckle`` from the edge (radius
    ``shell.a``, vertical tangent there, as where a head meets its cylinder) joined tangentially to a
    spherical crown of radius ``shell.R``; length scale ``R``.
``"table"``
    the profile tabulated in the CSV file ``shell.table`` (two columns ``r, z``, from the edge to the
    pole, which must be on the axis; a header line is allowed), interpolated by a spline; length
    scale its largest radius.

The classical pressure ``p_c = 2 E (h/L)^2 / sqrt(3 (1 - nu^2))`` of a scene uses its length scale
``L`` (for the sphere, the cap's ``R``).  The rise ``H`` is the pole's height above the edge; the
eversion depth ``2 H``.

Imperfections (``[imperfection]``, ``docs/model.md#imperfections``), the stress-free shape:
``kind = "dimple"`` a Gaussian dimple at the pole of depth ``delta_over_h h`` and width ``lambda_I``
(:func:`contin_models.shell.meridian.with_dimple`, with ``R`` the length scale); ``kind = "mode"``
the perfect shell's buckling mode (the null vector at the first fold or branch point of its path
under the scene's load, :func:`contin_models.shell_scene.build.buckling_mode`), scaled so that its
largest normal displacement is ``delta_over_h h`` inwards.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import numpy as np

    from contin_models.shell.meridian import ReferenceMeridian

__all__ = ["GEOMETRIES", "reference_meridian", "length_scale", "base_radius", "rise", "read_table",
           "torispherical_segments", "meridian_length", "bending_radius"]

GEOMETRIES = ("sphere", "cone", "plate", "torus", "ellipse", "table")


def read_table(path: str) -> tuple[np.ndarray, np.ndarray]:
    """The ``(r, z)`` columns of a profile CSV (a non-numeric first line is a header).

    Raises ``ValueError`` naming the file and the line when it cannot be read.
    """
    import numpy as np

    p = Path(path)
    if not p.exists():
        where = "" if p.is_absolute() else f" (looked for in the current directory {str(Path.cwd())!r})"
        raise ValueError(f"shell.table: file not found: {path!r}{where}")
    if not p.is_file():
        raise ValueError(f"shell.table: {path!r} is not a file")
    rows = []
    try:
        f = p.open(newline="")
    except OSError as exc:
        raise ValueError(f"shell.table: cannot read {path!r}: {exc.strerror or exc}") from None
    with f:
        for k, row in enumerate(csv.reader(f)):
            cells = [c.strip() for c in row if c.strip()]
            if not cells:
                continue
            try:
                values = [float(c) for c in cells[:2]]
            except ValueError:
                if k == 0:
                    continue  # a header
                raise ValueError(f"shell.table: line {k + 1} of {path!r} is not two numbers: {row!r}") from None
            if len(values) != 2 or not all(math.isfinite(v) for v in values):
                raise ValueError(f"shell.table: line {k + 1} of {path!r} needs two finite numbers r, z")
            rows.append(values)
    if len(rows) < 4:
        raise ValueError(f"shell.table: {path!r} has {len(rows)} points; a profile needs at least 4")
    a = np.array(rows)
    return a[:, 0], a[:, 1]


def torispherical_segments(R: float, a: float, knuckle: float) -> list:
    """Knuckle (torus arc) and crown (spherical arc) of a torispherical head, edge at ``(a, 0)``.

    The knuckle's centre is at ``(a - knuckle, 0)``; the crown's centre on the axis at
    ``(0, -sqrt((R - knuckle)^2 - (a - knuckle)^2))``, so the two arcs are tangent where the line
    through both centres meets them.
    """
    from contin_models.shell.meridian import SphericalArc, TorusArc

    if not (0.0 < knuckle < a < R):
        raise ValueError(f"torispherical head: needs 0 < shell.knuckle < shell.a < shell.R, got knuckle = {knuckle!r}, "
                         f"a = {a!r}, R = {R!r}")
    rc = a - knuckle
    zc = -math.sqrt((R - knuckle) ** 2 - rc * rc)
    theta_j = math.atan2(-zc, rc)  # direction from the crown's centre to the knuckle's
    return [TorusArc(rc, 0.0, knuckle, 0.0, theta_j), SphericalArc(R, theta_j, 0.5 * math.pi, zc=zc)]


def reference_meridian(shell: dict[str, Any], imperfection: dict[str, Any] | None = None,
                       ring_radius: float | None = None, N: int | None = None) -> ReferenceMeridian:
    """The scene's perfect (or dimpled) reference meridian.

    Parameters
    ----------
    shell : dict
        The scene's ``[shell]`` section.
    imperfection : dict, optional
        The ``[imperfection]`` section; a ``"dimple"`` is applied here, a ``"mode"`` is not (it needs a
        computed mode: :func:`contin_models.shell_scene.build.scene_meridian`).
    ring_radius : float, optional
        Put a node exactly at this radius (a ring load), with the spacing refined around it.
    N : int, optional
        Number of nodes other than ``shell.N``.
    """
    from contin_models.shell.geometry import POLE_RATIO
    from contin_models.shell.meridian import (Cone, ellipsoid_cap_meridian, meridian, plate_meridian,
                                              spherical_cap_meridian, table_meridian, with_dimple)

    geometry = shell.get("geometry", "sphere")
    N = shell["N"] if N is None else N
    q = shell.get("pole_ratio", POLE_RATIO)
    if geometry == "sphere":
        m = spherical_cap_meridian(shell["R"], shell["phi_hat"], N, q)
    elif geometry == "cone":
        m = meridian([Cone(shell["a"], 0.0, 0.0, shell["H"])], N, q, length_scale=shell["a"], kind="cone")
    elif geometry == "plate":
        m = plate_meridian(shell["a"], N, q)
    elif geometry == "ellipse":
        m = ellipsoid_cap_meridian(shell["a"], shell["b"], shell["t_edge"], N, q)
    elif geometry == "torus":
        m = meridian(torispherical_segments(shell["R"], shell["a"], shell["knuckle"]), N, q,
                     length_scale=shell["R"], kind="torispherical")
    elif geometry == "table":
        r, z = read_table(shell["table"])
        m = table_meridian(r, z, N, q)
        if not m.end_on_axis:
            raise ValueError(f"shell.table: the profile must end on the axis (last r = 0), got r = {r[-1]!r}")
    else:
        raise ValueError(f"shell.geometry must be one of {GEOMETRIES}, got {geometry!r}")
    if ring_radius is not None:
        m = _with_ring_node(m, float(ring_radius), q)
    if imperfection and imperfection.get("kind") == "dimple":
        m = with_dimple(m, imperfection["delta_over_h"] * shell["h"], lambda_I=imperfection["lambda_I"],
                        R=m.length_scale, h=shell["h"], nu=shell["nu"])
    return m


def _with_ring_node(m: ReferenceMeridian, radius: float, q: float) -> ReferenceMeridian:
    """The same meridian rebuilt with a node exactly where its smooth curve has radius ``radius``."""
    import numpy as np

    from contin_models.shell.meridian import meridian

    base = float(m.r[0])
    if not (0.0 < radius < base):
        raise ValueError(f"load.ring_radius must be in (0, {base:g}) (the edge's radius), got {radius!r}")
    # the arclength where r = radius, by bisection on the smooth segments (r decreases from the edge)
    starts = np.concatenate([[0.0], np.cumsum([seg.length for seg in m.segments])])

    def r_at(s: float) -> float:
        k = min(int(np.searchsorted(starts, s, side="right")) - 1, len(m.segments) - 1)
        return float(np.asarray(m.segments[k].point(np.array([s - starts[k]]))[0]).ravel()[0])

    lo, hi = 0.0, float(starts[-1])
    if r_at(hi) > radius:
        raise ValueError(f"load.ring_radius = {radius!r}: the meridian never comes that close to the axis")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if r_at(mid) > radius:
            lo = mid
        else:
            hi = mid
    return meridian(list(m.segments), m.N, q, ring=0.5 * (lo + hi), length_scale=m.length_scale, kind=m.kind,
                    R=m.R, phi_hat=m.phi_hat)


def length_scale(shell: dict[str, Any]) -> float:
    """The scene's length unit (module docstring): ``R`` for the sphere and the torispherical head."""
    g = shell.get("geometry", "sphere")
    if g in ("sphere", "torus"):
        return float(shell["R"])
    if g in ("cone", "plate"):
        return float(shell["a"])
    if g == "ellipse":
        return float(shell["a"]) ** 2 / float(shell["b"])
    import numpy as np

    return float(np.max(read_table(shell["table"])[0]))


def base_radius(shell: dict[str, Any]) -> float:
    """Radius of the edge."""
    g = shell.get("geometry", "sphere")
    if g == "sphere":
        return float(shell["R"]) * math.cos(shell["phi_hat"])
    if g == "ellipse":
        return float(shell["a"]) * math.cos(shell["t_edge"])
    if g == "table":
        return float(read_table(shell["table"])[0][0])
    return float(shell["a"])


def rise(shell: dict[str, Any]) -> float:
    """Height of the pole above the edge, ``H`` (the perfect shape's)."""
    g = shell.get("geometry", "sphere")
    if g == "sphere":
        return float(shell["R"]) * (1.0 - math.sin(shell["phi_hat"]))
    if g == "cone":
        return float(shell["H"])
    if g == "plate":
        return 0.0
    if g == "ellipse":
        return float(shell["b"]) * (1.0 - math.sin(shell["t_edge"]))
    if g == "torus":
        segs = torispherical_segments(shell["R"], shell["a"], shell["knuckle"])
        return float(segs[-1].end[1])
    r, z = read_table(shell["table"])
    return float(z[-1] - z[0])


def meridian_length(shell: dict[str, Any]) -> float:
    """Arclength of the perfect meridian from the edge to the pole."""
    g = shell.get("geometry", "sphere")
    if g == "sphere":
        return float(shell["R"]) * (0.5 * math.pi - shell["phi_hat"])
    return float(reference_meridian(shell, N=16).length)


def bending_radius(shell: dict[str, Any]) -> float:
    """The smallest radius of curvature of the perfect meridian that sets its bending length ``sqrt(rho h)``.

    The sphere's ``R``; the ellipse's smallest principal radius of curvature over the cap; the
    torispherical head's knuckle; the cone's and the plate's length scale (no curvature: the loaded
    zone's size); a table's largest radius.
    """
    g = shell.get("geometry", "sphere")
    if g == "ellipse":
        a, b, t = float(shell["a"]), float(shell["b"]), float(shell["t_edge"])
        # meridional radius (a^2 sin^2 + b^2 cos^2)^(3/2) / (a b) and hoop radius a sqrt(...) / b over t in [t_edge, pi/2]
        import numpy as np

        tt = np.linspace(t, 0.5 * math.pi, 64)
        s = a * a * np.sin(tt) ** 2 + b * b * np.cos(tt) ** 2
        return float(min(np.min(s ** 1.5 / (a * b)), np.min(a * np.sqrt(s) / b)))
    if g == "torus":
        return float(shell["knuckle"])
    return length_scale(shell)
