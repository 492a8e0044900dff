"""The topic inspector (issue 29): the chair's topics with their types; pick one to see its rate and
latest message.

The list is asked of rosapi on a worker thread (a blocking service call), else it is the topics the
link knows. Only the picked topic is subscribed, throttled (:mod:`pmk_nb.chair.link.streams.inspect`), and
it is unsubscribed when another is picked, the panel closes or the preview stops. The texts are
refreshed by :meth:`TopicInspector.tick` from Home's info timer, never per message.
"""

from __future__ import annotations

import logging
import threading
import time
from typing import Any

import ipywidgets as w

from pmk_nb.chair.link import LinkCore, TopicProbe, pretty_message, rate_text, topic_rows
from pmk_nb.errors import PmkError
from pmk_nb.ui.common.widgets import button, escape

log = logging.getLogger(__name__)

NONE = ""  # the list's "no topic" entry
#: the message box scrolls instead of pushing the page down by a screen per message
JSON_STYLE = "max-height: 320px; overflow: auto; font-size: 12px; background: #f5f7f9; padding: 6px; margin: 0"


def known_topics(link: LinkCore) -> dict[str, str]:
    """The topics the link itself streams, with their types: the list when there is no rosapi."""
    cfg = getattr(link, "config", None) or {}
    known = {
        str(cfg.get("odom_topic") or "/odom"): "nav_msgs/Odometry",
        str(cfg.get("scan_topic") or "/scan"): "sensor_msgs/LaserScan",
        "/tf": "tf2_msgs/TFMessage",
        "/plan": "nav_msgs/Path",
    }
    pose = cfg.get("pose_topic")
    if cfg.get("pose_source") == "pose_topic" and pose:
        known[str(pose)] = "geometry_msgs/PoseWithCovarianceStamped"
    return known


class TopicInspector:
    """``widget``: Refresh, the topic list, the picked topic's type and rate, its latest message."""

    def __init__(self) -> None:
        self.link: LinkCore | None = None
        self.types: dict[str, str] = {}
        self.probe: TopicProbe | None = None
        self._lock = threading.Lock()
        self._listing: threading.Thread | None = None
        self._pending: tuple[list[tuple[str, str]], str] | None = None
        self.refresh_button = button("Refresh", "pmk-topics-refresh", icon="refresh", width="auto")
        self.list = w.Select(options=[("— pick a topic —", NONE)], value=NONE, rows=5)
        self.list.layout = w.Layout(width="100%")
        self.list.add_class("pmk-topics-list")
        self.source = w.HTML("")
        self.source.add_class("pmk-topics-source")
        self.info = w.HTML("")
        self.info.add_class("pmk-topics-info")
        self.message = w.HTML("")
        self.message.add_class("pmk-topics-message")
        self.widget = w.VBox([w.HBox([self.refresh_button, self.source]), self.list, self.info, self.message])
        self.widget.add_class("pmk-topics")
        self.refresh_button.on_click(lambda _b: self.refresh())
        self.list.observe(self._on_pick, names="value")

    # -- link ---------------------------------------------------------------------------------------
    def attach(self, link: LinkCore | None) -> None:
        """Inspect ``link``'s chair (None: the preview stopped; the subscription ends)."""
        self.close_probe()
        self.link = link
        if link is not None:
            self.refresh()

    def refresh(self) -> None:
        """List the topics again (rosapi on a worker thread; the list updates on the next tick)."""
        link = self.link
        if link is None or (self._listing is not None and self._listing.is_alive()):
            return
        self.source.value = "<small>Listing the chair's topics…</small>"
        self._listing = threading.Thread(target=self._list, args=(link,), daemon=True, name="pmk-topics-list")
        self._listing.start()

    def _list(self, link: LinkCore) -> None:
        known = known_topics(link)
        try:
            rows, where = topic_rows(link.discovery.topics(timeout=5.0), known), "from rosapi"
        except (PmkError, OSError) as err:  # no rosapi, a busy bridge: the topics the link knows
            log.info("listing topics through rosapi failed: %s", err)
            rows, where = topic_rows(None, known), "known to this page (no rosapi answer)"
        with self._lock:
            self._pending = (rows, where)

    # -- picking --------------------------------------------------------------------------------------
    def _on_pick(self, change: dict[str, Any]) -> None:
        topic = change.get("new")
        self.close_probe()
        if not isinstance(topic, str) or topic not in self.types or self.link is None:
            return  # the "pick a topic" entry, or anything a page made up
        ros = self.link.ros if self.link.is_connected else None
        if ros is None:
            self.info.value = "<span class='pmk-msg-warning'>Not connected to the chair.</span>"
            return
        self.probe = TopicProbe(ros, topic, self.types[topic])
        self.tick()

    def close_probe(self) -> None:
        """Unsubscribe the inspected topic (the panel closed, another topic picked, preview stopped)."""
        probe, self.probe = self.probe, None
        if probe is not None:
            probe.stop()
        self.info.value = ""
        self.message.value = ""

    # -- timer ----------------------------------------------------------------------------------------
    def tick(self) -> None:
        """Apply a finished listing; show the picked topic's rate and latest message."""
        with self._lock:
            pending, self._pending = self._pending, None
        if pending is not None:
            rows, where = pending
            self.types = dict(rows)
            current = self.list.value if self.list.value in self.types else NONE
            self.list.options = [("— pick a topic —", NONE), *[(f"{n}  ({t or '?'})", n) for n, t in rows]]
            self.list.value = current
            self.source.value = f"<small>{len(rows)} topics {escape(where)}</small>"
        probe = self.probe
        if probe is None:
            return
        rate = rate_text(probe.meter.rate(time.monotonic()))
        self.info.value = f"<b>{escape(probe.topic)}</b> <code>{escape(probe.type_name or '?')}</code> · {escape(rate)}"
        latest = probe.latest()
        if latest is not None:
            text = escape(pretty_message(latest))
            self.message.value = f"<pre class='pmk-topics-json' style='{JSON_STYLE}'>{text}</pre>"
