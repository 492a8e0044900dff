"""Tokens are masked in the dashboard server's log (issue 38, low: Voilà logged full ``?token=`` URLs on 4xx)."""

from __future__ import annotations

import io
import logging
import subprocess
import sys

from pmk_nb.serve.tokenmask import MASK, TokenMask, logging_config, mask_tokens
from pmk_nb.serve.voila import server_config

SECRET = "Zq8sK2-secret_TOKEN"


def test_every_token_value_is_masked_and_the_rest_kept() -> None:
    line = f"404 GET /api/kernels/k/channels?session_id=s&token={SECRET}&x=1 (127.0.0.1) 3.0ms"
    assert mask_tokens(line) == f"404 GET /api/kernels/k/channels?session_id=s&token={MASK}&x=1 (127.0.0.1) 3.0ms"
    for text in (
        f"/login?next=%2F%3Ftoken%3D{SECRET}",
        f"uri='/?TOKEN={SECRET}', version='HTTP/1.1'",
        f"http://127.0.0.1:8866/?token={SECRET}",
    ):
        masked = mask_tokens(text)
        assert SECRET not in masked and MASK in masked, masked
    assert mask_tokens("GET /voila/static/x.js (127.0.0.1)") == "GET /voila/static/x.js (127.0.0.1)"


def test_the_filter_masks_message_arguments_and_traceback() -> None:
    out = io.StringIO()
    handler = logging.StreamHandler(out)
    handler.addFilter(TokenMask())
    log = logging.getLogger("pmk-test-tokenmask")
    log.propagate = False
    log.addHandler(handler)
    try:
        log.warning("%d %s", 404, f"GET /?token={SECRET} (127.0.0.1)")
        try:
            raise ValueError(f"/x?token={SECRET}")
        except ValueError:
            log.exception("Uncaught exception")
    finally:
        log.removeHandler(handler)
    text = out.getvalue()
    assert SECRET not in text
    assert f"404 GET /?token={MASK} (127.0.0.1)" in text and f"ValueError: /x?token={MASK}" in text


def test_voilas_config_masks_tokens_in_its_own_and_tornados_lines() -> None:
    """The served config's logging section, applied as Voilà applies it (dictConfig after its defaults)."""
    voila = server_config("t" * 20)["Voila"]
    assert isinstance(voila, dict) and voila["logging_config"] == logging_config()
    script = f"""
import logging
from traitlets.config import Application
from tornado.log import access_log, app_log
class Voila(Application):
    pass
app = Voila(logging_config={logging_config()!r})
app.log.warning("running at http://127.0.0.1:1/?token={SECRET}")
access_log.warning("403 GET /?token={SECRET} (127.0.0.1) 1.0ms")
app_log.error("Uncaught exception GET /?token={SECRET}")
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=True)
    assert SECRET not in done.stderr, done.stderr
    assert f"403 GET /?token={MASK} (127.0.0.1) 1.0ms" in done.stderr and done.stderr.count(MASK) == 3, done.stderr
