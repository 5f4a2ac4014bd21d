"""The command line: scenes, runs, sweeps and the files and figures they write.

=============  ============================================================================================
``cli``        the ``contin`` command
``scene``      declarative scene schemas, validation, trace and classification results (no numpy)
``registry``   the models registered as ``contin.models`` entry points
``sweep``      sweeps over scene keys; ``executors`` run them serially, on processes or on Dask
``restart``    a run saved with its states, and new runs started from its points
``saved``      the output directory of ``contin trace`` read back
``figures``    the command line's figures: a run's diagram and shapes, saved runs drawn again
=============  ============================================================================================
"""

from ..lazy import lazy_exports

lazy_exports(__name__, {})
