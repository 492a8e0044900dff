"""TLS to the tablet (issue 24): the certificate made once and reused, a given pair checked, plain HTTP
beyond loopback refused without --insecure, what ``pmk dashboard`` prints (fingerprint, QR code)."""

from __future__ import annotations

import argparse
import hashlib
import ipaddress
import json
import socket
import ssl
import threading
from pathlib import Path

import pytest
from cryptography import x509

from pmk_nb.cli import main
from pmk_nb.serve import tablet_tls
from pmk_nb.serve.procs import free_port
from pmk_nb.serve.serving import ServingRefused, check_transport, qr_lines, url_lines
from pmk_nb.serve.voila import preflight, server_config, tls_lines, voila_command
from pmk_nb.serve.voila_guard import certificate_hosts
from pmk_nb.serve.voila_tls import server_context


def _https_args(ip: str = "127.0.0.1", **more: object) -> argparse.Namespace:
    options = {"ip": ip, "token": None, "port": free_port(), "https": True, "certfile": None, "keyfile": None}
    return argparse.Namespace(**{**options, **more})


def _handshake(tls: tablet_tls.TlsFiles, server_hostname: str) -> str:
    """A real TLS handshake on 127.0.0.1 against ``tls``, the client trusting only its authority; the
    server certificate's SHA-256 as the client saw it."""
    context = server_context(str(tls.certfile), str(tls.keyfile))
    with socket.create_server(("127.0.0.1", 0)) as listener:
        port = listener.getsockname()[1]

        def accept() -> None:
            conn, _ = listener.accept()
            with conn, context.wrap_socket(conn, server_side=True) as tls_conn:
                tls_conn.recv(1)

        server = threading.Thread(target=accept, daemon=True)
        server.start()
        client = ssl.create_default_context(cafile=str(tls.ca_file))
        with (
            socket.create_connection(("127.0.0.1", port), timeout=10) as raw,
            client.wrap_socket(raw, server_hostname=server_hostname) as conn,
        ):
            der = conn.getpeercert(binary_form=True)
            conn.sendall(b"x")
        server.join(10)
    assert der is not None
    return hashlib.sha256(der).digest().hex(":").upper()


def test_https_makes_a_certificate_once_in_the_config_folder_and_reuses_it(tmp_path: Path) -> None:
    env = {"PMK_CONFIG_DIR": str(tmp_path / "config")}
    made = tablet_tls.resolve_tls(_https_args("0.0.0.0"), env)
    assert made is not None and made.created and made.ca_file is not None
    folder = tmp_path / "config" / tablet_tls.TLS_DIR
    assert made.certfile.parent == folder and (folder.stat().st_mode & 0o777) == 0o700
    for key in (made.keyfile, folder / tablet_tls.CA_KEY):
        assert key.stat().st_mode & 0o777 == 0o600
    # valid for every name and address the server is reached by, and the fingerprint is the DER's SHA-256
    assert set(tablet_tls.served_hosts("0.0.0.0")) <= set(made.names)
    assert {"localhost", "127.0.0.1", socket.gethostname().lower()} <= set(made.names)
    der = ssl.PEM_cert_to_DER_cert(made.certfile.read_text())
    assert made.fingerprint == hashlib.sha256(der).digest().hex(":").upper()
    assert _handshake(made, "localhost") == made.fingerprint  # the authority vouches for it, by name
    # a later run (loopback: names already covered) reuses it unchanged
    files = {p.name: p.read_bytes() for p in folder.iterdir()}
    again = tablet_tls.resolve_tls(_https_args(), env)
    assert again is not None and not again.created and again.fingerprint == made.fingerprint
    assert {p.name: p.read_bytes() for p in folder.iterdir()} == files
    assert not again.replaced_authority
    # a new address in a network the authority covers: a new server certificate under the same
    # authority (the tablet's trust survives a new DHCP lease), keeping the old names
    newer = tablet_tls.self_signed(folder, ["localhost", "192.168.77.20"])
    assert tablet_tls.self_signed(folder, ["localhost", "192.168.77.21"]).ca_fingerprint == newer.ca_fingerprint
    newer = tablet_tls.self_signed(folder, ["localhost", "192.168.77.22"])
    assert newer.created and not newer.replaced_authority and {"192.168.77.20", "192.168.77.22"} <= set(newer.names)
    # a name the authority does not cover: a new authority (the tablet must trust it again)
    other = tablet_tls.self_signed(folder, ["tablet-gw.example"])
    assert other.created and other.replaced_authority and other.ca_fingerprint != made.ca_fingerprint
    assert "tablet-gw.example" in other.names and "192.168.77.22" not in other.names
    assert _handshake(other, "tablet-gw.example") == other.fingerprint
    assert certificate_hosts(str(other.certfile)) == other.names  # what the server's Host check accepts


