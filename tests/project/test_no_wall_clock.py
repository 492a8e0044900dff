"""Time is an input (issue 39): a unit test never sleeps and never asserts on the wall clock.

An AST scan of every test file. A test (or a fixture, or a helper a test file defines) offends when it
calls ``time.sleep`` or asserts on a value read from ``time.time``/``monotonic``/``perf_counter``
(directly, or through a name assigned from one). Tests in the realtime tier may: the heavy folders,
``@pytest.mark.realtime``, and the tests using the realtime fixtures (conftest.py's
``REALTIME_FIXTURES``, directly or through a fixture). Unit tests advance ``pmk_nb.clock.VirtualClock``.

:data:`ALLOWED` names the offenders not converted yet, each with its reason; an entry that no longer
offends fails too, so the list only shrinks.
"""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterator
from pathlib import Path

import pytest

from conftest import HEAVY_FOLDERS, REALTIME_FIXTURES

TESTS = Path(__file__).resolve().parents[1]
WALL_CLOCK = {"time", "monotonic", "perf_counter", "monotonic_ns", "perf_counter_ns", "time_ns"}

#: "path::function": why it still reads the wall clock (one line each)
ALLOWED: dict[str, str] = {}


def _is_time_call(node: ast.AST, attrs: set[str]) -> bool:
    if not isinstance(node, ast.Call):
        return False
    func = node.func
    if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) and func.value.id == "time":
        return func.attr in attrs
    return False


def _marks(decorators: list[ast.expr]) -> set[str]:
    names = set()
    for dec in decorators:
        for node in ast.walk(dec):
            if isinstance(node, ast.Attribute):
                names.add(node.attr)
    return names


def _params(func: ast.FunctionDef | ast.AsyncFunctionDef) -> set[str]:
    args = func.args
    return {a.arg for a in [*args.posonlyargs, *args.args, *args.kwonlyargs]}


def _fixture_graph() -> dict[str, set[str]]:
    """Every fixture defined under tests/ (and conftest.py) -> the fixtures it takes."""
    graph: dict[str, set[str]] = {}
    for path in [*TESTS.rglob("*.py"), TESTS.parent / "conftest.py"]:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and "fixture" in _marks(node.decorator_list):
                graph.setdefault(node.name, set()).update(_params(node))
    return graph


def _realtime_fixtures() -> set[str]:
    graph, found = _fixture_graph(), set(REALTIME_FIXTURES)
    changed = True
    while changed:
        changed = False
        for name, uses in graph.items():
            if name not in found and uses & found:
                found.add(name)
                changed = True
    return found


def _offences(func: ast.AST) -> list[str]:
    """``time.sleep`` calls and asserts on the wall clock inside ``func`` (nested functions included)."""
    tainted: set[str] = set()
    assigns = [n for n in ast.walk(func) if isinstance(n, ast.Assign | ast.AugAssign | ast.AnnAssign)]
    changed = True
    while changed:  # names that hold a wall-clock reading, or arithmetic on one
        changed = False
        for node in assigns:
            value = node.value
            if value is None:
                continue
            reads = any(_is_time_call(n, WALL_CLOCK) for n in ast.walk(value)) or any(
                isinstance(n, ast.Name) and n.id in tainted for n in ast.walk(value)
            )
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                for n in ast.walk(target):
                    if reads and isinstance(n, ast.Name) and n.id not in tainted:
                        tainted.add(n.id)
                        changed = True
    found = [f"time.sleep at line {n.lineno}" for n in ast.walk(func) if _is_time_call(n, {"sleep"})]
    for node in ast.walk(func):
        if isinstance(node, ast.Assert) and (
            any(_is_time_call(n, WALL_CLOCK) for n in ast.walk(node.test))
            or any(isinstance(n, ast.Name) and n.id in tainted for n in ast.walk(node.test))
        ):
            found.append(f"assert on the wall clock at line {node.lineno}")
    return found


