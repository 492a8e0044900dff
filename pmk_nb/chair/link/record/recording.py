"""Record the chair's topics to MCAP (ROS 2 schemas, CDR messages): Foxglove, ``ros2 bag`` and rosbags open it.

Any type the bridge can describe is recorded: the bundled definitions (:mod:`.msgdefs`) need no round
trip; any other type's definition is asked once from rosapi's ``message_details`` (:mod:`.msgdetails`).

A recording has its own rosbridge connection (a second ``LinkRos``): roslibpy keys topic callbacks
by topic name and its ``unsubscribe`` drops every callback of that name, so sharing the link's
connection would cut the live view off when a recording stops; the link's streams may also be
throttled for the screen, and a recording wants every message.

Threads: the connection's I/O thread only pushes ``(receive time, topic, raw dict)`` into a bounded
queue (a full queue drops the message and counts it; the I/O thread never waits); the writer thread
converts (:mod:`.record_convert`), encodes and writes. The file is written through
``fileio.atomic_open``: it appears, complete, only when the recording stops; a failure leaves no
half file. ``log_time`` is the receive time, ``publish_time`` the header stamp when there is one.
"""

from __future__ import annotations

import logging
import os
import queue
import threading
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import roslibpy

from pmk_nb.chair.link.query.discovery import RosapiMissing
from pmk_nb.chair.link.record.msgdefs import DEFINITIONS
from pmk_nb.chair.link.record.msgdetails import describe
from pmk_nb.chair.link.record.record_convert import stamp_ns, to_ros2
from pmk_nb.chair.link.transport.ros import LinkRos
from pmk_nb.errors import ChairLinkError, PmkError
from pmk_nb.fileio import atomic_open
from pmk_nb.wire import spell_type, type_spellings

if TYPE_CHECKING:
    from pmk_nb.chair.link.core import LinkCore

LOG = logging.getLogger(__name__)
QUEUE_LIMIT = 2000  # messages waiting for the writer (~10 s of odom + scan + tf); more are dropped
#: Types of well-known topics, for a bridge without rosapi.
KNOWN_TYPES: dict[str, str] = {
    "/tf": "tf2_msgs/msg/TFMessage",
    "/tf_static": "tf2_msgs/msg/TFMessage",
    "/map": "nav_msgs/msg/OccupancyGrid",
    "/map_metadata": "nav_msgs/msg/MapMetaData",
    "/cmd_vel": "geometry_msgs/msg/Twist",
    "/amcl_pose": "geometry_msgs/msg/PoseWithCovarianceStamped",
    "/initialpose": "geometry_msgs/msg/PoseWithCovarianceStamped",
    "/plan": "nav_msgs/msg/Path",
}
#: Topics to record: names (types from rosapi), or {name: type}.
Topics = Sequence[str] | Mapping[str, str] | None
SUPPORTED: tuple[str, ...] = tuple(sorted(DEFINITIONS))


