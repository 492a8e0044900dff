"""Fixtures of the dashboard's screens, shared through the root conftest's ``pytest_plugins``."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from pmk_nb.ui import AppContext
from pmk_nb.ui.maps.screen import MapsScreen
from tests.helpers import app_context


@pytest.fixture
def ctx(tmp_path: Path) -> Iterator[AppContext]:
    """An app context on the test's own maps folder and profiles (see :func:`tests.helpers.app_context`)."""
    with app_context(tmp_path) as context:
        yield context


@pytest.fixture
def screen(ctx: AppContext) -> Iterator[MapsScreen]:
    """The Maps screen on that context, closed after the test."""
    s = MapsScreen(ctx)
    yield s
    s.close()
