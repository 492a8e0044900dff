"""The README's snippets run as written (issue 29, item 5: "From Python" failed verbatim).

Every ```python block is executed verbatim in a fresh interpreter, in a temporary folder that holds
what the README says to run it from (the checkout: ``sample_maps/``), with this checkout's package.
A block that is a file for another machine (the chair's ROS 2 launch file) says so on its first line
and is compiled only. Every `pmk ...` command line of the ```sh/```bash blocks must parse with the
CLI's own parser (an option renamed without its README is caught here).
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from pmk_nb.access import read_sidecar
from pmk_nb.cli import COMMANDS, build_parser
from pmk_nb.errors import MapNotFound

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
PYTHON_BLOCKS = re.findall(r"^```python\n(.*?)^```", README, re.S | re.M)
SHELL_BLOCKS = re.findall(r"^```(?:sh|bash)\n(.*?)^```", README, re.S | re.M)
#: first lines of blocks that are files for the chair (ROS 2 launch), not snippets to run here
FILE_MARKERS = ("# pmk_bringup.launch.py",)


def _runnable() -> list[str]:
    return [b for b in PYTHON_BLOCKS if not b.startswith(FILE_MARKERS)]


def test_the_readme_has_python_snippets_to_run() -> None:
    assert len(_runnable()) >= 1 and len(PYTHON_BLOCKS) >= 2


@pytest.mark.slow
@pytest.mark.parametrize("index", range(len(_runnable())))
def test_python_snippet_runs_verbatim(index: int, tmp_path: Path) -> None:
    (tmp_path / "sample_maps").symlink_to(ROOT / "sample_maps")
    script = tmp_path / f"snippet{index}.py"
    script.write_text(_runnable()[index], encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    done = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300
    )
    assert done.returncode == 0, done.stdout + done.stderr
    if "go_to(" in script.read_text():
        assert done.stdout.count(" arrived") >= 2, done.stdout  # the visit reached its rooms


def test_files_for_the_chair_compile() -> None:
    files = [b for b in PYTHON_BLOCKS if b.startswith(FILE_MARKERS)]
    for block in files:
        compile(block, "README.md", "exec")


def _pmk_commands() -> list[list[str]]:
    found = []
    for block in SHELL_BLOCKS:
        for line in block.replace("\\\n", " ").splitlines():
            for part in re.split(r"&&|\|\||;|\|", line):
                try:
                    words = shlex.split(re.sub(r"\[[^\]]*\]", "", part), comments=True)  # [optional] usage
                except ValueError:
                    continue
                at = next((i for i, w in enumerate(words) if w == "pmk" or w.endswith("/bin/pmk")), None)
                if at is not None and at + 1 < len(words) and words[at + 1] in COMMANDS:
                    found.append(words[at + 1 :])
    return found


def test_every_pmk_command_in_the_readme_parses() -> None:
    commands = _pmk_commands()
    assert len(commands) >= 10
    for argv in commands:
        try:
            build_parser(argv[0]).parse_args(argv)
        except SystemExit as err:
            raise AssertionError(f"README: `pmk {' '.join(argv)}` does not parse") from err


def test_a_missing_map_is_named_with_the_maps_present(tmp_path: Path) -> None:
    (tmp_path / "first_floor.yaml").write_text("image: first_floor.pgm\n")
    with pytest.raises(MapNotFound) as caught:
        read_sidecar(tmp_path / "clinic_floor.yaml")
    err = caught.value
    assert (err.name, err.present, err.folder) == ("clinic_floor", ["first_floor"], str(tmp_path))
    assert "rooms" not in str(err) and "first_floor" in str(err)
