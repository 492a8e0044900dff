"""Chair profiles: how to reach one wheelchair (rosbridge, SSH, map reload), saved between sessions.

The original app kept one set of values in Android shared preferences (IP, port, topics, user,
password) and pre-filled the Settings screen with the last used ones. Here several named profiles
live in ``profiles.json`` under the user config dir (``PMK_CONFIG_DIR`` overrides it); the last saved
one is the default. Passwords never reach that file: :mod:`pmk_nb.chair.secrets` keeps them (the
system keyring when one works, otherwise memory for this session only), bound to the SSH account.
"""

from __future__ import annotations

import builtins
import dataclasses
import json
import os
import re
import shutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import platformdirs

from pmk_nb.chair.secrets import PasswordCache, SecretBackend, SshAccount
from pmk_nb.defaults import DEFAULT_CHAIR_WIDTH
from pmk_nb.errors import SettingsError
from pmk_nb.fileio import atomic_write, private_dir

if TYPE_CHECKING:
    from pmk_nb.chair.link.goals.goal import GoalPolicy

POSE_SOURCES = ("odometry", "pose_topic", "tf")
AUTH_METHODS = ("password", "key")
RELOAD_KINDS = ("auto", "ros1", "nav2", "mapupdate")
HOST_KEY_CHECKS = ("tofu", "strict")
DRIVE_HANDS = ("right", "left")  # where the joystick docks on Home
PROFILES_FILE = "profiles.json"
FORMAT_VERSION = 1

#: Upper bounds of the driving fields: a powered wheelchair's top speed is about 2 m/s (EN 12184
#: class B goes to 15 km/h, far beyond what a touch screen should command).
MAX_SPEEDS: dict[str, tuple[float, str]] = {
    "max_linear": (2.0, "m/s"),
    "max_angular": (2.0, "rad/s"),
    "slow_factor": (1.0, "(1 = as fast as normal)"),
}
_HOST_RE = re.compile(r"^[A-Za-z0-9._\-:\[\]%]+$")
_SERVICE_RE = re.compile(r"^/?[A-Za-z_][A-Za-z0-9_/]*$")


def config_dir() -> Path:
    """Where profiles and the known_hosts file live (``PMK_CONFIG_DIR`` wins, for tests and kiosks)."""
    env = os.environ.get("PMK_CONFIG_DIR")
    return Path(env).expanduser() if env else Path(platformdirs.user_config_dir("pmk_nb"))


def default_known_hosts() -> Path:
    """Our own known_hosts, so trusting a chair never edits the user's ~/.ssh/known_hosts."""
    return config_dir() / "known_hosts"


