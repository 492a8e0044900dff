"""Chair profiles: validation, storage, last used, passwords never on disk."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pmk_nb.chair.profiles import ChairProfile, ProfileStore, config_dir, default_known_hosts
from pmk_nb.errors import SettingsError


@pytest.fixture(autouse=True)
def _config_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("PMK_CONFIG_DIR", str(tmp_path / "cfg"))
    return tmp_path / "cfg"


def chair(name: str = "alma", **kw: object) -> ChairProfile:
    values: dict[str, object] = {"host": "192.168.1.20", "ssh_user": "pmk", **kw}
    return ChairProfile(name=name, **values)  # type: ignore[arg-type]


def test_defaults_match_the_original_app(tmp_path: Path) -> None:
    p = chair()
    p.validate()
    assert (p.port, p.ssh_port, p.remote_maps_dir) == (9090, 22, "~/ALMA_MAPS")
    assert (p.reload_service, p.reload_kind, p.pose_source) == ("auto", "auto", "odometry")
    assert p.known_hosts_path == default_known_hosts() == tmp_path / "cfg" / "known_hosts"
    assert config_dir() == tmp_path / "cfg"


@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("port", 0),
        ("port", 70000),
        ("port", "9090"),
        ("ssh_port", -1),
        ("host", ""),
        ("host", "   "),
        ("host", "http://192.168.1.20"),
        ("host", "192.168.1.20:9090/x"),
        ("host", "my chair"),
        ("odom_topic", "odom"),
        ("scan_topic", "/sc an"),
        ("scan_topic", "/"),
        ("pose_source", "gps"),
        ("footprint_radius", -0.1),
        ("footprint_radius", float("nan")),
        ("auth", "token"),
        ("reload_kind", "ros3"),
        ("reload_service", "change map"),
        ("host_key_check", "never"),
        ("ssh_user", "pmk user"),
        ("goals_on_link_loss", "stop"),
        ("goal_accept_s", 0.0),
        ("goal_quiet_s", float("nan")),
    ],
)
def test_invalid_values_name_the_field(field: str, value: object) -> None:
    p = chair(**{field: value})
    with pytest.raises(SettingsError, match=rf"^{field}: invalid value"):
        p.validate()


def test_key_auth_needs_an_existing_key_file(tmp_path: Path) -> None:
    with pytest.raises(SettingsError, match=r"^key_file: .*give the private key file"):
        chair(auth="key").validate()
    with pytest.raises(SettingsError, match=r"^key_file: .*does not exist"):
        chair(auth="key", key_file=str(tmp_path / "nope")).validate()
    key = tmp_path / "id_ed25519"
    key.write_text("x")
    chair(auth="key", key_file=str(key)).validate()


def test_save_list_get_and_last_used(tmp_path: Path) -> None:
    store = ProfileStore(secrets=False)
    assert store.list() == [] and store.last_used() is None
    store.save(chair("a"))
    store.save(chair("b", port=9091))
    assert store.names() == ["a", "b"]
    assert store.last_used() == chair("b", port=9091)
    store.save(chair("a", scan_topic="/base_scan"))  # replace in place; becomes the default
    assert store.names() == ["a", "b"]
    assert store.get("a").scan_topic == "/base_scan"
    assert store.last_used() is not None and store.last_used().name == "a"  # type: ignore[union-attr]
    # a new store (new session) reads the same file
    again = ProfileStore(secrets=False)
    assert again.get("b").port == 9091 and again.last_used().name == "a"  # type: ignore[union-attr]
    again.mark_used("b")
    assert ProfileStore(secrets=False).last_used().name == "b"  # type: ignore[union-attr]
    again.delete("b")
    assert again.names() == ["a"] and again.last_used().name == "a"  # type: ignore[union-attr]
    with pytest.raises(SettingsError, match=r"no chair profile named 'zzz'.*profiles: a"):
        again.get("zzz")
    assert sorted(p.name for p in (tmp_path / "cfg").iterdir()) == ["profiles.json"]  # no temp files left


def test_invalid_profile_is_not_saved() -> None:
    store = ProfileStore(secrets=False)
    store.save(chair("a"))
    before = store.path.read_bytes()
    with pytest.raises(SettingsError, match=r"^port"):
        store.save(chair("a", port=0))
    assert store.path.read_bytes() == before


def test_passwords_never_written_to_disk() -> None:
    store = ProfileStore(secrets=False)
    store.save(chair("a"))
    store.set_password(chair("a"), "s3cret-pw")
    assert store.get_password(chair("a")) == "s3cret-pw"
    store.save(chair("a", port=9092))
    assert store.get_password(chair("a", port=9092)) == "s3cret-pw"  # same SSH account: rosbridge port is not part
    assert b"s3cret-pw" not in store.path.read_bytes()
    assert "session" in store.password_storage and not store.passwords_persist
    assert ProfileStore(secrets=False).get_password(chair("a")) is None  # next session asks again
    store.delete("a")
    assert store.get_password(chair("a")) is None


@pytest.mark.parametrize("change", [{"host": "192.168.1.99"}, {"ssh_user": "root"}, {"ssh_port": 2222}])
def test_a_password_stays_with_the_ssh_account_it_was_typed_for(change: dict[str, object]) -> None:
    ring = DictKeyring()
    for store in (ProfileStore(secrets=False), ProfileStore(secrets=ring)):
        store.save(chair("a"))
        store.set_password(chair("a"), "old-chair-pw")
        moved = chair("a", **change)
        store.save(moved)  # same profile name, another chair or account
        assert store.get_password(moved) is None
        assert store.get_password(chair("b")) == "old-chair-pw"  # another name, the same account
        store.set_password(moved, "new-chair-pw")
        assert (store.get_password(moved), store.get_password(chair("a"))) == ("new-chair-pw", "old-chair-pw")


class DictKeyring:
    """A keyring-API object backed by a dict: stands in for the OS keyring, which the box lacks."""

    def __init__(self) -> None:
        self.data: dict[tuple[str, str], str] = {}

    def get_password(self, service: str, username: str) -> str | None:
        return self.data.get((service, username))

    def set_password(self, service: str, username: str, password: str) -> None:
        self.data[(service, username)] = password

    def delete_password(self, service: str, username: str) -> None:
        self.data.pop((service, username), None)


def test_keyring_backend_persists_across_stores() -> None:
    ring = DictKeyring()
    store = ProfileStore(secrets=ring)
    store.save(chair("a"))
    store.set_password(chair("a"), "pw1")
    assert ring.data == {("pmk_nb", "pmk@192.168.1.20:22"): "pw1"}
    assert ProfileStore(secrets=ring).get_password(chair("a")) == "pw1"
    assert store.passwords_persist and "keyring" in store.password_storage
    assert b"pw1" not in store.path.read_bytes()


def test_autodetect_without_keyring_package_falls_back_to_memory() -> None:
    store = ProfileStore()
    try:
        import keyring  # type: ignore[import-not-found]  # noqa: F401
    except ImportError:
        assert not store.passwords_persist
        assert "keyring package is not installed" in store.password_storage
    else:
        assert store.password_storage  # a described backend either way
    store.set_password(chair("x"), "pw")
    assert store.get_password(chair("x")) == "pw"


def test_hand_edited_bad_value_names_file_profile_and_field() -> None:
    store = ProfileStore(secrets=False)
    store.save(chair("a"))
    data = json.loads(store.path.read_text())
    data["profiles"][0]["port"] = 99999
    store.path.write_text(json.dumps(data))
    with pytest.raises(SettingsError) as info:
        store.list()
    message = str(info.value)
    assert str(store.path) in message and "'a'" in message and "port" in message
    data["profiles"][0]["port"] = 9090
    data["profiles"][0]["prot"] = 1  # typo
    store.path.write_text(json.dumps(data))
    with pytest.raises(SettingsError, match=r"unknown field.*prot"):
        store.get("a")
    data["profiles"][0].pop("prot")
    data["profiles"][0]["password"] = "plain"
    store.path.write_text(json.dumps(data))
    with pytest.raises(SettingsError, match="password"):
        store.list()


def test_corrupt_file_is_reported_then_backed_up_not_overwritten() -> None:
    store = ProfileStore(secrets=False)
    store.path.parent.mkdir(parents=True)
    store.path.write_text('{"profiles": [ {"name": "a", ')
    with pytest.raises(SettingsError, match=r"profiles\.json: not valid JSON at line 1"):
        store.list()
    with pytest.raises(SettingsError):
        store.last_used()
    store.save(chair("fresh"))
    assert store.backup_of_corrupt is not None
    assert store.backup_of_corrupt.read_text() == '{"profiles": [ {"name": "a", '
    assert store.names() == ["fresh"]
    # a second corruption does not clobber the first backup
    first_backup = store.backup_of_corrupt
    store.path.write_text("not json")
    ProfileStore(secrets=False).save(chair("again"))
    assert first_backup.read_text() == '{"profiles": [ {"name": "a", '
    assert len(list(store.path.parent.glob("*.bak"))) == 2


def test_duplicate_names_in_file_rejected() -> None:
    store = ProfileStore(secrets=False)
    store.path.parent.mkdir(parents=True)
    entry = chair("a").to_dict()
    store.path.write_text(json.dumps({"version": 1, "last_used": "a", "profiles": [entry, entry]}))
    with pytest.raises(SettingsError, match="appears twice"):
        store.list()
