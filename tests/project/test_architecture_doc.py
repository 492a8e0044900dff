"""ARCHITECTURE.md's package table stays true: every module is named in its package's row, and
every row names a package or module that exists (issue 25: the map of the code had gone stale)."""

from __future__ import annotations

import ast
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


# -- the map's package list and arrows, against the real import graph (issue 42) -------------------------------------

PKG = REPO / "pmk_nb"
DOC = (REPO / "ARCHITECTURE.md").read_text(encoding="utf-8")
#: packages drawn apart from their parent package (a face of their own)
SUBPACKAGES = ("chair/link",)


def _node(module: str) -> str | None:
    """The package (``raster/``, ``chair/link``) or top-level module (``grid.py``) a dotted module belongs to."""
    parts = module.split(".")[1:]
    if not parts:
        return None
    for sub in SUBPACKAGES:
        if parts[: sub.count("/") + 1] == sub.split("/"):
            return sub
    return f"{parts[0]}/" if (PKG / parts[0]).is_dir() else f"{parts[0]}.py"


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _imports(path: Path) -> list[tuple[str, bool]]:
    module = ".".join(path.relative_to(REPO).with_suffix("").parts)
    return _imports_of(path.read_text(encoding="utf-8"), module, is_package=path.name == "__init__.py")


def _imports_of(source: str, module: str, *, is_package: bool) -> list[tuple[str, bool]]:
    """(module, type-only) for each pmk_nb import in ``source``, at any depth; type-only under ``if TYPE_CHECKING``."""
    package = module.split(".") if is_package else module.split(".")[:-1]
    found: list[tuple[str, bool]] = []
    stack: list[tuple[ast.AST, bool]] = [(ast.parse(source), False)]
    while stack:
        node, type_only = stack.pop()
        if isinstance(node, ast.If) and _is_type_checking(node):
            stack += [(child, True) for child in node.body] + [(child, type_only) for child in node.orelse]
            continue
        if isinstance(node, ast.Import):
            found += [(alias.name, type_only) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package[: len(package) - (node.level - 1)] + ([node.module] if node.module else []))
            found.append((base, type_only))
        else:
            stack += [(child, type_only) for child in ast.iter_child_nodes(node)]
    return [(name, type_only) for name, type_only in found if name.startswith("pmk_nb.")]


def real_arrows() -> dict[str, tuple[set[str], set[str]]]:
    """package -> (what it imports when it runs, what it imports for type checking only)."""
    arrows: dict[str, tuple[set[str], set[str]]] = {}
    for path in sorted(PKG.rglob("*.py")):
        if path.parent == PKG and path.name == "__init__.py":
            continue
        own = _node(".".join(path.relative_to(REPO).with_suffix("").parts).removesuffix(".__init__"))
        for module, type_only in _imports(path):
            target = _node(module)
            if own is not None and target is not None and target != own:
                arrows.setdefault(own, (set(), set()))[type_only].add(target)
    return {own: (run, types - run) for own, (run, types) in arrows.items()}


def _names(text: str) -> set[str]:
    return {name.strip() for name in text.split(",") if name.strip()}


def drawn_arrows() -> dict[str, tuple[set[str], set[str]]]:
    """The arrows ARCHITECTURE.md draws: ``pkg -> a, b; types: c`` lines in its "Imports between packages" block."""
    section = DOC.split("## Imports between packages", 1)[1]
    block = section.split("```text\n", 1)[1].split("```", 1)[0]
    drawn: dict[str, tuple[set[str], set[str]]] = {}
    for line in block.strip().splitlines():
        own, _, rest = line.partition(" -> ")
        run, _, types = rest.partition("; types: ")
        drawn[own.strip()] = (_names(run), _names(types))
    return drawn


def test_the_drawn_imports_are_the_real_ones() -> None:
    real, drawn = real_arrows(), drawn_arrows()
    wrong = []
    for own in sorted(set(real) | set(drawn)):
        (run, types), (drun, dtypes) = real.get(own, (set(), set())), drawn.get(own, (set(), set()))
        wrong += [f"{own} -> {t}: imported, not drawn" for t in sorted(run - drun)]
        wrong += [f"{own} -> {t}: drawn, not imported" for t in sorted(drun - run)]
        wrong += [f"{own} -> {t} (types): imported for types, not drawn" for t in sorted(types - dtypes)]
        wrong += [f"{own} -> {t} (types): drawn, not imported for types" for t in sorted(dtypes - types)]
    assert not wrong, "ARCHITECTURE.md's 'Imports between packages' is stale:\n" + "\n".join(wrong)