@dataclass
class ChairProfile:
    """Everything needed to talk to one chair. ``validate()`` names the first bad field."""

    name: str
    host: str
    port: int = 9090
    odom_topic: str = "/odom"
    scan_topic: str = "/scan"
    pose_source: str = "odometry"
    pose_topic: str = "/amcl_pose"
    # the navigation stack's planned path (nav_msgs/Path) drawn on Home: "auto" follows Nav2's /plan
    # and move_base's planners (pmk_nb.chair.link.streams.planpath), or name one topic
    plan_topic: str = "auto"
    ssh_user: str = ""
    ssh_port: int = 22
    auth: str = "password"
    key_file: str | None = None
    remote_maps_dir: str = "~/ALMA_MAPS"
    reload_service: str = "auto"
    reload_kind: str = "auto"
    footprint_radius: float = 0.35
    chair_width: float = DEFAULT_CHAIR_WIDTH  # metres: the wheelchair's width, for the maps' accessibility check
    known_hosts: str | None = None
    host_key_check: str = "tofu"
    # driving from Home (pmk_nb.drive): where velocity commands go, the largest speeds, slow mode
    cmd_vel_topic: str = "/cmd_vel"
    max_linear: float = 0.5  # m/s
    max_angular: float = 0.8  # rad/s
    slow_factor: float = 0.4  # of both, in slow mode
    drive_hand: str = "right"  # the screen edge the joystick and Stop dock at: the rider's hand
    # spoken feedback (pmk_nb.speech): on/off, voice (a language code such as "en": the browser's
    # voice for it, or espeak-ng's), rate (1 = normal, 0.5 to 2)
    speech_on: bool = True
    speech_voice: str = "en"
    speech_rate: float = 1.0
    # TLS to rosbridge (wss://, pmk_nb.chair.link.transport.tls): the CA file that signs the chair's certificate,
    # else its fingerprint pinned on first use in known_certs (beside known_hosts)
    tls: bool = False
    tls_ca_file: str | None = None
    # rosbridge authentication (rosauth's auth op, pmk_nb.chair.link.transport.bridge_auth): the file holding the
    # chair's secret, read at each connect; a classroom seat's chair in ``pmk hub`` requires it
    bridge_secret_file: str | None = None
    # goals (pmk_nb.chair.link.goals.navigate.GoalPolicy): when the dashboard loses the chair, "finish"
    # (let goals finish) or "cancel" (cancel them once the link is back); deadlines in seconds
    goals_on_link_loss: str = "finish"
    goal_accept_s: float = 5.0
    goal_quiet_s: float = 30.0
    # how the dashboard looks for this chair's rider (pmk_nb/ui/common/display_prefs.py, WCAG 2.2):
    # black on white with thick borders, and text a third larger
    high_contrast: bool = False
    large_text: bool = False

    @property
    def known_hosts_path(self) -> Path:
        return Path(self.known_hosts).expanduser() if self.known_hosts else default_known_hosts()

    @property
    def known_certs_path(self) -> Path:
        """The pinned TLS fingerprints of chairs: the SSH known_hosts file's sibling, same rules."""
        return self.known_hosts_path.with_name("known_certs")

    @property
    def bridge_url(self) -> str:
        return f"{'wss' if self.tls else 'ws'}://{self.host}:{self.port}"

    def link_options(self) -> dict[str, Any]:
        """What a ChairLink to this chair takes (topics, pose source, TLS trust), as keywords.

        The link is imported here, on use, because its package loads roslibpy (``pmk info`` must not);
        there is no cycle to dodge: the link never imports ``chair``."""
        from pmk_nb.chair.link.transport.bridge_auth import BridgeAuth
        from pmk_nb.chair.link.transport.tls import ChairTls

        return {
            "odom_topic": self.odom_topic,
            "scan_topic": self.scan_topic,
            "pose_source": self.pose_source,
            "pose_topic": self.pose_topic,
            "tls": ChairTls(self.known_certs_path, self.tls_ca_file or None) if self.tls else None,
            "auth": BridgeAuth(Path(self.bridge_secret_file).expanduser()) if self.bridge_secret_file else None,
        }

    def goal_policy(self) -> GoalPolicy:
        """The link's goal deadlines and link-loss setting, from this profile (the link imported on use)."""
        from pmk_nb.chair.link.goals.goal import GoalPolicy

        return GoalPolicy(accept_s=self.goal_accept_s, quiet_s=self.goal_quiet_s, on_link_loss=self.goals_on_link_loss)

    def validate(self) -> None:
        """Raise SettingsError naming the field and the fix; returns None when the profile is usable."""
        if not self.name.strip() or "/" in self.name or "\\" in self.name:
            _bad("name", self.name, "use a non-empty name without slashes")
        _check_host(self.host)
        _check_port("port", self.port)
        _check_port("ssh_port", self.ssh_port)
        _check_topic("odom_topic", self.odom_topic)
        _check_topic("scan_topic", self.scan_topic)
        if self.pose_source not in POSE_SOURCES:
            _bad("pose_source", self.pose_source, f"use one of {', '.join(POSE_SOURCES)}")
        if self.pose_source == "pose_topic" or self.pose_topic:
            _check_topic("pose_topic", self.pose_topic)
        if self.plan_topic != "auto":
            _check_topic("plan_topic", self.plan_topic)
        if any(c.isspace() for c in self.ssh_user) or ":" in self.ssh_user or "@" in self.ssh_user:
            _bad("ssh_user", self.ssh_user, "a user name has no spaces, ':' or '@'")
        if self.auth not in AUTH_METHODS:
            _bad("auth", self.auth, "use 'password' or 'key'")
        if self.auth == "key":
            if not self.key_file:
                _bad("key_file", self.key_file, "auth is 'key': give the private key file")
            elif not Path(self.key_file).expanduser().is_file():
                _bad("key_file", self.key_file, "the private key file does not exist")
        if not self.remote_maps_dir.strip() or "\n" in self.remote_maps_dir:
            _bad("remote_maps_dir", self.remote_maps_dir, "give a folder such as ~/ALMA_MAPS")
        if self.reload_service != "auto" and not _SERVICE_RE.match(self.reload_service):
            _bad("reload_service", self.reload_service, "use 'auto' or a ROS service name like /change_map")
        if self.reload_kind not in RELOAD_KINDS:
            _bad("reload_kind", self.reload_kind, f"use one of {', '.join(RELOAD_KINDS)}")
        radius = self.footprint_radius
        if isinstance(radius, bool) or not isinstance(radius, int | float) or not 0 <= radius < 10:
            _bad("footprint_radius", radius, "give the chair radius in metres (0 to 10)")
        width = self.chair_width
        if isinstance(width, bool) or not isinstance(width, int | float) or not 0.4 <= width <= 1.5:
            _bad("chair_width", width, "give the wheelchair's width in metres (0.4 to 1.5)")
        if self.host_key_check not in HOST_KEY_CHECKS:
            _bad("host_key_check", self.host_key_check, "use 'tofu' (trust on first use) or 'strict'")
        _check_drive(self)
        _check_hand(self)
        _check_speech(self)
        _check_tls(self)
        _check_goals(self)
        _check_display(self)

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, raw: dict[str, Any]) -> ChairProfile:
        """Build and validate; unknown keys are an error (a typo would otherwise be silently ignored)."""
        if not isinstance(raw, dict):
            raise SettingsError(f"a profile must be a mapping of field names to values, got {raw!r}")
        if "reload_flavour" in raw:  # the name before 0.2: saved profiles keep working
            raw = {**{k: v for k, v in raw.items() if k != "reload_flavour"}, "reload_kind": raw["reload_flavour"]}
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(raw) - names)
        if unknown:
            raise SettingsError(f"unknown field(s) {', '.join(unknown)}; known fields: {', '.join(sorted(names))}")
        for required in ("name", "host"):
            if required not in raw:
                raise SettingsError(f"{required}: missing (every profile needs a name and a host)")
        profile = cls(**raw)
        profile.validate()
        return profile


