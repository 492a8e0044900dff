"""``pmk hub``'s spawner: JupyterHub's ``SimpleLocalProcessSpawner`` with the class's home folders.

Each student's server runs as the current user (``LocalProcessSpawner`` would need root and a Unix
account per student) in ``--hub-dir``/users/<name>, which gets the dashboard and the tutorial notebooks
before the server starts (:func:`pmk_nb.cli.hub_config.prepare_home`), and its own settings folder.
Imported by JupyterHub (``spawner_class`` in the generated configuration), never by ``pmk`` itself.
"""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

from jupyterhub.spawner import SimpleLocalProcessSpawner

from pmk_nb.cli.hub_config import prepare_home


class ClassSpawner(SimpleLocalProcessSpawner):  # type: ignore[misc]
    """A student's single-user server: home folder made and filled, then JupyterHub's local spawner."""

    async def start(self) -> Any:
        await asyncio.to_thread(prepare_home, Path(self.home_dir))
        return await super().start()

    def get_env(self) -> dict[str, str]:
        env: dict[str, str] = super().get_env()
        env["PMK_CONFIG_DIR"] = str(Path(self.home_dir) / ".pmk")  # the student's own profiles (notebooks)
        return env
