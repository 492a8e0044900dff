"""The options of the commands that serve the dashboard (`pmk dashboard`, `pmk demo`, `pmk hub`).

Parsing only: what the options mean is :mod:`pmk_nb.serve`'s (who may open the page, TLS, the port).
"""

from __future__ import annotations

import argparse

from pmk_nb.serve import DEFAULT_IP, DEFAULT_PORT, TOKEN_ENV


def server_options(p: argparse.ArgumentParser) -> None:
    """``--port``, ``--ip``, ``--token``, ``--no-browser``: the options of every command that serves the dashboard."""
    p.add_argument("--port", type=int, default=DEFAULT_PORT, help=f"HTTP port (default {DEFAULT_PORT})")
    p.add_argument(
        "--ip",
        default=DEFAULT_IP,
        help=f"address to listen on (default {DEFAULT_IP}; 0.0.0.0 serves a tablet on the LAN and needs --token)",
    )
    p.add_argument(
        "--token",
        metavar="TOKEN",
        help="access token the page's URL must carry; 'auto' makes a random one "
        f"(required beyond loopback; also read from ${TOKEN_ENV})",
    )
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")
    tls_options(
        p,
        https_help="serve HTTPS with a certificate made once in the config folder (tls/); prints its fingerprint "
        "and a QR code of the URL",
    )


def tls_options(p: argparse.ArgumentParser, *, https_help: str) -> None:
    """``--https``, ``--certfile``, ``--keyfile``, ``--insecure``: how a served page is reached (also `pmk hub`)."""
    p.add_argument("--https", action="store_true", help=https_help)
    p.add_argument("--certfile", metavar="FILE", help="serve HTTPS with this PEM certificate (chain); needs --keyfile")
    p.add_argument("--keyfile", metavar="FILE", help="the PEM private key of --certfile")
    p.add_argument(
        "--insecure",
        action="store_true",
        help="allow plain HTTP beyond loopback (the tablet then has no Screen Wake Lock and the token travels "
        "in clear)",
    )


def positive_int(text: str) -> int:
    """``--max-chairs``, ``--cull-idle``: a whole number of at least 1 (argparse type)."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {value}")
    return value
