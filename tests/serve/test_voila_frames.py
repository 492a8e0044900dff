"""Kernel websocket frames are checked before jupyter_server parses them (issue 38, item 3).

A frame's header promised more offsets than it held, and jupyter_server allocated for the promise: a
68-byte v1 frame with a count of 2**24 held Voilà for 13 s (260 MB); read by the legacy deserializer,
a 68-byte frame grew it by 270 MB for good.
"""

from __future__ import annotations

import tracemalloc

from jupyter_server.services.kernels.connection.base import deserialize_msg_from_ws_v1, serialize_msg_to_ws_v1

from pmk_nb.serve.voila_frames import FrameFault, v1_frame_fault


def _frame(*parts: bytes, channel: str = "shell") -> bytes:
    return serialize_msg_to_ws_v1(list(parts), channel)


def test_a_frame_as_jupyter_serializes_it_passes() -> None:
    for parts in ((b"{}", b"{}", b"{}", b"{}"), (b'{"a": 1}', b"{}", b"{}", b"{}", b"\x00" * 1000), ()):
        frame = _frame(*parts)
        assert v1_frame_fault(frame) is None
        assert deserialize_msg_from_ws_v1(frame) == ("shell", list(parts))


def test_a_count_the_frame_cannot_hold_is_refused_without_allocating_for_it() -> None:
    for count in (3, 2**24, 2**63, 2**64 - 1):
        frame = count.to_bytes(8, "little") + b"\0" * 60  # 68 bytes: room for 7 offsets
        tracemalloc.start()
        try:
            fault = v1_frame_fault(frame)
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        assert fault is (FrameFault.COUNT_TOO_LARGE if count > 7 else FrameFault.OFFSET_OUT_OF_FRAME), count
        assert peak < 10_000, f"count {count}: {peak} bytes allocated"


def test_each_kind_of_malformed_frame_has_its_fault() -> None:
    good = _frame(b"{}", b"{}", b"{}", b"{}")
    assert v1_frame_fault(good.decode("latin-1")) is FrameFault.TEXT
    assert v1_frame_fault(b"\x02\0\0") is FrameFault.SHORT
    assert v1_frame_fault((1).to_bytes(8, "little") + b"\0" * 8) is FrameFault.TOO_FEW_OFFSETS
    assert v1_frame_fault(good[:-1]) is FrameFault.OFFSET_OUT_OF_FRAME  # the last offset is past the end
    inside_header = bytearray(good)
    inside_header[8:16] = (8).to_bytes(8, "little")  # the channel would start inside the offsets
    assert v1_frame_fault(bytes(inside_header)) is FrameFault.OFFSET_OUT_OF_FRAME
    swapped = bytearray(good)
    swapped[16:24], swapped[24:32] = good[24:32], good[16:24]
    assert v1_frame_fault(bytes(swapped)) is FrameFault.OFFSETS_OUT_OF_ORDER


def test_a_page_may_send_a_file_as_large_as_the_uploads_allow() -> None:
    """A file chosen on the device travels to the kernel as one websocket message: tornado's 10 MiB
    default closed the page's socket on a bigger MCAP or plan (tests/browser/test_browser_record.py
    uploads an 11 MiB one through the served page)."""
    from pmk_nb.recordings.folder import UPLOAD_MAX_BYTES as RECORDING_MAX
    from pmk_nb.serve.voila import server_config
    from pmk_nb.ui.maps.importer import UPLOAD_MAX_BYTES as PLAN_MAX

    tornado = server_config("t" * 20)["Voila"]["tornado_settings"]  # type: ignore[index]
    limit = tornado["websocket_max_message_size"]
    assert limit > max(RECORDING_MAX, PLAN_MAX) + 2**20  # the file and the message's own header
    assert limit < 2**30  # still bounded: a page cannot make the server buffer without end
