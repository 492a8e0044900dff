"""No import cycles between pmk_nb's modules (issues 25 and 42).

The graph is read from the AST: an import at module level and an import inside a function both
count (a lazy import inside a function is how cycles hid before: ``chair/link`` was a 7-module
knot held together that way). Imports under ``if TYPE_CHECKING:`` do not run: the run-time graph
leaves them out, and a second graph with them (what mypy follows) must have no cycle either (issue 42:
seven type-only knots had hidden there).
``from a.b import c`` is an edge to ``a.b.c`` when that is a module, else to ``a.b`` (its
``__init__``); importing a submodule is not counted as importing its package's ``__init__``.
"""

from __future__ import annotations

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[2] / "pmk_nb"


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PKG.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _imported(
    tree: ast.Module, name: str, is_package: bool, modules: set[str], *, type_checking: bool = False
) -> set[str]:
    """Modules of pmk_nb that ``tree`` imports when it runs (any depth); with ``type_checking``, also
    those it imports under ``if TYPE_CHECKING:`` (what mypy follows)."""
    found: set[str] = set()
    stack: list[ast.AST] = [tree]
    while stack:
        node = stack.pop()
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child) and not type_checking:
                stack.extend(child.orelse)
            elif isinstance(child, ast.Import):
                found |= {alias.name for alias in child.names}
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:
                    parts = name.split(".") if is_package else name.split(".")[:-1]
                    parts = parts[: len(parts) - (child.level - 1)]
                    base = ".".join([*parts, *([child.module] if child.module else [])])
                for alias in child.names:
                    sub = f"{base}.{alias.name}"
                    found.add(sub if sub in modules else base)
            else:
                stack.append(child)
    return {m for m in found if m in modules and m != name}


def import_graph(*, type_checking: bool = False) -> dict[str, set[str]]:
    paths = {_module_name(p): p for p in sorted(PKG.rglob("*.py"))}
    names = set(paths)
    return {
        name: _imported(
            ast.parse(path.read_text(encoding="utf-8")),
            name,
            path.name == "__init__.py",
            names,
            type_checking=type_checking,
        )
        for name, path in paths.items()
    }


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    on_stack: set[str] = set()
    stack: list[str] = []
    found: list[list[str]] = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, edges = work[-1]
            nxt = next(edges, None)
            if nxt is not None:
                if nxt not in index:
                    index[nxt] = low[nxt] = len(index)
                    stack.append(nxt)
                    on_stack.add(nxt)
                    work.append((nxt, iter(sorted(graph[nxt]))))
                elif nxt in on_stack:
                    low[node] = min(low[node], index[nxt])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_no_import_cycles() -> None:
    knots = cycles(import_graph())
    assert not knots, "import cycles (break them: a small shared module, a Protocol, or pass the thing in):\n" + (
        "\n".join(" <-> ".join(knot) for knot in knots)
    )


def test_the_graph_sees_lazy_imports_and_skips_type_checking_ones() -> None:
    """The reader itself: a cycle through an import inside a function is found; one through an
    ``if TYPE_CHECKING:`` import is not."""
    mods = {"pmk_nb.a", "pmk_nb.b", "pmk_nb.c"}
    a = ast.parse("from pmk_nb.b import X\n")
    b = ast.parse("def f():\n    from pmk_nb import a\n")
    c = ast.parse("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pmk_nb.a import Y\n")
    graph = {
        "pmk_nb.a": _imported(a, "pmk_nb.a", False, mods),
        "pmk_nb.b": _imported(b, "pmk_nb.b", False, mods),
        "pmk_nb.c": _imported(c, "pmk_nb.c", False, mods),
    }
    assert graph == {"pmk_nb.a": {"pmk_nb.b"}, "pmk_nb.b": {"pmk_nb.a"}, "pmk_nb.c": set()}
    assert cycles(graph) == [["pmk_nb.a", "pmk_nb.b"]]
    assert cycles({**graph, "pmk_nb.b": set()}) == []


def test_no_cycles_type_only_imports_included() -> None:
    """What mypy follows has no cycle either (issue 42): a type-only knot is the same two modules
    needing each other, only hidden from the run time."""
    graph = import_graph(type_checking=True)
    knots = sorted(cycles(graph), key=lambda k: (len(k), k))  # shortest first
    edges = {k[0]: ", ".join(f"{a} -> {b}" for a in k for b in sorted(graph[a]) if b in k) for k in knots}
    assert not knots, (
        "import cycles through `if TYPE_CHECKING:` imports (move the shared type to a small module both import, "
        "or let the lower module define the Protocol it needs):\n"
        + "\n".join(f"{' <-> '.join(knot)}   ({edges[knot[0]]})" for knot in knots)
    )


def test_the_type_checking_graph_counts_type_checking_imports() -> None:
    mods = {"pmk_nb.a", "pmk_nb.b"}
    a = ast.parse("from pmk_nb.b import X\n")
    b = ast.parse("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pmk_nb.a import Y\n")
    graph = {
        "pmk_nb.a": _imported(a, "pmk_nb.a", False, mods, type_checking=True),
        "pmk_nb.b": _imported(b, "pmk_nb.b", False, mods, type_checking=True),
    }
    assert graph == {"pmk_nb.a": {"pmk_nb.b"}, "pmk_nb.b": {"pmk_nb.a"}}
    assert cycles(graph) == [["pmk_nb.a", "pmk_nb.b"]]
