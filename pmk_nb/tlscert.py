"""TLS certificates: the SHA-256 fingerprint people compare, and a self-signed certificate.

One spelling of a fingerprint everywhere: upper-case hex pairs joined by colons, exactly what
``openssl x509 -noout -fingerprint -sha256 -in cert.pem`` prints after ``Fingerprint=``, so a person
can compare the dashboard's words with the chair's terminal character for character.

The self-signed certificate (``cryptography``, installed with paramiko) serves the simulator's
``pmk sim --tls`` and the tests; a real chair uses its own (see the README, "TLS to the chair").
"""

from __future__ import annotations

import datetime
import hashlib
import ipaddress
import re
from collections.abc import Sequence
from pathlib import Path

from pmk_nb.fileio import atomic_write

_HEX = re.compile(r"[0-9A-Fa-f]{64}")


def fingerprint(der: bytes) -> str:
    """SHA-256 of a DER certificate as ``openssl x509 -fingerprint -sha256`` prints it."""
    digest = hashlib.sha256(der).hexdigest().upper()
    return ":".join(digest[i : i + 2] for i in range(0, 64, 2))


def parse_fingerprint(text: str) -> str | None:
    """A fingerprint as typed or pasted (openssl's ``sha256 Fingerprint=AB:..``, with or without
    colons, any case) in :func:`fingerprint`'s spelling; None when it is not one."""
    raw = text.strip().rsplit("=", 1)[-1].replace(":", "").replace(" ", "")
    if not _HEX.fullmatch(raw):
        return None
    raw = raw.upper()
    return ":".join(raw[i : i + 2] for i in range(0, 64, 2))


def self_signed(names: Sequence[str], *, days: int = 825) -> tuple[bytes, bytes]:
    """A fresh ECDSA P-256 key and a self-signed certificate for ``names`` (host names or IP
    addresses, all in subjectAltName; the first is the common name): ``(cert_pem, key_pem)``."""
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import NameOID

    if not names:
        raise ValueError("a certificate needs at least one host name or address")
    key = ec.generate_private_key(ec.SECP256R1())
    alt: list[x509.GeneralName] = []
    for name in names:
        try:
            alt.append(x509.IPAddress(ipaddress.ip_address(name)))
        except ValueError:
            alt.append(x509.DNSName(name))
    subject = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, names[0])])
    now = datetime.datetime.now(datetime.UTC)
    cert = (
        x509.CertificateBuilder()
        .subject_name(subject)
        .issuer_name(subject)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - datetime.timedelta(minutes=5))
        .not_valid_after(now + datetime.timedelta(days=days))
        .add_extension(x509.SubjectAlternativeName(alt), critical=False)
        .add_extension(x509.BasicConstraints(ca=True, path_length=None), critical=True)
        .sign(key, hashes.SHA256())
    )
    key_pem = key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    )
    return cert.public_bytes(serialization.Encoding.PEM), key_pem


def write_self_signed(folder: Path, names: Sequence[str], *, stem: str = "cert") -> tuple[Path, Path]:
    """:func:`self_signed` written to ``folder/STEM.pem`` and ``folder/STEM.key`` (0600)."""
    cert_pem, key_pem = self_signed(names)
    certfile, keyfile = folder / f"{stem}.pem", folder / f"{stem}.key"
    atomic_write(keyfile, key_pem, mode=0o600, mkdir=True)
    atomic_write(certfile, cert_pem, mode=0o644)
    return certfile, keyfile


def file_fingerprint(certfile: Path) -> str:
    """The fingerprint of the first certificate in a PEM file."""
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization

    cert = x509.load_pem_x509_certificate(Path(certfile).read_bytes())
    return fingerprint(cert.public_bytes(serialization.Encoding.DER))
