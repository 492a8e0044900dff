"""axe-core in a Playwright page: WCAG 2.0, 2.1 and 2.2 A/AA rules, nothing excluded.

Shared by the accessibility browser tests.  axe-core comes from the npm package in ``tests/js``
(installed by the Makefile's JS stamp, versions fixed by the lock file); a missing install FAILS
with the command that makes it, never skips.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

AXE_JS = Path(__file__).parent / "js" / "node_modules" / "axe-core" / "axe.min.js"
#: The rule tags of WCAG 2.0, 2.1 and 2.2, levels A and AA (axe has no "wcag22a" rules).
WCAG_TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa", "wcag22aa"]


def run_axe(page: Any) -> list[dict[str, Any]]:
    """Every violation of the WCAG A/AA rules in the page as it is now (each with its nodes)."""
    if not AXE_JS.exists():
        pytest.fail(f"{AXE_JS} is missing: run `make tests/js/node_modules/.package-lock.json` (npm ci in tests/js)")
    if not page.evaluate("() => typeof window.axe !== 'undefined'"):
        page.add_script_tag(path=str(AXE_JS))
    result = page.evaluate(
        """(tags) => axe.run(document, {runOnly: {type: 'tag', values: tags}, resultTypes: ['violations']})
            .then((r) => r.violations.map((v) => ({
                id: v.id, impact: v.impact, help: v.help,
                nodes: v.nodes.map((n) => ({target: n.target.join(' '), summary: n.failureSummary,
                                            html: n.html.slice(0, 160)})),
            })))""",
        WCAG_TAGS,
    )
    return list(result)


def describe(violations: list[dict[str, Any]], limit: int = 4) -> str:
    """One readable line per rule, with its first few nodes: what a failing test prints."""
    lines = []
    for v in violations:
        nodes = "; ".join(f"{n['target']} ({n['summary'].splitlines()[-1].strip()})" for n in v["nodes"][:limit])
        lines.append(f"{v['id']} [{v['impact']}] x{len(v['nodes'])}: {v['help']}: {nodes}")
    return "\n".join(lines)