def test_a_given_certificate_is_checked_before_anything_starts(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    made = tablet_tls.self_signed(tmp_path / "a", ["localhost"])
    other = tablet_tls.self_signed(tmp_path / "b", ["localhost"])
    from cryptography.hazmat.primitives import serialization

    key = serialization.load_pem_private_key(made.keyfile.read_bytes(), password=None)
    pem = serialization.PrivateFormat.PKCS8
    locked = key.private_bytes(serialization.Encoding.PEM, pem, serialization.BestAvailableEncryption(b"secret"))
    (tmp_path / "locked.key").write_bytes(locked)
    given = tablet_tls.resolve_tls(_https_args(https=False, certfile=str(made.certfile), keyfile=str(made.keyfile)), {})
    assert given is not None and given.fingerprint == made.fingerprint and given.ca_file is None
    bad_cases = [
        {"https": False, "certfile": str(made.certfile), "keyfile": str(other.keyfile)},  # not its key
        {"https": False, "certfile": str(made.certfile), "keyfile": str(tmp_path / "locked.key")},  # no prompt
        {"https": False, "certfile": str(made.keyfile), "keyfile": str(made.keyfile)},  # not a certificate
        {"https": False, "certfile": str(tmp_path / "missing.crt"), "keyfile": str(made.keyfile)},
        {"https": False, "certfile": str(made.certfile), "keyfile": None},  # half a pair
        {"https": True, "certfile": str(made.certfile), "keyfile": str(made.keyfile)},  # both ways at once
    ]
    for case in bad_cases:
        with pytest.raises(ServingRefused) as caught:
            tablet_tls.resolve_tls(_https_args(**case), {})
        assert caught.value.reason == "bad-certificate" and "\n" not in str(caught.value), case
    assert tablet_tls.resolve_tls(_https_args(https=False), {}) is None  # plain HTTP
    # through the command line: one line, exit 2, before Voilà starts
    argv = ["dashboard", "--certfile", str(made.certfile), "--keyfile", str(other.keyfile), "--no-browser"]
    assert main([*argv, "--port", str(free_port())]) == 2
    err = capsys.readouterr().err.strip()
    assert str(other.keyfile) in err and len(err.splitlines()) == 1


def test_beyond_loopback_plain_http_needs_insecure(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(ServingRefused) as caught:
        check_transport("0.0.0.0", tls=False, insecure=False)
    assert caught.value.reason == "plain-http" and caught.value.ip == "0.0.0.0"
    check_transport("0.0.0.0", tls=True, insecure=False)
    check_transport("0.0.0.0", tls=False, insecure=True)
    for loopback in ("127.0.0.1", "localhost", "::1"):
        check_transport(loopback, tls=False, insecure=False)  # loopback stays HTTP by default
    # through the command line: one line on stderr, exit 2; --insecure or --https get past the check
    port = str(free_port())
    assert main(["dashboard", "--ip", "0.0.0.0", "--token", "auto", "--port", port, "--no-browser"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--insecure" in err and "--https" in err and len(err.splitlines()) == 1
    lan = argparse.Namespace(ip="0.0.0.0", token="t" * 20, port=free_port(), https=False, certfile=None)
    with pytest.raises(ServingRefused):
        preflight(lan, {})
    assert preflight(argparse.Namespace(**{**vars(lan), "insecure": True}), {}) == "t" * 20
    assert preflight(argparse.Namespace(**{**vars(lan), "https": True}), {}) == "t" * 20
    # pmk demo binds loopback by default (HTTP, as before); on the LAN it follows the same rule
    from pmk_nb.cli import build_parser

    demo = build_parser("demo").parse_args(["demo", "--port", port])
    assert demo.ip == "127.0.0.1" and preflight(demo, {}, kiosk=True)
    demo_lan = build_parser("demo").parse_args(["demo", "--ip", "0.0.0.0", "--token", "auto", "--port", port])
    with pytest.raises(ServingRefused):
        preflight(demo_lan, {})


def _modules(lines: list[str]) -> list[list[bool]]:
    """The dark modules drawn by :func:`qr_lines` (two rows a character), read back from the characters."""
    top = {"\u2588": False, "\u2580": False, "\u2584": True, " ": True}
    bottom = {"\u2588": False, "\u2580": True, "\u2584": False, " ": True}
    rows = []
    for line in lines:
        rows += [[top[c] for c in line], [bottom[c] for c in line]]
    return rows


def test_the_printed_lines_carry_the_https_url_fingerprint_and_a_qr_code_of_the_url(tmp_path: Path) -> None:
    import segno

    token = "k" * 24
    local = f"PMK dashboard: https://127.0.0.1:8866/?token={token}  (Ctrl-C to stop)"
    assert url_lines("127.0.0.1", 8866, token, "https") == [local]
    lan = url_lines("0.0.0.0", 8866, token, "https")
    assert all(line.split(": ", 1)[1].startswith("https://") and f"?token={token}" in line for line in lan)
    made = tablet_tls.self_signed(tmp_path, tablet_tls.served_hosts("0.0.0.0"))
    lines = tls_lines("0.0.0.0", 8866, token, made, color=False)
    assert lines[0] == f"  new certificate SHA-256: {made.fingerprint}"
    assert str(made.ca_file) in lines[1] and str(made.ca_fingerprint) in lines[1]
    url = lines[2].split(": ", 1)[1]
    assert url.startswith("https://") and url.endswith(f":8866/?token={token}")
    host = url.split("//", 1)[1].rsplit(":", 1)[0]
    assert host in made.names  # the QR code's address is one the certificate vouches for
    drawn = _modules(lines[3:])
    expected = [[bool(m) for m in row] for row in segno.make(url, error="m").matrix_iter(scale=1, border=4)]
    assert drawn[: len(expected)] == expected and not any(drawn[len(expected) :][0])
    # reused: no longer "new"; on loopback: no QR code (no tablet reaches it), still the fingerprints
    reused = tablet_tls.self_signed(tmp_path, ["localhost"])
    assert tls_lines("127.0.0.1", 8866, token, reused, color=False) == [lines[0].replace(" new", ""), lines[1]]
    assert qr_lines(url, color=True)[0].startswith("\x1b[")


def test_voila_is_started_with_the_certificate_in_its_config_only_when_asked(tmp_path: Path) -> None:
    made = tablet_tls.self_signed(tmp_path, ["localhost", "127.0.0.1", "pmk.ward.example"])
    tornado = server_config("t" * 20, "127.0.0.1", made)["Voila"]["tornado_settings"]  # type: ignore[index]
    assert tornado["ssl_options"] == {"certfile": str(made.certfile), "keyfile": str(made.keyfile)}
    # jupyter_server's own Host check (loopback) lets the certificate's names through, addresses stay its own
    assert tornado["local_hostnames"] == ["localhost", "pmk.ward.example"]
    assert "ssl_options" not in json.dumps(server_config("t" * 20, "127.0.0.1"))
    assert voila_command(tmp_path / "d.ipynb", tls=True)[1:3] == ["-m", "pmk_nb.serve.voila_tls"]
    assert voila_command(tmp_path / "d.ipynb")[1:3] == ["-m", "voila"]


def _signed_by(folder: Path, host: str) -> x509.Certificate:
    """A server certificate for ``host`` signed with the authority's key: what anyone holding that
    key (a stolen laptop, a leaked backup) could make."""
    import datetime as dt
    import ipaddress

    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

    ca = x509.load_pem_x509_certificate((folder / tablet_tls.CA_CERT).read_bytes())
    ca_key = serialization.load_pem_private_key((folder / tablet_tls.CA_KEY).read_bytes(), password=None)
    assert isinstance(ca_key, ec.EllipticCurvePrivateKey)
    try:
        alt: x509.GeneralName = x509.IPAddress(ipaddress.ip_address(host))
    except ValueError:
        alt = x509.DNSName(host)
    key = ec.generate_private_key(ec.SECP256R1())
    now = dt.datetime.now(dt.UTC)
    return (
        x509.CertificateBuilder()
        .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, host)]))
        .issuer_name(ca.subject)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - dt.timedelta(minutes=5))
        .not_valid_after(now + dt.timedelta(days=30))
        .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
        .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH]), critical=False)
        .add_extension(x509.SubjectAlternativeName([alt]), critical=False)
        .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(ca_key.public_key()), critical=False)
        .sign(ca_key, hashes.SHA256())
    )