def _bad(field: str, value: object, hint: str) -> None:
    raise SettingsError(f"{field}: invalid value {value!r}: {hint}", field=field)


def _check_host(host: object) -> None:
    if not isinstance(host, str) or not host.strip():
        _bad("host", host, "give the chair's IP address or host name, e.g. 192.168.1.20")
    assert isinstance(host, str)
    if "://" in host or "/" in host:
        _bad("host", host, "give only the address, without scheme or path (e.g. 192.168.1.20)")
    if not _HOST_RE.match(host):
        _bad("host", host, "an address has no spaces or special characters")


def _check_port(field: str, port: object) -> None:
    if isinstance(port, bool) or not isinstance(port, int) or not 1 <= port <= 65535:
        _bad(field, port, "give a port number between 1 and 65535")


def _check_drive(profile: ChairProfile) -> None:
    """The driving fields: a topic and speeds a wheelchair can take (MAX_SPEEDS)."""
    _check_topic("cmd_vel_topic", profile.cmd_vel_topic)
    for field, (top, unit) in MAX_SPEEDS.items():
        value = getattr(profile, field)
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0 < value <= top:
            _bad(field, value, f"give a speed above 0 and at most {top:g} {unit}")


def _check_hand(profile: ChairProfile) -> None:
    if profile.drive_hand not in DRIVE_HANDS:
        _bad("drive_hand", profile.drive_hand, "use 'left' or 'right' (the hand that drives)")


