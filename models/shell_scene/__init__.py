"""The shell with its loads: the scene of ``contin trace --model shell`` and its public builders.

Rooms:

* :mod:`.schema` - the scene keys (:data:`SHELL_SCHEMA`) and the eversion depth;
* :mod:`.build` - scene -> problem, settings, start (:func:`build`, :func:`point_problem`,
  :func:`contact_problem`, ...): the way in for the command line, studies, tests and users;
* :mod:`.point` - the point load's runs (displacement path, force control) and classification;
* :mod:`.contact` - the rigid sphere or plate's runs through the contact barrier;
* :mod:`.scene` - :data:`SHELL_SCENE`, which dispatches a scene to one of them, and
  :func:`classify_scene`.

The shell (:mod:`contin_models.shell`) and the contact (:mod:`contin_models.contact`) know nothing of this
package; it imports both.
"""

from .build import Build, build, contact_problem, contact_settings, end_of_path, point_problem, point_settings
from .point import classify
from .scene import SHELL_SCENE, classify_scene, run_scene
from .schema import MAX_NODES, SHELL_SCHEMA, eversion_displacement

__all__ = ["Build", "MAX_NODES", "SHELL_SCENE", "SHELL_SCHEMA", "build", "classify", "classify_scene", "contact_problem",
           "contact_settings", "end_of_path", "eversion_displacement", "point_problem", "point_settings", "run_scene"]
