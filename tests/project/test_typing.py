"""The pure core type-checks under ``mypy --strict`` (issue 25): a change that breaks a signature, returns
Optional where a value is promised or passes the wrong array shape fails here, not on a chair.

Runs mypy in-process through its API on the strict packages, with pyproject.toml's ``[tool.mypy]``
(checked here to hold every ``--strict`` flag for them) and its default cache, ``.mypy_cache``, which
``make lint`` fills just before: 3-6 s warm; cold about 20 s of CPU (90 s of wall time on a loaded box).
"""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
# the pure core: no widgets, no network, no ROS (ARCHITECTURE.md); strict in pyproject.toml's [tool.mypy] too
STRICT_PACKAGES = (
    "indoorgml",
    "openings",
    "raster",
    "rosmap",
    "access",
    "witness",
    "viewport",
    "drive",
    "guide",
    "speech",
    # issue 42: the simulator, the maps library and catalogue, the chair-side nodes, the serving stack and CLI
    "sim",
    "library",
    "catalogue",
    "robot",
    "classroom",
    "recordings",
    "wire",
    "serve",
    "cli",
    "seams",
    # and the chair with its rosbridge link (issue 42): `Any` only at the libraries' seams
    "chair",
)
# the top-level modules, strict one by one
STRICT_MODULES = (
    "errors",
    "grid",
    "progress",
    "fileio",
    "geometry",
    "clock",
    "defaults",
    "goalbeat",
    "lazyface",
    "pixels",
    "rosauth",
    "tlscert",
)
# the dashboard: every function annotated, the rest of --strict not yet
UI_FLAGS = ("disallow_untyped_defs", "disallow_incomplete_defs")
# what --strict turns on per module (mypy 2.4); warn_unused_configs and warn_redundant_casts are global
STRICT_FLAGS = (
    "disallow_any_generics",
    "disallow_subclassing_any",
    "disallow_untyped_calls",
    "disallow_untyped_defs",
    "disallow_incomplete_defs",
    "check_untyped_defs",
    "disallow_untyped_decorators",
    "warn_return_any",
    "no_implicit_reexport",
    "strict_equality",
    "extra_checks",
    "warn_unused_ignores",
)


def test_strict_packages_match_the_config() -> None:
    """pyproject.toml turns every --strict flag on for these packages (and the global ones)."""
    import tomllib

    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["mypy"]
    assert config.get("warn_unused_configs") and config.get("warn_redundant_casts"), config
    strict = next(o for o in config["overrides"] if o.get("disallow_untyped_defs"))
    named = {m.removeprefix("pmk_nb.").removesuffix(".*") for m in strict["module"]}
    assert set(STRICT_PACKAGES) | set(STRICT_MODULES) <= named, f"strict in pyproject.toml: {sorted(named)}"
    assert "pmk_nb" in strict["module"], "the package's own __init__ is strict too"
    off = [flag for flag in STRICT_FLAGS if strict.get(flag) is not True]
    assert not off, f"--strict flags missing from the strict override: {off}"
    loosened = [o["module"] for o in config["overrides"] if o.get("ignore_errors")]
    assert not any(m.startswith(tuple(f"pmk_nb.{p}" for p in STRICT_PACKAGES)) for ms in loosened for m in ms)
    for package in STRICT_PACKAGES:
        assert (ROOT / "pmk_nb" / package / "__init__.py").is_file(), package
    for module in STRICT_MODULES:
        assert (ROOT / "pmk_nb" / f"{module}.py").is_file(), module


def test_every_top_level_module_is_strict() -> None:
    """A module added beside pmk_nb/__init__.py joins the strict list (it cannot slip in untyped)."""
    here = {p.stem for p in (ROOT / "pmk_nb").glob("*.py") if p.stem != "__init__"}
    assert here == set(STRICT_MODULES), f"not strict: {sorted(here - set(STRICT_MODULES))}"


def test_ui_functions_are_annotated() -> None:
    """pyproject.toml has pmk_nb.ui.* refuse unannotated and half-annotated functions."""
    import tomllib

    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["mypy"]
    ui = [o for o in config["overrides"] if "pmk_nb.ui.*" in o["module"]]
    assert len(ui) == 1 and all(ui[0].get(flag) is True for flag in UI_FLAGS), ui


@pytest.mark.slow
def test_pure_core_is_strictly_typed(monkeypatch: pytest.MonkeyPatch) -> None:
    from mypy import api

    monkeypatch.chdir(ROOT)  # mypy finds pmk_nb, pyproject.toml and .mypy_cache from the checkout's root
    args = ["--config-file", str(ROOT / "pyproject.toml")]
    for package in STRICT_PACKAGES:
        args += ["-p", f"pmk_nb.{package}"]
    for module in STRICT_MODULES:
        args += ["-m", f"pmk_nb.{module}"]
    out, err, status = api.run(args)
    errors = [line for line in out.splitlines() if ": error: " in line]
    assert status == 0 and not errors, f"mypy --strict on the pure core ({len(errors)} errors):\n{out}{err}"
    assert "Success: no issues found" in out, out
