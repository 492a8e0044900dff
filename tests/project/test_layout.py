"""The package layout keeps its promises: one package per concept (modules sized by concept, not
by a line cap), short functions, no control flow on error text, the core free of widget libraries,
one atomic-write helper."""

from __future__ import annotations

import ast
import functools
import re
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[2] / "pmk_nb"
MAX_FUNCTION_LINES = 80
# Modules allowed at the top of pmk_nb: value types and helpers shared by several packages.
TOP_LEVEL = {"__init__.py", "errors.py", "fileio.py", "grid.py", "progress.py"}
TOP_LEVEL |= {"goalbeat.py"}  # the goal heartbeat's wire format: the link (chair/) and the watchdog (robot/)
TOP_LEVEL |= {"rosauth.py"}  # rosbridge's auth op (rosauth's MAC): the link speaks it, the simulator checks it
TOP_LEVEL |= {"tlscert.py"}  # certificate fingerprints and a self-signed one (sim, link, dashboard)
TOP_LEVEL |= {"defaults.py"}  # the converter's and access check's defaults, declared once (issue 25)
TOP_LEVEL |= {"geometry.py"}  # shapely helpers shared by the openings plan and the rasteriser (issue 25)
TOP_LEVEL |= {"lazyface.py"}  # the one lazy package face (issue 25)
TOP_LEVEL |= {"pixels.py"}  # erode by a disc, label regions: the access check, the guide and the witness (issue 37)
TOP_LEVEL |= {"clock.py"}  # time as an input: the real and the virtual clock (issue 39)
PACKAGES = {"access", "chair", "cli", "indoorgml", "library", "raster", "robot", "rosmap", "sim", "ui", "viewport"}
PACKAGES |= {"guide", "speech"}  # rooms and routes by name; spoken feedback
PACKAGES |= {"drive"}  # the joystick's deadman, pure
PACKAGES |= {"catalogue"}  # STAC map catalogues: publish, browse, install (issue 27)
PACKAGES |= {"classroom"}  # a simulated chair per page, the class's chair cap (issue 26)
PACKAGES |= {"seams"}  # the only modules touching a library's private members, one per library (issue 25)
PACKAGES |= {"openings"}  # where the navigation graph opens walls: raster draws it, access and guide read it (issue 25)
PACKAGES |= {"witness"}  # the written map judged against its plan, sharing no decision with the converter (issue 37)
PACKAGES |= {"wire"}  # what crosses the wire to the chair, written once for chair, sim, robot and viewport (issue 42)
PACKAGES |= {"recordings"}  # recordings (MCAP) opened as tables, for researchers (issue 40)
PACKAGES |= {"serve"}  # the serving stack: Voilà, its guards and kernels, TLS, the class hub (issue 42)
WIDGET_LIBRARIES = ("ipywidgets", "ipycanvas", "IPython.display", "traitlets")


def _modules() -> list[Path]:
    return sorted(PKG.rglob("*.py"))


def _rel(path: Path) -> str:
    return str(path.relative_to(PKG.parent))


def test_top_level_holds_only_shared_modules_and_concept_packages() -> None:
    files = {p.name for p in PKG.glob("*.py")}
    dirs = {p.name for p in PKG.iterdir() if p.is_dir() and p.name != "__pycache__"}
    assert files <= TOP_LEVEL, f"modules that belong in a concept package: {sorted(files - TOP_LEVEL)}"
    assert dirs <= PACKAGES, f"unexpected packages: {sorted(dirs - PACKAGES)}"
    for name in PACKAGES:
        init = PKG / name / "__init__.py"
        has_doc = init.is_file() and ast.get_docstring(ast.parse(init.read_text()))
        assert has_doc, f"{name}/__init__.py needs a docstring"


@pytest.mark.parametrize("path", _modules(), ids=_rel)
def test_functions_are_short(path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    long = [
        f"{node.name} ({node.end_lineno - node.lineno + 1} lines, line {node.lineno})"
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        and node.end_lineno is not None
        and node.end_lineno - node.lineno + 1 > MAX_FUNCTION_LINES
    ]
    assert not long, f"{_rel(path)}: functions over {MAX_FUNCTION_LINES} lines: {long}"


def _matches_error_text(node: ast.AST) -> bool:
    """``str(err)`` / ``err.args`` / ``message`` used in a comparison, ``in`` or startswith/endswith."""

    def is_error_text(expr: ast.AST) -> bool:
        if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name) and expr.func.id == "str":
            arg = expr.args[0] if expr.args else None
            return isinstance(arg, ast.Name) and arg.id in {"err", "exc", "e", "error"}
        if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Attribute) and expr.func.attr == "lower":
            return is_error_text(expr.func.value)
        return isinstance(expr, ast.Name) and expr.id in {"message", "msg_text", "reason"}

    if isinstance(node, ast.Compare):
        return is_error_text(node.left) or any(is_error_text(c) for c in node.comparators)
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
        return node.func.attr in {"startswith", "endswith"} and is_error_text(node.func.value)
    return False