def _verified(folder: Path, cert: x509.Certificate, host: str) -> bool:
    """cryptography's own path validation (RFC 5280 + CA/B Forum), the authority as the only root."""
    import datetime as dt
    import ipaddress

    from cryptography.x509 import verification

    ca = x509.load_pem_x509_certificate((folder / tablet_tls.CA_CERT).read_bytes())
    try:
        subject: verification.Subject = verification.IPAddress(ipaddress.ip_address(host))
    except ValueError:
        subject = verification.DNSName(host)
    verifier = (
        verification.PolicyBuilder()
        .store(verification.Store([ca]))
        .time(dt.datetime.now(dt.UTC))
        .build_server_verifier(subject)
    )
    try:
        verifier.verify(cert, [])
    except verification.VerificationError:
        return False
    return True


def _openssl_verifies(folder: Path, cert: x509.Certificate, tmp_path: Path) -> bool:
    import shutil
    import subprocess

    from cryptography.hazmat.primitives import serialization

    openssl = shutil.which("openssl")
    assert openssl, "openssl is needed to check the authority's name constraints (apt-get install openssl)"
    leaf = tmp_path / "leaf.pem"
    leaf.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    run = subprocess.run(
        [openssl, "verify", "-CAfile", str(folder / tablet_tls.CA_CERT), "-purpose", "sslserver", str(leaf)],
        capture_output=True,
        text=True,
        timeout=30,
        check=False,
    )
    return run.returncode == 0


