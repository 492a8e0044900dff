"""SHA-256 as the STAC file extension writes it: a multihash in hex (``1220`` + 64 hex digits).

``1220`` is the multihash prefix of sha2-256 (code 0x12, length 0x20). Any STAC tool reads the same
string; one function writes it and one reads it back, so publish and install cannot disagree.
"""

from __future__ import annotations

import hashlib
import re
from pathlib import Path

SHA256_PREFIX = "1220"
_MULTIHASH = re.compile(r"^1220([0-9a-f]{64})$")


def file_sha256(path: Path) -> str:
    """Hex SHA-256 of a file, read in 1 MiB pieces (a map image may be 100 MB)."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        while chunk := fh.read(1 << 20):
            digest.update(chunk)
    return digest.hexdigest()


def multihash(sha256_hex: str) -> str:
    """``file:checksum`` of a hex SHA-256."""
    return SHA256_PREFIX + sha256_hex


def sha256_of_multihash(value: object) -> str | None:
    """The hex SHA-256 in a ``file:checksum`` value, or None when it is not a sha2-256 multihash."""
    if not isinstance(value, str):
        return None
    match = _MULTIHASH.match(value.strip().lower())
    return match.group(1) if match else None
