"""Fixtures of the browser tests (this folder only)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from pmk_nb.cli.demo_setup import DemoWorld
from tests.browser.kiosk_page import serve_kiosk


@pytest.fixture
def kiosk(tmp_path: Path) -> Iterator[tuple[str, DemoWorld]]:
    with serve_kiosk(tmp_path) as served:
        yield served
