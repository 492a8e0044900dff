"""Kernel websocket frames checked before jupyter_server parses them: a header that promises more
than its frame holds is refused before anything is allocated for it.

jupyter_server 2.21.1 trusts the count at the head of each frame (docs/upstream/jupyter_server-legacy-deserializer.md):

  * the v1 protocol (``v1.kernel.websocket.jupyter.org``): an 8-byte little-endian count of offsets,
    then the offsets (8 bytes each), then the channel name and the message parts they delimit.
    ``deserialize_msg_from_ws_v1`` builds a list of ``count`` offsets: a 68-byte frame with a count of
    2**24 held Voilà for 13 s and took 260 MB; 2**30 would take 8 GB.
  * the legacy binary format: a 4-byte big-endian count, then 4-byte offsets.
    ``deserialize_binary_message`` builds a ``struct`` format of ``count`` codes, which ``struct``
    keeps in its cache: a 68-byte frame grew Voilà from 99 to 371 MB for good.  jupyter_server uses it
    for a v1 socket the server has already closed (the subprotocol is then read as None); the guard
    (:class:`pmk_nb.serve.voila_guard.PageChannelConnection`) drops such frames and serves v1 only,
    so nothing reaches that deserializer.
"""

from __future__ import annotations

import enum
import itertools

V1_COUNT_BYTES = 8  # the count of offsets, and each offset, in a v1 frame
V1_MIN_OFFSETS = 2  # the channel's start and end (a message's parts follow)


class FrameFault(enum.Enum):
    """Why a frame is refused."""

    TEXT = "a text frame (v1 frames are binary)"
    SHORT = "shorter than its count"
    TOO_FEW_OFFSETS = "fewer offsets than a channel needs"
    COUNT_TOO_LARGE = "more offsets than the frame holds"
    OFFSET_OUT_OF_FRAME = "an offset inside the header or past the end"
    OFFSETS_OUT_OF_ORDER = "offsets out of order"


def v1_frame_fault(frame: bytes | str) -> FrameFault | None:
    """What is wrong with ``frame`` as a v1 kernel message, or None when jupyter_server may parse it.

    Only the header is read: the count is checked against the frame's length before any offset is."""
    if isinstance(frame, str):
        return FrameFault.TEXT
    size = len(frame)
    if size < V1_COUNT_BYTES:
        return FrameFault.SHORT
    count = int.from_bytes(frame[:V1_COUNT_BYTES], "little")
    if count < V1_MIN_OFFSETS:
        return FrameFault.TOO_FEW_OFFSETS
    header = V1_COUNT_BYTES * (count + 1)
    if header > size:
        return FrameFault.COUNT_TOO_LARGE
    view, width = memoryview(frame), V1_COUNT_BYTES
    offsets = [int.from_bytes(view[width * i : width * (i + 1)], "little") for i in range(1, count + 1)]
    if offsets[0] < header or offsets[-1] > size:
        return FrameFault.OFFSET_OUT_OF_FRAME
    if any(a > b for a, b in itertools.pairwise(offsets)):
        return FrameFault.OFFSETS_OUT_OF_ORDER
    return None
