"""The Home screen's up-front warnings: a missing preview image, an unreachable chair.

The original app warned as soon as Home was shown (thesis 5.2.3.1: a dialog when the current map
has no image, another when the tablet's wifi is off), before the user pressed anything.  These are
the checks behind those warnings, kept free of widgets so they are tested on their own.
"""

from __future__ import annotations

import socket
import threading
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pmk_nb.ui.common.context import CurrentMap

PROBE_TIMEOUT = 2.0


def preview_image_path(current: CurrentMap) -> Path:
    """The map's ``NAME-visualization.png``: the one recorded when it was sent, else the usual name."""
    if current.preview is not None:
        return Path(current.preview)
    yaml = Path(current.yaml)
    return yaml.with_name(f"{yaml.stem}-visualization.png")


def preview_image_problem(current: CurrentMap) -> str | None:
    """A user message when the current map's preview image is missing, else None.

    The live view draws from the map files themselves, so this is a warning, not a blocker; the
    message says so and how to get the image back.
    """
    path = preview_image_path(current)
    if path.is_file():
        return None
    return (
        f"The preview image {path.name} of map '{current.name}' is missing from {path.parent}. "
        "The live view draws the map from its map file instead; convert the map again on the Maps "
        "screen to restore the image."
    )


def probe_chair(host: str, port: int, timeout: float = PROBE_TIMEOUT) -> str | None:
    """Can a TCP connection reach ``host:port`` (the chair's rosbridge)? None if so, else why not.

    A plain connect, no WebSocket handshake: cheap enough to run each time Home is shown, and it is
    exactly the question the original's "wifi is off" dialog answered.
    """
    try:
        with socket.create_connection((host, int(port)), timeout=timeout):
            return None
    except TimeoutError:
        return f"no answer within {timeout:g} s"
    except OSError as err:
        return err.strerror or str(err)
    except (ValueError, OverflowError) as err:  # bad port number from a hand-edited profile
        return str(err)


class ChairProbe:
    """Runs :func:`probe_chair` in a thread; only the newest check reports.

    ``report(host, port, problem)`` is called from the probe thread with None when the chair
    answers; a check superseded by a newer one or by :meth:`cancel` (the preview's own connection
    reports on the chair from then on) says nothing.
    """

    def __init__(self, report: Callable[[str, int, str | None], None]) -> None:
        self._report = report
        self._lock = threading.Lock()
        self._generation = 0

    def cancel(self) -> None:
        """Silence the checks under way."""
        with self._lock:
            self._generation += 1

    def check(self, host: str, port: int) -> threading.Thread:
        with self._lock:
            self._generation += 1
            generation = self._generation

        def probe() -> None:
            problem = probe_chair(host, port)
            with self._lock:
                if generation != self._generation:
                    return
            self._report(host, port, problem)

        thread = threading.Thread(target=probe, name="pmk-home-probe", daemon=True)
        thread.start()
        return thread
