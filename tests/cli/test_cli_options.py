"""One CLI (issue 29, item 8): one option name per concept, one default, --json where scripts read.

The walk covers every `pmk` command's parser, recursively: a new command or option that spells a
concept a second way, or a result-printing command without ``--json``, fails here.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import pytest

from pmk_nb.cli import COMMANDS, build_parser, main
from pmk_nb.cli.options import ALIASES, CANONICAL, DEFAULT_RESOLUTION, SHORT
from pmk_nb.errors import RosNotInstalled
from tests.indoorgml_samples import two_rooms

#: every leaf command, classified: it prints a result a script reads (must have --json), or it does not
PRINTS_RESULTS = {
    "info",
    "convert",
    "check",
    "send",
    "maps list",
    "maps catalogue",
    "maps import",  # issue 40: every maps action answers --json
    "maps download",
    "maps convert",
    "maps delete",
    "maps publish",
    "maps get",
    "chair list",
    "chair show",
    "chair test",
}
NO_RESULT = {  # servers, long-running nodes and actions whose outcome is the exit code and a one-line note
    "sim",
    "dashboard",
    "demo",
    "hub",
    "bench",
    "robot map-server",
    "robot sim-node",
    "robot goal-watchdog",
    "chair add",
    "chair delete",
}


def _leaves(parser: argparse.ArgumentParser, path: str) -> list[tuple[str, argparse.ArgumentParser]]:
    """(command path, parser) of ``parser`` and every sub-command under it."""
    found = [(path, parser)]
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                found += _leaves(sub, f"{path} {name}")
    return found


def _all_parsers() -> list[tuple[str, argparse.ArgumentParser]]:
    parsers = []
    for command in sorted(COMMANDS):
        top = build_parser(command)
        sub = next(a for a in top._actions if isinstance(a, argparse._SubParsersAction))
        parsers += _leaves(sub.choices[command], command)
    return parsers


def _is_leaf(parser: argparse.ArgumentParser) -> bool:
    return not any(isinstance(a, argparse._SubParsersAction) for a in parser._actions)


def option_problems(path: str, parser: argparse.ArgumentParser) -> list[str]:
    """Everything in ``parser`` that breaks the one-name-per-concept tables."""
    problems = []
    visible: dict[str, set[str]] = {}
    for action in parser._actions:
        longs = [o for o in action.option_strings if o.startswith("--")]
        if action.help == argparse.SUPPRESS:
            for option in longs:
                if option not in ALIASES:
                    problems.append(f"{path}: hidden option {option} is not a declared alias")
            continue
        for option in longs:
            if option in ALIASES:
                problems.append(f"{path}: deprecated {option} shown (use {ALIASES[option]})")
        if action.dest in CANONICAL and action.option_strings:
            allowed = {CANONICAL[action.dest], SHORT.get(action.dest)}
            if not set(action.option_strings) <= allowed:
                problems.append(f"{path}: {action.dest} spelled {action.option_strings}, not {CANONICAL[action.dest]}")
        for dest, option in CANONICAL.items():
            if option in action.option_strings and action.dest != dest:
                problems.append(f"{path}: {option} stores into {action.dest!r}, not {dest!r}")
        if action.dest == "resolution" and action.default != DEFAULT_RESOLUTION:
            problems.append(f"{path}: --resolution defaults to {action.default!r}, not {DEFAULT_RESOLUTION}")
        visible.setdefault(action.dest, set()).update(longs)
    for dest, options in visible.items():
        positive = {o for o in options if not (o.startswith("--no-") and "--" + o[5:] in options)}
        if len(positive) > 1:
            problems.append(f"{path}: one concept ({dest}) has several visible names {sorted(positive)}")
    return problems


def test_every_command_spells_each_concept_one_way_and_prints_json_where_scripts_read() -> None:
    problems: list[str] = []
    leaves = set()
    for path, parser in _all_parsers():
        problems += option_problems(path, parser)
        if not _is_leaf(parser):
            continue
        leaves.add(path)
        has_json = any("--json" in a.option_strings for a in parser._actions)
        if path in PRINTS_RESULTS and not has_json:
            problems.append(f"{path}: prints results but has no --json")
    assert not problems, "\n".join(problems)
    assert leaves == PRINTS_RESULTS | NO_RESULT, "classify every command: " + str(leaves ^ (PRINTS_RESULTS | NO_RESULT))


def test_the_walk_catches_a_second_spelling_a_shown_alias_and_a_wrong_default() -> None:
    bad = argparse.ArgumentParser()
    bad.add_argument("--maps", dest="maps_dir")
    bad.add_argument("--resolution", type=float, default=0.1)
    bad.add_argument("--out-dir", "--output", dest="out")
    found = option_problems("x", bad)
    assert any("deprecated --maps shown" in p for p in found)
    assert any("defaults to 0.1" in p for p in found)
    assert any("several visible names" in p for p in found)


@pytest.mark.parametrize(
    ("argv", "dest", "value"),
    [
        (["maps", "--dir", "D", "list"], "maps_dir", Path("D")),
        (["maps", "list", "--dir", "D"], "maps_dir", Path("D")),
        (["maps", "list", "--maps-dir", "D"], "maps_dir", Path("D")),
        (["robot", "map-server", "--maps", "D"], "maps_dir", Path("D")),
        (["robot", "sim-node", "--maps-dir", "D"], "maps_dir", Path("D")),
        (["demo", "--dir", "D"], "dir", Path("D")),
        (["convert", "f.gml"], "resolution", DEFAULT_RESOLUTION),
        (["maps", "convert", "b"], "resolution", DEFAULT_RESOLUTION),
        (["check", "f.gml"], "resolution", DEFAULT_RESOLUTION),
    ],
)
def test_old_spellings_still_parse(argv: list[str], dest: str, value: object) -> None:
    assert getattr(build_parser(argv[0]).parse_args(argv), dest) == value


def test_chair_add_footprint_radius_is_half_the_chair_width(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from pmk_nb.chair import ProfileStore

    monkeypatch.setenv("PMK_CONFIG_DIR", str(tmp_path))
    assert main(["chair", "add", "a", "--host", "127.0.0.1", "--chair-width", "0.8"]) == 0
    assert main(["chair", "add", "b", "--host", "127.0.0.1", "--footprint-radius", "0.45"]) == 0
    store = ProfileStore(secrets=False)
    assert (store.get("a").chair_width, store.get("a").footprint_radius) == (0.8, 0.4)
    assert (store.get("b").chair_width, store.get("b").footprint_radius) == (0.9, 0.45)


def test_convert_defaults_to_005_and_prints_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "house.gml"
    plan.write_bytes(two_rooms(("F1",), width=9.0))
    assert main(["convert", str(plan), "--out", str(tmp_path / "out"), "--json", "--no-progress"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is True and doc["unit"] == "m" and "transitions" in doc["graph"]
    (storey,) = doc["storeys"]
    assert storey["resolution"] == DEFAULT_RESOLUTION and Path(storey["yaml"]).is_file()
    assert storey["width"] > 0 and Path(storey["rooms"]).is_file() and "access" in storey


def test_maps_list_json_and_errors_as_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    plan = tmp_path / "house.gml"
    plan.write_bytes(two_rooms(("F1",), width=9.0))
    maps = tmp_path / "maps"
    assert main(["maps", "--maps-dir", str(maps), "import", str(plan)]) == 0
    assert main(["maps", "--maps-dir", str(maps), "convert", "house"]) == 0
    capsys.readouterr()
    assert main(["maps", "list", "--maps-dir", str(maps), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["maps_dir"] == str(maps)
    (entry,) = doc["maps"]
    assert entry["name"] == "house" and entry["status"] == "converted"
    assert entry["generated"][0]["resolution"] == DEFAULT_RESOLUTION and entry["generated"][0]["broken"] is None

    assert main(["convert", str(tmp_path / "missing.gml"), "--json"]) == 2
    err = json.loads(capsys.readouterr().out)
    assert err["ok"] is False and err["command"] == "convert" and err["error"] == "IndoorGMLError"
    assert err["fields"]["path"].endswith("missing.gml")


def test_robot_without_ros_says_what_to_install(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "rclpy", None)  # import rclpy raises ModuleNotFoundError(name="rclpy")
    assert main(["robot", "map-server", "--maps-dir", str(tmp_path)]) == 2
    said = capsys.readouterr().err
    assert "'rclpy' is not installed" in said and "make ros2" in said and "Traceback" not in said
    from pmk_nb.cli.robot import run_ros2

    with pytest.raises(RosNotInstalled) as caught:
        run_ros2("sim-node", lambda: __import__("rclpy"))
    assert (caught.value.module, caught.value.command) == ("rclpy", "sim-node")


@pytest.mark.parametrize(
    ("argv", "command"),
    [
        (["check", "plan.gml", "--bogus", "--json"], "check"),
        (["info", "--json"], "info"),  # its FILE missing
        (["maps", "convert", "--json"], "maps"),
        (["maps", "list", "--json", "--storey", "F1"], "maps"),
        (["--json"], "pmk"),
    ],
)
def test_a_refused_command_line_is_json_with_json(
    argv: list[str], command: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """Issue 40, item 2: argparse printed its usage on stderr and nothing on stdout, even with --json."""
    code = main(argv)
    out, err = capsys.readouterr()
    doc = json.loads(out)
    assert code == 2 and doc["ok"] is False and doc["error"] == "UsageError" and doc["command"] == command
    assert doc["fields"]["usage"].startswith("usage: pmk") and doc["message"]
    assert "usage: pmk" in err  # a person still reads argparse's words


def test_a_refused_command_line_without_json_exits_as_argparse_does(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exited:
        main(["check", "plan.gml", "--bogus"])
    out, err = capsys.readouterr()
    assert exited.value.code == 2 and out == "" and "unrecognized arguments: --bogus" in err
