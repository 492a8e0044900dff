"""Shared state of one dashboard session (one kernel): maps folder, chair profiles, current map.

Screens never talk to each other directly: the Maps screen sets the current map, the Home screen
observes it; every screen reports through :meth:`AppContext.notify`, so the app shell shows a
problem that has no place on the screen in its message line (instead of a traceback) and clears
that line when the next action reports.  The current map survives restarts in a
small JSON state file in the config dir (``PMK_CONFIG_DIR`` overrides), like the original app's
"last map used" preference.
"""

from __future__ import annotations

import functools
import json
import logging
import os
import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal, TypeVar

from pmk_nb.errors import KioskLocked
from pmk_nb.fileio import atomic_write

if TYPE_CHECKING:
    from pmk_nb.chair import ChairProfile, Fleet, ProfileStore
    from pmk_nb.chair.link import ChairLink
    from pmk_nb.library import MapsFolder
    from pmk_nb.ui.kiosk.pin import KioskLock

F = TypeVar("F", bound=Callable[..., Any])

log = logging.getLogger(__name__)

Level = Literal["info", "warning", "error"]
LEVELS: tuple[str, ...] = ("info", "warning", "error")
STATE_FILE = "ui_state.json"
#: Set to 1 (``pmk demo``, ``pmk dashboard --preview-on-start``) to start the Home screen's live
#: preview by itself: a kiosk or first-time user then sees the chair without pressing anything.
AUTOSTART_ENV = "PMK_AUTOSTART_PREVIEW"


def autostart_from_env() -> bool:
    """True when :data:`AUTOSTART_ENV` asks for the preview to start by itself."""
    return os.environ.get(AUTOSTART_ENV, "").strip().lower() in ("1", "true", "yes", "on")


def default_config_dir() -> Path:
    """Directory for UI state: the chair profiles' config dir (``PMK_CONFIG_DIR`` overrides)."""
    from pmk_nb.chair import config_dir

    return config_dir()


def needs_pin(action: str) -> Callable[[F], F]:
    """Decorator for the actions of a screen behind the kiosk PIN (methods of objects with ``ctx``).

    The action refuses with :class:`~pmk_nb.errors.KioskLocked` while the kiosk page is locked,
    whoever called it; :func:`~pmk_nb.ui.common.widgets.guard` turns that into the page's message.
    """

    def wrap(fn: F) -> F:
        @functools.wraps(fn)
        def wrapper(self: Any, *args: Any, **kwargs: Any) -> Any:
            self.ctx.require_unlocked(action)
            return fn(self, *args, **kwargs)

        return wrapper  # type: ignore[return-value]

    return wrap


@dataclass(frozen=True)
class CurrentMap:
    """The map the Home screen previews: the last one sent to the chair."""

    name: str
    yaml: Path
    preview: Path | None


@dataclass(frozen=True)
class Notification:
    """One message for the user.

    Attributes:
        message: the text, in the dashboard's words.
        level: "info", "warning" or "error".
        inline: the screen that sent it shows it in its own place (next to the control that
            started the action); the app's message line then clears instead of repeating it.
    """

    message: str
    level: Level
    inline: bool = False


def _atomic_write_json(path: Path, data: object) -> None:
    atomic_write(path, json.dumps(data, indent=2), mode=0o600, mkdir=True)