def _packages() -> list[str]:
    return sorted(p.name for p in PKG.iterdir() if (p / "__init__.py").is_file())


def test_every_package_and_top_level_module_has_a_row_and_a_place_in_the_picture() -> None:
    rows = _rows()
    top = [f"{p}/" for p in _packages()] + sorted(p.name for p in PKG.glob("*.py") if p.name != "__init__.py")
    assert [name for name in top if name not in rows] == [], "packages without a row in ARCHITECTURE.md"
    picture = DOC.split("## Data flow", 1)[1].split("```", 2)[1]
    assert [p for p in _packages() if f"{p}/" not in picture] == [], "packages missing from the data-flow picture"


def test_the_chain_runs_one_way() -> None:
    """The picture's main chain (``  -> pkg/`` lines): no package imports one drawn below it."""
    picture = DOC.split("## Data flow", 1)[1].split("```", 2)[1]
    chain = re.findall(r"^\s+-> (\w+/)", picture, re.M)
    assert len(chain) >= 8, chain
    real = real_arrows()
    upstream = [
        f"{own} imports {later}"
        for i, own in enumerate(chain)
        for later in chain[i + 1 :]
        if later in real.get(own, (set(), set()))[0]
    ]
    assert not upstream, "the data-flow picture draws these the wrong way round:\n" + "\n".join(upstream)


def test_every_package_is_in_the_readme_box() -> None:
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    box = readme.split("## What is in the box", 1)[1].split("\n## ", 1)[0]
    assert [p for p in _packages() if f"`pmk_nb.{p}`" not in box] == [], "README's 'What is in the box' misses these"


def test_the_map_reader_sees_both_kinds_of_import() -> None:
    """The reader itself: a lazy import counts as run time, one under ``if TYPE_CHECKING:`` as types only."""
    source = "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pmk_nb.grid import G\n"
    source += "def f():\n    from pmk_nb.errors import E\n    from . import angles\n"
    got = _imports_of(source, "pmk_nb.wire.x", is_package=False)
    assert sorted(got) == [("pmk_nb.errors", False), ("pmk_nb.grid", True), ("pmk_nb.wire", False)]


def test_every_public_error_derives_from_pmk_error() -> None:
    """ARCHITECTURE.md: every error PMK Notebook raises derives from ``PmkError`` (its other bases kept: an
    OSError stays one). Read from the class statements: a class with a built-in exception among its
    ancestors needs ``PmkError`` among them too; a private ``_Name`` is control flow that never escapes."""
    import builtins

    builtin = {n for n, v in vars(builtins).items() if isinstance(v, type) and issubclass(v, BaseException)}
    bases: dict[str, set[str]] = {}
    for path in PKG.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                names = {b.id if isinstance(b, ast.Name) else getattr(b, "attr", "") for b in node.bases}
                bases.setdefault(node.name, set()).update(names)

    def ancestors(name: str, seen: frozenset[str] = frozenset()) -> set[str]:
        found: set[str] = set()
        for base in bases.get(name, set()) - seen:
            found |= {base} | ancestors(base, seen | {name})
        return found

    stray = [
        name
        for name in sorted(bases)
        if not name.startswith("_")
        and name != "PmkError"
        and ancestors(name) & builtin
        and "PmkError" not in ancestors(name)
    ]
    assert not stray, f"errors that do not derive from pmk_nb.errors.PmkError: {stray}"


def test_every_test_the_map_names_exists() -> None:
    """A test named in ARCHITECTURE.md is where it says (``<library>`` stands for any name)."""
    named = set(re.findall(r"`(tests/[\w/<>.]+\.py)`", DOC))
    assert len(named) >= 5, named
    missing = [n for n in sorted(named) if not list(REPO.glob(re.sub(r"<\w+>", "*", n)))]
    assert not missing, f"ARCHITECTURE.md names tests that are not there: {missing}"
