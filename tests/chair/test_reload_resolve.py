"""The one reload-service resolver (pmk_nb.chair.link.query.reload.resolve), as deploy and ChairLink use it."""

from __future__ import annotations

import pytest

from pmk_nb.chair.link.query import reload
from pmk_nb.chair.link.query.reload import RELOAD_KINDS, MapReloadError, ReloadService, resolve

TYPES = {
    "/change_map": "nav_msgs/LoadMap",
    "/map_server/load_map": "nav2_msgs/srv/LoadMap",
    "/map_update": "pmk/MapUpdate",
    "/robot/swap_map": "nav2_msgs/srv/LoadMap",
}


def test_kinds_are_the_reload_protocols() -> None:
    assert RELOAD_KINDS == ("ros1", "nav2", "mapupdate")
    assert set(reload.SERVICE_TYPES) == set(RELOAD_KINDS)


def test_detects_the_preferred_service() -> None:
    assert resolve(["/rosapi/topics", "/map_update", "/change_map"], TYPES.get) == ReloadService("/change_map", "ros1")


def test_named_service_takes_its_kind_from_rosapi_then_its_name() -> None:
    assert resolve(list(TYPES), TYPES.get, service="robot/swap_map") == ReloadService("/robot/swap_map", "nav2")
    assert resolve(["/x/change_map"], lambda _: None, service="/x/change_map") == ReloadService("/x/change_map", "ros1")
    assert resolve(["/odd"], lambda _: None, service="/odd", kind="mapupdate") == ReloadService("/odd", "mapupdate")


def test_named_service_must_exist_and_be_understood() -> None:
    with pytest.raises(MapReloadError, match="has no service /nope") as info:
        resolve(list(TYPES), TYPES.get, service="/nope")
    assert info.value.keeps_old_map is True and "keeps its previous map" in str(info.value)
    with pytest.raises(MapReloadError, match="cannot tell which reload protocol /odd"):
        resolve(["/odd"], lambda _: None, service="/odd")


def test_asked_kind_picks_its_service_or_says_what_there_is() -> None:
    both = ["/change_map", "/map_update"]
    assert resolve(both, TYPES.get, kind="mapupdate") == ReloadService("/map_update", "mapupdate")
    with pytest.raises(MapReloadError, match=r"no nav2 reload service such as /map_server/load_map.*/change_map"):
        resolve(both, TYPES.get, kind="nav2")
    with pytest.raises(MapReloadError, match="unknown reload kind"):
        resolve(both, TYPES.get, kind="ros3")


def test_nothing_to_call() -> None:
    with pytest.raises(MapReloadError, match="the chair at h:1 offers no map reload service") as info:
        resolve(["/rosapi/topics"], TYPES.get, where="the chair at h:1")
    err = info.value
    assert err.keeps_old_map is True
    assert str(err).count("keeps its previous map") == 1
    assert "keeps its previous map" not in err.detail


def test_a_refusal_keeps_the_old_map_but_an_unreadable_answer_cannot_tell() -> None:
    service = ReloadService("/change_map", "ros1")
    with pytest.raises(MapReloadError) as refused:
        reload.check_response(service, "/m.yaml", {"result": 255})
    assert refused.value.keeps_old_map is True and refused.value.code == 255
    with pytest.raises(MapReloadError) as garbled:
        reload.check_response(service, "/m.yaml", {"what": 1})
    assert garbled.value.keeps_old_map is None
    assert "keeps its previous map" not in str(garbled.value)
