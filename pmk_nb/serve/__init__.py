"""The serving stack: who may open the dashboard, Voilà with its guards and kernels, TLS, the class hub.

Not command parsing (that is :mod:`pmk_nb.cli`): the rules for serving beyond loopback
(:mod:`.serving`), the tablet's certificate (:mod:`.tablet_tls`), Voilà started on the generated
notebook (:mod:`.voila`) and, inside that server, its guards (:mod:`.voila_guard`, :mod:`.voila_frames`),
page-bound kernels (:mod:`.voila_kernels`), HTTPS (:mod:`.voila_tls`) and masked tokens
(:mod:`.tokenmask`); JupyterHub for a class (:mod:`.hub_config`, :mod:`.hub_spawner`, :mod:`.hub_users`,
:mod:`.hub_process`);
the child-process helpers every server start uses (:mod:`.procs`). Jupyter and JupyterHub load some
classes by their dotted path (``voila.json``, ``jupyterhub_config.json``). The face is lazy: `pmk --help`
imports none of the servers' libraries.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from pmk_nb.lazyface import lazy_face

if TYPE_CHECKING:
    from pmk_nb.serve.hub_config import (
        CULL_IDLE,
        PASSWORD_ENV,
        HubPlan,
        check_jupyterhub,
        check_password,
        find_proxy,
        hub_environment,
        parse_users,
        prepare_home,
        write_hub_config,
    )
    from pmk_nb.serve.hub_process import end_class_processes, stop_hub, wait_until_healthy
    from pmk_nb.serve.hub_spawner import ClassSpawner
    from pmk_nb.serve.hub_users import (
        SEATS_DIR,
        Isolation,
        check_reachable,
        check_students_can_run,
        choose_isolation,
        create_users,
        lock_class_folders,
        remove_users,
    )
    from pmk_nb.serve.procs import (
        ProcessStartError,
        check_port_number,
        free_port,
        sigterm_as_interrupt,
        stop_process,
        wait_for_port,
    )
    from pmk_nb.serve.serving import (
        DEFAULT_IP,
        DEFAULT_PORT,
        TOKEN_ENV,
        ServingRefused,
        check_port_free,
        check_transport,
        dashboard_url,
        local_host,
    )
    from pmk_nb.serve.tablet_tls import TlsFiles, resolve_tls, wants_tls
    from pmk_nb.serve.voila import preflight, serve_dashboard

_WHERE = {
    **dict.fromkeys(
        (
            "CULL_IDLE",
            "PASSWORD_ENV",
            "HubPlan",
            "check_jupyterhub",
            "check_password",
            "find_proxy",
            "hub_environment",
            "parse_users",
            "prepare_home",
            "write_hub_config",
        ),
        "hub_config",
    ),
    "ClassSpawner": "hub_spawner",
    **dict.fromkeys(("end_class_processes", "stop_hub", "wait_until_healthy"), "hub_process"),
    **dict.fromkeys(
        (
            "SEATS_DIR",
            "Isolation",
            "check_reachable",
            "check_students_can_run",
            "choose_isolation",
            "create_users",
            "lock_class_folders",
            "remove_users",
        ),
        "hub_users",
    ),
    **dict.fromkeys(
        (
            "ProcessStartError",
            "check_port_number",
            "free_port",
            "sigterm_as_interrupt",
            "stop_process",
            "wait_for_port",
        ),
        "procs",
    ),
    **dict.fromkeys(
        (
            "DEFAULT_IP",
            "DEFAULT_PORT",
            "TOKEN_ENV",
            "ServingRefused",
            "check_port_free",
            "check_transport",
            "dashboard_url",
            "local_host",
        ),
        "serving",
    ),
    **dict.fromkeys(("TlsFiles", "resolve_tls", "wants_tls"), "tablet_tls"),
    **dict.fromkeys(("preflight", "serve_dashboard"), "voila"),
}

__all__ = [
    "CULL_IDLE",
    "DEFAULT_IP",
    "DEFAULT_PORT",
    "PASSWORD_ENV",
    "SEATS_DIR",
    "TOKEN_ENV",
    "ClassSpawner",
    "HubPlan",
    "Isolation",
    "ProcessStartError",
    "ServingRefused",
    "TlsFiles",
    "check_jupyterhub",
    "check_password",
    "check_port_free",
    "check_port_number",
    "check_reachable",
    "check_students_can_run",
    "check_transport",
    "choose_isolation",
    "create_users",
    "dashboard_url",
    "end_class_processes",
    "find_proxy",
    "free_port",
    "hub_environment",
    "local_host",
    "lock_class_folders",
    "parse_users",
    "preflight",
    "prepare_home",
    "remove_users",
    "resolve_tls",
    "serve_dashboard",
    "sigterm_as_interrupt",
    "stop_hub",
    "stop_process",
    "wait_for_port",
    "wait_until_healthy",
    "wants_tls",
    "write_hub_config",
]

__getattr__, __dir__ = lazy_face(__name__, _WHERE, __all__)
