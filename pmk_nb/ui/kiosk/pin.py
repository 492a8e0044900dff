"""The kiosk PIN: stored as a salted scrypt hash (never the PIN itself), checked in constant time.

Kept free of widgets so the CLI can read :data:`KIOSK_ENV` without importing ipywidgets.  The hash
lives in ``kiosk_pin.json`` (mode 0600) in the settings folder; wrong guesses are slowed down
(:data:`MAX_TRIES` then :data:`LOCKOUT_S` seconds, doubled at each lockout in a row up to
:data:`MAX_LOCKOUT_S`) so a four-digit PIN cannot be tried through.
The wrong-PIN count and the lockout live beside it (``kiosk_pin_tries.json``), shared by every page
of the kiosk: a reload or a second page starts no fresh count.  :class:`KioskLock` is what the
kernel asks before it builds a screen behind the PIN or runs one of its actions.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import hmac
import json
import os
import secrets
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.errors import SettingsError
from pmk_nb.fileio import atomic_write

#: Set to 1 (``pmk dashboard --kiosk``, ``pmk demo``) to serve the locked-down kiosk page.
KIOSK_ENV = "PMK_KIOSK"
PIN_FILE = "kiosk_pin.json"
#: The wrong-PIN count and lockout end (wall clock), per kiosk, not per page.
TRIES_FILE = "kiosk_pin_tries.json"
#: The screens behind the PIN (their widgets exist in the kernel only while this page is unlocked).
LOCKED = ("maps", "settings")
PIN_MIN, PIN_MAX = 4, 12
MAX_TRIES = 5
LOCKOUT_S = 30.0
#: Lockouts in a row double up to this (five guesses per 15 min: weeks for every four-digit PIN).
MAX_LOCKOUT_S = 900.0
_SCRYPT = {"n": 2**14, "r": 8, "p": 1}


def kiosk_from_env() -> bool:
    """True when :data:`KIOSK_ENV` asks for the kiosk page."""
    return os.environ.get(KIOSK_ENV, "").strip().lower() in ("1", "true", "yes", "on")


def check_new_pin(pin: str, repeat: str) -> str:
    """The PIN to store, or a SettingsError saying what is wrong with it (digits only, 4 to 12, typed twice)."""
    pin, repeat = pin.strip(), repeat.strip()
    if not (pin.isascii() and pin.isdigit()) or not PIN_MIN <= len(pin) <= PIN_MAX:
        raise SettingsError(f"The PIN must be {PIN_MIN} to {PIN_MAX} digits.", field="pin")
    if pin != repeat:
        raise SettingsError("The two PINs differ: type the same PIN twice.", field="pin_repeat")
    return pin


def _digest(pin: str, salt: bytes) -> bytes:
    return hashlib.scrypt(pin.encode(), salt=salt, dklen=32, **_SCRYPT)


@dataclass(frozen=True)
class PinCheck:
    """The answer to a PIN attempt: ``ok``, or why not (``wait_s`` > 0 while locked out)."""

    ok: bool
    wait_s: float = 0.0


class PinStore:
    """The kiosk PIN of one settings folder.

    Args:
        config_dir: the settings folder (``AppContext.config_dir``).
        clock: seconds, for the lockout (tests pass a fake).
    """

    def __init__(self, config_dir: Path, *, clock: Callable[[], float] = time.time) -> None:
        self.path = Path(config_dir) / PIN_FILE
        self.tries_path = Path(config_dir) / TRIES_FILE
        self._clock = clock  # wall clock: the lockout end is kept on disk, read by other kernels
        self._lock = threading.Lock()

    def is_set(self) -> bool:
        """True when a PIN protects Maps and Settings (a damaged PIN file counts as set: fail closed)."""
        return self.path.exists()

    def set_pin(self, pin: str, repeat: str) -> None:
        """Check and store a new PIN (salted hash only).

        Raises:
            SettingsError: the PIN is not 4-12 digits or the two entries differ; the file cannot be written.
        """
        pin = check_new_pin(pin, repeat)
        salt = secrets.token_bytes(16)
        record = {"scheme": "scrypt", **_SCRYPT, "salt": salt.hex(), "hash": _digest(pin, salt).hex()}
        try:
            atomic_write(self.path, json.dumps(record) + "\n", mode=0o600, mkdir=True)
            self.tries_path.unlink(missing_ok=True)  # a new PIN: the wrong guesses at the old one are over
        except OSError as err:
            raise SettingsError(f"Could not save the PIN in {self.path.parent}: {err.strerror}") from err

    def clear(self) -> None:
        """Remove the PIN: Maps and Settings open without one."""
        self.path.unlink(missing_ok=True)
        self.tries_path.unlink(missing_ok=True)

    def check(self, pin: str) -> PinCheck:
        """Compare ``pin`` with the stored hash in constant time; too many wrong tries lock out for a while.

        The count is read and written under a lock on the settings folder, so pages of one kiosk
        (kernels) count together and a guess cannot slip between another's read and write.

        Raises:
            SettingsError: the PIN file is damaged (remove it to reset the PIN), or the count cannot
                be written (then no PIN is accepted: fail closed).
        """
        now = float(self._clock())
        with self._lock, _folder_lock(self.path.parent):
            failures, locked_until, lockouts = self._read_tries(now)
            if now < locked_until:
                return PinCheck(False, locked_until - now)
            stored_salt, stored_hash = self._read()
            if hmac.compare_digest(_digest(pin.strip(), stored_salt), stored_hash):
                if failures or lockouts:
                    self._write_tries(0, 0.0, 0)
                return PinCheck(True)
            if failures + 1 >= MAX_TRIES:
                wait = min(LOCKOUT_S * 2.0**lockouts, MAX_LOCKOUT_S)
                self._write_tries(0, now + wait, lockouts + 1)
                return PinCheck(False, wait)
            self._write_tries(failures + 1, 0.0, lockouts)
        return PinCheck(False)

    def _read_tries(self, now: float) -> tuple[int, float, int]:
        """(wrong PINs so far, lockout end, lockouts in a row); a damaged file or a lockout ending
        beyond the longest (the clock went back) starts a fresh lockout: fail closed, never for ever."""
        try:
            record = json.loads(self.tries_path.read_text(encoding="utf-8"))
            failures, until, lockouts = int(record["failures"]), float(record["locked_until"]), int(record["lockouts"])
            if not 0 <= failures < MAX_TRIES or not 0 <= lockouts <= 64 or not until - now <= MAX_LOCKOUT_S:  # NaN too
                raise ValueError("out of range")
            return failures, until, lockouts
        except FileNotFoundError:
            return 0, 0.0, 0
        except (OSError, ValueError, KeyError, TypeError, OverflowError):
            self._write_tries(0, now + LOCKOUT_S, 1)
            return 0, now + LOCKOUT_S, 1

    def _write_tries(self, failures: int, locked_until: float, lockouts: int) -> None:
        record = {"failures": failures, "locked_until": locked_until, "lockouts": lockouts}
        try:
            atomic_write(self.tries_path, json.dumps(record) + "\n", mode=0o600)
        except OSError as err:
            raise SettingsError(
                f"Could not record the PIN attempt in {self.tries_path.parent}: {err.strerror}",
                hint="No PIN is accepted until it can be recorded.",
            ) from err

    def _read(self) -> tuple[bytes, bytes]:
        try:
            record = json.loads(self.path.read_text(encoding="utf-8"))
            if record.get("scheme") != "scrypt" or any(record.get(k) != v for k, v in _SCRYPT.items()):
                raise ValueError("unknown scheme")
            return bytes.fromhex(record["salt"]), bytes.fromhex(record["hash"])
        except (OSError, ValueError, KeyError, TypeError, AttributeError) as err:
            raise SettingsError(
                f"The kiosk PIN file {self.path} is damaged ({err}).", hint="Delete it to remove the PIN."
            ) from err


@contextlib.contextmanager
def _folder_lock(folder: Path) -> Iterator[None]:
    """An exclusive lock on the settings folder (flock), held by one kernel at a time."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # closing releases the lock


class KioskLock:
    """Whether this page may use the screens behind the PIN (:data:`LOCKED`).

    The kernel asks it before building those screens and before each of their actions
    (``AppContext.require_unlocked``): the navigation buttons are not the gate, a page script can
    send any message.  Locked means a PIN is set and was not typed on this page since it last went
    back Home; with no PIN the kiosk is open (Settings says how to lock it).
    """

    def __init__(self, pins: PinStore) -> None:
        self.pins = pins
        self.screens: tuple[str, ...] = LOCKED
        self._unlocked = False

    @property
    def locked(self) -> bool:
        return not self._unlocked and self.pins.is_set()

    def unlock(self) -> None:
        """The PIN was typed (or set) on this page."""
        self._unlocked = True

    def lock(self) -> None:
        """Back Home: the PIN is asked again."""
        self._unlocked = False

    def allows(self, screen: str) -> bool:
        """True when ``screen`` may be built and used now."""
        return screen not in self.screens or not self.locked


def kiosk_lock(config_dir: Path) -> KioskLock | None:
    """The lock of a kiosk page (:data:`KIOSK_ENV` set), None elsewhere (a notebook, ``pmk dashboard``)."""
    return KioskLock(PinStore(config_dir)) if kiosk_from_env() else None
