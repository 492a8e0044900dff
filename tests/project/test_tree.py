"""The tests mirror the package tree, so a change to ``pmk_nb/<package>`` has its tests in ``tests/<package>``.

Rule: every test file sits in ``tests/<package path>/`` (``tests/chair/link/`` for ``pmk_nb/chair/link``)
and imports that package (or a helper beside it in its folder); ``tests/core/`` holds the tests of
pmk_nb's top-level modules. The tests of the whole system have folders of their own: ``project`` (layout,
docs), ``browser`` (Chromium), ``real`` (real ROS stacks), ``kernels`` (notebook kernels, Voilà); the
last three are the heavy tier that ``make check`` leaves out (root ``conftest.py``). No test file sits at
``tests/`` itself: new ones go to their package's folder.
"""

from __future__ import annotations

import ast
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TESTS = REPO / "tests"
PKG = REPO / "pmk_nb"
WHOLE_SYSTEM = {"project", "browser", "real", "kernels"}
CORE = "core"
# test files that reach their package only through a process or a shared fixture, not an import
THROUGH_A_PROCESS = {
    "cli/test_cli_send.py": "runs `pmk send` as a process",
    "chair/test_chair_key_auto.py": "runs `pmk chair add` / `pmk send` as processes (the key set-up)",
    "sim/test_sim_sftp_confine.py": "the simulator from fixtures_sim's sim_factory",
    "sim/test_sim_mapserver.py": "the simulator from fixtures_sim's sim_factory",
    "sim/test_sim_sftp.py": "the simulator from fixtures_sim's fixtures",
    "sim/test_sim_reload.py": "the simulator from fixtures_sim's fixtures",
}


def _test_files() -> list[Path]:
    return sorted(p for p in TESTS.rglob("test_*.py") if "node_modules" not in p.parts)


def _imported(path: Path) -> set[str]:
    """Every dotted module name the file imports (``from a.b import c`` gives ``a.b`` and ``a.b.c``)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


def _imports_its_package(path: Path) -> bool:
    folder = path.parent.relative_to(TESTS).parts
    imported = _imported(path)
    if folder == (CORE,):
        top = {p.stem for p in PKG.glob("*.py")} - {"__init__"}
        return any(name.split(".")[:2] in (["pmk_nb", t] for t in top) for name in imported)
    package, helpers = "pmk_nb." + ".".join(folder), "tests." + ".".join(folder)
    return any(name == n or name.startswith(n + ".") for name in imported for n in (package, helpers))


def test_no_test_file_sits_at_the_tests_root() -> None:
    loose = [p.name for p in TESTS.glob("test_*.py")]
    assert not loose, f"move these into tests/<package>/ (the package they test): {loose}"


def test_every_test_folder_mirrors_a_package_or_is_a_whole_system_folder() -> None:
    folders = {p.parent.relative_to(TESTS) for p in _test_files()}
    wrong = [
        str(f)
        for f in folders
        if f.parts[0] not in WHOLE_SYSTEM | {CORE} and not (PKG.joinpath(*f.parts) / "__init__.py").is_file()
    ]
    assert not wrong, f"not a pmk_nb package nor a whole-system folder: {sorted(wrong)}"
    unpackaged = [str(f) for f in folders if not (TESTS / f / "__init__.py").is_file()]
    assert not unpackaged, f"folders without __init__.py (equal file names would clash): {sorted(unpackaged)}"


def test_every_test_file_imports_the_package_of_its_folder() -> None:
    stray = [
        str(p.relative_to(TESTS))
        for p in _test_files()
        if p.parent.relative_to(TESTS).parts[0] not in WHOLE_SYSTEM
        and str(p.relative_to(TESTS)) not in THROUGH_A_PROCESS
        and not _imports_its_package(p)
    ]
    assert not stray, f"these test files do not import the package of their folder: {stray}"


def test_the_exceptions_still_exist() -> None:
    missing = [name for name in THROUGH_A_PROCESS if not (TESTS / name).is_file()]
    assert not missing, f"stale entries in THROUGH_A_PROCESS: {missing}"
