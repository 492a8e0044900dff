"""The Voilà internal pmk_nb/seams/voila_seam.py overrides is still there, in the pinned version."""

from __future__ import annotations

import inspect

from voila.app import Voila

from pmk_nb.seams.voila_seam import TOUCHED, UrlHookVoila
from pmk_nb.serve.voila_tls import TlsVoila
from tests.seam_pins import assert_pinned_and_installed


def test_installed_voila_is_the_pinned_version() -> None:
    assert_pinned_and_installed("voila")


def test_voila_still_logs_its_url_through_url() -> None:
    assert TOUCHED == ("_url",)
    assert list(inspect.signature(Voila._url).parameters) == ["self", "ip"]
    assert 'proto = "http"' in inspect.getsource(Voila._url)  # still no https of its own
    assert "self._url(" in inspect.getsource(Voila)


def test_the_logged_url_says_https_when_serving_tls() -> None:
    plain, tls = TlsVoila(), TlsVoila()
    tls.tornado_settings = {"ssl_options": {"certfile": "c.pem", "keyfile": "k.pem"}}
    for app in (plain, tls):
        app.port, app.base_url = 8866, "/"
    assert isinstance(plain, UrlHookVoila)
    assert plain._url("127.0.0.1") == "http://127.0.0.1:8866/"
    assert tls._url("127.0.0.1") == "https://127.0.0.1:8866/"
