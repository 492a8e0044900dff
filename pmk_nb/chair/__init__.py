"""The chair: profiles, the rosbridge link, SFTP transfer, map reload and deploy.

``profiles`` (validated chair settings and the profile store), ``link/`` (rosbridge via roslibpy),
``messages`` (ROS message shapes both ROS versions use), ``ssh`` + ``transfer`` (SFTP with verified
host keys), ``reload`` (the three map reload services) and ``deploy`` (upload, reload, confirm).
Submodules are imported on use, so that `pmk info` never pays for roslibpy or paramiko.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from pmk_nb.chair.deploy import STEP_SPANS, close_links, link_for
    from pmk_nb.chair.keysetup import make_key_pair, setup_key
    from pmk_nb.chair.profiles import PROFILES_FILE, ChairProfile, ProfileStore, config_dir
    from pmk_nb.chair.transfer import check_ssh

_WHERE = {
    "STEP_SPANS": "deploy",
    "close_links": "deploy",
    "link_for": "deploy",
    "make_key_pair": "keysetup",
    "setup_key": "keysetup",
    "ChairProfile": "profiles",
    "PROFILES_FILE": "profiles",
    "ProfileStore": "profiles",
    "config_dir": "profiles",
    "check_ssh": "transfer",
}

__all__ = [
    "PROFILES_FILE",
    "STEP_SPANS",
    "ChairProfile",
    "ProfileStore",
    "check_ssh",
    "close_links",
    "config_dir",
    "link_for",
    "make_key_pair",
    "setup_key",
]


def __getattr__(name: str) -> Any:
    """The face is lazy: a name loads only its own module (no paramiko, roslibpy or ROS for one name)."""
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
    globals()[name] = value  # once is enough
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *__all__})
