#!/usr/bin/env python3
"""Entry point of the project's image (deploy/Dockerfile): a student's class, then their Jupyter server.

KubeSpawner runs ``jupyterhub-singleuser ...`` as the container's arguments; this entry point first
makes, in the student's home (their volume), what ``pmk hub`` makes for each student on one machine:
the class (the converted sample map, an SFTP key pair, the chair cap: ``PMK_MAX_CHAIRS``, default 2,
a student's two pages) and the home folder (the dashboard and the tutorial notebooks), then execs
the arguments with the class's environment, so each page's kernel starts its own parked chair.
"""

from __future__ import annotations

import os
import sys
from pathlib import Path


def main(argv: list[str]) -> None:
    from pmk_nb.cli.demo_classroom import prepare_classroom
    from pmk_nb.serve import prepare_home

    home = Path(os.environ.get("HOME") or Path.home())
    room = prepare_classroom(home / ".pmk-class", max_chairs=int(os.environ.get("PMK_MAX_CHAIRS", "2")))
    prepare_home(home)
    env = {**room.env, "PMK_CONFIG_DIR": str(home / ".pmk")}
    command = argv or ["jupyterhub-singleuser"]
    os.execvpe(command[0], command, env)


if __name__ == "__main__":
    main(sys.argv[1:])
