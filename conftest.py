"""Root conftest: registers the shared fixture modules so every test file can use them.

With ``-n 2 --dist loadgroup`` (``make test``) every test that starts a browser, Voilà, a notebook
kernel or a real ROS stack runs on one worker, one at a time: two of them at once on two cores would
only slow each other; the light tests fill the other worker.
"""

from __future__ import annotations

import pytest

pytest_plugins = ["tests.fixtures_sim", "tests.fixtures_ssh", "tests.fixtures_ui"]

HEAVY_PREFIXES = ("test_browser_", "test_real_", "test_notebook", "test_voila_")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if item.path.name.startswith(HEAVY_PREFIXES) or item.get_closest_marker("browser"):
            item.add_marker(pytest.mark.heavy)
            item.add_marker(pytest.mark.xdist_group("heavy"))
