"""Chair SSH passwords: the one session cache, backed by the system keyring when one works.

A password belongs to the SSH account it was typed for (user, host, SSH port), never to a profile
name: a profile edited to point at another chair must not send the old chair's password there. The
keyring entry is named the same way (``user@host:port`` under service ``pmk_nb``). Passwords never
reach a file of ours; without a keyring they live in memory until the kernel ends.

On a box without a desktop keyring, keyring finds keyrings.alt's plain-file backend (a 0600 file in
the user's data folder) as its last resort. That is used only when chosen explicitly
(``PYTHON_KEYRING_BACKEND=keyrings.alt.file.PlaintextKeyring`` or keyringrc.cfg): the easy default is an
SSH key (`pmk chair add NAME --key auto`, :mod:`pmk_nb.chair.keysetup`), which needs no password at all.
"""

from __future__ import annotations

import os
import threading
from dataclasses import dataclass
from typing import Protocol

KEYRING_SERVICE = "pmk_nb"
PLAIN_FILE_BACKEND = "keyrings.alt.file.PlaintextKeyring"
MEMORY_ONLY = "memory (this session only: asked again next session)"


class SecretBackend(Protocol):
    """The part of the ``keyring`` module API we use."""

    def get_password(self, service: str, username: str) -> str | None: ...
    def set_password(self, service: str, username: str, password: str) -> None: ...
    def delete_password(self, service: str, username: str) -> None: ...


class HasSshAccount(Protocol):
    """What names an SSH account (a :class:`~pmk_nb.chair.profiles.ChairProfile` has these)."""

    ssh_user: str
    host: str
    ssh_port: int


@dataclass(frozen=True)
class SshAccount:
    """The (user, host, SSH port) a password was entered for."""

    user: str
    host: str
    port: int

    @classmethod
    def of(cls, profile: HasSshAccount) -> SshAccount:
        return cls(profile.ssh_user, profile.host, int(profile.ssh_port))

    @property
    def key(self) -> str:
        """The keyring user name: ``user@host:port``."""
        return f"{self.user}@{self.host}:{self.port}"


def detect_keyring() -> tuple[SecretBackend | None, str]:
    """The keyring module when it is installed and has a real backend; else (None, why not)."""
    try:
        import keyring  # type: ignore[import-not-found, unused-ignore]  # optional: absent on most installs
        import keyring.backends.fail  # type: ignore[import-not-found, unused-ignore]
    except Exception:
        return None, "the keyring package is not installed"
    try:
        backend = keyring.get_keyring()
    except Exception as err:
        return None, f"keyring has no usable backend ({err})"
    if isinstance(backend, keyring.backends.fail.Keyring) or getattr(backend, "priority", 1) <= 0:
        return None, "keyring has no usable backend"
    if type(backend).__name__ == "ChainerBackend" and not getattr(backend, "backends", None):
        return None, "keyring has no usable backend"
    if is_plain_file(backend) and not plain_file_chosen():
        return None, PLAIN_FILE_NOT_CHOSEN
    return keyring, f"system keyring ({type(backend).__name__})"


#: why a plain-file keyring found on its own is not used, and the two ways forward (README: Passwords)
PLAIN_FILE_NOT_CHOSEN = (
    "only a plain-file keyring here (no desktop keyring): choose it with "
    f"PYTHON_KEYRING_BACKEND={PLAIN_FILE_BACKEND}, or use an SSH key: pmk chair add NAME --key auto"
)


def is_plain_file(backend: object) -> bool:
    """keyrings.alt's PlaintextKeyring: passwords in a 0600 file, readable by anyone who reads the user's files."""
    cls = type(backend)
    return f"{cls.__module__}.{cls.__name__}" == PLAIN_FILE_BACKEND


def plain_file_chosen() -> bool:
    """The plain-file keyring was chosen by the user, through keyring's own settings (the environment
    variable or keyringrc.cfg), not merely found as the last resort of a box without a desktop keyring."""
    if os.environ.get("PYTHON_KEYRING_BACKEND", "").strip() == PLAIN_FILE_BACKEND:
        return True
    try:
        import keyring.core

        configured = keyring.core.load_config()
    except Exception:  # an unreadable keyringrc.cfg chooses nothing
        return False
    return configured is not None and is_plain_file(configured)


class PasswordCache:
    """Passwords of this session by SSH account, written through to a keyring when there is one.

    Args:
        backend: a keyring-like object; ``None``/``True`` auto-detects; ``False`` keeps passwords
            in memory only (tests, kiosks without a keyring).
    """

    def __init__(self, backend: SecretBackend | bool | None = None) -> None:
        self._lock = threading.Lock()
        self._session: dict[SshAccount, str] = {}
        self._backend: SecretBackend | None
        if backend is False:
            self._backend, self._where = None, MEMORY_ONLY
        elif backend is None or backend is True:
            self._backend, why = detect_keyring()
            self._where = why if self._backend else f"memory (this session only: {why})"
        else:
            self._backend, self._where = backend, f"keyring ({type(backend).__name__})"

    @property
    def where(self) -> str:
        """Where passwords go, in words for the Settings screen."""
        return self._where

    @property
    def persists(self) -> bool:
        """True when passwords survive the session (a keyring works)."""
        return self._backend is not None

    def remember(self, account: SshAccount, password: str) -> None:
        """Keep a password for this session only (typed in a dialog, never stored)."""
        with self._lock:
            self._session[account] = password

    def store(self, account: SshAccount, password: str) -> None:
        """Keep a password for this session and, when a keyring works, for later sessions.

        A keyring that fails is dropped for the rest of the session (``where`` says so).
        """
        backend = self._backend
        if backend is not None:
            try:
                backend.set_password(KEYRING_SERVICE, account.key, password)
            except Exception as err:  # any keyring failure means "memory only"
                with self._lock:
                    self._backend = None
                    self._where = f"memory (this session only: keyring failed: {err})"
        self.remember(account, password)

    def lookup(self, account: SshAccount) -> str | None:
        """This session's password for ``account``, else the keyring's, else None."""
        with self._lock:
            if account in self._session:
                return self._session[account]
            backend = self._backend
        if backend is None:
            return None
        try:
            return backend.get_password(KEYRING_SERVICE, account.key) or None
        except Exception:  # an unreadable keyring is the same as no stored password
            return None

    def forget(self, account: SshAccount) -> None:
        with self._lock:
            self._session.pop(account, None)
            backend = self._backend
        if backend is not None:
            try:
                backend.delete_password(KEYRING_SERVICE, account.key)
            except Exception:  # nothing stored is fine
                pass