LAB_HOSTS = ["localhost", "127.0.0.1", "::1", "chair-pc", "chair-pc.local", "192.168.1.20"]


def test_the_authority_vouches_only_for_the_dashboards_own_names_and_networks(tmp_path: Path) -> None:
    """Issue 38: a tablet that installed the authority trusted it for every site."""
    folder = tmp_path / "tls"
    made = tablet_tls.self_signed(folder, LAB_HOSTS)
    ca = x509.load_pem_x509_certificate((folder / tablet_tls.CA_CERT).read_bytes())
    ext = ca.extensions.get_extension_for_class(x509.NameConstraints)
    assert ext.critical and ext.value.excluded_subtrees is None
    permitted = list(ext.value.permitted_subtrees or [])
    names = {t.value for t in permitted if isinstance(t, x509.DNSName)}
    networks = {t.value for t in permitted if isinstance(t, x509.IPAddress)}
    own = set(tablet_tls.served_hosts("0.0.0.0")) | set(LAB_HOSTS)
    assert {"localhost", "chair-pc", "chair-pc.local"} <= names <= own
    lab_nets = {ipaddress.ip_network(n) for n in ("127.0.0.1/32", "::1/128", "192.168.1.0/24")}
    assert lab_nets <= networks
    assert all(n.prefixlen >= (24 if n.version == 4 else 64) for n in networks)  # never a wide range
    assert len(permitted) == len(names) + len(networks)  # no other kind of name is vouched for
    served = x509.load_pem_x509_certificate(made.certfile.read_bytes())
    for host in ("localhost", "chair-pc.local", "192.168.1.20", "::1"):
        assert _verified(folder, served, host), host
    assert _openssl_verifies(folder, served, tmp_path)
    # the key in the wrong hands still cannot vouch for another site, name or address
    for host in ("bank.example", "www.google.com", "chair-pc.evil.example", "8.8.8.8", "192.168.2.7", "10.0.0.1"):
        forged = _signed_by(folder, host)
        assert not _verified(folder, forged, host), host
        assert not _openssl_verifies(folder, forged, tmp_path), host
    # within its names (a subdomain of its own name) a certificate it signs is valid, as the constraints say
    assert _verified(folder, _signed_by(folder, "tablet.chair-pc.local"), "tablet.chair-pc.local")


def test_an_authority_without_name_constraints_is_replaced(tmp_path: Path) -> None:
    """One made before the constraints is not kept: it would still vouch for every site."""
    import datetime as dt

    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import NameOID

    folder = tmp_path / "tls"
    folder.mkdir(mode=0o700)
    key = ec.generate_private_key(ec.SECP256R1())
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "PMK dashboard CA (old)")])
    now = dt.datetime.now(dt.UTC)
    old = (
        x509.CertificateBuilder()
        .subject_name(name)
        .issuer_name(name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - dt.timedelta(days=1))
        .not_valid_after(now + dt.timedelta(days=3000))
        .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
        .sign(key, hashes.SHA256())
    )
    pkcs8 = serialization.PrivateFormat.PKCS8
    (folder / tablet_tls.CA_KEY).write_bytes(
        key.private_bytes(serialization.Encoding.PEM, pkcs8, serialization.NoEncryption())
    )
    (folder / tablet_tls.CA_CERT).write_bytes(old.public_bytes(serialization.Encoding.PEM))
    made = tablet_tls.self_signed(folder, LAB_HOSTS)
    assert made.replaced_authority and made.ca_fingerprint != tablet_tls.fingerprint(old)
    ca = x509.load_pem_x509_certificate((folder / tablet_tls.CA_CERT).read_bytes())
    assert ca.extensions.get_extension_for_class(x509.NameConstraints).critical
    again = tablet_tls.self_signed(folder, LAB_HOSTS)
    assert not again.replaced_authority and not again.created  # kept from now on
    lines = tls_lines("127.0.0.1", 8866, None, made)
    assert any(line.startswith("  a new authority to trust on the tablet (again): ") for line in lines)
    assert any(
        line.startswith("  to trust on the tablet (once): ") for line in tls_lines("127.0.0.1", 8866, None, again)
    )
