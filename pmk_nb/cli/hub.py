"""``pmk hub``: the real JupyterHub for a class on one machine, each student with their own chair.

JupyterHub (and its proxy, ``configurable-http-proxy``) runs as a child process on the
configuration :mod:`pmk_nb.serve.hub_config` writes into ``--hub-dir``/hub; the class (sample map, SFTP
key, chair cap) is :func:`pmk_nb.cli.demo_classroom.prepare_classroom`'s, so every dashboard page a
student opens starts its own parked simulated chair in its kernel.  Loopback by default; ``--ip``
beyond it follows ``pmk dashboard``'s rules (plain HTTP needs ``--insecure``, ``--https`` or
``--certfile/--keyfile`` serve TLS, and the class password must be as long as a token).
Ctrl-C / SIGTERM: JupyterHub stops every student's server and the proxy (``cleanup_servers``); a
process of the class still alive after that (a server that did not stop) is ended here.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import signal
import subprocess
import sys
import time
import webbrowser
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from pmk_nb.cli.options import Subparsers
from pmk_nb.cli.server_options import positive_int, tls_options
from pmk_nb.serve import (
    CULL_IDLE,
    DEFAULT_IP,
    PASSWORD_ENV,
    SEATS_DIR,
    HubPlan,
    Isolation,
    ServingRefused,
    TlsFiles,
    check_jupyterhub,
    check_password,
    check_port_free,
    check_port_number,
    check_reachable,
    check_students_can_run,
    check_transport,
    choose_isolation,
    create_users,
    dashboard_url,
    end_class_processes,
    find_proxy,
    free_port,
    hub_environment,
    local_host,
    lock_class_folders,
    parse_users,
    remove_users,
    resolve_tls,
    sigterm_as_interrupt,
    stop_hub,
    wait_for_port,
    wait_until_healthy,
    wants_tls,
    write_hub_config,
)

if TYPE_CHECKING:
    from pmk_nb.cli.demo_classroom import Classroom

DEFAULT_HUB_PORT = 8000
HUB_START_TIMEOUT = 120.0


def add_parser(subparsers: Subparsers) -> None:
    """Register ``pmk hub``."""
    p = subparsers.add_parser(
        "hub",
        help="run JupyterHub for a class: a dashboard and a simulated chair per student",
        description="Run JupyterHub for a class on this machine: one server per student, opening on the dashboard "
        "with their own parked simulated chair and the tutorial notebooks; Ctrl-C stops everything.",
    )
    p.add_argument("--users", required=True, help="the students' user names, comma-separated: ana,ben,chloe")
    p.add_argument(
        "--password",
        help=f"the class password every student logs in with (or ${PASSWORD_ENV}: a command line is visible "
        "to every local user)",
    )
    p.add_argument("--port", type=int, default=DEFAULT_HUB_PORT, help=f"HTTP port (default {DEFAULT_HUB_PORT})")
    p.add_argument("--ip", default=DEFAULT_IP, help="address to listen on (default 127.0.0.1)")
    p.add_argument("--hub-dir", dest="dir", type=Path, default=Path(".hub"), help="the class folder (default: ./.hub)")
    p.add_argument("--dir", dest="dir", type=Path, default=argparse.SUPPRESS, help=argparse.SUPPRESS)  # deprecated
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")
    p.add_argument("--max-chairs", type=positive_int, metavar="N", help="chairs at once (default: cores and memory)")
    p.add_argument("--cull-idle", type=positive_int, default=CULL_IDLE, metavar="S", help="stop servers idle S s")
    p.add_argument("--proxy", metavar="PATH", help="configurable-http-proxy to use (default: PATH, then proxy/)")
    tls_options(p, https_help="serve HTTPS with a certificate made once (tls/)")
    p.add_argument(
        "--shared-user",
        action="store_true",
        help="run every student as the hub's own user: no isolation (a student's code can read the others' files "
        "and drive their chairs; each page says so). Without it pmk hub needs root, and gives each student a "
        "system user of their own",
    )
    p.add_argument("--user-prefix", metavar="P", help="the students' system users are P<name> (default: pmk-<class>-)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    check_port_number(args.port)
    check_jupyterhub()
    env = dict(os.environ)
    users = parse_users(args.users)
    isolation = choose_isolation(args.shared_user, args.user_prefix, args.dir.expanduser().resolve(), users)
    password = check_password(args.password or env.get(PASSWORD_ENV), args.ip)
    check_transport(args.ip, tls=wants_tls(args), insecure=args.insecure)
    check_port_free(args.ip, args.port)
    proxy = find_proxy(args.proxy)
    tls = resolve_tls(args, env)
    # Ctrl-C as KeyboardInterrupt even when started with SIGINT ignored (a background job): JupyterHub
    # and its children then get the default disposition too, and stop on the SIGINT they are sent
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with sigterm_as_interrupt():
            return _serve(args, _Class(users, password, isolation), proxy, tls, env)
    finally:
        signal.signal(signal.SIGINT, previous)


@dataclass(frozen=True)
class _Class:
    users: tuple[str, ...]
    password: str
    isolation: Isolation


def _serve(
    args: argparse.Namespace,
    klass: _Class,
    proxy: tuple[str, ...],
    tls: TlsFiles | None,
    env: dict[str, str],
) -> int:
    users, password = klass.users, klass.password
    print("Preparing the class: converting the sample map...", flush=True)
    root = args.dir.expanduser().resolve()
    room = _prepare_class(root, args.max_chairs, klass)
    plan = HubPlan(
        users=users,
        password=password,
        ip=args.ip,
        port=args.port,
        hub_port=free_port(),
        proxy_api_port=free_port(),
        state_dir=root / "hub",
        users_dir=root / "users",
        maps_dir=root / "maps",
        classroom_file=room.settings_file,
        proxy_command=proxy,
        tls=tls,
        cull_idle=args.cull_idle,
        user_prefix=klass.isolation.prefix,
    )
    config = write_hub_config(plan)
    created = create_users(klass.isolation, users, plan.users_dir)
    try:
        check_students_can_run(klass.isolation, users[0], env)
    except ServingRefused:
        remove_users(created)
        raise
    log = (plan.state_dir / "jupyterhub.log").open("ab")
    hub = subprocess.Popen(
        [sys.executable, "-m", "jupyterhub", "-f", str(config)],
        cwd=plan.state_dir,
        env=hub_environment(plan, env),
        stdout=log,
        stderr=log,
    )
    try:
        wait_for_port(local_host(args.ip), args.port, hub, "JupyterHub", HUB_START_TIMEOUT)
        url = dashboard_url(local_host(args.ip), args.port, None, "https" if tls else "http")
        wait_until_healthy(url, hub, HUB_START_TIMEOUT)
        print(f"PMK class hub: {url}  (users: {', '.join(users)}; log: {plan.state_dir / 'jupyterhub.log'})")
        print(f"Each student gets their own simulated chair, at most {room.settings.max_chairs} at once. Ctrl-C stops.")
        sys.stdout.flush()
        if not args.no_browser:
            webbrowser.open(url)
        while hub.poll() is None:
            time.sleep(0.5)
        print(f"pmk: JupyterHub exited ({hub.returncode}); see {plan.state_dir / 'jupyterhub.log'}", file=sys.stderr)
        return 1 if hub.returncode else 0
    except KeyboardInterrupt:
        return 0
    finally:
        stop_hub(hub)
        log.close()
        left = end_class_processes(room.settings_file, plan.state_dir)
        if left:
            print(f"pmk: ended {left} process(es) of the class JupyterHub left behind", file=sys.stderr)
        remove_users(created)


def _prepare_class(root: Path, max_chairs: int | None, klass: _Class) -> Classroom:
    """The class (sample map, key, cap); isolated: its folders locked down and the cap in a folder every
    student's user may write (:func:`pmk_nb.serve.hub_users.lock_class_folders`)."""
    from pmk_nb.cli.demo_classroom import prepare_classroom

    if klass.isolation.isolated:  # refuse an unreachable class folder before converting anything
        check_reachable(root)
    room = prepare_classroom(root, max_chairs=max_chairs)
    if not klass.isolation.isolated:
        return room
    lock_class_folders(root, root / "hub", root / "users", root / "config", root / "classroom" / SEATS_DIR)
    settings = dataclasses.replace(room.settings, state_dir=str(root / "classroom" / SEATS_DIR))
    settings.write(room.settings_file)
    return dataclasses.replace(room, settings=settings)
