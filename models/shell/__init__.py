"""The discrete axisymmetric shell (paper section 3(a)): reference geometry and elastic energy.

Element energies and their exact derivatives come from :mod:`contin_models.shell._generated`, plain numpy
emitted by ``python -m contin_models.shell.codegen`` (the only module that needs sympy; it is not imported
here).
"""

from .energy import HALF_BANDWIDTH, ShellEnergy
from .geometry import ReferenceCap, interleave, spherical_cap, split
from .meridian import (Cone, EllipseArc, ReferenceMeridian, Segment, SphericalArc, TableProfile, TorusArc,
                       annulus_meridian, complete_sphere_meridian, cone_meridian, ellipsoid_cap_meridian, meridian,
                       plate_meridian, spherical_cap_meridian, table_meridian, torus_meridian, with_dimple, with_mode)
from .pressure import ShellPressure
from .problem import PoleMirror, ShellPointLoad

__all__ = ["HALF_BANDWIDTH", "PoleMirror", "ReferenceCap", "ShellEnergy", "ShellPointLoad", "ShellPressure", "interleave",
           "spherical_cap", "split",
           "Cone", "EllipseArc", "ReferenceMeridian", "Segment", "SphericalArc", "TableProfile", "TorusArc",
           "annulus_meridian", "complete_sphere_meridian", "cone_meridian", "ellipsoid_cap_meridian", "meridian",
           "plate_meridian", "spherical_cap_meridian", "table_meridian", "torus_meridian", "with_dimple", "with_mode"]
