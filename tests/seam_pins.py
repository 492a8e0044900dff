"""The exact pin of a library in pyproject.toml, for the seam tests."""

from __future__ import annotations

import re
import tomllib
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def assert_pinned_and_installed(library: str) -> None:
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    pins = [d for d in deps if re.match(rf"{re.escape(library)}\b", d, re.IGNORECASE)]
    assert len(pins) == 1 and re.fullmatch(rf"{re.escape(library)}==\d+(\.\d+)+", pins[0]), pins
    assert pins[0] == f"{library}=={metadata.version(library)}", (pins[0], metadata.version(library))
