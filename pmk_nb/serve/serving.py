"""Who may open the dashboard and where: loopback vs network, the access token, the port really used.

Rules (issue 10): serving beyond loopback without a token is refused (anyone on the ward's Wi-Fi
could otherwise edit profiles and send maps); the printed URL carries the token; a taken port is a
clear error, never a silent move to the next port.  Issue 24: beyond loopback, plain HTTP needs
``--insecure`` (the tablet gets no secure context, so no Screen Wake Lock, and the token crosses the
Wi-Fi in clear); HTTPS is :mod:`pmk_nb.serve.tablet_tls`.
"""

from __future__ import annotations

import errno
import ipaddress
import secrets
import socket

from pmk_nb.errors import PmkError

DEFAULT_PORT = 8866
DEFAULT_IP = "127.0.0.1"
TOKEN_ENV = "PMK_DASHBOARD_TOKEN"
AUTO_TOKEN = "auto"
MIN_TOKEN_CHARS = 16


class ServingRefused(PmkError):
    """The dashboard would be served in an unsafe or impossible way.

    Attributes:
        ip, port: what was asked for.
        reason: ``"no-token"``, ``"weak-token"``, ``"port-taken"``, ``"plain-http"`` (beyond loopback
            without TLS or ``--insecure``) or ``"bad-certificate"`` (:mod:`pmk_nb.serve.tablet_tls`).
    """

    def __init__(self, message: str, *, ip: str, port: int | None, reason: str) -> None:
        super().__init__(message)
        self.ip, self.port, self.reason = ip, port, reason


def is_loopback(ip: str) -> bool:
    """True for addresses only this machine can reach (127.0.0.0/8, ::1, localhost)."""
    if ip == "localhost":
        return True
    try:
        return ipaddress.ip_address(ip).is_loopback
    except ValueError:
        return False  # a host name: it may resolve to a LAN address


def is_ip_address(host: str) -> bool:
    """Whether ``host`` is an IP address (not a name)."""
    try:
        ipaddress.ip_address(host)
    except ValueError:
        return False
    return True


def resolve_token(option: str | None, env: dict[str, str]) -> str | None:
    """The token to require: ``--token`` ('auto' = a new random one), else ``$PMK_DASHBOARD_TOKEN``, else None."""
    value = option if option is not None else env.get(TOKEN_ENV) or None
    if value is not None and value.strip().lower() == AUTO_TOKEN:
        return secrets.token_urlsafe(24)
    return value.strip() if value is not None else None


def check_serving(ip: str, token: str | None) -> None:
    """Refuse a non-loopback address without a token, and a token too short to resist guessing.

    Raises:
        ServingRefused: with a one-line explanation.
    """
    if token is not None and len(token) < MIN_TOKEN_CHARS:
        raise ServingRefused(
            f"--token is too short ({len(token)} characters): use at least {MIN_TOKEN_CHARS}, or --token auto",
            ip=ip,
            port=None,
            reason="weak-token",
        )
    if not token and not is_loopback(ip):
        raise ServingRefused(
            f"--ip {ip} lets anyone on the network use the dashboard: add --token auto (or --token TOKEN)",
            ip=ip,
            port=None,
            reason="no-token",
        )


def check_transport(ip: str, *, tls: bool, insecure: bool) -> None:
    """Refuse plain HTTP beyond loopback unless ``--insecure`` says the user accepts it.

    A tablet's browser treats ``http://<LAN address>`` as no secure context: the kiosk's Screen Wake
    Lock does not exist there (the tablet dims and locks mid-ride), and the token in the URL and
    cookie crosses the Wi-Fi in clear.  Loopback stays HTTP (a secure context already, never on the air).

    Raises:
        ServingRefused: reason ``"plain-http"``.
    """
    if not tls and not insecure and not is_loopback(ip):
        raise ServingRefused(
            f"--ip {ip} over plain HTTP: a tablet gets no secure context (no Screen Wake Lock: the screen "
            "dims mid-ride) and the token crosses the Wi-Fi in clear; add --https (or --certfile/--keyfile), "
            "or --insecure to accept that",
            ip=ip,
            port=None,
            reason="plain-http",
        )


