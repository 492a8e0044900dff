"""Why a recording could not be opened as tables: types with fields, beside the package that raises them."""

from __future__ import annotations

from pmk_nb.errors import PmkError


class RecordingReadError(PmkError):
    """A recording could not be read; ``path`` is the file."""

    def __init__(self, message: str, *, path: str, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.path = path


class NotARecording(RecordingReadError):
    """The file is missing or is not a readable MCAP file (``reason``: what the reader said)."""

    def __init__(self, *, path: str, reason: str) -> None:
        super().__init__(f"cannot read {path} as an MCAP recording: {reason}", path=path)
        self.reason = reason


class UnsupportedEncoding(RecordingReadError):
    """A topic asked for is written in an encoding this reader does not decode (protobuf, flatbuffer...)."""

    def __init__(self, *, path: str, topic: str, message_encoding: str, schema_encoding: str) -> None:
        super().__init__(
            f"cannot decode {topic} in {path}: {message_encoding} messages with {schema_encoding or 'no'} schemas",
            path=path,
            hint="Readable: cdr (ros2msg, ros2idl), ros1 (ros1msg) and json.",
        )
        self.topic, self.message_encoding, self.schema_encoding = topic, message_encoding, schema_encoding


class MissingPackage(RecordingReadError):
    """A Python package the reading needs is not installed (``package``: its name, ``purpose``: for what)."""

    def __init__(self, *, path: str, package: str, purpose: str) -> None:
        super().__init__(
            f"reading {path} {purpose} needs the Python package {package!r}, which is not installed",
            path=path,
            hint=f"Install {package} into the notebook's environment (pip install {package}).",
        )
        self.package, self.purpose = package, purpose


class RecordingFileError(PmkError):
    """A recording could not be chosen or stored in the recordings folder (``name``: the file as the user
    named it, ``folder``: the recordings folder, ``reason``: why)."""

    def __init__(self, *, name: str, folder: str, reason: str, hint: str = "") -> None:
        super().__init__(f"{name}: {reason}", hint=hint)
        self.name, self.folder, self.reason = name, folder, reason
