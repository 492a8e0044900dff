"""Recordings (MCAP files) opened as tables: one per topic, flat columns, for researchers (issue 40).

``read_recording(path)`` -> :class:`Tables` (rows of flat dicts per topic: ``received``, ``stamp``,
``pose.pose.position.x``, ...; no pandas needed); ``read_frames(path)`` or ``Tables.frames()`` -> one
``pandas.DataFrame`` per topic (pandas is optional: :class:`MissingPackage` without it). Decodes ours,
``ros2 bag``'s and Foxglove's files (cdr with ros2msg or ros2idl schemas, ros1, json). ``Timeline``:
pose, laser and path at any time, and any numeric field as a series, for the dashboard's replay;
``list_recordings`` / ``save_upload``: the recordings folder it opens them from. The face is lazy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.recordings.errors import (
        MissingPackage,
        NotARecording,
        RecordingFileError,
        RecordingReadError,
        UnsupportedEncoding,
    )
    from pmk_nb.recordings.flatten import flatten, stamp_seconds
    from pmk_nb.recordings.folder import RecordingFile, list_recordings, recording_in, save_upload
    from pmk_nb.recordings.read import Tables, read_frames, read_recording
    from pmk_nb.recordings.timeline import ReplayFrame, Timeline

_WHERE = {
    "MissingPackage": "errors",
    "NotARecording": "errors",
    "RecordingFileError": "errors",
    "RecordingReadError": "errors",
    "RecordingFile": "folder",
    "list_recordings": "folder",
    "recording_in": "folder",
    "save_upload": "folder",
    "UnsupportedEncoding": "errors",
    "flatten": "flatten",
    "stamp_seconds": "flatten",
    "Tables": "read",
    "read_frames": "read",
    "read_recording": "read",
    "ReplayFrame": "timeline",
    "Timeline": "timeline",
}

__all__ = [
    "MissingPackage",
    "NotARecording",
    "RecordingFile",
    "RecordingFileError",
    "RecordingReadError",
    "ReplayFrame",
    "Tables",
    "Timeline",
    "UnsupportedEncoding",
    "flatten",
    "list_recordings",
    "read_frames",
    "read_recording",
    "recording_in",
    "save_upload",
    "stamp_seconds",
]

__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
