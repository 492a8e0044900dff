"""The roslibpy internals the chair link relies on are still there, in the pinned version.

``pmk_nb.seams.roslibpy_seam`` touches every private roslibpy name the link uses; each test here
fails when a roslibpy release moves one of them, before a link misbehaves at run time.
"""

from __future__ import annotations

import ast
import inspect
import re
import textwrap
import threading
import tomllib
from importlib import metadata
from pathlib import Path

import roslibpy
from roslibpy.comm import comm_asyncio

from pmk_nb.chair.link.transport.factory import LinkFactory, start_private_loop
from pmk_nb.chair.link.transport.ros import LinkRos
from pmk_nb.seams.roslibpy_seam import TOUCHED, FactorySeam

ROOT = Path(__file__).resolve().parents[2]


def _self_assignments(fn: object) -> set[str]:
    """Names ``self.X`` assigned in a function's source."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(fn)))  # type: ignore[arg-type]
    return {
        target.attr
        for node in ast.walk(tree)
        if isinstance(node, ast.Assign | ast.AnnAssign)
        for target in (node.targets if isinstance(node, ast.Assign) else [node.target])
        if isinstance(target, ast.Attribute) and isinstance(target.value, ast.Name) and target.value.id == "self"
    }


def _shared_loop_threads() -> int:
    return sum(t.name == "roslibpy-asyncio" for t in threading.enumerate())


def test_installed_roslibpy_is_the_pinned_version() -> None:
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    pins = [d for d in deps if re.match(r"roslibpy\b", d)]
    assert len(pins) == 1 and re.fullmatch(r"roslibpy==\d+\.\d+\.\d+", pins[0]), pins
    assert pins[0] == f"roslibpy=={roslibpy.__version__}" == f"roslibpy=={metadata.version('roslibpy')}"


def test_ros_init_sets_only_what_link_ros_sets() -> None:
    # LinkRos skips Ros.__init__ and sets these itself; a new field there must be mirrored.
    assert _self_assignments(roslibpy.Ros.__init__) == {"_id_counter", "factory", "is_connecting"}
    assert list(inspect.signature(roslibpy.Ros.__init__).parameters) == [
        "self",
        "host",
        "port",
        "is_secure",
        "headers",
        "transport",
    ]
    assert "self._id_counter += 1" in inspect.getsource(roslibpy.Ros.id_counter.fget)  # type: ignore[attr-defined]


def test_factory_constructor_binds_its_manager_through_the_private_name() -> None:
    init = inspect.getsource(comm_asyncio.AsyncioRosBridgeClientFactory.__init__)
    assert "self._manager = _get_shared_manager()" in init
    assert 'kwargs.setdefault("loop", self._manager.loop)' in init
    assert {"_manager", "_stop", "_proto", "_proto_lock"} <= _self_assignments(
        comm_asyncio.AsyncioRosBridgeClientFactory.__init__
    )
    manager_prop = inspect.getsource(comm_asyncio.AsyncioRosBridgeClientFactory.manager.fget)  # type: ignore[attr-defined]
    assert "return self._manager" in manager_prop


def test_stop_flag_still_gates_reconnects() -> None:
    factory_cls = comm_asyncio.AsyncioRosBridgeClientFactory
    assert "if self._stop:" in inspect.getsource(factory_cls._schedule_reconnect)
    assert "self._stop" in inspect.getsource(factory_cls.connection_lost)


def test_public_surface_used_by_the_link() -> None:
    assert list(inspect.signature(comm_asyncio.AsyncioEventLoopManager).parameters) == []
    for name in ("run", "terminate", "loop"):
        assert hasattr(comm_asyncio.AsyncioEventLoopManager(), name)
    assert callable(comm_asyncio.AsyncioRosBridgeProtocol.send_close)
    factory_cls = comm_asyncio.AsyncioRosBridgeClientFactory
    assert 'self.emit("ready", proto)' in inspect.getsource(factory_cls.ready)
    assert 'self.emit("close", proto)' in inspect.getsource(factory_cls.connection_lost)
    assert callable(roslibpy.set_default_transport)


def test_link_factory_runs_on_its_own_loop_only() -> None:
    shared = _shared_loop_threads()
    manager, thread = start_private_loop("pmk-seam-test")
    try:
        assert thread.name == "pmk-seam-test" and thread.is_alive()
        factory = LinkFactory(
            LinkFactory.create_url("127.0.0.1", 9),
            manager,
            initial_delay=0.5,
            max_delay=3.0,
            ping_interval=2.0,
            ping_timeout=2.0,
        )
        assert factory.manager is manager and factory.loop is manager.loop
        assert factory._reconnect_delay == 0.5 and factory.maxDelay == 3.0  # our backoff, not roslibpy's hour
        assert factory._stop is False
        factory.stop_reconnecting()
        assert factory._stop is True
        assert _shared_loop_threads() == shared  # the process-wide loop was not started
    finally:
        manager.terminate()
    assert not thread.is_alive()


def test_link_ros_counts_ids_and_releases_its_thread() -> None:
    ros = LinkRos("127.0.0.1", 9, thread_name="pmk-seam-ros")
    try:
        assert (ros.id_counter, ros.id_counter) == (1, 2)
        assert not ros.is_connected and ros.loop_thread.name == "pmk-seam-ros"
    finally:
        ros.shutdown(1.0)
    assert not ros.loop_thread.is_alive()


def test_wss_connect_is_roslibpys_own_with_the_links_context() -> None:
    """LinkFactory._connect_async (wss links only) is roslibpy's attempt with the link's TLS context:
    roslibpy must still open connections through it, the same way, and build our protocol class."""
    from autobahn.asyncio.websocket import WebSocketAdapterFactory, WebSocketAdapterProtocol

    factory_cls = comm_asyncio.AsyncioRosBridgeClientFactory
    assert "asyncio.ensure_future(self._connect_async())" in inspect.getsource(factory_cls._open_connection)
    attempt = inspect.getsource(factory_cls._connect_async)
    assert "ssl_module.create_default_context()" in attempt  # no way to pass our own context
    assert "await loop.create_connection(self, self.host, self.port, ssl=ssl)" in attempt
    assert "self._schedule_reconnect()" in attempt
    assert factory_cls.protocol is comm_asyncio.AsyncioRosBridgeProtocol
    assert LinkFactory.protocol.__mro__[1] is comm_asyncio.AsyncioRosBridgeProtocol
    # the certificate check runs before Autobahn starts the websocket in connection_made
    assert "proto = self.protocol()" in inspect.getsource(WebSocketAdapterFactory.__call__)
    assert "self._connectionMade()" in inspect.getsource(WebSocketAdapterProtocol.connection_made)


def test_the_seam_is_the_link_factorys_first_base_and_touches_what_it_lists() -> None:
    assert LinkFactory.__mro__[1] is FactorySeam and comm_asyncio.AsyncioRosBridgeClientFactory in LinkFactory.__mro__
    assert set(TOUCHED) == {
        "_manager",
        "_stop",
        "_schedule_reconnect",
        "_connect_async",
        "_message_handlers",
        "_id_counter",
    }
    factory_cls = comm_asyncio.AsyncioRosBridgeClientFactory
    assert callable(factory_cls._schedule_reconnect) and callable(factory_cls._connect_async)
    assert list(inspect.signature(factory_cls._schedule_reconnect).parameters) == ["self"]
    protocol_init = inspect.getsource(roslibpy.comm.RosBridgeProtocol.__init__)
    assert '"status": None' in protocol_init or "'status': None" in protocol_init  # still no handler of its own