@pytest.mark.parametrize("path", _modules(), ids=_rel)
def test_no_control_flow_on_error_text(path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    hits = [node.lineno for node in ast.walk(tree) if _matches_error_text(node)]
    assert not hits, f"{_rel(path)} decides on the text of an error at lines {hits}: use the error's type or fields"


@pytest.mark.slow
def test_core_imports_no_widget_library() -> None:
    offenders = []
    for path in _modules():
        if path.is_relative_to(PKG / "ui"):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module]
            offenders += [f"{_rel(path)}: {n}" for n in names if n.startswith(WIDGET_LIBRARIES)]
    assert not offenders, offenders


def test_one_atomic_write_helper() -> None:
    """Temp-file-and-rename is written once, in pmk_nb/fileio.py."""
    writers = [
        _rel(p)
        for p in _modules()
        if p.name != "fileio.py" and re.search(r"\bmkstemp\(|\bos\.replace\(", p.read_text(encoding="utf-8"))
    ]
    assert not writers, f"hand-written atomic writes (use pmk_nb.fileio): {writers}"


# Which packages each package may import: the data flow of ARCHITECTURE.md, one direction only.
SHARED = {"errors", "progress", "fileio", "grid"}
SHARED |= {"rosauth"}  # a leaf: the auth op's MAC for the link and the simulator
SHARED |= {"tlscert"}  # a leaf like fileio: certificates for the simulator, the link and the dashboard
SHARED |= {"defaults"}  # plain numbers: the one declaration of each converter default
SHARED |= {"geometry"}  # shapely helpers (polygon parts, boxes): a leaf over shapely and numpy
SHARED |= {"lazyface"}  # the one lazy package face: a name loads only its own module
SHARED |= {"pixels"}  # numpy pixel maths (erosion, labelling), property-tested against scipy
SHARED |= {"clock"}  # a stdlib-only leaf: everything that decides by time takes a Clock
ALLOWED_IMPORTS: dict[str, set[str]] = {
    "viewport": {"grid", "wire"},  # the shared grid type and its greys; angles and the ray caster
    "grid": set(),
    "indoorgml": SHARED,
    "openings": SHARED | {"indoorgml"},  # the plan of openings: from the building, before any grid
    "raster": SHARED | {"indoorgml", "openings"},
    "access": SHARED | {"indoorgml", "openings", "raster", "rosmap"},
    "rosmap": SHARED,
    "library": SHARED | {"indoorgml", "openings", "raster", "rosmap", "access"},
    "chair": SHARED | {"rosmap", "viewport"},  # the link fills viewport.TfTree; pose maths live there
    "sim": SHARED | {"rosmap", "indoorgml", "raster"},
    "robot": SHARED | {"rosmap", "sim"},  # chair-side ROS nodes: the map server, the simulator as a node
    "ui": SHARED | {"viewport", "indoorgml", "openings", "raster", "rosmap", "library", "chair", "access"},
    "guide": SHARED | {"indoorgml", "openings", "raster", "rosmap", "access"},  # rooms file + accessibility rules
    "speech": SHARED,
    "cli": SHARED | {"viewport", "indoorgml", "raster", "rosmap", "library", "chair", "sim", "ui", "robot", "access"},
}
ALLOWED_IMPORTS["ui"] |= {"guide", "speech"}
ALLOWED_IMPORTS["cli"] |= {"openings"}
ALLOWED_IMPORTS["cli"] |= {"guide", "speech"}
ALLOWED_IMPORTS["drive"] = set(SHARED)
ALLOWED_IMPORTS["ui"] |= {"drive"}
ALLOWED_IMPORTS["cli"] |= {"drive"}
# The goal heartbeat's wire format (issue 24): the link speaks it, the chair's goal watchdog hears it.
ALLOWED_IMPORTS["goalbeat"] = set()
ALLOWED_IMPORTS["chair"] |= {"goalbeat"}
ALLOWED_IMPORTS["robot"] |= {"goalbeat"}
ALLOWED_IMPORTS["cli"] |= {"goalbeat"}
ALLOWED_IMPORTS["catalogue"] = SHARED | {"library", "access", "indoorgml", "rosmap"}  # on top of the maps folder
ALLOWED_IMPORTS["ui"] |= {"catalogue"}
# The witness (issue 37) reads the plan and the written files only: never openings/, raster/ or access/,
# so none of the converter's decisions can be repeated in the verdict on its output.
ALLOWED_IMPORTS["witness"] = SHARED | {"indoorgml", "rosmap"}
for _user in ("library", "cli", "ui", "catalogue"):
    ALLOWED_IMPORTS[_user] |= {"witness"}