def _units(tree: ast.Module) -> Iterator[tuple[str, ast.AST, set[str], set[str]]]:
    """(name, node, marks, fixtures taken) of each top-level function and class (its methods as one)."""
    for node in tree.body:
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            yield node.name, node, _marks(node.decorator_list), _params(node)
        elif isinstance(node, ast.ClassDef):
            params = set()
            for item in node.body:
                if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef):
                    params |= _params(item)
            yield node.name, node, _marks(node.decorator_list), params


def _module_marks(tree: ast.Module) -> set[str]:
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "pytestmark" for t in node.targets):
            return _marks([node.value])
    return set()


def _file_offenders(path: Path, realtime_fixtures: set[str], label: str) -> dict[str, list[str]]:
    """The file's units outside the realtime tier that offend; a helper counts as realtime when every
    test or fixture that reaches it (by name) is realtime."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    units = {name: (node, marks, params) for name, node, marks, params in _units(tree)}
    module_rt = bool(_module_marks(tree) & {"realtime", "browser"})

    def realtime(marks: set[str], params: set[str]) -> bool:
        return module_rt or bool(marks & {"realtime", "browser"}) or bool(params & realtime_fixtures)

    roots = {n: realtime(m, p) for n, (_, m, p) in units.items() if n.startswith("test") or "fixture" in m}
    reached_by: dict[str, set[bool]] = {name: set() for name in units}
    for root, is_rt in roots.items():
        seen, todo = {root}, [root]
        while todo:
            current = todo.pop()
            reached_by[current].add(is_rt)
            for n in ast.walk(units[current][0]):
                if isinstance(n, ast.Name) and n.id in units and n.id not in seen:
                    seen.add(n.id)
                    todo.append(n.id)
    offenders = {}
    for name, (node, _, _) in units.items():
        if reached_by[name] == {True}:
            continue  # only realtime tests and fixtures use it
        found = _offences(node)
        if found:
            offenders[f"{label}::{name}"] = found
    return offenders


@functools.cache
def _offenders() -> dict[str, list[str]]:
    realtime_fixtures = _realtime_fixtures()
    found: dict[str, list[str]] = {}
    for path in sorted(TESTS.rglob("test_*.py")):
        if path.relative_to(TESTS).parts[0] in HEAVY_FOLDERS:
            continue
        found.update(_file_offenders(path, realtime_fixtures, str(path.relative_to(TESTS.parent))))
    return found


@pytest.mark.slow
def test_no_unit_test_sleeps_or_asserts_on_the_wall_clock() -> None:
    offenders = {key: where for key, where in _offenders().items() if key not in ALLOWED}
    lines = [f"{key}: {', '.join(where)}" for key, where in sorted(offenders.items())]
    assert not offenders, (
        "unit tests that read the wall clock (advance a pmk_nb.clock.VirtualClock, or mark the test realtime):\n"
        + "\n".join(lines)
    )


@pytest.mark.slow
def test_the_allow_list_only_shrinks() -> None:
    stale = sorted(set(ALLOWED) - set(_offenders()))
    assert not stale, f"no longer offending: remove from ALLOWED: {stale}"


def test_the_scan_finds_a_sleep_and_an_asserted_rate(tmp_path: Path) -> None:
    """The scan itself: a sleep and an asserted wall-clock rate offend; the same under a realtime fixture does not."""
    source = (
        "import time\n"
        "def test_sleeps():\n    time.sleep(0.1)\n"
        "def test_rate():\n    t0 = time.monotonic()\n    n = 3\n    hz = n / (time.monotonic() - t0)\n"
        "    assert hz < 30\n"
        "def test_real(sim_factory):\n    time.sleep(0.1)\n"
        "def test_virtual():\n    deadline = time.monotonic() + 5\n    assert True\n"
    )
    sample = tmp_path / "test_sample.py"
    sample.write_text(source)
    assert sorted(_file_offenders(sample, {"sim_factory"}, "sample")) == ["sample::test_rate", "sample::test_sleeps"]
