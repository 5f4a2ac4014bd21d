"""Registry alias: the shell scene lives in :mod:`models.shell_scene` (it combines the shell with its loads).

``pyproject.toml`` registers the command-line model as ``models.shell.scene:SHELL_SCENE``; this module
keeps that entry point resolving until the registry names :mod:`models.shell_scene` directly, and
then goes.  Nothing in :mod:`models.shell` imports it, and new code imports :mod:`models.shell_scene`.
"""

from models.shell_scene import SHELL_SCENE, SHELL_SCHEMA, classify, classify_scene, eversion_displacement

__all__ = ["SHELL_SCENE", "SHELL_SCHEMA", "classify", "classify_scene", "eversion_displacement"]
