"""No access to another module's or a library's private members outside the seams (issue 25).

A ``._name`` attribute (single underscore) may be used on ``self`` / ``cls`` or when the module
itself defines ``_name`` (its own class's field on another instance, say); ``super()._name``,
``getattr(x, "_name")`` and ``from m import _name`` count too. Everything else goes through one seam
module per library (``pmk_nb/seams/<library>_seam.py``), whose library is pinned exactly in
``pyproject.toml`` and checked by ``tests/test_<library>_seam.py``.
"""

from __future__ import annotations

import ast
import re
import tomllib
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PKG = ROOT / "pmk_nb"
# (module, name): why it is not a seam's business
ALLOWED = {
    ("pmk_nb/indoorgml/drafts.py", "_Element"): "lxml's element type, documented under that name (annotations)",
    ("pmk_nb/indoorgml/gml.py", "_Element"): "lxml's element type, documented under that name (annotations)",
    ("pmk_nb/indoorgml/scan.py", "_Element"): "lxml's element type, documented under that name (annotations)",
    ("pmk_nb/indoorgml/sniff.py", "_Element"): "lxml's element type, documented under that name (annotations)",
    ("pmk_nb/indoorgml/xmlsafe.py", "_Element"): "lxml's element type, documented under that name (annotations)",
    ("pmk_nb/cli/options.py", "_SubParsersAction"): "argparse's add_subparsers() type, named once as Subparsers",
    ("pmk_nb/library/netguard.py", "_GLOBAL_DEFAULT_TIMEOUT"): "stdlib: socket.create_connection's own default",
    ("pmk_nb/library/netguard.py", "_context"): "stdlib: urllib's HTTPSHandler fields, passed on as it does",
    ("pmk_nb/library/netguard.py", "_check_hostname"): "stdlib: urllib's HTTPSHandler fields, passed on as it does",
    ("pmk_nb/robot/wheels.py", "_base_executable"): "stdlib: the interpreter a venv was made from (venv's own way)",
}


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _defined(tree: ast.Module) -> set[str]:
    """Names the module defines: functions, classes, assigned names, ``self.x`` / ``cls.x`` fields."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store | ast.Del):
            if isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"):
                names.add(node.attr)
        elif isinstance(node, ast.arg):
            names.add(node.arg)
        elif isinstance(node, ast.alias):
            names.add(node.asname or node.name)
    return names


def private_accesses(source: str) -> list[tuple[int, str, str]]:
    """(line, name, code) of each private member of another module or library that ``source`` uses."""
    tree = ast.parse(source)
    own = _defined(tree)
    hits: list[tuple[int, str, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _private(node.attr):
            value = node.value
            is_super = isinstance(value, ast.Call) and isinstance(value.func, ast.Name) and value.func.id == "super"
            if is_super or node.attr not in own:
                hits.append((node.lineno, node.attr, ast.unparse(node)))
        elif isinstance(node, ast.ImportFrom):
            hits += [
                (node.lineno, a.name, f"from {node.module} import {a.name}") for a in node.names if _private(a.name)
            ]
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and len(node.args) > 1:
            name = node.args[1].value if isinstance(node.args[1], ast.Constant) else None
            reflective = node.func.id in ("getattr", "setattr", "hasattr", "delattr")
            if reflective and isinstance(name, str) and _private(name) and name not in own:
                hits.append((node.lineno, name, ast.unparse(node)))
    return sorted(hits)


def _is_seam(rel: str) -> bool:
    return rel.startswith("pmk_nb/seams/")


def test_no_private_access_outside_the_seams() -> None:
    found = []
    for path in sorted(PKG.rglob("*.py")):
        rel = str(path.relative_to(ROOT))
        if _is_seam(rel):
            continue
        for line, name, code in private_accesses(path.read_text(encoding="utf-8")):
            if (rel, name) not in ALLOWED:
                found.append(f"{rel}:{line}: {code}")
    assert not found, "private members used outside pmk_nb/seams (add a seam, or a public member):\n" + "\n".join(found)


def test_the_allow_list_is_still_needed() -> None:
    used = set()
    for path in sorted(PKG.rglob("*.py")):
        rel = str(path.relative_to(ROOT))
        used |= {(rel, name) for _line, name, _code in private_accesses(path.read_text(encoding="utf-8"))}
    assert set(ALLOWED) <= used, f"stale allow-list entries: {sorted(set(ALLOWED) - used)}"


def test_each_seam_library_is_pinned_exactly_and_installed_at_that_version() -> None:
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    pins = {re.split(r"[=<>~! \[]", d, maxsplit=1)[0].lower().replace("_", "-"): d for d in deps}
    seams = sorted(p.stem.removesuffix("_seam") for p in (PKG / "seams").glob("*_seam.py"))
    assert seams, "no seam modules found"
    for library in seams:
        key = library.lower().replace("_", "-")
        pin = pins.get(key, "")
        assert re.fullmatch(rf"{re.escape(key)}==\d+(\.\d+)+", pin.split("#")[0].strip().lower().replace("_", "-")), (
            f"{library} (touched in a seam) must be pinned exactly in pyproject.toml, found {pin!r}"
        )
        assert pin.split("==")[1].strip() == metadata.version(library), f"installed {library} is not the pinned one"
        found = list((ROOT / "tests").rglob(f"test_{library}_seam.py"))
        assert found, f"{library} needs tests/seams/test_{library}_seam.py"


def test_the_reader_finds_each_kind_of_access() -> None:
    source = """
import x
from m import _hidden
class A(x.Base):
    def f(self, other):
        self._own = 1
        other._own = 2             # the module's own field: fine
        other._theirs()            # flagged
        super()._own               # a base class's private: flagged
        getattr(other, "_deep")    # flagged
        return self._inherited     # defined nowhere here: flagged
"""
    names = [name for _line, name, _code in private_accesses(source)]
    assert names == ["_hidden", "_theirs", "_own", "_deep", "_inherited"]
