"""What moved between the lock and the interpreter running this: `make test-latest` prints it.

Run with the newest releases installed (``.venv-latest``), it names every package whose version
differs from ``requirements/dev.txt``, so drift is seen before a fresh install meets it.
"""

from __future__ import annotations

import re
import sys
from importlib import metadata
from pathlib import Path

LOCK = Path(__file__).resolve().parent / "dev.txt"
_PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==([^\s;\\]+)")


def canonical(name: str) -> str:
    """A distribution name as PEP 503 compares them."""
    return re.sub(r"[-_.]+", "-", name).lower()


def locked(lock: Path = LOCK) -> dict[str, str]:
    """Name -> version of every pin in a pip-compile lock."""
    return {canonical(m[1]): m[2] for line in lock.read_text().splitlines() if (m := _PIN.match(line))}


def installed() -> dict[str, str]:
    """Name -> version of every distribution this interpreter sees."""
    return {canonical(d.metadata["Name"]): d.version for d in metadata.distributions() if d.metadata["Name"]}


def moves(pins: dict[str, str], now: dict[str, str]) -> list[str]:
    """One line per locked package whose installed version differs, or that is missing."""
    lines = []
    for name in sorted(pins):
        if name not in now:
            lines.append(f"{name}: locked {pins[name]}, not installed")
        elif now[name] != pins[name]:
            lines.append(f"{name}: locked {pins[name]} -> newest {now[name]}")
    return lines


def main() -> int:
    lines = moves(locked(), installed())
    print(f"{len(lines)} of {len(locked())} locked packages moved" + (":" if lines else ""))
    for line in lines:
        print(f"  {line}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
