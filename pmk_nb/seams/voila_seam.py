"""Voilà internals (pinned: voila==0.5.13; tests/seams/test_voila_seam.py).

Touched: ``Voila._url(ip)``, the URL Voilà logs ("Voilà is running at ..."), which says ``http``
whatever the server speaks (its source carries "TODO: https / certfile").
"""

from __future__ import annotations

from voila.app import Voila

TOUCHED = ("_url",)


class UrlHookVoila(Voila):  # type: ignore[misc]  # voila ships no type hints: its classes are Any
    """Voilà whose logged URL passes through :meth:`public_url` (unchanged here)."""

    def public_url(self, url: str) -> str:
        return url

    def _url(self, ip: str) -> str:
        return self.public_url(str(super()._url(ip)))
