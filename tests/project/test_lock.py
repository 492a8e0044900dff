"""The lock (issue 39): every dependency pinned with hashes, within pyproject's ranges, and used by make."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest
import yaml
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

from requirements.drift import locked, moves

ROOT = Path(__file__).resolve().parents[2]
REQS = ROOT / "requirements"
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]


def _pins(name: str) -> dict[str, str]:
    return locked(REQS / name)


def _declared(*extras: str) -> list[Requirement]:
    names = list(PROJECT["dependencies"])
    for extra in extras:
        names += PROJECT["optional-dependencies"][extra]
    return [Requirement(r) for r in names]


@pytest.mark.parametrize("lock", ["build.txt", "dev.txt", "base.txt", "ros2.txt"])
def test_every_pin_carries_a_hash(lock: str) -> None:
    text = (REQS / lock).read_text()
    entries = re.split(r"\n(?=[A-Za-z0-9])", text)
    pinned = [e for e in entries if re.match(r"[A-Za-z0-9][A-Za-z0-9._-]*==", e)]
    assert pinned, f"{lock} pins nothing"
    for entry in pinned:
        assert "--hash=sha256:" in entry, f"{lock}: {entry.splitlines()[0]} has no hash"


@pytest.mark.parametrize(("lock", "extras"), [("dev.txt", ("dev", "hub")), ("base.txt", ())])
def test_every_declared_dependency_is_pinned_inside_its_range(lock: str, extras: tuple[str, ...]) -> None:
    pins = _pins(lock)
    for req in _declared(*extras):
        name = canonicalize_name(req.name)
        assert name in pins, f"{req.name} is declared in pyproject.toml but not in requirements/{lock}: make lock"
        assert req.specifier.contains(pins[name], prereleases=True), f"{lock}: {name}=={pins[name]} outside {req}"


def test_the_base_lock_agrees_with_the_dev_lock() -> None:
    dev, base = _pins("dev.txt"), _pins("base.txt")
    assert {n: v for n, v in base.items() if dev.get(n) != v} == {}


def test_make_installs_from_the_lock_with_hashes() -> None:
    make = (ROOT / "Makefile").read_text()
    stamp = make[make.index("$(STAMP): pyproject.toml") :].split("\n\n", 1)[0]
    assert "--require-hashes --no-deps -r requirements/dev.txt" in stamp
    assert "--require-hashes -r requirements/build.txt" in stamp
    assert "--no-deps --no-build-isolation -e ." in stamp
    assert "pip install --quiet -e" not in stamp  # nothing resolved afresh
    wheels = (ROOT / "pmk_nb" / "robot" / "wheels.py").read_text()
    assert '"--require-hashes", "-r", str(LOCK)' in wheels


def test_drift_names_what_moved() -> None:
    pins = {"lxml": "6.0.2", "numpy": "2.1.0", "gone": "1.0"}
    now = {"lxml": "6.2.1", "numpy": "2.1.0"}
    assert moves(pins, now) == ["gone: locked 1.0, not installed", "lxml: locked 6.0.2 -> newest 6.2.1"]


def test_housekeeping_a_newcomer_expects() -> None:
    assert PROJECT["license"] == "MIT"
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")
    hooks = yaml.safe_load((ROOT / ".pre-commit-config.yaml").read_text())["repos"][0]["hooks"]
    assert [(h["id"], h["entry"].split()[0]) for h in hooks] == [
        ("ruff", ".venv/bin/ruff"),
        ("ruff-format", ".venv/bin/ruff"),
    ]
    make = (ROOT / "Makefile").read_text()
    for target in ("format:", "lock:", "test-latest:"):
        assert f"\n{target}" in make


#: runtime dependencies that pmk_nb never imports by name, each with its reason
NOT_IMPORTED = {
    "jupyterlab": "the notebook app the notebooks and the dashboard run in",
    "keyrings-alt": "keyring loads its plain-file backend by name (chair/secrets.PLAIN_FILE_BACKEND)",
}


@pytest.mark.slow
def test_every_runtime_dependency_is_used() -> None:
    """A runtime dependency is imported by pmk_nb, or says why not; one used only by tests belongs in the dev extra
    (issue 42: scipy was a runtime dependency that only tests import)."""
    import ast
    import importlib.metadata

    imported: set[str] = set()
    for path in (ROOT / "pmk_nb").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                imported |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                imported.add(node.module.split(".")[0])
    providers = importlib.metadata.packages_distributions()
    used = {canonicalize_name(dist) for module in imported for dist in providers.get(module, [])}
    unused = [canonicalize_name(r.name) for r in _declared() if canonicalize_name(r.name) not in used]
    assert sorted(set(unused) - set(NOT_IMPORTED)) == [], "runtime dependencies pmk_nb does not import"
    assert sorted(set(NOT_IMPORTED) - set(unused)) == [], "NOT_IMPORTED names a dependency that is imported now"
