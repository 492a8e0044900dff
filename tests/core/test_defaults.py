"""Every converter default is declared once, in pmk_nb/defaults.py, and ConvertOptions passes whole
(issue 25): a literal 0.5 for the wall gap in one signature and 0.10 in another drift apart unseen."""

from __future__ import annotations

import ast
import inspect
from dataclasses import fields
from pathlib import Path

import pytest

from pmk_nb import defaults
from pmk_nb.library import ConvertOptions, convert_plan
from pmk_nb.raster import RasterOptions, rasterise_storey

PKG = Path(__file__).resolve().parents[2] / "pmk_nb"
SAMPLE = PKG.parent / "sample_maps" / "clinic_floor.gml"
# parameter / field names that carry one of the defaults
NAMES = {"resolution", "wall_thickness", "max_wall_gap", "max_gap", "door_width", "chair_width", "max_cells"}
# the names pmk_nb/defaults.py declares: declared again anywhere else, they drift apart
DECLARED = {name for name in vars(defaults) if name.isupper()}
# files allowed to keep a literal default: none left
PENDING: set[str] = set()


def _literal_defaults(path: Path) -> list[str]:
    """``name: float = 0.5`` fields and ``name=0.5`` parameter defaults for the names above."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        pairs: list[tuple[str, ast.expr | None]] = []
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            args = node.args
            positional = args.posonlyargs + args.args
            with_default = positional[len(positional) - len(args.defaults) :]
            pairs += list(zip([a.arg for a in with_default], args.defaults, strict=True))
            pairs += [(a.arg, d) for a, d in zip(args.kwonlyargs, args.kw_defaults, strict=True)]
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            pairs.append((node.target.id, node.value))
        elif isinstance(node, ast.Assign):  # `self.chair_width = 0.70`, `DEFAULT_RESOLUTION = 0.05`
            for target in node.targets:
                if isinstance(target, ast.Attribute):
                    pairs.append((target.attr, node.value))
                elif isinstance(target, ast.Name) and target.id in DECLARED:
                    pairs.append((target.id, node.value))
        for name, value in pairs:
            if (
                (name in NAMES or name in DECLARED)
                and isinstance(value, ast.Constant)
                and type(value.value) in (int, float)
            ):
                found.append(f"{path.relative_to(PKG.parent)}:{value.lineno} {name} = {value.value!r}")
    return found


@pytest.mark.slow
def test_defaults_are_not_repeated_as_literals() -> None:
    found = [
        hit
        for path in sorted(PKG.rglob("*.py"))
        if path.name != "defaults.py" and str(path.relative_to(PKG.parent)) not in PENDING
        for hit in _literal_defaults(path)
    ]
    assert not found, "defaults written as literals (use pmk_nb.defaults):\n" + "\n".join(found)


def test_convert_options_carry_the_resolution(tmp_path: Path) -> None:
    assert ConvertOptions().resolution == defaults.DEFAULT_RESOLUTION
    assert ConvertOptions().chair_width == defaults.DEFAULT_CHAIR_WIDTH
    options = ConvertOptions(resolution=0.2, preview=False, check=False)
    result = convert_plan(SAMPLE, tmp_path / "a", "clinic", options=options)  # the options alone
    assert {m.resolution for m in result.maps} == {0.2}
    override = convert_plan(SAMPLE, tmp_path / "b", "clinic", 0.25, options)  # a positional one still wins
    assert {m.resolution for m in override.maps} == {0.25}


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan")])
def test_a_bad_resolution_in_the_options_is_refused(tmp_path: Path, bad: float) -> None:
    from pmk_nb.errors import OccupancyError

    with pytest.raises(OccupancyError):
        convert_plan(SAMPLE, tmp_path, "clinic", options=ConvertOptions(resolution=bad))
    assert not (tmp_path / "clinic.yaml").exists()


def test_the_rasteriser_takes_its_options_whole() -> None:
    """rasterise_storey took 12 keyword arguments, each caller repeating the defaults: now one
    RasterOptions, which ConvertOptions hands on field for field."""
    assert list(inspect.signature(rasterise_storey).parameters) == [
        "building",
        "storey",
        "resolution",
        "options",
        "openings",
        "progress",
    ]
    assert ConvertOptions().raster == RasterOptions()
    changed = {
        "wall_thickness": 0.2,
        "max_wall_gap": 0.3,
        "door_width": 1.1,
        "outside": "occupied",
        "max_cells": 123,
        "allow_large": True,
    }
    assert set(changed) == {f.name for f in fields(RasterOptions)} & {f.name for f in fields(ConvertOptions)}
    for name, value in changed.items():
        assert getattr(ConvertOptions(**{name: value}).raster, name) == value, name