class AppContext:
    """Per-kernel session state shared by the dashboard screens.

    Args:
        maps: the maps folder the Maps screen lists and converts into.
        profiles: chair profiles; the last used one is "the chair".
        config_dir: where the UI state file lives (default :func:`default_config_dir`).
    """

    def __init__(self, maps: MapsFolder, profiles: ProfileStore, *, config_dir: Path | None = None) -> None:
        self.maps = maps
        self.profiles = profiles
        self.config_dir = Path(config_dir) if config_dir is not None else default_config_dir()
        self._lock = threading.RLock()
        self._map_observers: list[Callable[[CurrentMap | None], None]] = []
        self._note_observers: list[Callable[[Notification], object]] = []
        # The chair this page talks to; its link lives in the kernel's link registry, not here.
        self._chair: tuple[str, int] | None = None
        self.notifications: list[Notification] = []
        self._current_map = self._load_current_map()
        self._closed = False
        self._profile_unreadable = False  # reported once per breakage, not on every poll
        #: The kiosk page's lock (set by ``build_app`` on a kiosk page); None: nothing is locked.
        self.kiosk: KioskLock | None = None
        #: Several chairs on this page (issue 26, :mod:`pmk_nb.chair.fleet`): its chair in control is
        #: "the chair"; the others' links stay open. None: the page has one chair, its profile's.
        self.fleet: Fleet | None = None
        #: Frame cap of Home's live view; None: the live view's own (a classroom page sets a lower one).
        self.live_fps: float | None = None

    # -- kiosk lock --------------------------------------------------------------------------------
    def may_open(self, screen: str) -> bool:
        """True when ``screen`` may be built and shown now (always, outside a locked kiosk page)."""
        return self.kiosk is None or self.kiosk.allows(screen)

    def require_unlocked(self, action: str) -> None:
        """The kernel's own check before an action of a screen behind the kiosk PIN.

        Called by the action itself (see :func:`needs_pin`), not by the button that shows it: a
        page script can send a click for any widget it knows, or keep one from before the lock.

        Raises:
            KioskLocked: this kiosk page is locked.
        """
        if self.kiosk is not None and self.kiosk.locked:
            raise KioskLocked("the kiosk is locked.", action=action, hint="Open the screen with the PIN first.")

    # -- chair -------------------------------------------------------------------------------------
    def profile(self) -> ChairProfile | None:
        """The current chair profile (the fleet's chair in control, else the last one saved or used),
        or None before any is saved."""
        fleet = self.fleet
        member = fleet.controlled if fleet is not None else None
        if member is not None:
            return member.profile
        try:
            profile = self.profiles.last_used()
        except Exception as err:  # a corrupt profile file must not break the whole app
            if not self._profile_unreadable:
                self._profile_unreadable = True
                self.notify(f"Cannot read chair settings: {err}", "error")
            return None
        self._profile_unreadable = False
        return profile

    def link(self) -> ChairLink:
        """The rosbridge link for the current profile (the kernel's link from the link registry).

        When the profile now points at another chair, the link to the previous one is closed
        (:func:`~pmk_nb.chair.link.registry.use_only`): a page holds one chair connection.

        Raises:
            SettingsError: when no chair profile has been saved yet.
        """
        from pmk_nb.chair.link import use_only
        from pmk_nb.errors import SettingsError

        profile = self.profile()
        if profile is None:
            raise SettingsError("No wheelchair configured yet: fill in and save the Settings screen first.")
        keep = [m.key for m in self.fleet.members] if self.fleet is not None else []
        with self._lock:
            link = use_only(profile.host, int(profile.port), keep=keep, **profile.link_options())
            link.goal_policy = profile.goal_policy()  # goal deadlines, what a link loss does (issue 24)
            self._chair = (link.host, link.port)
        return link

    def ssh_password(self, profile: ChairProfile) -> str | None:
        """Password for SFTP to ``profile``'s SSH account: typed this session, else stored (keyring)."""
        return self.profiles.get_password(profile)

    def remember_password(self, profile: ChairProfile, password: str) -> None:
        """Keep a password typed in a dialog for this session only (never written to disk)."""
        from pmk_nb.chair import SshAccount

        self.profiles.passwords.remember(SshAccount.of(profile), password)

    # -- current map -------------------------------------------------------------------------------
    @property
    def current_map(self) -> CurrentMap | None:
        with self._lock:
            return self._current_map

    def set_current_map(self, name: str, yaml: Path | str, preview: Path | str | None) -> CurrentMap:
        """Make a map the current one (after sending it), persist it and tell the observers."""
        current = CurrentMap(str(name), Path(yaml), Path(preview) if preview is not None else None)
        with self._lock:
            self._current_map = current
            observers = list(self._map_observers)
        try:
            _atomic_write_json(
                self.config_dir / STATE_FILE,
                {
                    "current_map": {
                        "name": current.name,
                        "yaml": str(current.yaml),
                        "preview": str(current.preview) if current.preview else None,
                    }
                },
            )
        except OSError as err:
            self.notify(f"Could not remember the current map in {self.config_dir}: {err}", "warning")
        for cb in observers:
            self._safe_call(cb, current)
        return current

    def observe_current_map(self, cb: Callable[[CurrentMap | None], None]) -> Callable[[], None]:
        """Call ``cb(current_map)`` on every change; returns a function that unsubscribes."""
        with self._lock:
            self._map_observers.append(cb)
        return lambda: self._remove(self._map_observers, cb)

    def _load_current_map(self) -> CurrentMap | None:
        path = self.config_dir / STATE_FILE
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
            cur = data["current_map"]
            if not cur:
                return None
            preview = cur.get("preview")
            return CurrentMap(str(cur["name"]), Path(cur["yaml"]), Path(preview) if preview else None)
        except FileNotFoundError:
            return None
        except (OSError, ValueError, KeyError, TypeError) as err:
            log.warning("ignoring unreadable UI state %s: %s", path, err)
            return None

    # -- notifications -----------------------------------------------------------------------------
    def notify(self, message: str, level: Level = "info", *, inline: bool = False) -> None:
        """Report something to the user; safe to call from worker threads.

        Every notification replaces the app's message line, so a later success clears an older
        failure; an ``inline`` one (shown by its screen) leaves the line empty.
        """
        if level not in LEVELS:
            level = "info"
        note = Notification(str(message), level, bool(inline))
        with self._lock:
            self.notifications.append(note)
            del self.notifications[:-50]
            observers = list(self._note_observers)
        log.log({"info": logging.INFO, "warning": logging.WARNING}.get(level, logging.ERROR), "%s", message)
        for cb in observers:
            self._safe_call(cb, note)

    def observe_notifications(self, cb: Callable[[Notification], object]) -> Callable[[], None]:
        """Call ``cb(notification)`` for every :meth:`notify`; returns a function that unsubscribes."""
        with self._lock:
            self._note_observers.append(cb)
        return lambda: self._remove(self._note_observers, cb)

    # -- lifecycle ---------------------------------------------------------------------------------
    def close(self) -> None:
        """Close the chair link this session used (called when the kernel goes away)."""
        from pmk_nb.chair.link import forget_link

        with self._lock:
            if self._closed:
                return
            self._closed = True
            chair, self._chair = self._chair, None
            self._map_observers.clear()
            self._note_observers.clear()
        if chair is not None:
            try:
                forget_link(*chair)
            except Exception as err:
                log.warning("closing chair link failed: %s", err)

    def _remove(self, observers: list, cb: object) -> None:
        with self._lock:
            if cb in observers:
                observers.remove(cb)

    @staticmethod
    def _safe_call(cb: Callable[..., object], arg: object) -> None:
        try:
            cb(arg)
        except Exception:  # an observer's bug must not stop the others
            log.exception("observer %r failed", cb)