class RecordError(PmkError):
    """A recording could not start or could not be written; ``path`` is the file it was for."""

    def __init__(self, message: str, *, path: str, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.path = path


class UnknownTopic(RecordError):
    """The chair publishes no such topic (rosapi lists it not), so its type is unknown."""

    def __init__(self, *, path: str, topic: str, known: list[str]) -> None:
        super().__init__(f"the chair has no topic {topic}", path=path, hint="Pass {topic: type} to record it anyway.")
        self.topic, self.known = topic, known


class UnsupportedType(RecordError):
    """The topic's type has no bundled definition and the bridge cannot describe it (no rosapi, or
    rosapi's ``message_details`` does not know it), so it cannot be written with a schema.
    ``supported``: the bundled types; ``rosapi``: False when the bridge has no rosapi to ask."""

    def __init__(self, *, path: str, topic: str, type_name: str, rosapi: bool = True) -> None:
        super().__init__(
            f"cannot record {topic}: the chair's bridge cannot describe {type_name}",
            path=path,
            hint="" if rosapi else "Start rosapi with the bridge: it describes the message types.",
        )
        self.topic, self.type_name, self.supported, self.rosapi = topic, type_name, SUPPORTED, rosapi


class RecordDiskError(RecordError):
    """The file could not be written (disk full, no permission); no partial file is left."""

    def __init__(self, *, path: str, reason: str, errno: int | None) -> None:
        super().__init__(f"could not write the recording {path}: {reason}", path=path)
        self.reason, self.errno = reason, errno


@dataclass
class RecordStats:
    """What a recording holds so far (``messages`` per topic written; ``dropped``: queue full;
    ``invalid``: a message that did not fit its type's schema)."""

    path: Path
    started: float  # time.time() at start
    duration: float = 0.0
    messages: dict[str, int] = field(default_factory=dict)
    dropped: int = 0
    invalid: int = 0
    finished: bool = False

    @property
    def total(self) -> int:
        return sum(self.messages.values())

    @property
    def silent(self) -> list[str]:
        """The topics that delivered no message (e.g. ``/cmd_vel`` on a parked chair), sorted."""
        return sorted(t for t, n in self.messages.items() if not n)


def ros2_type(type_name: str) -> str:
    """Any spelling -> ``pkg/msg/Type``."""
    spellings = type_spellings(type_name)
    return next((s for s in spellings if s.count("/") == 2), type_name)


def resolve_topics(link: LinkCore, topics: Topics, path: str) -> dict[str, str]:
    """{topic: ROS 2 type} to record. ``None``: the link's odometry, scan and pose topics, /tf,
    /tf_static, /cmd_vel and /map, those the chair has. Types come from rosapi, else ``KNOWN_TYPES``.

    Raises:
        UnknownTopic; ChairLinkError when the link is not connected.
    """
    cfg = link.config
    given = dict(topics) if isinstance(topics, Mapping) else dict.fromkeys(topics or (), "")
    defaults = {cfg["odom_topic"]: "nav_msgs/msg/Odometry", cfg["scan_topic"]: "sensor_msgs/msg/LaserScan"}
    if cfg["pose_topic"]:
        defaults[cfg["pose_topic"]] = ""
    defaults |= {t: KNOWN_TYPES[t] for t in ("/tf", "/tf_static", "/cmd_vel", "/map")}
    try:
        listed: dict[str, str] | None = link.discovery.topics()
    except RosapiMissing:
        listed = None
    wanted = given or {t: ty for t, ty in defaults.items() if listed is None or t in listed}
    found: dict[str, str] = {}
    for topic, type_name in wanted.items():
        type_name = type_name or (listed or {}).get(topic) or KNOWN_TYPES.get(topic) or defaults.get(topic, "")
        if not type_name:
            raise UnknownTopic(path=path, topic=topic, known=sorted(listed or ()))
        found[topic] = ros2_type(type_name)
    return found


def resolve_definitions(link: LinkCore, types: Mapping[str, str], path: str) -> dict[str, str]:
    """{ROS 2 type: concatenated definition} for ``types`` ({topic: type}): the bundled one without a
    round trip, else the bridge's (rosapi ``message_details``, one call per type).

    Raises:
        UnsupportedType: the bridge cannot describe a type; ChairTimeout: rosapi did not answer.
    """
    found: dict[str, str] = {}
    for topic, type_name in sorted(types.items()):
        if type_name in found:
            continue
        definition = DEFINITIONS.get(type_name)
        if definition is None:
            try:
                definition = describe(link.discovery, type_name)
            except RosapiMissing:
                raise UnsupportedType(path=path, topic=topic, type_name=type_name, rosapi=False) from None
        if definition is None:
            raise UnsupportedType(path=path, topic=topic, type_name=type_name)
        found[type_name] = definition
    return found


class Inbox:
    """The bounded queue between the I/O thread and the writer: ``push`` never waits; a full inbox
    drops the message and counts it in ``dropped``."""

    def __init__(self, limit: int = QUEUE_LIMIT) -> None:
        self._queue: queue.Queue[tuple[int, str, dict[str, Any]]] = queue.Queue(maxsize=limit)
        self.dropped = 0  # counted on the one pushing thread

    def push(self, topic: str, msg: dict[str, Any]) -> bool:
        try:
            self._queue.put_nowait((time.time_ns(), topic, msg))
        except queue.Full:
            self.dropped += 1
            return False
        return True

    def get(self, timeout: float) -> tuple[int, str, dict[str, Any]] | None:
        try:
            return self._queue.get(timeout=timeout)
        except queue.Empty:
            return None

    def empty(self) -> bool:
        return self._queue.empty()


class _Abandoned(Exception):
    """Raised in the writer when the recording never started: the temporary file is removed."""


class Recording:
    """A running recording; :meth:`stop` finishes the file. Create with :meth:`ChairLink.start_recording`."""

    def __init__(
        self,
        link: LinkCore,
        path: str | os.PathLike[str],
        types: dict[str, str],
        queue_limit: int = QUEUE_LIMIT,
        definitions: Mapping[str, str] | None = None,
    ):
        self.path = Path(path)
        self.types = types
        #: {ROS 2 type: concatenated definition} written as schemas (default: the bundled ones)
        self.definitions = dict(definitions) if definitions is not None else {t: DEFINITIONS[t] for t in types.values()}
        self.stats = RecordStats(self.path, time.time(), messages=dict.fromkeys(types, 0))
        self.inbox = Inbox(queue_limit)
        self._abandoned = False
        self._stopping = threading.Event()
        self._error: RecordError | None = None
        self._ready = threading.Event()  # the file is open (or failed to open)
        self._writer = threading.Thread(target=self._write_all, name=f"pmk-record-{self.path.name}", daemon=True)
        self._writer.start()
        self._ready.wait(10.0)
        if self._error is not None:
            raise self._error
        self._heard: set[str] = set()  # topics that delivered a message (I/O thread adds)
        self._flowing = threading.Event()  # a topic has delivered one: the connection's subscriptions are live
        self._ros = self._connect(link)
        self._ros_version = link.ros_version
        self._topics = {topic: self._subscribe(topic, type_name) for topic, type_name in types.items()}

    # -- the connection (I/O thread: push only) ---------------------------------------------------
    def _connect(self, link: LinkCore, timeout: float = 5.0) -> LinkRos:
        ros = LinkRos(
            link.host, link.port, thread_name=f"pmk-record-io-{link.host}:{link.port}", tls=link.tls, auth=link.auth
        )
        ros.connect()
        if not ros.settled.wait(timeout) or ros.refusal is not None:
            ros.shutdown(1.0)
            self._abandoned = True
            self._finish()
            raise ros.refusal or ChairLinkError(
                f"the recording's connection to {link.host}:{link.port} did not open within {timeout:.0f} s",
                host=link.host,
                port=link.port,
            )
        return ros

    def _subscribe(self, topic: str, type_name: str) -> roslibpy.Topic:
        sub = roslibpy.Topic(self._ros, topic, spell_type(type_name, self._ros_version), queue_length=50)
        sub.subscribe(lambda msg, name=topic: self._receive(name, msg))
        return sub

    def _receive(self, topic: str, msg: dict[str, Any]) -> None:
        self.inbox.push(topic, msg)
        if topic not in self._heard:
            self._heard.add(topic)
            self._flowing.set()

    def wait_flowing(self, timeout: float = 10.0) -> bool:
        """Wait until the recording's connection delivers its first message, from any topic; True when it has.

        A ROS 2 bridge's subscription is live only once DDS has matched it with the publisher
        (a second or more on a loaded machine): a short recording started blind would hold
        little or nothing. It never waits for one topic in particular: a topic may be silent for
        the whole recording (``/cmd_vel`` on a parked chair; issue 40: 'seconds=2.0' took 12 s), and
        ``stats.silent`` names those. When nothing came halfway, every topic is subscribed once more
        (a bridge may have dropped subscriptions made while the topics were being set up).
        """
        if self._flowing.wait(timeout / 2) or not self.running:
            return self._flowing.is_set()
        for topic in sorted(self.types):
            self._topics.pop(topic).unsubscribe()
            self._topics[topic] = self._subscribe(topic, self.types[topic])
        return self._flowing.wait(timeout / 2)

    # -- the writer thread ------------------------------------------------------------------------
    def _write_all(self) -> None:
        from mcap_ros2.writer import Writer

        try:
            with atomic_open(self.path) as fh:
                writer = Writer(fh)
                schemas = {t: writer.register_msgdef(t, self.definitions[t]) for t in sorted(set(self.types.values()))}
                self._ready.set()
                while not (self._stopping.is_set() and self.inbox.empty()):
                    item = self.inbox.get(0.1)
                    if item is not None:
                        self._write_one(writer, schemas[self.types[item[1]]], *item)
                if self._abandoned:
                    raise _Abandoned
                writer.finish()  # type: ignore[no-untyped-call]  # mcap_ros2 has no hints on finish
        except _Abandoned:
            pass
        except OSError as err:
            self._error = RecordDiskError(path=str(self.path), reason=err.strerror or str(err), errno=err.errno)
            LOG.warning("recording %s failed: %s", self.path, err)
        finally:
            self._ready.set()

    def _write_one(self, writer: Any, schema: Any, received: int, topic: str, msg: dict[str, Any]) -> None:
        try:
            type_name = self.types[topic]
            message = to_ros2(msg, type_name, self.definitions[type_name])
            writer.write_message(topic, schema, message, log_time=received, publish_time=stamp_ns(message) or received)
        except (ValueError, TypeError, KeyError, OverflowError) as err:  # one odd message must not end the file
            self.stats.invalid += 1
            LOG.debug("skipped a %s message on %s: %s", self.types[topic], topic, err)
            return
        self.stats.messages[topic] += 1
        self.stats.dropped = self.inbox.dropped
        self.stats.duration = time.time() - self.stats.started

    # -- stopping ---------------------------------------------------------------------------------
    @property
    def running(self) -> bool:
        return not self._stopping.is_set()

    @property
    def error(self) -> RecordError | None:
        """Why the file could not be written (the writer has stopped; :meth:`stop` raises it)."""
        return self._error

    def _finish(self) -> None:
        self._stopping.set()
        self._writer.join(30.0)

    def stop(self) -> RecordStats:
        """Unsubscribe, write what is queued, finish the file; returns the stats (idempotent).

        Raises:
            RecordDiskError: the file could not be written (nothing is left at ``path``).
        """
        if self._stopping.is_set():
            return self.stats
        for sub in self._topics.values():
            sub.unsubscribe()
        self._ros.shutdown(2.0)
        self.stats.duration = time.time() - self.stats.started
        self._finish()
        self.stats.dropped = self.inbox.dropped
        self.stats.finished = self._error is None
        if self._error is not None:
            raise self._error
        return self.stats
