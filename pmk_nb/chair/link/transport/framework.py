"""Which of roslibpy's transports the link runs on: the one place that picks it (as roslibpy's ``comm/`` does).

Autobahn binds one framework per process (txaio). Importing this module makes asyncio roslibpy's default
through its public ``set_default_transport`` unless ``ROSLIBPY_TRANSPORT`` decides or Twisted is already
bound; a link then takes the factory module of the framework the process uses (see :mod:`.ros`).
"""

from __future__ import annotations

import os
import sys
from types import ModuleType

import roslibpy

#: roslibpy's module for its Twisted transport: once imported, asyncio cannot be used any more.
TWISTED_MODULE = "roslibpy.comm.comm_autobahn"


def twisted_bound() -> bool:
    """Whether Autobahn's txaio is (or is about to be) bound to Twisted in this process, by anyone."""
    txaio = sys.modules.get("txaio")
    return TWISTED_MODULE in sys.modules or (txaio is not None and bool(getattr(txaio, "using_twisted", False)))


def prefer_asyncio_transport() -> None:
    """Make asyncio roslibpy's default transport, unless the process already decided otherwise."""
    if os.environ.get("ROSLIBPY_TRANSPORT") or twisted_bound():
        return
    roslibpy.set_default_transport("asyncio")


prefer_asyncio_transport()


def factory_module() -> ModuleType:
    """The factory module for the framework this process uses (asyncio unless Twisted came first)."""
    if twisted_bound() or os.environ.get("ROSLIBPY_TRANSPORT", "").strip().lower() == "twisted":
        from pmk_nb.chair.link.transport import factory_twisted

        return factory_twisted
    from pmk_nb.chair.link.transport import factory

    return factory
