"""One connected rosbridge client: its own send queues, so a slow client never blocks the sim.

Control messages (service responses, status, latched messages on subscribe) go in an unbounded
queue and are sent first; topic data goes in a bounded queue that drops the oldest message when a
client falls behind, which is what rosbridge's ``queue_length`` promises per subscription.
"""

from __future__ import annotations

import asyncio
import base64
import io
import json
import math
from collections import deque
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from websockets.exceptions import ConnectionClosed

if TYPE_CHECKING:
    from websockets.asyncio.server import ServerConnection

STATUS_LEVELS = {"none": 0, "error": 1, "warning": 2, "info": 3}
DEFAULT_CLIENT_QUEUE = 200


def resolve_name(name: object) -> str:
    """A topic or service name as rosbridge resolves it in the root namespace."""
    text = str(name)
    return text if text.startswith("/") else "/" + text.lstrip("~/")


@dataclass
class SubParams:
    throttle_ms: int = 0
    queue_length: int = 0
    fragment_size: int | None = None
    compression: str = "none"


@dataclass
class Subscription:
    """All subscribe requests of one client to one topic, merged the way rosbridge merges them."""

    client: ClientSession
    topic: str
    by_id: dict[str, SubParams] = field(default_factory=dict)
    spelled: str = ""  # the client's own spelling of the topic (may be relative)
    last_sent: float = -math.inf
    pending: deque[str] = field(default_factory=deque)
    flush_handle: asyncio.TimerHandle | None = None

    @property
    def throttle_s(self) -> float:
        return min(p.throttle_ms for p in self.by_id.values()) / 1000.0

    @property
    def queue_length(self) -> int:
        return max(p.queue_length for p in self.by_id.values())

    @property
    def fragment_size(self) -> int | None:
        sizes = [p.fragment_size for p in self.by_id.values() if p.fragment_size]
        return min(sizes) if sizes else None

    @property
    def compression(self) -> str:
        return "png" if any(p.compression == "png" for p in self.by_id.values()) else "none"

    def cancel(self) -> None:
        if self.flush_handle is not None:
            self.flush_handle.cancel()
            self.flush_handle = None


class ClientSession:
    """Send side of one WebSocket connection; all methods run on the server's loop."""

    def __init__(self, cid: int, ws: ServerConnection, max_queue: int = DEFAULT_CLIENT_QUEUE) -> None:
        self.cid = cid
        self.ws = ws
        self.level = STATUS_LEVELS["error"]
        self.dropped = 0
        self.advertised: dict[str, str] = {}  # topic -> type this client advertised
        self.services: set[str] = set()  # services this client provides
        self.authenticated = True  # False until a granted ``auth`` op when the bridge requires one
        self.held: deque[str] | None = None  # ops waiting behind a running goal (official bridge mode)
        self._control: deque[str] = deque()
        self._data: deque[str] = deque(maxlen=max_queue)
        self._wake = asyncio.Event()
        self._closed = False

    def send_control(self, msg: dict[str, Any] | str) -> None:
        if not self._closed:
            self._control.append(msg if isinstance(msg, str) else json.dumps(msg))
            self._wake.set()

    def send_data(self, text: str) -> None:
        if self._closed:
            return
        if len(self._data) == self._data.maxlen:
            self.dropped += 1
        self._data.append(text)
        self._wake.set()

    def status(self, level: str, msg: str, op_id: str | None = None) -> None:
        if STATUS_LEVELS[level] <= self.level:
            out: dict[str, Any] = {"op": "status", "level": level, "msg": msg}
            if op_id is not None:
                out["id"] = op_id
            self.send_control(out)

    async def run_writer(self) -> None:
        """Drain the queues into the socket; awaiting ``send`` here is where backpressure lands."""
        try:
            while not self._closed:
                await self._wake.wait()
                self._wake.clear()
                while self._control or self._data:
                    text = self._control.popleft() if self._control else self._data.popleft()
                    await self.ws.send(text)
        except ConnectionClosed:
            pass
        finally:
            self._closed = True

    def close(self) -> None:
        self._closed = True
        self._wake.set()


def fragments(text: str, size: int, frag_id: str) -> list[str]:
    """Split an encoded message into rosbridge ``fragment`` ops of at most ``size`` characters."""
    pieces = [text[i : i + size] for i in range(0, len(text), size)]
    return [
        json.dumps({"op": "fragment", "id": frag_id, "data": p, "num": n, "total": len(pieces)})
        for n, p in enumerate(pieces)
    ]


def png_encode(text: str) -> str:
    """rosbridge ``png`` op: the JSON bytes packed as RGB pixels of a PNG, newline padded, base64."""
    from PIL import Image

    raw = text.encode("utf-8")
    width = max(1, math.floor(math.sqrt(len(raw) / 3.0)))
    height = max(1, math.ceil(len(raw) / 3.0 / width))
    raw += b"\n" * (width * height * 3 - len(raw))
    buf = io.BytesIO()
    Image.frombytes("RGB", (width, height), raw).save(buf, "png")
    return json.dumps({"op": "png", "data": base64.standard_b64encode(buf.getvalue()).decode("ascii")})


def png_decode(data: str) -> str:
    """Inverse of :func:`png_encode` (used by tests and by clients written in Python)."""
    from PIL import Image

    img = Image.open(io.BytesIO(base64.standard_b64decode(data))).convert("RGB")
    return img.tobytes().rstrip(b"\n").decode("utf-8")