ALLOWED_IMPORTS["cli"] |= {"catalogue"}
# A chair per classroom page (issue 26): a simulator and a profile for it, for the ui and the cli.
ALLOWED_IMPORTS["classroom"] = SHARED | {"sim", "chair"}
# Recordings read back as tables (issue 40): files only, no link; the screens and notebooks use it.
ALLOWED_IMPORTS["recordings"] = set(SHARED)
ALLOWED_IMPORTS["ui"] |= {"recordings"}
ALLOWED_IMPORTS["cli"] |= {"recordings"}
ALLOWED_IMPORTS["ui"] |= {"classroom"}
ALLOWED_IMPORTS["cli"] |= {"classroom"}
# Library seams (issue 25): leaves over their library, used by the link, the screens and the commands.
ALLOWED_IMPORTS["clock"] = set()  # a leaf: the standard library only
ALLOWED_IMPORTS["seams"] = {"lazyface"}  # its face is lazy: one seam never loads another library
for _user in ("chair", "ui", "cli"):
    ALLOWED_IMPORTS[_user] |= {"seams"}
# The wire (issue 42): a leaf under both ends of the wire, so neither end imports the other for it.
ALLOWED_IMPORTS["wire"] = {"errors", "grid", "lazyface"}
for _user in ("chair", "sim", "robot", "viewport", "ui", "cli"):
    ALLOWED_IMPORTS[_user] |= {"wire"}
# The serving stack (issue 42): what `pmk dashboard`, `pmk demo` and `pmk hub` run, under cli/ (which only
# parses). It serves ui/ (the page-gone message), guards with seams/, hands the hub's students a classroom/
# chair and chair/'s config folder and keys.
ALLOWED_IMPORTS["serve"] = SHARED | {"ui", "seams", "classroom", "chair", "rosauth", "tlscert"}
ALLOWED_IMPORTS["cli"] |= {"serve"}


def _package_of(path: Path) -> str:
    rel = path.relative_to(PKG)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


@pytest.mark.slow
def test_imports_follow_the_data_flow() -> None:
    wrong = []
    for path in _modules():
        own = _package_of(path)
        allowed = ALLOWED_IMPORTS.get(own)
        if allowed is None:
            continue  # errors, progress, fileio, __init__: leaves
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            modules = []
            if isinstance(node, ast.Import):
                modules = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                modules = [node.module]
            for module in modules:
                parts = module.split(".")
                if parts[0] != "pmk_nb" or len(parts) < 2:
                    continue
                target = parts[1]
                if target != own and target not in allowed:
                    wrong.append(f"{_rel(path)}:{node.lineno} imports {module}")
    assert not wrong, "imports against the data flow (see ARCHITECTURE.md):\n" + "\n".join(wrong)


# Cross-package imports go through the package faces (issue 25): `from pmk_nb.raster import Frame`, not
# `from pmk_nb.raster.scanline import Frame`, and each name is in the face's `__all__`, so the face says
# what other packages use. `chair/link` (the rosbridge link) is a face of its own, beside chair's.
SUBFACES = ("chair.link",)
# packages whose imports may still go past the faces: none since ui was split into subpackages
NOT_THROUGH_FACES_YET: set[str] = set()
# (module, name) imported past a face, each with its reason
PAST_THE_FACE = {
    ("pmk_nb.catalogue.publish", "publish"): "a function named as its module: the lazy face's attribute is the module",
    ("pmk_nb.catalogue.install", "install"): "a function named as its module: the lazy face's attribute is the module",
    ("pmk_nb.chair.deploy", "deploy"): "a function named as its module: the lazy face's attribute is the module",
}


def _face_of(module: str) -> str | None:
    """The face (dotted, under pmk_nb) that ``module`` belongs to; None for a top-level module."""
    rel = module.removeprefix("pmk_nb.")
    for sub in SUBFACES:
        if rel == sub or rel.startswith(sub + "."):
            return sub
    top = rel.split(".")[0]
    return top if (PKG / top / "__init__.py").is_file() else None


@functools.cache
def _face_names(face: str) -> frozenset[str]:
    tree = ast.parse((PKG.joinpath(*face.split(".")) / "__init__.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            return frozenset(ast.literal_eval(node.value))
    return frozenset()


def test_cross_package_imports_go_through_the_faces() -> None:
    wrong = []
    for path in _modules():
        own = _package_of(path)
        if own in NOT_THROUGH_FACES_YET:
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                wrong += [
                    f"{_rel(path)}:{node.lineno} import {a.name}" for a in node.names if a.name.startswith("pmk_nb.")
                ]
            if not (isinstance(node, ast.ImportFrom) and node.level == 0 and (node.module or "").startswith("pmk_nb.")):
                continue
            face = _face_of(node.module or "")
            if face is None or face.split(".")[0] in {own} | NOT_THROUGH_FACES_YET:
                continue
            for alias in node.names:
                if node.module != f"pmk_nb.{face}" and (node.module, alias.name) not in PAST_THE_FACE:
                    wrong.append(f"{_rel(path)}:{node.lineno} {node.module}.{alias.name} (use pmk_nb.{face})")
                elif node.module == f"pmk_nb.{face}" and alias.name not in _face_names(face):
                    wrong.append(f"{_rel(path)}:{node.lineno} {alias.name} is not in pmk_nb.{face}'s __all__")
    assert not wrong, "cross-package imports past the package faces (see ARCHITECTURE.md):\n" + "\n".join(wrong)