def check_port_free(ip: str, port: int) -> None:
    """Refuse a port another program listens on (Voilà would silently move to the next one).

    Raises:
        ServingRefused: the port is taken.
    """
    family = socket.AF_INET6 if ":" in ip else socket.AF_INET
    with socket.socket(family, socket.SOCK_STREAM) as sock:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as Voilà binds: TIME_WAIT is no obstacle
        try:
            sock.bind((ip, port))
        except OSError as err:
            if err.errno != errno.EADDRINUSE:
                raise
            raise ServingRefused(
                f"port {port} is already in use on {ip} (another dashboard?): stop it or pick another with --port",
                ip=ip,
                port=port,
                reason="port-taken",
            ) from None


def server_names(ip: str) -> list[str]:
    """Host names a page may use for a server on ``ip`` besides its addresses: none on loopback
    (``localhost`` is always allowed), the machine's own names when it serves the LAN."""
    if is_loopback(ip):
        return []
    name = socket.gethostname().lower()
    names = [name, f"{name}.local", socket.getfqdn().lower()]
    if ip not in ("0.0.0.0", "", "::"):
        names.append(ip.lower())  # --ip given as a name
    return sorted(set(names))


def lan_addresses() -> list[str]:
    """This machine's non-loopback IPv4 addresses: the one its default route leaves by first (what a
    tablet on the same Wi-Fi reaches), then those its host name resolves to."""
    found: list[str] = []
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("192.0.2.1", 9))  # TEST-NET: a UDP connect only picks the route, sends nothing
            found.append(probe.getsockname()[0])
        except OSError:
            pass  # no route at all: no LAN
    try:
        infos = socket.getaddrinfo(socket.gethostname(), None, socket.AF_INET)
    except OSError:
        infos = []
    found += [str(info[4][0]) for info in infos]
    return [a for a in dict.fromkeys(found) if not ipaddress.ip_address(a).is_loopback and a != "0.0.0.0"]


def local_host(ip: str) -> str:
    """Where this machine reaches a server listening on ``ip`` (all interfaces -> loopback)."""
    return "127.0.0.1" if ip in ("0.0.0.0", "", "::") else ip


def dashboard_url(host: str, port: int, token: str | None, scheme: str = "http") -> str:
    """The page's URL, with the token when one is required."""
    shown = f"[{host}]" if ":" in host else host
    return f"{scheme}://{shown}:{port}/" + (f"?token={token}" if token else "")


def tablet_url(ip: str, port: int, token: str | None, scheme: str = "http") -> str | None:
    """The URL a tablet opens (by address: a tablet rarely resolves this machine's name); None on loopback."""
    if is_loopback(ip):
        return None
    host = ip
    if ip in ("0.0.0.0", "", "::"):
        host = next(iter(lan_addresses()), socket.gethostname())
    return dashboard_url(host, port, token, scheme)


def url_lines(ip: str, port: int, token: str | None, scheme: str = "http") -> list[str]:
    """What ``pmk dashboard`` prints: the URL on this machine and, when served to the LAN, for other devices."""
    lines = [f"PMK dashboard: {dashboard_url(local_host(ip), port, token, scheme)}  (Ctrl-C to stop)"]
    if not is_loopback(ip):
        host = socket.gethostname() if ip in ("0.0.0.0", "", "::") else ip
        lines.append(f"  from a tablet: {dashboard_url(host, port, token, scheme)}")
        by_address = tablet_url(ip, port, token, scheme)
        if by_address and by_address not in lines[-1]:
            lines.append(f"  or by address: {by_address}")
    return lines


def qr_lines(text: str, *, color: bool = False) -> list[str]:
    """``text`` as a QR code in terminal characters, two modules a character (half blocks), with the
    standard 4-module quiet zone.  Light modules are drawn (a terminal is usually dark); ``color``
    forces white on black with ANSI codes so a light terminal shows the same code."""
    import segno  # here: `pmk --help` does not pay for it

    rows = [[bool(m) for m in r] for r in segno.make(text, error="m", micro=False).matrix_iter(scale=1, border=4)]
    if len(rows) % 2:
        rows.append([False] * len(rows[0]))  # a light row: the quiet zone grows by one
    chars = {(False, False): "\u2588", (False, True): "\u2580", (True, False): "\u2584", (True, True): " "}
    pairs = zip(rows[::2], rows[1::2], strict=True)
    lines = ["".join(chars[a, b] for a, b in zip(top, bottom, strict=True)) for top, bottom in pairs]
    return [f"\x1b[97;40m{line}\x1b[0m" for line in lines] if color else lines
