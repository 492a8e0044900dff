"""TLS from the tablet to the dashboard: a certificate given by the user, or one made here once and kept.

Why: over plain HTTP a tablet on the LAN has no secure context, so the kiosk's Screen Wake Lock does
not exist there, and the access token crosses the Wi-Fi in clear.  ``pmk dashboard --certfile F
--keyfile K`` serves a certificate the lab already has; ``--https`` makes its own in the config
folder (``tls/``), the way mkcert does: a small certificate authority (``dashboard-ca.crt``, made
once; the tablet trusts it once) and the server certificate it signs (``dashboard.crt``), valid for
every name and address this server is reached by.  The server certificate is reissued under the
same authority when a new name or address appears or it nears its end.  Keys are 0600, the folder 0700.

The authority is bound by name constraints (issue 38: a tablet that installed an unconstrained one
trusted it for every site): it may vouch only for this machine's names (and their subdomains),
loopback, and the networks of its LAN addresses (a /24 for a private IPv4 address, a /64 for a
private IPv6 one, the address alone otherwise), so the tablet's trust survives a new DHCP lease in
the same network.  A name or network the authority does not cover (or an authority made before the
constraints) gets a new authority, which the tablet must trust again (``TlsFiles.replaced_authority``).
"""

from __future__ import annotations

import argparse
import datetime as dt
import ipaddress
import socket
import ssl
from dataclasses import dataclass
from pathlib import Path

from cryptography import x509
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

from pmk_nb.fileio import atomic_write, private_dir
from pmk_nb.serve.serving import ServingRefused, is_loopback, lan_addresses, server_names
from pmk_nb.tlscert import fingerprint as der_fingerprint

TLS_DIR = "tls"
CA_CERT, CA_KEY = "dashboard-ca.crt", "dashboard-ca.key"
CERT, KEY = "dashboard.crt", "dashboard.key"
#: a server certificate's life: within the 398 days browsers accept for any server certificate
CERT_DAYS = 397
CA_DAYS = 3650
#: a server certificate this close to its end is reissued
RENEW_DAYS = 30
LOOPBACK_HOSTS = ("localhost", "127.0.0.1", "::1")


@dataclass(frozen=True)
class TlsFiles:
    """What Voilà serves and what a person compares on the tablet.

    Attributes:
        certfile, keyfile: the server's certificate (PEM, chain allowed) and private key.
        fingerprint: SHA-256 of the server certificate, ``AA:BB:...`` as browsers show it.
        names: the DNS names and IP addresses the certificate is valid for.
        ca_file, ca_fingerprint: the authority to trust on the tablet (``--https`` only).
        created: True when this run made or reissued the server certificate.
        replaced_authority: True when this run replaced the folder's authority (tablets must trust it again).
    """

    certfile: Path
    keyfile: Path
    fingerprint: str
    names: tuple[str, ...]
    ca_file: Path | None = None
    ca_fingerprint: str | None = None
    created: bool = False
    replaced_authority: bool = False


def fingerprint(cert: x509.Certificate) -> str:
    """SHA-256 of the certificate, spelled by the one helper (:func:`pmk_nb.tlscert.fingerprint`)."""
    return der_fingerprint(cert.public_bytes(serialization.Encoding.DER))


def certificate_names(cert: x509.Certificate) -> tuple[str, ...]:
    """The subject alternative names (DNS names, then IP addresses); none when the extension is missing."""
    try:
        san = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    except x509.ExtensionNotFound:
        return ()
    return (*san.get_values_for_type(x509.DNSName), *(str(a) for a in san.get_values_for_type(x509.IPAddress)))


def _refused(why: str, path: Path | None = None) -> ServingRefused:
    where = f" ({path})" if path is not None else ""
    return ServingRefused(f"TLS: {why}{where}", ip="", port=None, reason="bad-certificate")


def load_pair(certfile: Path, keyfile: Path) -> TlsFiles:
    """Check that ``certfile`` and ``keyfile`` are a matching PEM pair Python's TLS can serve.

    Raises:
        ServingRefused: reason ``"bad-certificate"``, naming the file and why.
    """
    try:
        cert = x509.load_pem_x509_certificate(certfile.read_bytes())
    except OSError as err:
        raise _refused(f"cannot read the certificate: {err.strerror}", certfile) from None
    except ValueError:
        raise _refused("the certificate is not a PEM certificate", certfile) from None
    try:
        # an empty password: an encrypted key fails here instead of prompting on the terminal
        ssl.create_default_context(ssl.Purpose.CLIENT_AUTH).load_cert_chain(certfile, keyfile, password=b"")
    except OSError as err:  # ssl.SSLError is an OSError
        why = "not its key, not PEM, or encrypted (give an unencrypted PEM key)"
        if not isinstance(err, ssl.SSLError):
            why = err.strerror or str(err)
        raise _refused(f"cannot serve the certificate with this key: {why}", keyfile) from None
    return TlsFiles(certfile, keyfile, fingerprint(cert), certificate_names(cert))


