"""Results as data: traced branches and their special points, and how result files are written.

===========  ==============================================================================================
``branch``   :class:`Branch`, :class:`SpecialPoint`, saved to and loaded from one ``.npz`` file
``io``       atomic writes, JSON-ready values, bundles (arrays plus a JSON header), output directories
===========  ==============================================================================================

Nothing here computes or knows a model: the watch, the driver and the analyses fill these records.
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
