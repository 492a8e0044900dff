"""Voilà over HTTPS: ``python -m pmk_nb.serve.voila_tls`` is Voilà serving ``tornado_settings.ssl_options``.

Voilà 0.5 has no TLS option of its own: its ``tornado_settings`` help promises "ssl", but its
``listen()`` calls tornado's ``Application.listen(port, ip)`` without the ``ssl_options`` tornado's
HTTP server takes (its ``_url`` even carries "TODO: https / certfile").  This subclass hands
``Voila.tornado_settings["ssl_options"]`` (``{"certfile": ..., "keyfile": ...}``, tornado's own form)
to the server and says ``https`` in Voilà's log; everything else is Voilà's.  The options come from
``voila.json`` (:func:`pmk_nb.serve.voila.server_config`), never the command line.
Kernel websockets follow the page's scheme (``wss:``): the page builds their URL from its location.
"""

from __future__ import annotations

import functools
import ssl

from pmk_nb.seams import UrlHookVoila

SSL_OPTIONS = "ssl_options"


def server_context(certfile: str, keyfile: str) -> ssl.SSLContext:
    """A server-side context with Python's defaults (TLS 1.2 or newer, no compression)."""
    context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
    context.load_cert_chain(certfile, keyfile)
    return context


class TlsVoila(UrlHookVoila):
    """Voilà serving HTTPS when its tornado settings carry ``ssl_options`` (plain Voilà otherwise)."""

    @property
    def tls(self) -> dict[str, str] | None:
        options = self.tornado_settings.get(SSL_OPTIONS)
        return options if isinstance(options, dict) and options.get("certfile") else None

    def listen(self) -> None:
        if self.tls:
            context = server_context(self.tls["certfile"], self.tls["keyfile"])
            self.app.listen = functools.partial(self.app.listen, ssl_options=context)
        super().listen()

    def public_url(self, url: str) -> str:
        return "https" + url.removeprefix("http") if self.tls else url


main = TlsVoila.launch_instance

if __name__ == "__main__":
    main()