def served_hosts(ip: str) -> list[str]:
    """Every name and address a browser may use for a server listening on ``ip`` (the certificate's names)."""
    hosts = list(LOOPBACK_HOSTS)
    if not is_loopback(ip):
        hosts += server_names(ip)
        hosts += lan_addresses() if ip in ("0.0.0.0", "", "::") else [ip]
    return list(dict.fromkeys(h.lower() for h in hosts if h))


def _name_entry(host: str) -> x509.GeneralName:
    try:
        return x509.IPAddress(ipaddress.ip_address(host))
    except ValueError:
        return x509.DNSName(host)


#: the network a private LAN address stands for in the authority's constraints, by IP version
PRIVATE_PREFIX = {4: 24, 6: 64}


def permitted_subtrees(hosts: list[str]) -> list[x509.GeneralName]:
    """What the authority may vouch for: each name, and each address's network (see the module)."""
    trees: list[x509.GeneralName] = []
    for host in hosts:
        entry = _name_entry(host)
        if isinstance(entry, x509.IPAddress):
            address = ipaddress.ip_address(host)
            wide = address.is_private and not address.is_loopback
            prefix = PRIVATE_PREFIX[address.version] if wide else address.max_prefixlen
            entry = x509.IPAddress(ipaddress.ip_network(f"{address}/{prefix}", strict=False))
        if entry not in trees:
            trees.append(entry)
    return trees


def authority_permits(ca: x509.Certificate, host: str) -> bool:
    """Whether ``ca``'s name constraints let it vouch for ``host``; an authority without them never
    does (one made before issue 38 is replaced, not trusted for every site any longer)."""
    try:
        constraints = ca.extensions.get_extension_for_class(x509.NameConstraints).value
    except x509.ExtensionNotFound:
        return False
    entry = _name_entry(host)
    for tree in constraints.permitted_subtrees or []:
        if isinstance(entry, x509.IPAddress) and isinstance(tree, x509.IPAddress):
            network = tree.value
            if isinstance(network, ipaddress.IPv4Network | ipaddress.IPv6Network) and entry.value in network:
                return True
        elif isinstance(entry, x509.DNSName) and isinstance(tree, x509.DNSName):
            name, base = entry.value.lower(), tree.value.lower()
            if name == base or name.endswith("." + base):
                return True
    return False


def _key_pem(key: ec.EllipticCurvePrivateKey) -> bytes:
    pkcs8 = serialization.PrivateFormat.PKCS8
    return key.private_bytes(serialization.Encoding.PEM, pkcs8, serialization.NoEncryption())


def _certificate(
    subject: str,
    key: ec.EllipticCurvePrivateKey,
    issuer: x509.Certificate | None,
    signer: ec.EllipticCurvePrivateKey,
    days: int,
    hosts: list[str],
) -> x509.Certificate:
    """An authority (``issuer`` None: self-signed, may sign server certificates for ``hosts`` only) or a
    server certificate for ``hosts``."""
    now = dt.datetime.now(dt.UTC)
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, subject)])
    builder = (
        x509.CertificateBuilder()
        .subject_name(name)
        .issuer_name(issuer.subject if issuer else name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - dt.timedelta(minutes=5))  # a tablet's clock a little behind
        .not_valid_after(now + dt.timedelta(days=days))
        .add_extension(x509.SubjectKeyIdentifier.from_public_key(key.public_key()), critical=False)
    )
    if issuer is None:
        usage = dict(digital_signature=True, key_cert_sign=True, crl_sign=True, key_encipherment=False)
        builder = builder.add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
        constraints = x509.NameConstraints(permitted_subtrees=permitted_subtrees(hosts), excluded_subtrees=None)
        builder = builder.add_extension(constraints, critical=True)  # RFC 5280: critical
    else:
        usage = dict(digital_signature=True, key_cert_sign=False, crl_sign=False, key_encipherment=False)
        builder = (
            builder.add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
            .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH]), critical=False)
            .add_extension(x509.SubjectAlternativeName([_name_entry(h) for h in hosts]), critical=False)
            .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(signer.public_key()), critical=False)
        )
    flags = dict(content_commitment=False, data_encipherment=False, key_agreement=False, encipher_only=False)
    builder = builder.add_extension(x509.KeyUsage(**usage, **flags, decipher_only=False), critical=True)
    return builder.sign(signer, hashes.SHA256())


def _write_pair(folder: Path, names: tuple[str, str], cert: x509.Certificate, key: ec.EllipticCurvePrivateKey) -> None:
    """``names``: (certificate file, key file); the key is 0600."""
    cert_name, key_name = names
    atomic_write(folder / key_name, _key_pem(key), mode=0o600)
    atomic_write(folder / cert_name, cert.public_bytes(serialization.Encoding.PEM), mode=0o644)


