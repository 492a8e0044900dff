"""``pmk hub``'s spawner: JupyterHub's local process spawner with the class's homes, students apart.

Isolated (a users' prefix in the hub's environment, the hub runs as root): each student's server runs as their own
system user (JupyterHub's ``LocalProcessSpawner`` setuid, :func:`jupyterhub.spawner.set_user_setuid`) in
their 0700 home, ``--hub-dir``/users/<name> (:mod:`pmk_nb.serve.hub_users`). Shared (no prefix,
``--shared-user``): ``SimpleLocalProcessSpawner``, every server as the hub's user. Either way the home
gets the dashboard, the tutorial notebooks and the student's own chair secret and SFTP key before the
server starts (:func:`pmk_nb.serve.hub_config.prepare_home`, :func:`pmk_nb.serve.hub_users.prepare_student`).
Imported by JupyterHub (``spawner_class`` in the generated configuration), never by ``pmk`` itself.
"""

from __future__ import annotations

import asyncio
import os
from pathlib import Path
from typing import Any

from jupyterhub.spawner import SimpleLocalProcessSpawner, set_user_setuid

from pmk_nb.serve.hub_config import prepare_home
from pmk_nb.serve.hub_users import USER_PREFIX_ENV, Isolation, prepare_student, student_env


class ClassSpawner(SimpleLocalProcessSpawner):  # type: ignore[misc]
    """A student's single-user server: home folder made and filled, then JupyterHub's local spawner."""

    @property
    def isolation(self) -> Isolation:
        """The hub's environment says (``pmk hub`` sets it for JupyterHub: :func:`hub_config.hub_environment`)."""
        return Isolation(os.environ.get(USER_PREFIX_ENV, ""))

    async def start(self) -> Any:
        home, owner = Path(self.home_dir), self.isolation.system_user(self.user.name)
        maps = self.environment.get("PMK_MAPS_DIR")

        def prepare() -> None:
            prepare_home(home)
            prepare_student(home, owner, Path(maps) if maps else None)

        await asyncio.to_thread(prepare)
        return await super().start()

    def make_preexec_fn(self, name: str) -> Any:
        owner = self.isolation.system_user(name)
        return set_user_setuid(owner) if owner else super().make_preexec_fn(name)

    def user_env(self, env: dict[str, str]) -> dict[str, str]:
        env = super().user_env(env)
        owner = self.isolation.system_user(self.user.name)
        if owner:
            env.update(USER=owner, SHELL="/bin/sh")
        return env

    def get_env(self) -> dict[str, str]:
        env: dict[str, str] = super().get_env()
        env["PMK_CONFIG_DIR"] = str(Path(self.home_dir) / ".pmk")  # the student's own profiles (notebooks)
        env.update(student_env(Path(self.home_dir), self.isolation))
        return env
