"""ARCHITECTURE.md's package table stays true: every module is named in its package's row, and
every row names a package or module that exists (issue 25: the map of the code had gone stale)."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
ROW = re.compile(r"^\| `([^`]+)` \| (.*)$")


def _rows() -> dict[str, str]:
    rows = {}
    for line in (REPO / "ARCHITECTURE.md").read_text(encoding="utf-8").splitlines():
        m = ROW.match(line)
        if m and (m.group(1).endswith("/") or m.group(1).endswith(".py")):
            rows[m.group(1)] = m.group(2)
    return rows


def _modules() -> list[Path]:
    root = REPO / "pmk_nb"
    return sorted(p.relative_to(root) for p in root.rglob("*.py") if p.name != "__init__.py")


def test_every_module_is_named_in_its_packages_row() -> None:
    rows = _rows()
    unnamed = []
    for rel in _modules():
        if len(rel.parts) == 1:
            if rel.name not in rows:
                unnamed.append(f"{rel}: no row `{rel.name}`")
            continue
        package = "/".join(rel.parts[:-1]) + "/"
        row = rows.get(package)
        if row is None:
            unnamed.append(f"{rel}: no row `{package}`")
        elif not re.search(rf"`{re.escape(rel.stem)}(\.py)?[`.]|`{re.escape(rel.stem.split('_')[0])}_\*`", row):
            unnamed.append(f"{rel}: not named in the `{package}` row")
    assert not unnamed, "ARCHITECTURE.md does not say what these are:\n" + "\n".join(unnamed)


def test_every_row_names_something_that_exists() -> None:
    missing = [name for name in _rows() if not (REPO / "pmk_nb" / name).exists()]
    assert not missing, f"ARCHITECTURE.md has rows for what is gone: {missing}"
