"""``pmk hub``'s JupyterHub configuration: users, the class password, the proxy, the spawner, the culler.

Generated, not hand-written, so the class's choices are in one place and tested
(``tests/cli/test_hub.py``); it is JupyterHub's own traitlets configuration as JSON
(``jupyterhub_config.json``, 0600: it holds the class password), beside a 0600 cookie secret and
the hub's database in the hub's state folder.  Nothing home-made where JupyterHub already does it:

* login: JupyterHub's ``SharedPasswordAuthenticator`` (one class password, ``allowed_users`` = the list);
* one single-user server per student: :class:`pmk_nb.serve.hub_spawner.ClassSpawner`, JupyterHub's
  local process spawner (a home folder per student under ``--hub-dir``/users; as root each student's
  own system user, else with ``--shared-user`` the hub's user: :mod:`pmk_nb.serve.hub_users`) that first
  puts the dashboard, the tutorial notebooks and the student's chair secret in the home folder;
  it opens on the dashboard rendered by Voilà's server extension;
* a simulated chair per page: the kernels find the class (``PMK_CLASSROOM``, :mod:`pmk_nb.classroom`);
* idle servers: ``jupyterhub-idle-culler`` as a hub-managed service, with only the scopes it needs;
* the proxy: ``configurable-http-proxy`` (npm), on a loopback API port.
"""

from __future__ import annotations

import json
import os
import re
import secrets
import shutil
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import pmk_nb
from pmk_nb.classroom import CLASSROOM_ENV
from pmk_nb.fileio import atomic_write
from pmk_nb.serve import serving

if TYPE_CHECKING:
    from pmk_nb.serve.tablet_tls import TlsFiles

CONFIG_FILE = "jupyterhub_config.json"
COOKIE_SECRET = "jupyterhub_cookie_secret"
DASHBOARD_URL = "/voila/render/dashboard.ipynb"
PROXY_BIN = "configurable-http-proxy"
PASSWORD_ENV = "PMK_HUB_PASSWORD"
MIN_PASSWORD = 8  # JupyterHub's SharedPasswordAuthenticator refuses shorter ones
USER_NAME = re.compile(r"^[a-z0-9][a-z0-9._-]{0,31}$")
CULL_IDLE = 3600  # seconds a student's server may sit idle before the culler stops it
KERNEL_IDLE = 600  # seconds a kernel without a page lives on in a student's server (its chair with it)
SPAWN_TIMEOUT = 120  # a loaded machine starts a single-user server slowly
CULLER_SCOPES = ["list:users", "read:users:activity", "read:servers", "delete:servers"]


@dataclass(frozen=True)
class HubPlan:
    """Everything the configuration is made from (the command line, resolved)."""

    users: tuple[str, ...]
    password: str
    ip: str
    port: int
    hub_port: int
    proxy_api_port: int
    state_dir: Path
    users_dir: Path
    maps_dir: Path
    classroom_file: Path
    proxy_command: tuple[str, ...]
    tls: TlsFiles | None = None
    cull_idle: int = CULL_IDLE
    user_prefix: str = ""  # the students' system users: <prefix><name> (pmk_nb.serve.hub_users); empty: shared


def parse_users(text: str) -> tuple[str, ...]:
    """``a,b,c`` -> the class's user names (JupyterHub's lower-case names, no repeats).

    Raises:
        ServingRefused: reason ``"bad-users"``: none given, a repeat or a name JupyterHub would change.
    """
    names = [n.strip() for n in text.split(",") if n.strip()]
    bad = [n for n in names if not USER_NAME.match(n)]
    why = ""
    if not names:
        why = "--users names no one: give the students' user names, e.g. --users ana,ben,chloe"
    elif bad:
        why = f"--users: {', '.join(bad)} not a user name (lower-case letters, digits, '.', '_', '-'; 1-32 characters)"
    elif len(set(names)) != len(names):
        why = f"--users names someone twice: {', '.join(sorted({n for n in names if names.count(n) > 1}))}"
    if why:
        raise serving.ServingRefused(why, ip="", port=None, reason="bad-users")
    return tuple(names)


def check_password(password: str | None, ip: str) -> str:
    """The class password, if strong enough: JupyterHub's minimum on loopback, a token's beyond it.

    Beyond loopback the password is what the dashboard's token is there (anyone on the network can
    try it), so it follows the token's rule (:data:`pmk_nb.serve.serving.MIN_TOKEN_CHARS`).

    Raises:
        ServingRefused: reason ``"no-password"`` or ``"weak-password"``.
    """
    if not password:
        why = f"pmk hub needs the class password: --password P (or ${PASSWORD_ENV})"
        raise serving.ServingRefused(why, ip=ip, port=None, reason="no-password")
    least = MIN_PASSWORD if serving.is_loopback(ip) else max(MIN_PASSWORD, serving.MIN_TOKEN_CHARS)
    if len(password) < least:
        where = "on loopback" if serving.is_loopback(ip) else f"with --ip {ip} (anyone on the network can try it)"
        raise serving.ServingRefused(
            f"the class password is too short ({len(password)} characters): use at least {least} {where}",
            ip=ip,
            port=None,
            reason="weak-password",
        )
    return password


def check_jupyterhub() -> None:
    """JupyterHub and its idle culler must be installed (the optional extra ``hub``).

    Raises:
        ServingRefused: reason ``"no-jupyterhub"``.
    """
    import importlib.util

    missing = [m for m in ("jupyterhub", "jupyterhub_idle_culler") if importlib.util.find_spec(m) is None]
    if missing:
        raise serving.ServingRefused(
            f"pmk hub needs {' and '.join(missing)}: pip install 'pmk_nb[hub]' (make hub does it)",
            ip="",
            port=None,
            reason="no-jupyterhub",
        )


