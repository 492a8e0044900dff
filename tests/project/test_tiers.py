"""`make check` is the fast loop of issue 25: it must keep covering at least half the suite, or the
slow mark has turned into a way to leave tests out. Reads the marker expression from the Makefile, so
the test and the command cannot drift apart."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def check_marker_expression() -> str:
    recipe = (ROOT / "Makefile").read_text().split("\ncheck:", 1)[1].split("\n\n", 1)[0]
    found = re.search(r'-m "([^"]+)"', recipe)
    assert found, "the Makefile's check recipe has no -m marker expression"
    return found.group(1)


@pytest.mark.slow
def test_the_fast_tier_holds_at_least_half_the_tests() -> None:
    expression = check_marker_expression()
    assert "heavy" in expression and "slow" in expression
    out = subprocess.run(
        [sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider", "-m", expression],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=240,
    ).stdout
    counts = re.search(r"(\d+)/(\d+) tests collected \((\d+) deselected\)", out)
    assert counts, out[-2000:]
    fast, total = int(counts.group(1)), int(counts.group(2))
    assert total > 2000  # the whole suite was collected, not a fragment
    assert fast >= total / 2, f"make check runs {fast} of {total} tests"
