"""The one guarded import of meshcat: on first use, never at import time (it costs 0.2 s).

meshcat's package imports its server module, which imports ``zmq.eventloop.ioloop``,
deprecated since pyzmq 17: the import runs with that DeprecationWarning silenced. A missing
meshcat is a :class:`~springbalance.errors.SpringBalanceError` that says what to install.
"""

from __future__ import annotations

import functools
import warnings
from types import ModuleType

from springbalance.errors import SpringBalanceError


@functools.cache
def import_meshcat() -> ModuleType:
    """The ``meshcat`` package, with ``meshcat.animation``, ``meshcat.commands``, ``meshcat.geometry``,
    ``meshcat.servers.tree`` and ``meshcat.servers.zmqserver`` imported (attributes of it from then on).

    Raises:
        SpringBalanceError: meshcat is not installed.
    """
    with warnings.catch_warnings():
        # meshcat's server module imports zmq.eventloop.ioloop, deprecated since pyzmq 17
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            import meshcat
            import meshcat.animation
            import meshcat.commands
            import meshcat.geometry
            import meshcat.servers.tree
            import meshcat.servers.zmqserver
        except ImportError as error:
            raise SpringBalanceError(
                f"drawing a scene needs meshcat, which could not be imported ({error}); "
                "install it with `pip install meshcat`"
            ) from error
    return meshcat
