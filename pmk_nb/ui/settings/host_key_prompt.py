"""The dashboard's first-use SSH host key step: the key's fingerprint is shown and confirmed first.

Issue 30: the dashboard sent maps with trust-on-first-use, so the first key any machine presented
(a spoofed chair on the same network) was recorded silently and got the upload. Here the dashboard
always connects with strict checking: an unknown key stops the send before authenticating or
uploading, the page shows its SHA256 fingerprint with how to check it on the chair, and only "Trust
and send" records THAT key (:func:`pmk_nb.chair.ssh.trust_host_key`) and sends again. A changed key
stays refused (ssh.open_sftp).

Issue 24: a ``wss://`` chair's TLS certificate gets the same step in Settings
(:class:`CertificatePrompt`): the link refuses an unknown certificate (never trusts it alone), the
page shows its SHA-256 fingerprint, and only "Trust and connect" pins THAT fingerprint
(:func:`pmk_nb.chair.link.transport.tls.trust_certificate`). A changed certificate stays refused.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import TYPE_CHECKING, TypeVar

from pmk_nb.errors import UnknownChairCertificate, UnknownHostKey
from pmk_nb.ui.common.context import needs_pin
from pmk_nb.ui.common.widgets import ConfirmBox, set_progress

if TYPE_CHECKING:
    import ipywidgets as w

    from pmk_nb.chair import ChairProfile
    from pmk_nb.ui.common.context import AppContext


def strict(profile: ChairProfile) -> ChairProfile:
    """The profile as the dashboard connects with it: unknown host keys are asked about, not recorded."""
    return dataclasses.replace(profile, host_key_check="strict")


E = TypeVar("E", bound=BaseException)


def cause_of(err: BaseException | None, kind: type[E]) -> E | None:
    """The ``kind`` error behind ``err`` (a deploy wraps the transfer's error), if any."""
    for _ in range(5):  # bounded walk down the cause chain
        if err is None or isinstance(err, kind):
            return err
        err = err.__cause__
    return None


def unknown_key(err: BaseException | None) -> UnknownHostKey | None:
    """The UnknownHostKey behind ``err``, if any."""
    return cause_of(err, UnknownHostKey)


class HostKeyPrompt:
    """A confirm box under the Maps screen's Send; ``widget`` goes in the screen."""

    def __init__(self, ctx: AppContext, bar: w.FloatProgress, status: w.HTML) -> None:
        self.ctx = ctx
        self.box = ConfirmBox(ctx, "pmk-maps-hostkey", yes="Trust and send", no="Cancel")
        self.widget = self.box.widget
        self.pending: UnknownHostKey | None = None
        self._bar, self._status = bar, status

    def ask(self, err: BaseException, retry: Callable[[], object]) -> bool:
        """Show the confirm step when ``err`` is an unknown host key; False (nothing shown) otherwise."""
        unknown = unknown_key(err)
        if unknown is None:
            return False
        self.pending = unknown
        set_progress(self._bar, None)
        self._status.value = "Confirm the chair's SSH host key (first connection) to send."
        self.box.ask(
            f"First connection to {unknown.host}: nothing was sent. The chair's SSH host key is "
            f"{unknown.key_type} {unknown.fingerprint}. Check it on the chair "
            "(ssh-keygen -lf /etc/ssh/ssh_host_ed25519_key.pub) before trusting it.",
            lambda: self._trust(unknown, retry),
        )
        return True

    @needs_pin("Trusting the chair's host key")  # it writes known_hosts: a locked kiosk page may not
    def _trust(self, unknown: UnknownHostKey, retry: Callable[[], object]) -> None:
        from pmk_nb.chair import trust_host_key

        self.pending = None
        trust_host_key(unknown)
        retry()


class CertificatePrompt:
    """A confirm box under Settings' Test connection for a wss chair's first certificate."""

    def __init__(self, ctx: AppContext) -> None:
        self.ctx = ctx
        self.box = ConfirmBox(ctx, "pmk-settings-cert", yes="Trust and connect", no="Cancel")
        self.widget = self.box.widget
        self.pending: UnknownChairCertificate | None = None

    def ask(self, err: BaseException | None, retry: Callable[[], object]) -> bool:
        """Show the confirm step when ``err`` is an unknown certificate; False (box hidden) otherwise."""
        unknown = cause_of(err, UnknownChairCertificate)
        self.pending = unknown
        if unknown is None:
            self.box.hide()
            return False
        self.box.ask(
            f"First TLS connection to {unknown.host}:{unknown.port}: nothing was sent. The chair's certificate "
            f"has the SHA-256 fingerprint {unknown.presented}. Compare it with the chair's "
            "(openssl x509 -noout -fingerprint -sha256 -in CERTFILE) before trusting it.",
            lambda: self._trust(unknown, retry),
        )
        return True

    @needs_pin("Trusting the chair's certificate")  # it writes known_certs: a locked kiosk page may not
    def _trust(self, unknown: UnknownChairCertificate, retry: Callable[[], object]) -> None:
        from pmk_nb.chair.link import trust_certificate

        self.pending = None
        trust_certificate(unknown)
        retry()
