"""Issue 24: wss to the chair. The real link (roslibpy on its private loop) against the simulator
serving TLS: first contact refused until a person pins the certificate, then a changed certificate
refused with both fingerprints; trust by a CA file; and the link's own socket checked, not only
the probe's."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from pmk_nb.chair.link.client import ChairLink, LinkState
from pmk_nb.chair.link.transport.ros import LinkRos
from pmk_nb.chair.link.transport.tls import ChairTls, pinned, trust_certificate
from pmk_nb.errors import (
    ChairCertificateChanged,
    ChairCertificateUntrusted,
    ChairLinkError,
    UnknownChairCertificate,
)
from pmk_nb.sim import SimChair
from pmk_nb.tlscert import file_fingerprint, write_self_signed
from tests.helpers import wait_until

NAMES = ("127.0.0.1", "localhost")


@pytest.fixture
def certs(tmp_path: Path) -> Callable[[str], tuple[Path, Path]]:
    """``certs("a")`` -> a fresh self-signed (certfile, keyfile) for 127.0.0.1."""
    return lambda stem: write_self_signed(tmp_path / "certs", NAMES, stem=stem)


def _link(sim: SimChair, tls: ChairTls) -> ChairLink:
    return ChairLink("127.0.0.1", sim.port, tls=tls, reconnect_initial=0.2)


def test_wss_link_pins_on_first_use_then_refuses_a_changed_certificate(
    sim_factory: Any, certs: Any, tmp_path: Path
) -> None:
    cert_a, cert_b = certs("a"), certs("b")
    sim = sim_factory(tls=cert_a)
    assert sim.url.startswith("wss://")
    tls = ChairTls(known_certs=tmp_path / "cfg" / "known_certs")
    link = _link(sim, tls)
    try:
        with pytest.raises(UnknownChairCertificate) as first:
            link.connect(timeout=5.0)
        unknown = first.value
        assert (unknown.host, unknown.port, unknown.presented) == ("127.0.0.1", sim.port, file_fingerprint(cert_a[0]))
        assert not tls.known_certs.exists() and sim.client_count == 0  # nothing trusted, no link opened

        trust_certificate(unknown)  # what a person's "Trust" does
        assert pinned(tls, "127.0.0.1", sim.port) == unknown.presented
        assert tls.known_certs.stat().st_mode & 0o077 == 0
        link.connect(timeout=5.0)  # over wss now: a real rosbridge round trip
        info = link.map_info(5.0)
        assert info.width > 0 and link.is_connected

        sim.stop()
        sim.tls = cert_b  # the "chair" now presents another certificate on the same address
        sim.start()
        ros = link.ros  # roslibpy reconnects by itself: that socket is checked too
        assert ros is not None
        wait_until(lambda: ros.refusal is not None, timeout=15.0, what="the reconnect's refusal")
        assert isinstance(ros.refusal, ChairCertificateChanged) and not link.is_connected
        assert link.state is LinkState.DISCONNECTED  # not "connecting" forever: reconnects stopped
        assert sim.client_count == 0
        link.close()
        with pytest.raises(ChairCertificateChanged) as changed:
            link.connect(timeout=5.0)
        err = changed.value
        assert err.expected == unknown.presented and err.presented == file_fingerprint(cert_b[0])
        assert err.expected != err.presented and err.known_certs == str(tls.known_certs)
        assert pinned(tls, "127.0.0.1", sim.port) == unknown.presented  # the pin is never replaced silently
        report = link.test_connection(timeout=5.0)  # the Settings verb: the same typed error, not raised
        assert not report.ok and isinstance(report.error, ChairCertificateChanged)
    finally:
        link.close()


def test_the_links_own_socket_is_checked_not_only_the_probe(sim_factory: Any, certs: Any, tmp_path: Path) -> None:
    """A certificate swapped after the probe: the link's own TLS socket is refused before any
    websocket byte (the sim never sees a client) and roslibpy stops reconnecting."""
    cert_a, cert_b = certs("a"), certs("b")
    sim = sim_factory(tls=cert_a)
    store = tmp_path / "known_certs"
    store.write_text(f"[127.0.0.1]:{sim.port} sha256 {file_fingerprint(cert_b[0])}\n")
    ros = LinkRos("127.0.0.1", sim.port, thread_name="test-tls-io", tls=ChairTls(known_certs=store))
    try:
        ros.connect()
        assert ros.settled.wait(5.0)
        assert isinstance(ros.refusal, ChairCertificateChanged)
        assert ros.refusal.presented == file_fingerprint(cert_a[0])
        assert not ros.is_connected and sim.client_count == 0 and ros.factory._stop
    finally:
        ros.shutdown(1.0)


def test_ca_file_trust_needs_no_pin_and_refuses_another_issuer(sim_factory: Any, certs: Any, tmp_path: Path) -> None:
    cert_a, cert_b = certs("a"), certs("b")
    sim = sim_factory(tls=cert_a)
    store = tmp_path / "known_certs"
    with _link(sim, ChairTls(known_certs=store, ca_file=str(cert_a[0]))) as link:
        link.connect(timeout=5.0)
        assert link.map_info(5.0).width > 0
    assert not store.exists()  # a CA-checked chair is not pinned
    other_ca = ChairTls(known_certs=store, ca_file=str(cert_b[0]))
    with _link(sim, other_ca) as link, pytest.raises(ChairCertificateUntrusted) as untrusted:
        link.connect(timeout=5.0)
    assert untrusted.value.ca_file == str(cert_b[0]) and untrusted.value.reason
    assert sim.client_count == 0


def test_scheme_mismatch_is_named_both_ways(sim_factory: Any, certs: Any, tmp_path: Path) -> None:
    """ws to a wss bridge and wss to a ws bridge: failures that say to switch TLS, not a vague timeout."""
    tls_sim = sim_factory(tls=certs("a"))
    plain_sim = sim_factory()
    with ChairLink("127.0.0.1", tls_sim.port) as link:
        report = link.test_connection(timeout=3.0)
    assert not report.ok and "TLS on" in report.reason and report.error is None
    with _link(plain_sim, ChairTls(known_certs=tmp_path / "k")) as link, pytest.raises(ChairLinkError) as err:
        link.connect(timeout=3.0)
    assert type(err.value) is ChairLinkError and "TLS handshake" in str(err.value)


def test_trusting_never_replaces_a_pin_made_meanwhile(tmp_path: Path) -> None:
    """Two pages asked about the same first certificate... and another one was pinned in between:
    "Trust" on the stale question refuses as a change instead of adding a second pin."""
    store = tmp_path / "known_certs"
    first, other = "AA:" * 31 + "AA", "BB:" * 31 + "BB"
    store.write_text(f"[127.0.0.1]:9 sha256 {first}\n")
    stale = UnknownChairCertificate("first", host="127.0.0.1", port=9, presented=other, known_certs=str(store))
    with pytest.raises(ChairCertificateChanged):
        trust_certificate(stale)
    trust_certificate(
        UnknownChairCertificate("same", host="127.0.0.1", port=9, presented=first, known_certs=str(store))
    )
    assert store.read_text() == f"[127.0.0.1]:9 sha256 {first}\n"


@pytest.mark.slow
def test_wss_on_the_twisted_transport_is_refused_with_the_reason(tmp_path: Path) -> None:
    """A process where Twisted came first (a plain roslibpy.Ros): a wss link says why it cannot run,
    instead of connecting without the certificate check. A subprocess: the binding is process-wide."""
    import subprocess
    import sys

    code = (
        "import roslibpy.comm.comm_autobahn\n"  # what a plain roslibpy.Ros imports: Twisted bound
        "from pathlib import Path\n"
        "from pmk_nb.chair.link.transport.tls import ChairTls\n"
        "from pmk_nb.chair.link.transport.ros import LinkRos\n"
        "from pmk_nb.errors import ChairLinkError\n"
        "try:\n"
        f"    LinkRos('127.0.0.1', 9, thread_name='t', tls=ChairTls(Path({str(tmp_path / 'k')!r})))\n"
        "except ChairLinkError as err:\n"
        "    print('refused', err.host, err.port)\n"
    )
    root = Path(__file__).resolve().parents[3]
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=root)
    assert done.stdout.strip() == "refused 127.0.0.1 9", done.stdout + done.stderr
