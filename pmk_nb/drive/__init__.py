"""Driving the chair by hand, safely: stick -> velocity, and the gate that decides what is sent.

No widgets and no ROS here: the dashboard's joystick (:mod:`pmk_nb.ui.drive.panel`) and a notebook
both feed a :class:`~pmk_nb.drive.session.DriveSession`, which publishes through anything with the
chair link's ``publish_cmd_vel`` / ``is_connected`` / ``latest_odom``.

* ``limits``: per-profile speed limits, slow mode and dead zone; stick position -> (v, w).
* ``stick``: one message from the page (validated: a page can send any JSON) and the page->kernel
  clock offset that tells how old a message is.
* ``gate``: the deadman: commands only while held and fresh; one zero on release, then silence;
  a command older than 200 ms is dropped; a stale link, a hidden page or missing keepalives stop.
* ``claim``: one driving page per chair and the chair-wide Stop latch, in a file all kernels see,
  keyed on the chair's resolved address (``chairkey``: one chair, one key, whatever the spelling).
* ``stopwatch``: every page's eye on that latch for navigation goals: another page's Stop cancels
  this kernel's goals, and a latched Stop refuses new ones (the link's goal gate).
* ``session``: the gate plus the bounded publisher thread (20 Hz), and :func:`drive_for` for scripts.
"""

from pmk_nb.drive.claim import ClaimView, DriveClaim, Hold
from pmk_nb.drive.gate import DriveGate, GateTiming, StopReason
from pmk_nb.drive.limits import SpeedLimits, stick_to_twist
from pmk_nb.drive.session import DriveSession, drive_for
from pmk_nb.drive.stick import ClockOffset, StickEvent, StickMessageError, parse_stick_message
from pmk_nb.drive.stopwatch import StopWatch

__all__ = [
    "ClaimView",
    "ClockOffset",
    "DriveClaim",
    "DriveGate",
    "DriveSession",
    "GateTiming",
    "Hold",
    "SpeedLimits",
    "StickEvent",
    "StickMessageError",
    "StopReason",
    "StopWatch",
    "drive_for",
    "parse_stick_message",
    "stick_to_twist",
]
