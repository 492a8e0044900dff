"""One blocking rosbridge service call with a deadline and typed errors.

Never queued: the caller passes an open ``Ros`` (see ``ChairLink._require_ros``), so a call made
while disconnected fails at once instead of running later after a reconnect.
"""

from __future__ import annotations

from typing import Any

import roslibpy
from roslibpy.core import RosTimeoutError, ServiceException

from pmk_nb.errors import ChairLinkError, ChairTimeout


def call_service(
    ros: roslibpy.Ros, chair: tuple[str, int], name: str, type_name: str, args: dict[str, Any], seconds: float
) -> dict[str, Any]:
    """Call ``name`` and return its answer.

    Raises:
        ChairTimeout: no answer within ``seconds`` (``operation`` is the service name).
        ChairLinkError: the service answered with an error.
    """
    host, port = chair
    service = roslibpy.Service(ros, name, type_name)
    try:
        result = service.call(roslibpy.ServiceRequest(args), timeout=seconds)
    except RosTimeoutError:
        raise ChairTimeout(
            f"timed out: {name} on {host}:{port} did not answer within {seconds:.1f} s",
            operation=name,
            seconds=seconds,
            host=host,
            port=port,
        ) from None
    except ServiceException as err:
        raise ChairLinkError(f"{name} on {host}:{port} failed: {err}", host=host, port=port) from err
    return dict(result)
