"""The link's errors are types with facts (host, port, operation, seconds), and one registry holds links."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from pmk_nb.chair.link.client import ChairLink, MapReloadError
from pmk_nb.chair.link.query.connectivity import OPEN_WEBSOCKET, ConnectFailure
from pmk_nb.chair.link.query.reload import KEEPS_OLD_MAP, ReloadService
from pmk_nb.chair.link.registry import close_all_links, get_link, open_links, use_only
from pmk_nb.errors import ChairLinkError, ChairTimeout
from pmk_nb.sim import SimChair
from tests.chair.link.test_link_halfopen import FreezableProxy
from tests.fixtures_sim import wait_until


@pytest.fixture
def frozen_link(sim_chair: SimChair) -> Iterator[tuple[ChairLink, FreezableProxy]]:
    proxy = FreezableProxy(sim_chair.port)
    link = ChairLink("127.0.0.1", proxy.port, ping_interval=30.0, ping_timeout=30.0, rosapi_timeout=0.5)
    try:
        link.connect(timeout=10.0)
        yield link, proxy
    finally:
        proxy.frozen.clear()
        link.close()
        proxy.close()


@pytest.mark.slow
def test_a_service_that_never_answers_raises_chair_timeout(frozen_link: tuple[ChairLink, FreezableProxy]) -> None:
    link, proxy = frozen_link
    assert "/rosapi/services" in link.services()
    proxy.frozen.set()
    with pytest.raises(ChairTimeout) as info:
        link.services()
    err = info.value
    assert (err.operation, err.seconds, err.host, err.port) == ("/rosapi/services", 0.5, "127.0.0.1", proxy.port)


@pytest.mark.slow
def test_reload_timeout_and_refusal_are_told_apart_by_type(
    frozen_link: tuple[ChairLink, FreezableProxy], monkeypatch: pytest.MonkeyPatch
) -> None:
    link, proxy = frozen_link
    target = ReloadService("/change_map", "ros1")
    monkeypatch.setattr(link.discovery, "reload_target", lambda *_args: target)
    proxy.frozen.set()
    with pytest.raises(MapReloadError) as slow:
        link.reload_map("/home/pmk/ALMA_MAPS/a.yaml", timeout=0.5)
    assert isinstance(slow.value.__cause__, ChairTimeout)
    assert "may still be loading /home/pmk/ALMA_MAPS/a.yaml" in str(slow.value)
    proxy.frozen.clear()

    def refuse(*_args: object) -> dict:
        raise ChairLinkError("/change_map failed: no such service", host=link.host, port=link.port)

    monkeypatch.setattr(link, "call", refuse)
    with pytest.raises(MapReloadError) as refused:
        link.reload_map("/home/pmk/ALMA_MAPS/a.yaml", timeout=0.5)
    assert not isinstance(refused.value.__cause__, ChairTimeout) and KEEPS_OLD_MAP in str(refused.value)


def test_connect_failures_carry_host_and_port() -> None:
    refused = ConnectFailure("connection refused: nobody listens").error("10.0.0.7", 9090)
    assert type(refused) is ChairLinkError and (refused.host, refused.port) == ("10.0.0.7", 9090)
    slow = ConnectFailure("timed out opening the rosbridge websocket within 2.0 s", 2.0).error("10.0.0.7", 9090)
    assert isinstance(slow, ChairTimeout) and (slow.operation, slow.seconds) == (OPEN_WEBSOCKET, 2.0)
    assert "10.0.0.7:9090" in str(slow)


def test_not_connected_error_names_the_chair() -> None:
    link = ChairLink("127.0.0.1", 9)
    with pytest.raises(ChairLinkError) as info:
        link.services()
    assert (info.value.host, info.value.port) == ("127.0.0.1", 9)


def test_use_only_closes_links_to_other_chairs(sim_factory) -> None:
    first, second = sim_factory(), sim_factory()
    try:
        a = get_link("127.0.0.1", first.port)
        a.connect(timeout=10.0)
        b = use_only("127.0.0.1", second.port)
        assert b is not a and open_links() == [b]
        assert not a.is_connected and wait_until(lambda: first.client_count == 0, 5.0)
        assert use_only("127.0.0.1", second.port) is b  # the same chair again: the same link
    finally:
        close_all_links()
    assert open_links() == []