def find_proxy(explicit: str | None = None) -> tuple[str, ...]:
    """JupyterHub's proxy: ``--proxy``, else ``configurable-http-proxy`` on PATH, else the source tree's
    ``proxy/node_modules`` (``make hub`` installs it there).

    Raises:
        ServingRefused: reason ``"no-proxy"``.
    """
    candidates = [explicit] if explicit else [shutil.which(PROXY_BIN), str(source_proxy())]
    for found in candidates:
        if found and Path(found).is_file():
            return (str(Path(found).resolve()),)
    raise serving.ServingRefused(
        f"JupyterHub's proxy ({PROXY_BIN}) not found"
        + (f" at {explicit}" if explicit else "")
        + ": run `make hub` (npm installs it into proxy/), or pass --proxy PATH",
        ip="",
        port=None,
        reason="no-proxy",
    )


def source_proxy() -> Path:
    return Path(pmk_nb.__file__).resolve().parents[1] / "proxy" / "node_modules" / ".bin" / PROXY_BIN


def hub_config(plan: HubPlan) -> dict[str, dict[str, object]]:
    """JupyterHub's configuration for ``plan`` (traitlets classes -> traits), JSON-ready."""
    hub: dict[str, object] = {
        "ip": plan.ip,
        "port": plan.port,
        "hub_ip": "127.0.0.1",
        "hub_port": plan.hub_port,
        "authenticator_class": "jupyterhub.authenticators.shared.SharedPasswordAuthenticator",
        "spawner_class": "pmk_nb.serve.hub_spawner.ClassSpawner",
        "cookie_secret_file": str(plan.state_dir / COOKIE_SECRET),
        "db_url": f"sqlite:///{plan.state_dir / 'jupyterhub.sqlite'}",
        "pid_file": str(plan.state_dir / "jupyterhub.pid"),
        "cleanup_servers": True,  # Ctrl-C ends every student's server (and so their kernels and chairs)
        "cleanup_proxy": True,
        "services": [
            {
                "name": "idle-culler",
                "command": [sys.executable, "-m", "jupyterhub_idle_culler", f"--timeout={int(plan.cull_idle)}"],
            }
        ],
        "load_roles": [{"name": "idle-culler", "scopes": CULLER_SCOPES, "services": ["idle-culler"]}],
    }
    if plan.tls is not None:
        hub.update(ssl_cert=str(plan.tls.certfile), ssl_key=str(plan.tls.keyfile))
    single_user_args = [
        f"--MappingKernelManager.cull_idle_timeout={KERNEL_IDLE}",
        "--MappingKernelManager.cull_interval=30",
        "--MappingKernelManager.cull_connected=False",
    ]
    if os.geteuid() == 0 and not plan.user_prefix:  # root, --shared-user: the students' servers run as root
        single_user_args.append("--ServerApp.allow_root=True")
    return {
        "JupyterHub": hub,
        "Authenticator": {"allowed_users": list(plan.users)},
        "SharedPasswordAuthenticator": {"user_password": plan.password},
        "ConfigurableHTTPProxy": {
            "command": list(plan.proxy_command),
            "api_url": f"http://127.0.0.1:{plan.proxy_api_port}",
        },
        "Spawner": {
            "cmd": [sys.executable, "-m", "jupyterhub.singleuser"],
            "args": single_user_args,
            "default_url": DASHBOARD_URL,
            "start_timeout": SPAWN_TIMEOUT,
            "http_timeout": SPAWN_TIMEOUT,
            "environment": {
                CLASSROOM_ENV: str(plan.classroom_file),
                "PMK_MAPS_DIR": str(plan.maps_dir),
                "PMK_AUTOSTART_PREVIEW": "1",
            },
        },
        "SimpleLocalProcessSpawner": {"home_dir_template": str(plan.users_dir / "{username}")},
    }


def hub_environment(plan: HubPlan, env: dict[str, str]) -> dict[str, str]:
    """JupyterHub's environment: ``env`` and the students' users' prefix for its spawner (empty: shared)."""
    from pmk_nb.serve.hub_users import USER_PREFIX_ENV

    return {**env, USER_PREFIX_ENV: plan.user_prefix}


def write_hub_config(plan: HubPlan) -> Path:
    """Write ``jupyterhub_config.json`` and a new cookie secret (both 0600) into the state folder; return the config."""
    plan.state_dir.mkdir(parents=True, exist_ok=True, mode=0o700)
    atomic_write(plan.state_dir / COOKIE_SECRET, secrets.token_hex(32) + "\n", mode=0o600)
    path = plan.state_dir / CONFIG_FILE
    atomic_write(path, json.dumps(hub_config(plan), indent=1) + "\n", mode=0o600)
    return path


def tutorial_notebooks() -> list[Path]:
    """The tutorial notebooks of the source tree (none in a wheel install)."""
    folder = Path(pmk_nb.__file__).resolve().parents[1] / "notebooks"
    return sorted(p for p in folder.glob("[0-9]*.ipynb")) if folder.is_dir() else []


def prepare_home(home: Path) -> None:
    """A student's home folder: the dashboard notebook (always the current one) and the tutorials (a
    student's edited copy is kept)."""
    from pmk_nb.serve.voila import dashboard_notebook

    home.mkdir(parents=True, exist_ok=True, mode=0o700)
    atomic_write(home / "dashboard.ipynb", json.dumps(dashboard_notebook(), indent=1) + "\n")
    for notebook in tutorial_notebooks():
        if not (home / notebook.name).exists():
            shutil.copyfile(notebook, home / notebook.name)
