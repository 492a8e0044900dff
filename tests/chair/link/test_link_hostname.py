"""A host name the resolver cannot even encode (a part over 63 characters) is a reason, not KeyError('infos')."""

from __future__ import annotations

import pytest

from pmk_nb.chair.link.client import ChairLink
from pmk_nb.chair.link.transport.probe import HOST_UNKNOWN


@pytest.mark.parametrize("host", ["chair-" + "x" * 70 + ".local", "a..b", "y" * 300])
def test_an_impossible_host_name_is_reported_in_words(host: str) -> None:
    link = ChairLink(host, 9090)
    try:
        report = link.test_connection(timeout=3.0)
    finally:
        link.close()
    assert not report.ok
    assert report.reason.startswith(HOST_UNKNOWN), report.reason
    assert "not a valid host name" in report.reason and "infos" not in report.reason
