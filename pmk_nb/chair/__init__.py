"""The chair: profiles, the rosbridge link, SFTP transfer, map reload and deploy.

``profiles`` (validated chair settings and the profile store), ``link/`` (rosbridge via roslibpy),
``messages`` (ROS message shapes both ROS versions use), ``ssh`` + ``transfer`` (SFTP with verified
host keys), ``reload`` (the three map reload services) and ``deploy`` (upload, reload, confirm).
Submodules are imported on use, so that `pmk info` never pays for roslibpy or paramiko.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.chair.confirm import map_sha256
    from pmk_nb.chair.deploy import STEP_SPANS, close_links, link_for
    from pmk_nb.chair.fleet import (
        ChairStatus,
        Fleet,
        FleetError,
        FleetMember,
        NoChairChosen,
        NotInFleet,
        SameAddress,
        row_words,
    )
    from pmk_nb.chair.fleet_links import FleetLinks
    from pmk_nb.chair.keysetup import make_key_pair, setup_key
    from pmk_nb.chair.link.streams.messages import Odometry, Pose2D, Scan
    from pmk_nb.chair.link.streams.ranges import BLIND_KINDS, NO_RETURN, UNKNOWN, blind_ahead
    from pmk_nb.chair.profiles import AUTH_METHODS, POSE_SOURCES, PROFILES_FILE, ChairProfile, ProfileStore, config_dir
    from pmk_nb.chair.secrets import SshAccount
    from pmk_nb.chair.ssh import trust_host_key
    from pmk_nb.chair.transfer import check_ssh

_WHERE = {
    "map_sha256": "confirm",
    "STEP_SPANS": "deploy",
    "close_links": "deploy",
    "link_for": "deploy",
    "ChairStatus": "fleet",
    "Fleet": "fleet",
    "FleetError": "fleet",
    "FleetMember": "fleet",
    "NotInFleet": "fleet",
    "NoChairChosen": "fleet",
    "SameAddress": "fleet",
    "row_words": "fleet",
    "FleetLinks": "fleet_links",
    "make_key_pair": "keysetup",
    "setup_key": "keysetup",
    "Odometry": "link.streams.messages",
    "Pose2D": "link.streams.messages",
    "Scan": "link.streams.messages",
    "AUTH_METHODS": "profiles",
    "ChairProfile": "profiles",
    "POSE_SOURCES": "profiles",
    "PROFILES_FILE": "profiles",
    "ProfileStore": "profiles",
    "config_dir": "profiles",
    "BLIND_KINDS": "link.streams.ranges",
    "NO_RETURN": "link.streams.ranges",
    "UNKNOWN": "link.streams.ranges",
    "blind_ahead": "link.streams.ranges",
    "SshAccount": "secrets",
    "trust_host_key": "ssh",
    "check_ssh": "transfer",
}

__all__ = [
    "AUTH_METHODS",
    "BLIND_KINDS",
    "NO_RETURN",
    "POSE_SOURCES",
    "PROFILES_FILE",
    "STEP_SPANS",
    "UNKNOWN",
    "ChairProfile",
    "ChairStatus",
    "Fleet",
    "FleetError",
    "FleetLinks",
    "FleetMember",
    "NoChairChosen",
    "NotInFleet",
    "Odometry",
    "Pose2D",
    "ProfileStore",
    "SameAddress",
    "Scan",
    "SshAccount",
    "blind_ahead",
    "check_ssh",
    "close_links",
    "config_dir",
    "link_for",
    "make_key_pair",
    "map_sha256",
    "row_words",
    "setup_key",
    "trust_host_key",
]


__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
