"""The kiosk PIN: stored as a salted scrypt hash (never the PIN itself), checked in constant time.

Kept free of widgets so the CLI can read :data:`KIOSK_ENV` without importing ipywidgets.  The hash
lives in ``kiosk_pin.json`` (mode 0600) in the settings folder; wrong guesses are slowed down
(:data:`MAX_TRIES` then :data:`LOCKOUT_S` seconds) so a four-digit PIN cannot be tried through.
"""

from __future__ import annotations

import hashlib
import hmac
import json
import os
import secrets
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.errors import SettingsError
from pmk_nb.fileio import atomic_write

#: Set to 1 (``pmk dashboard --kiosk``, ``pmk demo``) to serve the locked-down kiosk page.
KIOSK_ENV = "PMK_KIOSK"
PIN_FILE = "kiosk_pin.json"
PIN_MIN, PIN_MAX = 4, 12
MAX_TRIES = 5
LOCKOUT_S = 30.0
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

    def __init__(self, config_dir: Path, *, clock: object = time.monotonic) -> None:
        self.path = Path(config_dir) / PIN_FILE
        self._clock = clock
        self._lock = threading.Lock()
        self._failures = 0
        self._locked_until = 0.0

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
        except OSError as err:
            raise SettingsError(f"Could not save the PIN in {self.path.parent}: {err.strerror}") from err

    def clear(self) -> None:
        """Remove the PIN: Maps and Settings open without one."""
        self.path.unlink(missing_ok=True)

    def check(self, pin: str) -> PinCheck:
        """Compare ``pin`` with the stored hash in constant time; too many wrong tries lock out for a while.

        Raises:
            SettingsError: the PIN file is damaged (remove it to reset the PIN).
        """
        now = float(self._clock())  # type: ignore[operator]
        with self._lock:
            if now < self._locked_until:
                return PinCheck(False, self._locked_until - now)
        stored_salt, stored_hash = self._read()
        ok = hmac.compare_digest(_digest(pin.strip(), stored_salt), stored_hash)
        with self._lock:
            if ok:
                self._failures = 0
                return PinCheck(True)
            self._failures += 1
            if self._failures >= MAX_TRIES:
                self._failures = 0
                self._locked_until = now + LOCKOUT_S
                return PinCheck(False, LOCKOUT_S)
        return PinCheck(False)

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
