"""One decoder per MCAP channel: raw bytes -> a message (object or dict) :mod:`.flatten` reads.

* ``cdr`` + ``ros2msg`` (ours, ``ros2 bag``'s): mcap_ros2's decoder;
* ``cdr`` + ``ros2idl`` (``ros2 bag`` for types defined in IDL): rosbags, from the file's schema;
* ``ros1`` + ``ros1msg`` (Foxglove's and ``mcap convert``'s ROS 1 bags): rosbags, from the file's schema;
* ``json`` (Foxglove's JSON channels, any schema): the standard library.

rosbags is needed only for the second and third; without it they raise :class:`MissingPackage`.
Anything else (protobuf, flatbuffer, ...) is :class:`UnsupportedEncoding`.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from pmk_nb.recordings.errors import MissingPackage, UnsupportedEncoding

Decoder = Callable[[bytes], Any]
SEPARATOR = "=" * 80 + "\n"


def _ros2_name(name: str) -> str:
    parts = name.strip("/").split("/")
    return f"{parts[0]}/msg/{parts[-1]}" if len(parts) == 2 else name


def _rosbags_store(path: str) -> Any:
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise MissingPackage(path=path, package="rosbags", purpose="(ROS 1 or IDL schemas)") from None
    return get_typestore(Stores.EMPTY)


def _rosbags_decoder(path: str, schema: Any, ros1: bool) -> Decoder:
    from rosbags.typesys import get_types_from_idl, get_types_from_msg

    store = _rosbags_store(path)
    text = schema.data.decode()
    name = _ros2_name(schema.name)
    if schema.encoding == "ros2idl":
        parts = [p.split("\n", 1)[1] for p in text.split(SEPARATOR)[1:]] if text.startswith(SEPARATOR) else [text]
        for part in parts:
            store.register(get_types_from_idl(part))
    else:
        store.register(get_types_from_msg(text, name))
    if ros1:
        return lambda raw: store.deserialize_ros1(raw, name)
    return lambda raw: store.deserialize_cdr(raw, name)


def decoder_for(path: str, topic: str, message_encoding: str, schema: Any) -> Decoder:
    """The decoder of one channel (``schema``: the MCAP Schema record, or None).

    Raises:
        UnsupportedEncoding: no decoder for this pair of encodings; MissingPackage: rosbags is needed.
    """
    schema_encoding = schema.encoding if schema is not None else ""
    if message_encoding == "json":
        return json.loads
    if message_encoding == "cdr" and schema_encoding == "ros2msg":
        from mcap_ros2.decoder import DecoderFactory

        decoder = DecoderFactory().decoder_for(message_encoding, schema)
        if decoder is not None:
            return decoder
    if (message_encoding, schema_encoding) in (("cdr", "ros2idl"), ("ros1", "ros1msg")):
        return _rosbags_decoder(path, schema, ros1=message_encoding == "ros1")
    raise UnsupportedEncoding(
        path=path, topic=topic, message_encoding=message_encoding, schema_encoding=schema_encoding
    )
