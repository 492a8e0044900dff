"""TLS (``wss://``) to a chair's rosbridge: which certificate is trusted, checked before any ROS message.

Two ways to trust a chair, chosen per profile:

* a CA file (``tls_ca_file``): OpenSSL checks the chain and the host name, like a browser would;
* pinning (no CA file): the chair's certificate is its own identity, as an SSH host key is. Its
  SHA-256 fingerprint is kept in ``known_certs``, the sibling of the profile's SSH known_hosts file,
  one line per chair in the known_hosts spelling (``[host]:port sha256 AB:CD:...``), written by
  the same helper (:func:`pmk_nb.fileio.append_line`).

The link never trusts by itself: an unknown certificate raises :class:`UnknownChairCertificate`
with the fingerprint; only a person who compared it with the chair's pins it
(:func:`trust_certificate`: Settings' "Trust this certificate", or ``pmk chair test`` on a
terminal). Without a person (Home's automatic connect, a kiosk, ``pmk`` without a tty) first contact
is refused, never trusted silently: a wheelchair is commanded over this link. A changed certificate
is always refused (:class:`ChairCertificateChanged`, with both fingerprints and how to re-pin).

The check runs on every socket: in the probe (:mod:`.probe`), and in the link's own connection
(:mod:`.factory`), whose TLS handshake ends before the websocket's first byte is sent.
"""

from __future__ import annotations

import ssl
from dataclasses import dataclass
from pathlib import Path

from pmk_nb.errors import (
    ChairCertificateChanged,
    ChairCertificateError,
    ChairCertificateUntrusted,
    UnknownChairCertificate,
)
from pmk_nb.fileio import append_line
from pmk_nb.tlscert import fingerprint


@dataclass(frozen=True)
class ChairTls:
    """How a link trusts a ``wss://`` chair: ``ca_file``, else the fingerprints in ``known_certs``."""

    known_certs: Path
    ca_file: str | None = None

    def context(self) -> ssl.SSLContext:
        """The client context: the CA file verifies chain and host name; pinning checks afterwards."""
        if self.ca_file:
            return ssl.create_default_context(cafile=str(Path(self.ca_file).expanduser()))
        ctx = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        ctx.minimum_version = ssl.TLSVersion.TLSv1_2
        ctx.check_hostname = False  # the pinned fingerprint is the identity, not a name
        ctx.verify_mode = ssl.CERT_NONE
        return ctx


def entry_name(host: str, port: int) -> str:
    """The known_certs name of a chair (always with the port: two bridges may share a host)."""
    return f"[{host}]:{port}"


def pinned(tls: ChairTls, host: str, port: int) -> str | None:
    """The fingerprint pinned for ``host:port``, None when there is none yet."""
    if not tls.known_certs.exists():
        return None
    name = entry_name(host, port)
    for line in tls.known_certs.read_text(encoding="utf-8").splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[0] == name and parts[1] == "sha256":
            return parts[2]
    return None


def check_peer(tls: ChairTls, host: str, port: int, der: bytes | None, *, presented: str | None = None) -> str:
    """The presented certificate's fingerprint once trusted; raises a ChairCertificateError otherwise.

    With a CA file OpenSSL has already verified it during the handshake (see :func:`handshake_failure`).
    ``presented`` stands for ``der`` when only the fingerprint is at hand.
    """
    presented = fingerprint(der) if der else presented
    store = str(tls.known_certs)
    if presented is None:
        raise ChairCertificateError(
            f"The chair at {host}:{port} presented no TLS certificate; refusing to connect.",
            host=host,
            port=port,
            presented=None,
            known_certs=store,
        )
    if tls.ca_file:
        return presented
    expected = pinned(tls, host, port)
    if expected is None:
        raise UnknownChairCertificate(
            f"First TLS connection to the chair at {host}:{port}: its certificate (SHA-256 {presented}) is not "
            "trusted yet, nothing was sent. Compare it with the chair's (openssl x509 -noout -fingerprint -sha256 "
            "-in CERTFILE on the chair), then trust it in Settings (Test connection) or with `pmk chair test` "
            "in a terminal.",
            host=host,
            port=port,
            presented=presented,
            known_certs=store,
        )
    if expected != presented:
        raise ChairCertificateChanged(
            f"The TLS certificate of the chair at {host}:{port} CHANGED (now SHA-256 {presented}, pinned "
            f"{expected}); refusing to connect: another machine may be answering for the chair. If the chair's "
            f"certificate was replaced on purpose, check the new fingerprint on the chair, delete the line "
            f"'{entry_name(host, port)}' from {store} and connect again to trust the new one.",
            host=host,
            port=port,
            presented=presented,
            expected=expected,
            known_certs=store,
        )
    return presented


def handshake_failure(tls: ChairTls, host: str, port: int, err: ssl.SSLError) -> ChairCertificateError | None:
    """The typed error for a certificate the CA file does not vouch for; None for other TLS failures."""
    if not isinstance(err, ssl.SSLCertVerificationError):
        return None
    reason = str(err.verify_message or err.reason or err)
    return ChairCertificateUntrusted(
        f"The TLS certificate of the chair at {host}:{port} is not signed by the CA in {tls.ca_file} ({reason}); "
        "refusing to connect. Check the CA file in the chair profile, that the certificate names the address "
        "you connect to, and that it has not expired.",
        host=host,
        port=port,
        presented=None,
        ca_file=str(tls.ca_file),
        reason=reason,
    )


def trust_certificate(unknown: UnknownChairCertificate) -> None:
    """Pin the certificate a person saw and confirmed: exactly that fingerprint, so another one
    presented at the next connection is refused as changed."""
    if unknown.host is None or unknown.port is None or unknown.presented is None:
        raise ValueError("an UnknownChairCertificate always names the chair and its certificate")
    store = ChairTls(Path(unknown.known_certs))
    if pinned(store, unknown.host, unknown.port) is not None:  # pinned meanwhile (another page): check it
        check_peer(store, unknown.host, unknown.port, None, presented=unknown.presented)
        return
    append_line(Path(unknown.known_certs), f"{entry_name(unknown.host, unknown.port)} sha256 {unknown.presented}")
