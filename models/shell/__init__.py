"""The discrete shell of revolution (paper section 3(a)): reference geometry, the energy written once, its views.

Element energies and their exact derivatives come from :mod:`contin_models.shell._generated`, plain numpy
emitted by ``python -m contin_models.shell.codegen`` (the only module that needs sympy; it is not imported
here).

Reading order:

1. **Reference geometry**: :mod:`~contin_models.shell.supports`, :mod:`~contin_models.shell.geometry`,
   :mod:`~contin_models.shell.meridian`, and :mod:`~contin_models.shell.reference`, the one read-only table of
   every element's reference data (:class:`~contin_models.shell.reference.ShellReference`).
2. **The energy written once**: :mod:`~contin_models.shell.density`, the 2-D energy densities, and the pole and
   edge elements (:mod:`~contin_models.shell.elements`); the generators :mod:`~contin_models.shell.codegen`
   (the axisymmetric kernels, derived from the densities), :mod:`~contin_models.shell.harmonic_codegen` and
   :mod:`~contin_models.shell.density_codegen` (the densities at any state, served by
   :mod:`~contin_models.shell.density_kernels`), and the kernels they emit.
3. **The views**: :mod:`~contin_models.shell.layouts` (which rings each density reads, shared by every view),
   :mod:`~contin_models.shell.jets` (forward second derivatives), :mod:`~contin_models.shell.energy`
   (the traced axisymmetric energy, :class:`ShellEnergy`), :mod:`~contin_models.shell.harmonic` (the blocks per
   wave number), :mod:`~contin_models.shell.fourier` (the 3-D view: rings moving in three directions, Fourier
   series in the angle, :class:`FourierShell`; its imperfect references from
   :mod:`~contin_models.shell.imperfection3d`), :mod:`~contin_models.shell.ring_mesh` (the same energy on a
   ring of points per node, finite differences in the angle: an independent check).
4. **Loads**: :mod:`~contin_models.shell.volume` (the forces live in the problems; contact in
   :mod:`contin_models.contact`).
5. **The problem**: :mod:`~contin_models.shell.structure`, :mod:`~contin_models.shell.problem`,
   :mod:`~contin_models.shell.problem3d` (the 3-D view under a load, :class:`Shell3D`),
   :mod:`~contin_models.shell.lift` (a bifurcation into ``n`` waves carried into the 3-D view and followed),
   :mod:`~contin_models.shell.pressure`, :mod:`~contin_models.shell.strain`, :mod:`~contin_models.shell.boundaries`.

The public names are imported on first use (:mod:`contin.lazy`), so a light module of the package, such
as :mod:`contin_models.shell.supports` (which the scene schema reads), loads without numpy: the command
line loads every model's schema to print its help or to refuse a scene.
"""

from contin.lazy import lazy_exports

#: Public name -> the module of this package that defines it.
_EXPORTS: dict[str, str] = {
    **dict.fromkeys(("HALF_BANDWIDTH", "ShellEnergy"), "energy"),
    **dict.fromkeys(("ReferenceCap", "interleave", "spherical_cap", "split"), "geometry"),
    **dict.fromkeys(("Cone", "EllipseArc", "ReferenceMeridian", "Segment", "SphericalArc", "TableProfile", "TorusArc",
                     "annulus_meridian", "complete_sphere_meridian", "cone_meridian", "ellipsoid_cap_meridian",
                     "meridian", "plate_meridian", "spherical_cap_meridian", "table_meridian", "torus_meridian",
                     "with_dimple", "with_mode"), "meridian"),
    "ShellPressure": "pressure",
    **dict.fromkeys(("AngularBasis", "FourierShell"), "fourier"),
    "Shell3D": "problem3d",
    **dict.fromkeys(("WavesBranch", "follow_waves", "rotated_half", "shell_lift"), "lift"),
    **dict.fromkeys(("branch_mode", "dimple_imperfection", "mode_imperfection"), "imperfection3d"),
    "PoleMirror": "elements",
    "ShellPointLoad": "problem",
}

__all__ = ["AngularBasis", "FourierShell", "HALF_BANDWIDTH", "Shell3D", "branch_mode", "dimple_imperfection",
           "mode_imperfection", "WavesBranch", "follow_waves", "rotated_half", "shell_lift", "PoleMirror", "ReferenceCap", "ShellEnergy", "ShellPointLoad", "ShellPressure", "interleave",
           "spherical_cap", "split",
           "Cone", "EllipseArc", "ReferenceMeridian", "Segment", "SphericalArc", "TableProfile", "TorusArc",
           "annulus_meridian", "complete_sphere_meridian", "cone_meridian", "ellipsoid_cap_meridian", "meridian",
           "plate_meridian", "spherical_cap_meridian", "table_meridian", "torus_meridian", "with_dimple", "with_mode"]

lazy_exports(__name__, _EXPORTS)
