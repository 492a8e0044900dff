"""Every `pmk` command, sub-command and option says what it does (issue 10: several had no help)."""

from __future__ import annotations

import argparse

import pytest

from pmk_nb.cli import COMMANDS, build_parser
from pmk_nb.cli.options import ALIASES


def _missing_help(parser: argparse.ArgumentParser, path: str) -> list[str]:
    """Options and positionals of ``parser`` (and its sub-commands, recursively) without a help text."""
    missing = []
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        if isinstance(action, argparse._SubParsersAction):
            helped = {choice.dest for choice in action._choices_actions if choice.help}
            for name, sub in action.choices.items():
                if name not in helped:
                    missing.append(f"{path} {name} (sub-command)")
                missing += _missing_help(sub, f"{path} {name}")
            continue
        if action.help == argparse.SUPPRESS and set(action.option_strings) <= set(ALIASES):
            continue  # a deprecated spelling kept hidden (issue 29): its canonical option has the help
        if not action.help or action.help == argparse.SUPPRESS:
            missing.append(f"{path} {'/'.join(action.option_strings) or action.dest}")
    return missing


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_every_command_and_option_has_help(command: str) -> None:
    parser = build_parser(command)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert sub.choices[command].description or any(c.help for c in sub._choices_actions if c.dest == command)
    missing = _missing_help(sub.choices[command], f"pmk {command}")
    assert not missing, "no help text: " + "; ".join(missing)


def test_the_walk_finds_a_missing_help() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--documented", help="says what it does")
    parser.add_argument("--bare")
    subs = parser.add_subparsers()
    subs.add_parser("quiet").add_argument("name")
    assert _missing_help(parser, "pmk x") == ["pmk x --bare", "pmk x quiet (sub-command)", "pmk x quiet name"]