def _authority(folder: Path, hosts: list[str]) -> tuple[x509.Certificate, ec.EllipticCurvePrivateKey, bool]:
    """The folder's authority and whether it replaced another: made on first use, or when the one
    there is unreadable, expired, or its name constraints do not cover every one of ``hosts``."""
    try:
        cert = x509.load_pem_x509_certificate((folder / CA_CERT).read_bytes())
        key = serialization.load_pem_private_key((folder / CA_KEY).read_bytes(), password=None)
        live = cert.not_valid_after_utc > dt.datetime.now(dt.UTC)
        if isinstance(key, ec.EllipticCurvePrivateKey) and live and all(authority_permits(cert, h) for h in hosts):
            return cert, key, False
    except (OSError, ValueError):
        pass
    replaced = (folder / CA_CERT).exists()
    key = ec.generate_private_key(ec.SECP256R1())
    own = list(dict.fromkeys([*hosts, *served_hosts("0.0.0.0")]))  # a loopback run's authority serves the LAN too
    cert = _certificate(f"PMK dashboard CA ({socket.gethostname()})", key, None, key, CA_DAYS, own)
    _write_pair(folder, (CA_CERT, CA_KEY), cert, key)
    return cert, key, replaced


def _current(folder: Path, ca: x509.Certificate, hosts: list[str]) -> x509.Certificate | None:
    """The folder's server certificate when it is the authority's, names every host and is not near its end."""
    try:
        cert = x509.load_pem_x509_certificate((folder / CERT).read_bytes())
        (folder / KEY).stat()
        cert.verify_directly_issued_by(ca)
    except (OSError, ValueError, TypeError, InvalidSignature):
        return None
    fresh = cert.not_valid_after_utc - dt.datetime.now(dt.UTC) > dt.timedelta(days=RENEW_DAYS)
    return cert if fresh and set(hosts) <= set(certificate_names(cert)) else None


def self_signed(folder: Path, hosts: list[str]) -> TlsFiles:
    """The server certificate in ``folder`` for ``hosts``: reused when it already names them all, else made
    (keeping the names it had, so a tablet using an old name still gets through)."""
    private_dir(folder, tighten=True)
    ca, ca_key, replaced_authority = _authority(folder, hosts)
    cert = _current(folder, ca, hosts)
    created = cert is None
    if cert is None:
        old: tuple[str, ...] = ()
        try:
            old = certificate_names(x509.load_pem_x509_certificate((folder / CERT).read_bytes()))
        except (OSError, ValueError):
            pass
        names = list(dict.fromkeys([*hosts, *(n for n in old if authority_permits(ca, n))]))
        key = ec.generate_private_key(ec.SECP256R1())
        cert = _certificate(f"PMK dashboard ({socket.gethostname()})", key, ca, ca_key, CERT_DAYS, names)
        _write_pair(folder, (CERT, KEY), cert, key)
    return TlsFiles(
        folder / CERT,
        folder / KEY,
        fingerprint(cert),
        certificate_names(cert),
        ca_file=folder / CA_CERT,
        ca_fingerprint=fingerprint(ca),
        created=created,
        replaced_authority=replaced_authority,
    )


def tls_folder(env: dict[str, str]) -> Path:
    """``tls/`` in the config folder the dashboard uses (``--config-dir``/``$PMK_CONFIG_DIR`` or the user's)."""
    from pmk_nb.chair import config_dir

    configured = env.get("PMK_CONFIG_DIR")
    return (Path(configured).expanduser() if configured else config_dir()) / TLS_DIR


def wants_tls(args: argparse.Namespace) -> bool:
    """Whether the command line asks for HTTPS (``--https`` or ``--certfile``)."""
    return bool(getattr(args, "https", False) or getattr(args, "certfile", None))


def resolve_tls(args: argparse.Namespace, env: dict[str, str]) -> TlsFiles | None:
    """The certificate to serve for these options, or None for plain HTTP.

    Raises:
        ServingRefused: ``--certfile`` without ``--keyfile`` (or the other way), both with ``--https``,
            or files that are not a matching pair.
    """
    certfile, keyfile = getattr(args, "certfile", None), getattr(args, "keyfile", None)
    if getattr(args, "https", False):
        if certfile or keyfile:
            raise _refused("give either --https (a certificate made here) or --certfile/--keyfile, not both")
        return self_signed(tls_folder(env), served_hosts(args.ip))
    if bool(certfile) != bool(keyfile):
        raise _refused("--certfile and --keyfile go together")
    if certfile and keyfile:
        return load_pair(Path(certfile).expanduser(), Path(keyfile).expanduser())
    return None
