"""Root conftest: registers the shared fixture modules so every test file can use them.

Every test that starts a browser, Voilà, a notebook kernel or a real ROS stack is marked ``heavy``:
``make check`` (the fast tier) leaves them out. (pytest-xdist's ``--dist loadgroup`` would keep them on
one worker, but with pytest 9.2 it does not group: xdist 3.8 writes the group into ``item._nodeid``,
which pytest 9.2 no longer reads. ``make test`` therefore uses plain ``-n 2``, measured green.)

Browser modules run first, and ``make test`` uses ``--dist worksteal``: plain load scheduling gave
the first worker an initial chunk of 297 tests holding every browser test (about 1200 s of the
1348 s run) while the second finished the rest and waited; with the browser tests at the head of
one worker's queue, an idle worker steals the light tests from its tail instead.
"""

from __future__ import annotations

import pytest

pytest_plugins = ["tests.fixtures_sim", "tests.fixtures_ssh", "tests.fixtures_ui"]

HEAVY_PREFIXES = ("test_browser_", "test_real_", "test_notebook", "test_voila_")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    browser_modules = set()
    for item in items:
        if item.path.name.startswith(HEAVY_PREFIXES) or item.get_closest_marker("browser"):
            item.add_marker(pytest.mark.heavy)
        if item.get_closest_marker("browser"):
            browser_modules.add(item.path)
    # stable: modules stay whole (module fixtures set up once) and keep their order within a tier
    items.sort(key=lambda item: item.path not in browser_modules)
