"""A recording (MCAP) -> one table per topic: rows of flat dicts (:mod:`.flatten`), and DataFrames on demand.

Reads any MCAP whose channels :mod:`.decode` decodes: ours (``ChairLink.record``), ``ros2 bag``'s,
Foxglove's (JSON, ROS 1). The rows need nothing beyond the MCAP readers; :meth:`Tables.frames` needs
pandas (:mod:`.frames`).
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pmk_nb.recordings.decode import Decoder, decoder_for
from pmk_nb.recordings.errors import NotARecording, UnsupportedEncoding
from pmk_nb.recordings.flatten import row
from pmk_nb.recordings.frames import require_pandas, to_frames

if TYPE_CHECKING:
    import pandas as pd  # type: ignore[import-untyped,import-not-found,unused-ignore]  # optional


@dataclass
class Tables:
    """One recording's tables. ``rows[topic]``: its messages in file order, each a flat dict starting
    with ``received`` and ``stamp``; ``types[topic]``: the schema's type name; ``skipped[topic]``: a
    channel in an encoding this reader cannot decode (read only when no topics were asked for);
    ``bad[topic]``: messages whose bytes did not decode with their schema (left out, counted)."""

    path: Path
    rows: dict[str, list[dict[str, Any]]] = field(default_factory=dict)
    types: dict[str, str] = field(default_factory=dict)
    skipped: dict[str, UnsupportedEncoding] = field(default_factory=dict)
    bad: dict[str, int] = field(default_factory=dict)

    def frames(self) -> dict[str, pd.DataFrame]:
        """One ``pandas.DataFrame`` per topic (columns: ``received``, ``stamp``, then the fields).

        Raises:
            MissingPackage: pandas is not installed.
        """
        return to_frames(self)


def _open_reader(path: Path, fh: Any) -> Any:
    from mcap.exceptions import McapError
    from mcap.reader import make_reader

    try:
        return make_reader(fh)
    except (McapError, ValueError, EOFError) as err:
        raise NotARecording(path=str(path), reason=str(err) or type(err).__name__) from err


class _Channels:
    """Decoders per channel id, made on first use; undecodable channels remembered in ``tables.skipped``."""

    def __init__(self, tables: Tables, wanted: set[str] | None) -> None:
        self.tables, self.wanted = tables, wanted
        self._decoders: dict[int, Decoder | None] = {}

    def register_all(self, reader: Any) -> None:
        """Every channel the file's summary lists, messages or not: a silent topic is an empty table."""
        summary = reader.get_summary()
        for channel in (summary.channels if summary is not None else {}).values():
            if self.wanted is None or channel.topic in self.wanted:
                self.decoder(summary.schemas.get(channel.schema_id), channel)

    def decoder(self, schema: Any, channel: Any) -> Decoder | None:
        if channel.id not in self._decoders:
            topic = channel.topic
            try:
                self._decoders[channel.id] = decoder_for(str(self.tables.path), topic, channel.message_encoding, schema)
            except UnsupportedEncoding as err:
                if self.wanted is not None:
                    raise
                self.tables.skipped[topic] = err
                self._decoders[channel.id] = None
            else:
                self.tables.rows.setdefault(topic, [])
                self.tables.types[topic] = schema.name if schema is not None else ""
        return self._decoders[channel.id]


def read_recording(path: str | os.PathLike[str], topics: Iterable[str] | None = None) -> Tables:
    """Read the recording at ``path`` into rows per topic (``topics``: only these; a topic asked for
    that the file lacks has no rows).

    Raises:
        NotARecording: missing file or not MCAP; UnsupportedEncoding: a topic asked for cannot be
        decoded; MissingPackage: its encoding needs rosbags.
    """
    from mcap.exceptions import McapError

    file = Path(path)
    wanted = set(topics) if topics is not None else None
    tables = Tables(file, rows={t: [] for t in sorted(wanted or ())})
    channels = _Channels(tables, wanted)
    try:
        with file.open("rb") as fh:
            reader = _open_reader(file, fh)
            channels.register_all(reader)
            for schema, channel, message in reader.iter_messages(topics=sorted(wanted) if wanted else None):
                decode = channels.decoder(schema, channel)
                if decode is None:
                    continue
                try:
                    decoded = decode(message.data)
                except Exception:  # any decoder's error: one message that does not fit its schema is counted
                    tables.bad[channel.topic] = tables.bad.get(channel.topic, 0) + 1
                    continue
                tables.rows[channel.topic].append(row(decoded, message.log_time))
    except OSError as err:
        raise NotARecording(path=str(file), reason=err.strerror or str(err)) from err
    except McapError as err:
        raise NotARecording(path=str(file), reason=str(err) or type(err).__name__) from err
    return tables


def read_frames(path: str | os.PathLike[str], topics: Iterable[str] | None = None) -> dict[str, pd.DataFrame]:
    """``read_recording(path, topics).frames()``: one ``pandas.DataFrame`` per topic.

    Raises:
        MissingPackage: pandas is not installed (checked before the file is read); as :func:`read_recording`.
    """
    require_pandas(str(path))
    return read_recording(path, topics).frames()
