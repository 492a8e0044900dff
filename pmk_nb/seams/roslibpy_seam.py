"""roslibpy internals (pinned: roslibpy==2.1.0; tests/seams/test_roslibpy_seam.py).

Imports no roslibpy transport: importing ``roslibpy.comm.comm_asyncio`` (or the Twisted one) binds
Autobahn's txaio to that framework for the whole process, which :mod:`pmk_nb.chair.link.transport.framework`
decides only when a link connects. So this module holds a mixin and functions; the link's
factory (:mod:`pmk_nb.chair.link.transport.factory`) mixes it into roslibpy's asyncio factory.

Touched:

* ``AsyncioRosBridgeClientFactory._manager``: the constructor assigns the process-wide loop manager
  to it and starts that manager. A read-only property here turns the assignment into a no-op, so
  the real constructor runs entirely on the link's own manager (``link_manager``) and loop.
* ``AsyncioRosBridgeClientFactory._stop``: roslibpy has no public way to stop the reconnect loop of
  a connection that is not open (:meth:`FactorySeam.stop_reconnecting`).
* ``AsyncioRosBridgeClientFactory._schedule_reconnect``: the next attempt after a failed one
  (:meth:`FactorySeam.schedule_reconnect`).
* ``AsyncioRosBridgeClientFactory._connect_async``: one connect attempt; roslibpy opens TLS with
  ``ssl.create_default_context()`` and no way to pass another, so :meth:`FactorySeam.connect_attempt`
  may make the attempt itself (a wss link with its own trust).
* ``RosBridgeProtocol._message_handlers["status"]``: roslibpy sets it to None, so the public
  ``register_message_handlers`` refuses it (:func:`install_status_handler`).
* ``Ros._id_counter``: the link's ``Ros`` skips ``Ros.__init__`` (it would start the process-wide
  loop and connect at once) and sets the one private field it would set (:func:`init_id_counter`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

TOUCHED = ("_manager", "_stop", "_schedule_reconnect", "_connect_async", "_message_handlers", "_id_counter")


class FactorySeam:
    """Mixed in before ``AsyncioRosBridgeClientFactory``: a private loop manager, a reconnect switch,
    and a hook for the connect attempt. Subclasses set ``link_manager`` before the constructor."""

    link_manager: Any

    @property
    def _manager(self) -> Any:
        return self.link_manager

    @_manager.setter
    def _manager(self, _shared: Any) -> None:
        """roslibpy's constructor offers the process-wide manager here: keep the private one."""

    def stop_reconnecting(self) -> None:
        """No further reconnect attempts."""
        self._stop = True

    def schedule_reconnect(self) -> None:
        """Try again after the backoff delay (roslibpy's own schedule)."""
        self._schedule_reconnect()  # type: ignore[attr-defined]

    async def connect_attempt(self) -> bool:
        """Make one connect attempt and return True, or return False to let roslibpy make it."""
        return False

    async def _connect_async(self) -> None:
        if not await self.connect_attempt():
            await super()._connect_async()  # type: ignore[misc]


def install_status_handler(proto: Any, handler: Callable[[Any], None]) -> None:
    """Receive rosbridge's ``status`` op on ``proto`` (once; roslibpy leaves that handler None)."""
    if proto._message_handlers.get("status") is None:
        proto._message_handlers["status"] = handler


def init_id_counter(ros: Any) -> None:
    """The field ``Ros.__init__`` sets that a ``Ros`` built without it needs (``Ros.id_counter``)."""
    ros._id_counter = 0
