"""The model registry: scene runners found through the ``contin.models`` entry-point group.

A package registers a model by naming a :class:`contin.app.scene.ModelRunner` (or a zero-argument factory
returning one) in its ``pyproject.toml``::

    [project.entry-points."contin.models"]
    mymodel = "mypackage.scene:MY_SCENE"

The command line, the sweeps (also in worker processes) and the studies all find models here, so the
engine never imports a model.  A runner with a true ``default`` attribute is the model used when
none is named (:func:`default_model`); its ``examples`` feed the command line's help.
"""

from __future__ import annotations

import functools
from importlib.metadata import EntryPoint, entry_points
from typing import Any

from .scene import ModelRunner

__all__ = ["ENTRY_POINT_GROUP", "ModelNotFound", "registered_models", "forget_models", "load_model",
           "default_model", "model_examples"]

#: Entry-point group in which models register their scene runners.
ENTRY_POINT_GROUP = "contin.models"


class ModelNotFound(LookupError):
    """No usable model of that name: the message is one paragraph fit to show a user."""


def registered_models() -> dict[str, EntryPoint]:
    """Entry points of the ``contin.models`` group, by name, sorted (the first registration of a name wins).

    The installed distributions are scanned once per process (a few milliseconds each time, and the help
    texts ask often); after installing a model into a running process, call :func:`forget_models`.
    """
    return dict(_scan())


@functools.lru_cache(maxsize=1)
def _scan() -> tuple[tuple[str, EntryPoint], ...]:
    found: dict[str, EntryPoint] = {}
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        found.setdefault(ep.name, ep)
    return tuple(sorted(found.items()))


def forget_models() -> None:
    """Scan the installed distributions again at the next :func:`registered_models` (a model installed since)."""
    _scan.cache_clear()


def load_model(name: str) -> ModelRunner:
    """Load the runner registered as ``name``.

    Raises
    ------
    ModelNotFound
        If no such model is registered or its entry point does not load a runner.
    """
    models = registered_models()
    if name not in models:
        if not models:
            raise ModelNotFound(f"unknown model {name!r}: no models are registered in the entry-point group "
                                f"{ENTRY_POINT_GROUP!r} (is the package installed with 'pip install -e .'?)")
        raise ModelNotFound(f"unknown model {name!r}; registered models: {', '.join(models)} (see 'contin models')")
    ep = models[name]
    try:
        obj = ep.load()
    except Exception as exc:  # any import-time failure of a plugin is reported, not raised
        raise ModelNotFound(f"model {name!r} could not be loaded from {ep.value}: {type(exc).__name__}: "
                            f"{exc}") from None
    if not hasattr(obj, "run") and callable(obj):
        obj = obj()
    missing = [a for a in ("name", "description", "schema", "run") if not hasattr(obj, a)]
    if missing:
        raise ModelNotFound(f"model {name!r} ({ep.value}) is not a scene runner: it lacks {', '.join(missing)}")
    return obj


def default_model() -> str | None:
    """The name of the one registered model whose runner says ``default = True``; None if not exactly one.

    Models that cannot be loaded are passed over (:func:`load_model` reports them when named).
    """
    marked = []
    for name in registered_models():
        try:
            if getattr(load_model(name), "default", False) is True:
                marked.append(name)
        except ModelNotFound:
            continue
    return marked[0] if len(marked) == 1 else None


def model_examples(model: Any, command: str) -> list[tuple[str, str]]:
    """The model's examples for ``contin COMMAND``: pairs of (arguments after the command, comment).

    A runner lists them in an ``examples`` mapping of command to pairs; a runner without one has none.
    """
    examples = getattr(model, "examples", None) or {}
    return [(str(args), str(comment)) for args, comment in examples.get(command, ())]