def _check_goals(profile: ChairProfile) -> None:
    if profile.goals_on_link_loss not in ("finish", "cancel"):
        _bad("goals_on_link_loss", profile.goals_on_link_loss, "use 'finish' (let goals finish) or 'cancel'")
    for field, top in (("goal_accept_s", 60.0), ("goal_quiet_s", 600.0)):
        value = getattr(profile, field)
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0.2 <= value <= top:
            _bad(field, value, f"give seconds from 0.2 to {top:g}")


def _check_display(profile: ChairProfile) -> None:
    for field in ("high_contrast", "large_text"):
        if not isinstance(getattr(profile, field), bool):
            _bad(field, getattr(profile, field), "use true or false")


def _check_speech(profile: ChairProfile) -> None:
    if not isinstance(profile.speech_on, bool):
        _bad("speech_on", profile.speech_on, "use true or false")
    if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_+-]{0,40}", str(profile.speech_voice)):
        _bad("speech_voice", profile.speech_voice, "give a language code such as en or en-gb")
    rate = profile.speech_rate
    if isinstance(rate, bool) or not isinstance(rate, int | float) or not 0.5 <= rate <= 2.0:
        _bad("speech_rate", rate, "give a speaking rate from 0.5 to 2 (1 = normal)")


def _check_tls(profile: ChairProfile) -> None:
    if not isinstance(profile.tls, bool):
        _bad("tls", profile.tls, "use true (wss://) or false (ws://)")
    ca_file = profile.tls_ca_file
    if ca_file and not profile.tls:
        _bad("tls_ca_file", ca_file, "a CA file is for TLS: turn TLS on, or leave the CA file empty")
    if ca_file and not Path(ca_file).expanduser().is_file():
        _bad("tls_ca_file", ca_file, "the CA file does not exist (leave it empty to pin the chair's certificate)")


def _check_topic(field: str, topic: object) -> None:
    if not isinstance(topic, str) or not topic.startswith("/"):
        _bad(field, topic, "a ROS topic name starts with '/', e.g. /odom")
    assert isinstance(topic, str)
    if len(topic) < 2 or any(c.isspace() for c in topic):
        _bad(field, topic, "a ROS topic name has no spaces, e.g. /scan")


