"""One blocking rosbridge service call with a deadline and typed errors.

Never queued: the caller passes an open ``Ros`` (see ``ChairLink.require_ros``), so a call made
while disconnected fails at once instead of running later after a reconnect. When the websocket
closes while the call is out (rosbridge-server-rs closes a client whose answer does not fit its
send queue: "send queue full; closing slow client"), the call ends at once with
:class:`AnswerLost` instead of waiting for an answer that cannot come.
"""

from __future__ import annotations

import threading
import time
from typing import Any

import roslibpy

from pmk_nb.errors import ChairLinkError, ChairTimeout

POLL = 0.05  # s between checks of the websocket while waiting


class AnswerLost(ChairLinkError):
    """The request was sent but the connection closed before the answer came: nobody knows
    whether the service ran. ``service`` names it."""

    def __init__(self, message: str, *, service: str, host: str, port: int) -> None:
        super().__init__(message, host=host, port=port)
        self.service = service


class ServiceFailed(ChairLinkError):
    """The bridge answered the call with an error: the service does not exist (rosbridge says so at
    once) or its callback failed. ``answer`` is the bridge's text, kept for the message only."""

    def __init__(self, message: str, *, service: str, answer: str, host: str, port: int) -> None:
        super().__init__(message, host=host, port=port)
        self.service = service
        self.answer = answer


def call_service(
    ros: roslibpy.Ros, chair: tuple[str, int], name: str, type_name: str, args: dict[str, Any], seconds: float
) -> dict[str, Any]:
    """Call ``name`` and return its answer.

    Raises:
        ChairTimeout: no answer within ``seconds`` (``operation`` is the service name).
        AnswerLost: the websocket closed while the call was out.
        ServiceFailed: the service answered with an error (or does not exist).
    """
    host, port = chair
    done = threading.Event()
    box: dict[str, Any] = {}

    def ok(result: Any) -> None:  # I/O thread: store and wake, nothing else
        box["result"] = result
        done.set()

    def failed(error: Any) -> None:
        box["error"] = error
        done.set()

    sent_on = getattr(ros, "protocol", None)
    roslibpy.Service(ros, name, type_name).call(roslibpy.ServiceRequest(args), ok, failed)
    deadline = time.monotonic() + seconds
    while not done.wait(max(0.0, min(POLL, deadline - time.monotonic()))):
        if sent_on is not None and getattr(ros, "protocol", None) is not sent_on:
            raise AnswerLost(
                f"the connection to {host}:{port} closed while {name} was answering (the bridge may have "
                "dropped an answer too big for its send queue)",
                service=name,
                host=host,
                port=port,
            )
        if time.monotonic() >= deadline:
            raise ChairTimeout(
                f"timed out: {name} on {host}:{port} did not answer within {seconds:.1f} s",
                operation=name,
                seconds=seconds,
                host=host,
                port=port,
            )
    if "error" in box:
        answer = str(box["error"])
        raise ServiceFailed(
            f"{name} on {host}:{port} failed: {answer}", service=name, answer=answer, host=host, port=port
        )
    return dict(box["result"])
