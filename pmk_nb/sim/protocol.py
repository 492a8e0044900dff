"""A rosbridge v2 server core: topic and service registry plus the JSON ops, over ``websockets``.

The simulator registers its own topics/services here (``advertise_internal``, ``add_service``,
``listen``) and publishes with :meth:`Bridge.publish`; clients speak the rosbridge v2 protocol
(advertise, unadvertise, publish, subscribe, unsubscribe, call_service, advertise_service,
unadvertise_service, service_response, fragment, set_level, and the ROS 2 action ops in
:mod:`pmk_nb.sim.actions`); with an ``auth_secret`` a client must first send a granted ``auth`` op
(:mod:`pmk_nb.rosauth`), else its socket is closed. Bad requests get a ``status`` op with
level ``error`` (rosbridge's behaviour), never a dropped connection. Topic ops live here, service
ops in :mod:`pmk_nb.sim.services`, per-client send queues in :mod:`pmk_nb.sim.session`.
Everything runs on one asyncio loop; nothing here blocks it.
"""

from __future__ import annotations

import asyncio
import itertools
import json
import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from pmk_nb.rosauth import granted
from pmk_nb.sim.actions import ActionEntry, ActionOps
from pmk_nb.sim.bridge_modes import DEFAULT_BRIDGE, BridgeMode, facts
from pmk_nb.sim.jsonfast import dumps
from pmk_nb.sim.messages import conformance_error
from pmk_nb.sim.services import ServiceEntry, ServiceOps
from pmk_nb.sim.session import (
    STATUS_LEVELS,
    ClientSession,
    SubParams,
    Subscription,
    fragments,
    png_encode,
    resolve_name,
)
from pmk_nb.wire import is_type_name
from pmk_nb.wire import normalise_type as canonical_type

if TYPE_CHECKING:
    from websockets.asyncio.server import ServerConnection

LOG = logging.getLogger("pmk_nb.sim")
Listener = Callable[[dict[str, Any]], None]

_REQUIRED: dict[str, tuple[str, ...]] = {
    "advertise": ("topic", "type"),
    "unadvertise": ("topic",),
    "publish": ("topic", "msg"),
    "subscribe": ("topic",),
    "unsubscribe": ("topic",),
    "call_service": ("service",),
    "advertise_service": ("service", "type"),
    "unadvertise_service": ("service",),
    "service_response": ("service",),
    "fragment": ("id", "data", "num", "total"),
    "set_level": ("level",),
    "send_action_goal": ("action",),
    "cancel_action_goal": ("action", "id"),
}


@dataclass
class TopicEntry:
    name: str
    type: str
    latched: bool = False
    internal: bool = False  # published by the simulator itself
    last: str | None = None  # encoded publish op kept for latched topics
    publishers: set[int] = field(default_factory=set)
    listeners: list[Listener] = field(default_factory=list)
    # keyed by (client id, the client's spelling): rosbridge keeps 'odom' and '/odom' apart per client
    subs: dict[tuple[int, str], Subscription] = field(default_factory=dict)

    @property
    def unused(self) -> bool:
        return not (self.internal or self.publishers or self.listeners or self.subs)