class ProfileStore:
    """Named chair profiles in one JSON file, plus the session's password cache (:attr:`passwords`).

    Args:
        path: the profiles file; default ``config_dir()/profiles.json``.
        secrets: a keyring-like backend; default auto-detected. Pass ``False`` to keep passwords in
            memory only (tests, kiosks without a keyring).
    """

    def __init__(self, path: Path | str | None = None, *, secrets: SecretBackend | bool | None = None) -> None:
        self.path = Path(path) if path is not None else config_dir() / PROFILES_FILE
        self.passwords = PasswordCache(secrets)
        self.backup_of_corrupt: Path | None = None

    # -- file --------------------------------------------------------------------------------------
    def _read(self) -> dict[str, Any]:
        if not self.path.exists():
            return {"version": FORMAT_VERSION, "last_used": None, "profiles": []}
        try:
            raw = json.loads(self.path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError) as err:
            raise SettingsError(f"{self.path}: cannot read the chair profiles file ({err})") from err
        except json.JSONDecodeError as err:
            raise SettingsError(
                f"{self.path}: not valid JSON at line {err.lineno} column {err.colno} ({err.msg}); "
                "fix it by hand, or save a profile to start a new file (the broken one is kept as .bak)"
            ) from err
        if not isinstance(raw, dict) or not isinstance(raw.get("profiles"), list):
            raise SettingsError(f"{self.path}: expected an object with a 'profiles' list; fix or delete the file")
        if raw.get("password") or any("password" in p for p in raw["profiles"] if isinstance(p, dict)):
            raise SettingsError(f"{self.path}: holds a password field; passwords are never stored here, remove it")
        seen: set[str] = set()
        for i, item in enumerate(raw["profiles"]):
            label = item.get("name", f"#{i + 1}") if isinstance(item, dict) else f"#{i + 1}"
            try:
                profile = ChairProfile.from_dict(item)
            except (SettingsError, TypeError) as err:
                raise SettingsError(f"{self.path}: profile {label!r}: {err}") from err
            if profile.name in seen:
                raise SettingsError(f"{self.path}: profile name {profile.name!r} appears twice; rename one")
            seen.add(profile.name)
        return raw

    def _write(self, data: dict[str, Any]) -> None:
        private_dir(self.path.parent, tighten=True)  # the settings folder: 0700, an older lax one too
        atomic_write(self.path, json.dumps(data, indent=2) + "\n", mode=0o600)

    def _read_for_update(self) -> dict[str, Any]:
        """Current content; a broken file is moved aside to ``.bak`` (never silently overwritten)."""
        try:
            return self._read()
        except SettingsError:
            if not self.path.exists():
                raise
            backup = self.path.with_name(self.path.name + ".bak")
            if backup.exists():
                backup = self.path.with_name(f"{self.path.name}.{time.strftime('%Y%m%d-%H%M%S')}.bak")
            shutil.copy2(self.path, backup)
            self.backup_of_corrupt = backup
            return {"version": FORMAT_VERSION, "last_used": None, "profiles": []}

    # -- profiles ----------------------------------------------------------------------------------
    def list(self) -> list[ChairProfile]:
        return [ChairProfile.from_dict(p) for p in self._read()["profiles"]]

    def names(self) -> builtins.list[str]:
        return [p.name for p in self.list()]

    def get(self, name: str) -> ChairProfile:
        for profile in self.list():
            if profile.name == name:
                return profile
        known = ", ".join(self.names()) or "none yet"
        raise SettingsError(f"no chair profile named {name!r} in {self.path} (profiles: {known})")

    def save(self, profile: ChairProfile) -> None:
        """Validate, insert or replace by name, and make it the last used (the default next time)."""
        profile.validate()
        data = self._read_for_update()
        profiles = [p for p in data["profiles"] if p.get("name") != profile.name]
        existing = [p.get("name") for p in data["profiles"]]
        entry = profile.to_dict()
        if profile.name in existing:
            profiles.insert(existing.index(profile.name), entry)
        else:
            profiles.append(entry)
        data.update(version=FORMAT_VERSION, profiles=profiles, last_used=profile.name)
        self._write(data)

    def mark_used(self, name: str) -> None:
        """Remember ``name`` as the default without changing it (after a successful send or test)."""
        data = self._read()
        if name not in [p["name"] for p in data["profiles"]]:
            raise SettingsError(f"no chair profile named {name!r} in {self.path}")
        data["last_used"] = name
        self._write(data)

    def delete(self, name: str) -> None:
        """Remove the profile and forget the password of its SSH account."""
        profile = self.get(name)
        data = self._read()
        data["profiles"] = [p for p in data["profiles"] if p["name"] != name]
        if data.get("last_used") == name:
            data["last_used"] = data["profiles"][-1]["name"] if data["profiles"] else None
        self._write(data)
        self.forget_password(profile)

    def last_used(self) -> ChairProfile | None:
        data = self._read()
        profiles = [ChairProfile.from_dict(p) for p in data["profiles"]]
        for profile in profiles:
            if profile.name == data.get("last_used"):
                return profile
        return profiles[-1] if profiles else None

    # -- passwords ---------------------------------------------------------------------------------
    @property
    def password_storage(self) -> str:
        """Where passwords go, in words for the Settings screen."""
        return self.passwords.where

    @property
    def passwords_persist(self) -> bool:
        return self.passwords.persists

    def set_password(self, profile: ChairProfile, password: str) -> None:
        """Keep the password of ``profile``'s SSH account (keyring when it works, else this session)."""
        self.passwords.store(SshAccount.of(profile), password)

    def get_password(self, profile: ChairProfile) -> str | None:
        """The password entered for ``profile``'s SSH account (user, host, port), or None."""
        return self.passwords.lookup(SshAccount.of(profile))

    def forget_password(self, profile: ChairProfile) -> None:
        self.passwords.forget(SshAccount.of(profile))
