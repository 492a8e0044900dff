"""rosbridge service ops: calls to the simulator's services and to services other clients advertise.

A call to an unknown service, or one whose handler raises, gets both an error ``status`` and a
``service_response`` with ``result: false`` (rosbridge's behaviour), so blocking clients fail fast
instead of timing out. Calls to a client-provided service are forwarded with a private id and the
provider's ``service_response`` is routed back to the caller under the caller's id.
"""

from __future__ import annotations

import asyncio
import itertools
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Any

from pmk_nb.sim.jsonfast import dumps
from pmk_nb.sim.session import ClientSession, fragments, png_encode, resolve_name

ServiceHandler = Callable[[dict[str, Any]], Awaitable[tuple[dict[str, Any], bool]]]


@dataclass
class ServiceEntry:
    name: str
    type: str
    handler: ServiceHandler | None = None
    provider: ClientSession | None = None


class ServiceOps:
    """Mixin of :class:`pmk_nb.sim.protocol.Bridge` holding the service registry and its ops."""

    services: dict[str, ServiceEntry]
    _ids: itertools.count[int]
    _pending: dict[str, tuple[ClientSession, str | None, str]]
    _tasks: set[asyncio.Task[Any]]

    def add_service(self, name: str, type_name: str, handler: ServiceHandler) -> None:
        self.services[name] = ServiceEntry(name, type_name, handler=handler)

    def _op_call_service(self, client: ClientSession, msg: dict[str, Any]) -> None:
        name, op_id = str(msg["service"]), msg.get("id")
        args = msg.get("args") or {}
        entry = self.services.get(resolve_name(name))
        if entry is None:
            self._service_failure(client, name, op_id, f"Service {name} does not exist")
            return
        if isinstance(args, list):  # rosbridge also accepts positional args; ours take none
            args = {}
        if not isinstance(args, dict):
            self._service_failure(client, name, op_id, f"call_service {name}: args must be a JSON object")
            return
        if entry.provider is not None:
            inner = f"service_request:{name}:{next(self._ids)}"
            self._pending[inner] = (client, op_id, name)
            entry.provider.send_control({"op": "call_service", "id": inner, "service": entry.name, "args": args})
            return
        assert entry.handler is not None
        task = asyncio.ensure_future(self._run_service(client, entry, args, op_id, msg))
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _run_service(
        self, client: ClientSession, entry: ServiceEntry, args: dict[str, Any], op_id: Any, msg: dict[str, Any]
    ) -> None:
        assert entry.handler is not None
        try:
            values, ok = await entry.handler(args)
        except Exception as err:
            self._service_failure(client, str(msg["service"]), op_id, f"{type(err).__name__}: {err}")
            return
        # answer in the caller's spelling of the name, as rosbridge does
        out: dict[str, Any] = {"op": "service_response", "service": str(msg["service"]), "values": values, "result": ok}
        if op_id is not None:
            out["id"] = op_id
        text = dumps(out)  # values may hold pre-encoded RawJSON (a whole map)
        if msg.get("compression") == "png":
            text = png_encode(text)
        size = msg.get("fragment_size")
        if isinstance(size, int) and size > 0 and len(text) > size:
            for piece in fragments(text, size, str(op_id or entry.name)):
                client.send_control(piece)
        else:
            client.send_control(text)

    def _service_failure(self, client: ClientSession, name: str, op_id: Any, why: str) -> None:
        client.status("error", f"call_service {name}: {why}", op_id)
        out: dict[str, Any] = {"op": "service_response", "service": name, "values": why, "result": False}
        if op_id is not None:
            out["id"] = op_id
        client.send_control(out)

    def _op_advertise_service(self, client: ClientSession, msg: dict[str, Any]) -> None:
        name, type_name = resolve_name(msg["service"]), str(msg["type"])
        existing = self.services.get(name)
        if existing is not None and existing.provider is None:
            client.status("error", f"advertise_service {name}: the simulator already provides it")
            return
        self.services[name] = ServiceEntry(name, type_name, provider=client)
        client.services.add(name)

    def _op_unadvertise_service(self, client: ClientSession, msg: dict[str, Any]) -> None:
        name = resolve_name(msg["service"])
        entry = self.services.get(name)
        if entry is None or entry.provider is not client:
            client.status("warning", f"unadvertise_service {name}: not advertised by this client")
            return
        del self.services[name]
        client.services.discard(name)

    def _op_service_response(self, client: ClientSession, msg: dict[str, Any]) -> None:
        pending = self._pending.pop(str(msg.get("id")), None)
        if pending is None:
            client.status("warning", f"service_response {msg['service']}: no call with id {msg.get('id')!r}")
            return
        caller, caller_id, name = pending
        out: dict[str, Any] = {
            "op": "service_response",
            "service": name,
            "values": msg.get("values", {}),
            "result": bool(msg.get("result", True)),
        }
        if caller_id is not None:
            out["id"] = caller_id
        caller.send_control(out)

    def drop_services_of(self, client: ClientSession) -> None:
        for name in client.services:
            entry = self.services.get(name)
            if entry is not None and entry.provider is client:
                del self.services[name]
        for key, (caller, caller_id, name) in list(self._pending.items()):
            if caller is client:
                del self._pending[key]
            elif self.services.get(name) is None:
                del self._pending[key]
                self._service_failure(caller, name, caller_id, f"Service {name} provider disconnected")
