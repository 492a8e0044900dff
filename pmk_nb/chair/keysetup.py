"""SSH keys made easy (issue 29: passwords were never remembered): `pmk chair add --key auto`.

A chair profile with a key never asks for a password again, in any kernel or CLI call, with no
keyring at all. ``--key auto`` makes an ed25519 key in the settings folder (0600) if there is none,
logs in once with the password, appends the public key to the chair's ``~/.ssh/authorized_keys``
(over SFTP: works where only SFTP is allowed; ``~/.ssh`` 0700, the file 0600, a key already there is
not added twice), switches the profile to ``auth: key`` and checks a key-only login.
"""

from __future__ import annotations

import dataclasses
import posixpath
from pathlib import Path

from pmk_nb.chair.profiles import ChairProfile, config_dir
from pmk_nb.errors import TransferError
from pmk_nb.fileio import atomic_write, private_dir

KEYS_FOLDER = "keys"


def make_key_pair(directory: Path, name: str, comment: str = "pmk") -> tuple[Path, Path]:
    """A new ed25519 key pair: ``directory/name`` (OpenSSH private key, 0600) and ``name.pub``.

    Made with ``cryptography`` (paramiko's own dependency), so no ``ssh-keygen`` is needed.
    Returns (private key path, public key path).
    """
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

    key = Ed25519PrivateKey.generate()
    private = key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.OpenSSH, serialization.NoEncryption()
    )
    public = key.public_key().public_bytes(serialization.Encoding.OpenSSH, serialization.PublicFormat.OpenSSH)
    private_dir(directory)
    private_path, public_path = directory / name, directory / f"{name}.pub"
    atomic_write(private_path, private, mode=0o600)
    atomic_write(public_path, public + f" {comment}\n".encode(), mode=0o644)
    return private_path, public_path


def profile_key(profile_name: str, folder: Path | None = None) -> tuple[Path, str]:
    """The profile's key in ``<settings>/keys/`` (made on first use) and its public line."""
    folder = folder if folder is not None else config_dir() / KEYS_FOLDER
    private = folder / f"{profile_name}_ed25519"
    public = private.with_name(private.name + ".pub")
    if not (private.is_file() and public.is_file()):
        private, public = make_key_pair(folder, private.name, comment=f"pmk-{profile_name}")
    return private, public.read_text(encoding="ascii").strip()


def install_public_key(profile: ChairProfile, password: str, public_line: str, *, timeout: float = 15.0) -> bool:
    """Append ``public_line`` to the chair's ``~/.ssh/authorized_keys`` after a password login.

    Returns False when the key was already there. The chair's host key is checked as for a send.
    """
    from pmk_nb.chair.ssh import open_sftp

    with open_sftp(dataclasses.replace(profile, auth="password"), password=password, timeout=timeout) as session:
        ssh_dir = posixpath.join(session.home, ".ssh")
        path = posixpath.join(ssh_dir, "authorized_keys")
        sftp = session.sftp
        try:
            sftp.stat(ssh_dir)
        except FileNotFoundError:
            sftp.mkdir(ssh_dir, mode=0o700)
        try:
            with sftp.open(path, "r") as fh:
                present = fh.read().decode("utf-8", "replace")
        except FileNotFoundError:
            present = ""
        body = public_line.split()[:2]
        if any(line.split()[:2] == body for line in present.splitlines() if line.strip()):
            return False
        try:
            with sftp.open(path, "a") as fh:
                fh.write(("" if not present or present.endswith("\n") else "\n") + public_line + "\n")
            sftp.chmod(path, 0o600)
        except OSError as err:
            raise TransferError(f"{session.where}: cannot add the key to {path} ({err})") from err
        return True


def setup_key(profile: ChairProfile, password: str, *, timeout: float = 15.0) -> tuple[ChairProfile, bool]:
    """``--key auto``: key made, installed with ``password``, then a key-only login checked.

    Returns the profile switched to ``auth: key`` and whether the key was newly installed.
    """
    from pmk_nb.chair.transfer import check_ssh

    private, public_line = profile_key(profile.name)
    added = install_public_key(profile, password, public_line, timeout=timeout)
    keyed = dataclasses.replace(profile, auth="key", key_file=str(private))
    check_ssh(keyed, password=None, timeout=timeout)  # the key alone logs in, or this raises
    return keyed, added