class Bridge(ServiceOps, ActionOps):
    """Registry + protocol handler. Create on the loop that will run it."""

    def __init__(
        self,
        client_queue: int = 200,
        mode: BridgeMode = DEFAULT_BRIDGE,
        action_ops: bool = True,
        auth_secret: str | None = None,
    ) -> None:
        self.mode: BridgeMode = mode
        self.auth_secret = auth_secret  # rosbridge's authenticate:=true with rosauth's secret
        self.action_ops = action_ops  # False: ROS 1 rosbridge (0.11) has no action ops at all
        self.bridge_facts = facts(mode)
        self.topics: dict[str, TopicEntry] = {}
        self.services: dict[str, ServiceEntry] = {}
        self.actions: dict[str, ActionEntry] = {}
        self.clients: dict[int, ClientSession] = {}
        self._client_queue = client_queue
        self._ids = itertools.count(1)
        self._pending: dict[str, tuple[ClientSession, str | None, str]] = {}
        self._fragments: dict[str, dict[int, str]] = {}
        self._tasks: set[asyncio.Task[Any]] = set()

    # -- simulator side -------------------------------------------------------------------------

    def advertise_internal(self, name: str, type_name: str, *, latched: bool = False) -> None:
        entry = self.topics.setdefault(name, TopicEntry(name, type_name))
        entry.type, entry.latched, entry.internal = type_name, latched, True

    def listen(self, name: str, type_name: str, callback: Listener) -> None:
        """Simulator-side subscriber: ``callback(msg)`` runs on the loop for every client publish."""
        entry = self.topics.setdefault(name, TopicEntry(name, type_name))
        entry.listeners.append(callback)

    def has_subscribers(self, name: str) -> bool:
        entry = self.topics.get(name)
        return bool(entry and entry.subs)

    def publish(self, name: str, msg: dict[str, Any]) -> None:
        """Encode once and fan out to every subscription (and keep it if the topic is latched)."""
        entry = self.topics[name]
        if not entry.subs and not entry.latched:
            return
        text = dumps({"op": "publish", "topic": name, "msg": msg})  # msg may hold pre-encoded RawJSON
        self._fan_out(entry, text)

    # -- connection handling ----------------------------------------------------------------------

    async def handle(self, ws: ServerConnection) -> None:
        client = ClientSession(next(self._ids), ws, self._client_queue)
        client.authenticated = self.auth_secret is None
        self.clients[client.cid] = client
        writer = asyncio.create_task(client.run_writer())
        try:
            async for raw in ws:
                text = raw if isinstance(raw, str) else raw.decode("utf-8", "replace")
                if client.authenticated:
                    self.receive(client, text)
                elif not self._admit(client, text):
                    await self._refuse(client)
                    break
        except Exception:
            pass
        finally:
            self._drop_client(client)
            client.close()
            writer.cancel()

    def _admit(self, client: ClientSession, raw: str) -> bool:
        """An unauthenticated client's op: only a granted ``auth`` is accepted (rosbridge with rosauth)."""
        try:
            msg = json.loads(raw)
        except ValueError:
            return False
        if not isinstance(msg, dict) or msg.get("op") != "auth" or self.auth_secret is None:
            return False
        client.authenticated = granted(self.auth_secret, msg)
        if client.authenticated:
            LOG.info("client %d has authenticated", client.cid)
        return client.authenticated

    async def _refuse(self, client: ClientSession) -> None:
        """rosbridge's answer to a client that did not authenticate: the socket is closed, nothing served."""
        LOG.warning("client %d did not authenticate: closing its connection", client.cid)
        await client.ws.close(code=1008, reason="not authenticated")

    async def close_all(self) -> None:
        for client in list(self.clients.values()):
            await client.ws.close()

    def dispatch(self, client: ClientSession, raw: str) -> None:
        try:
            msg = json.loads(raw)
        except ValueError as err:
            client.status("error", f"Unable to parse message as JSON: {err}")
            return
        if not isinstance(msg, dict) or not isinstance(msg.get("op"), str):
            client.status("error", "Message has no 'op' field (expected a JSON object with an 'op' string)")
            return
        op, op_id = msg["op"], msg.get("id")
        handler = getattr(self, f"_op_{op}", None)
        if handler is None or (not self.action_ops and op in ("send_action_goal", "cancel_action_goal")):
            client.status("error", f"Unknown operation '{op}'", op_id)
            return
        missing = [k for k in _REQUIRED.get(op, ()) if k not in msg]
        if missing:
            client.status("error", f"{op}: missing required field(s) {', '.join(missing)}", op_id)
            return
        try:
            handler(client, msg)
        except Exception as err:  # a bug or an odd field type must not end the connection
            LOG.exception("rosbridge op %s failed", op)
            client.status("error", f"{op}: {type(err).__name__}: {err}", op_id)

    # -- topic ops --------------------------------------------------------------------------------
    # rosbridge resolves relative names against its namespace ("/"), and answers in the client's
    # own spelling (roslibjs 2.x routes by that exact string and uses relative rosapi names).

    def _op_advertise(self, client: ClientSession, msg: dict[str, Any]) -> None:
        name, type_name, op_id = resolve_name(msg["topic"]), str(msg["type"]), msg.get("id")
        if not is_type_name(type_name):
            client.status("error", f"advertise {name}: cannot resolve type '{type_name}'", op_id)
            return
        entry = self.topics.get(name)
        if entry and canonical_type(entry.type) != canonical_type(type_name):
            client.status("error", f"advertise {name}: topic already has type {entry.type}, not {type_name}", op_id)
            return
        entry = entry or self.topics.setdefault(name, TopicEntry(name, type_name))
        entry.publishers.add(client.cid)
        entry.latched = entry.latched or bool(msg.get("latch", False))
        client.advertised[name] = entry.type

    def _op_unadvertise(self, client: ClientSession, msg: dict[str, Any]) -> None:
        name = resolve_name(msg["topic"])
        entry = self.topics.get(name)
        if entry is None or client.cid not in entry.publishers:
            client.status("warning", f"unadvertise {name}: this client does not advertise it", msg.get("id"))
            return
        entry.publishers.discard(client.cid)
        client.advertised.pop(name, None)
        self._forget_if_unused(entry)

    def _op_publish(self, client: ClientSession, msg: dict[str, Any]) -> None:
        name, op_id = resolve_name(msg["topic"]), msg.get("id")
        entry = self.topics.get(name)
        if entry is None:
            client.status("error", f"publish {name}: topic does not exist (advertise it first)", op_id)
            return
        err = conformance_error(entry.type, msg["msg"])
        if err:
            client.status("error", f"publish {name}: message does not conform to {entry.type}: {err}", op_id)
            return
        if msg.get("latch"):
            entry.latched = True
        for listener in list(entry.listeners):
            listener(msg["msg"])
        if entry.subs or entry.latched:
            text = dumps({"op": "publish", "topic": name, "msg": msg["msg"]})  # NaN / inf -> null
            self._fan_out(entry, text)

    def _op_subscribe(self, client: ClientSession, msg: dict[str, Any]) -> None:
        spelled, op_id = str(msg["topic"]), msg.get("id")
        name = resolve_name(spelled)
        type_name = msg.get("type") or None
        entry = self.topics.get(name)
        if entry is None and type_name is None:
            client.status("error", f"subscribe {name}: cannot infer topic type, topic does not exist", op_id)
            return
        if type_name is not None and not is_type_name(str(type_name)):
            client.status("error", f"subscribe {name}: cannot resolve type '{type_name}'", op_id)
            return
        if entry and type_name and canonical_type(entry.type) != canonical_type(str(type_name)):
            client.status("error", f"subscribe {name}: topic has type {entry.type}, not {type_name}", op_id)
            return
        compression = str(msg.get("compression") or "none")
        if compression not in ("none", "png"):
            client.status("warning", f"subscribe {name}: compression '{compression}' not supported, using none")
            compression = "none"
        try:
            params = SubParams(
                throttle_ms=max(0, int(msg.get("throttle_rate") or 0)),
                queue_length=max(0, int(msg.get("queue_length") or 0)),
                fragment_size=int(msg["fragment_size"]) if msg.get("fragment_size") else None,
                compression=compression,
            )
        except (TypeError, ValueError):
            client.status("error", f"subscribe {name}: throttle_rate/queue_length must be integers", op_id)
            return
        entry = entry or self.topics.setdefault(name, TopicEntry(name, str(type_name)))
        sub = entry.subs.setdefault((client.cid, spelled), Subscription(client, name, spelled=spelled))
        sub.by_id[str(op_id) if op_id is not None else f"anon:{next(self._ids)}"] = params
        if entry.last is not None:
            self._deliver_now(sub, entry.last)

    def _op_unsubscribe(self, client: ClientSession, msg: dict[str, Any]) -> None:
        spelled, op_id = str(msg["topic"]), msg.get("id")
        name = resolve_name(spelled)
        entry = self.topics.get(name)
        sub = entry.subs.get((client.cid, spelled)) if entry else None
        if entry is None or sub is None:
            client.status("warning", f"unsubscribe {name}: not subscribed", op_id)
            return
        if op_id is not None and str(op_id) in sub.by_id:
            del sub.by_id[str(op_id)]
        else:
            sub.by_id.clear()
        if not sub.by_id:
            sub.cancel()
            del entry.subs[(client.cid, spelled)]
            self._forget_if_unused(entry)

    def _op_set_level(self, client: ClientSession, msg: dict[str, Any]) -> None:
        level = str(msg["level"])
        if level not in STATUS_LEVELS:
            client.status("error", f"set_level: unknown level '{level}' (none, error, warning, info)")
            return
        client.level = STATUS_LEVELS[level]

    def _op_fragment(self, client: ClientSession, msg: dict[str, Any]) -> None:
        parts = self._fragments.setdefault(f"{client.cid}:{msg['id']}", {})
        parts[int(msg["num"])] = str(msg["data"])
        if len(parts) == int(msg["total"]):
            del self._fragments[f"{client.cid}:{msg['id']}"]
            self.dispatch(client, "".join(parts[i] for i in sorted(parts)))

    # -- internals --------------------------------------------------------------------------------

    def _fan_out(self, entry: TopicEntry, text: str) -> None:
        if entry.latched:
            entry.last = text
        now = time.monotonic()
        for sub in list(entry.subs.values()):
            throttle = sub.throttle_s
            if sub.queue_length > 0:
                sub.pending.append(text)
                while len(sub.pending) > sub.queue_length:
                    sub.pending.popleft()
                self._flush(sub, now)
            elif throttle <= 0 or now - sub.last_sent >= throttle:
                sub.last_sent = now
                self._send(sub, text, control=False)
            # else: throttled with no queue -> dropped, as rosbridge does

    def _flush(self, sub: Subscription, now: float | None = None) -> None:
        sub.flush_handle = None
        if not sub.by_id:  # every subscriber left while a throttled send was pending
            sub.pending.clear()
            return
        now = time.monotonic() if now is None else now
        wait = sub.throttle_s - (now - sub.last_sent)
        if sub.pending and wait <= 0:
            sub.last_sent = now
            self._send(sub, sub.pending.popleft(), control=False)
        if sub.pending and sub.flush_handle is None:
            delay = max(sub.throttle_s - (now - sub.last_sent), 0.001)
            sub.flush_handle = asyncio.get_running_loop().call_later(delay, self._flush, sub)

    def _deliver_now(self, sub: Subscription, text: str) -> None:
        sub.last_sent = time.monotonic()
        self._send(sub, text, control=True)

    def _send(self, sub: Subscription, text: str, *, control: bool) -> None:
        if sub.spelled and sub.spelled != sub.topic:  # the topic field comes first after "op"
            text = text.replace(json.dumps(sub.topic), json.dumps(sub.spelled), 1)
        if sub.compression == "png":
            text = png_encode(text)
        size = sub.fragment_size
        pieces = fragments(text, size, f"{sub.topic}:{next(self._ids)}") if size and len(text) > size else [text]
        for piece in pieces:
            if control:
                sub.client.send_control(piece)
            else:
                sub.client.send_data(piece)

    def _forget_if_unused(self, entry: TopicEntry) -> None:
        if entry.unused and not entry.latched:
            self.topics.pop(entry.name, None)

    def _drop_client(self, client: ClientSession) -> None:
        self.clients.pop(client.cid, None)
        for entry in list(self.topics.values()):
            for key in [k for k in entry.subs if k[0] == client.cid]:
                entry.subs.pop(key).cancel()
            entry.publishers.discard(client.cid)
            self._forget_if_unused(entry)
        self.drop_services_of(client)
        self.drop_actions_of(client)
