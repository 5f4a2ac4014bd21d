"""Which rings each density reads, and how: the local-vector layouts that every view shares.

A density of :mod:`contin_models.shell.density` is a function of a few *local vectors* of one element at
one angle ``theta``: differences of ring positions ``P``, their ``theta``-derivatives ``P'`` and ``P''``
(and, at a pole, the neighbour ring's point half a turn away).  A **layout** says how each local vector is
formed from the element's rings: a tuple, one entry per local vector, of ``(combination, kind)`` where
``combination`` lists ``(slot, coefficient)`` pairs (``slot`` the position of a ring among the
element's nodes) and ``kind`` is the quantity combined:

=======  =====================================================================================
kind     the ring quantity at ``theta``, in the local frame ``(e_r, e_theta, e_z)`` at ``theta``
=======  =====================================================================================
``P``    the position ``P(theta)``
``Pp``   ``P'(theta)``
``Ppp``  ``P''(theta)``
``Q``    the position at ``theta + pi`` (its components in the frame at ``theta``)
``Qp``   ``P'`` at ``theta + pi`` (the same)
=======  =====================================================================================

Every view (the traced axisymmetric energy's restriction, the harmonic blocks, the Fourier 3-D view)
differs only in how its unknowns give these ring quantities and how the angle is integrated; the layouts
themselves are written here once.
"""

from __future__ import annotations

__all__ = ["STRETCH", "BEND", "VOLUME", "CLAMP", "FREE_EDGE", "POLE", "SKIRT", "KINDS"]

#: The ring quantities a layout may combine.
KINDS = ("P", "Pp", "Ppp", "Q", "Qp")

#: Stretching, edge ``(i, i+1)``: ``D = P_{i+1} - P_i``, ``Mp = (P'_i + P'_{i+1}) / 2``.
STRETCH = (((1, 1.0), (0, -1.0)), "P"), (((0, 0.5), (1, 0.5)), "Pp")

#: Bending, node ``i`` with slots ``(i-1, i, i+1)``: ``e1``, ``e2``, ``Dp = P'_{i+1} - P'_{i-1}``, ``P'_i``, ``P''_i``.
BEND = ((((1, 1.0), (0, -1.0)), "P"), (((2, 1.0), (1, -1.0)), "P"), (((2, 1.0), (0, -1.0)), "Pp"),
        (((1, 1.0),), "Pp"), (((1, 1.0),), "Ppp"))

#: Volume strip, edge ``(i, i+1)``: ``P_i``, ``P_{i+1}``, ``P'_i``, ``P'_{i+1}``.
VOLUME = (((0, 1.0),), "P"), (((1, 1.0),), "P"), (((0, 1.0),), "Pp"), (((1, 1.0),), "Pp")

#: The clamp's bending element on ``(ghost, 0, 1)``, slots ``(0, 1)`` (the ghost ring is fixed in space and
#: enters as a constant: ``e1 = P_0 - G``, ``Dp = P'_1 - G'``; the view adds ``-G`` and ``-G'``).
CLAMP = ((((0, 1.0),), "P"), (((1, 1.0), (0, -1.0)), "P"), (((1, 1.0),), "Pp"), (((0, 1.0),), "Pp"),
         (((0, 1.0),), "Ppp"))

#: A rotating (moment-free) edge's half cell, slots ``(0, 1)``: ``e``, ``Dp = P'_1 - P'_0``, ``P'_0``, ``P''_0``.
FREE_EDGE = ((((1, 1.0), (0, -1.0)), "P"), (((1, 1.0), (0, -1.0)), "Pp"), (((0, 1.0),), "Pp"),
             (((0, 1.0),), "Ppp"))

#: A pole's directional curvature, slots ``(neighbour, pole)``: ``Pm``, ``Pm'``, ``Pc``, ``Pq``, ``Pq'``
#: (:func:`contin_models.shell.density.pole_curvature`).
POLE = ((((0, 1.0),), "P"), (((0, 1.0),), "Pp"), (((1, 1.0),), "P"), (((0, 1.0),), "Q"), (((0, 1.0),), "Qp"))

#: The skirt from the base plane up to ring 0: ``P_0``, ``P'_0``.
SKIRT = (((0, 1.0),), "P"), (((0, 1.0),), "Pp")
