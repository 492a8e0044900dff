"""One password cache per session, keyed by SSH account, shared by the profile store and the dashboard."""

from __future__ import annotations

import stat
from pathlib import Path

import pytest

from pmk_nb.chair.profiles import ChairProfile, ProfileStore
from pmk_nb.chair.secrets import KEYRING_SERVICE, PasswordCache, SshAccount
from pmk_nb.library import MapsFolder
from pmk_nb.ui import AppContext
from tests.chair.test_settings import DictKeyring

ALMA = SshAccount("pmk", "192.168.1.20", 22)


class BrokenKeyring(DictKeyring):
    def set_password(self, service: str, username: str, password: str) -> None:
        raise OSError("keyring locked")

    def get_password(self, service: str, username: str) -> str | None:
        raise OSError("keyring locked")


def test_account_of_a_profile_and_its_keyring_name() -> None:
    profile = ChairProfile(name="alma", host="192.168.1.20", port=9091, ssh_user="pmk")
    assert SshAccount.of(profile) == ALMA  # the rosbridge port and the profile name are not part of it
    assert ALMA.key == "pmk@192.168.1.20:22"


def test_session_password_wins_over_the_keyring_and_forget_clears_both() -> None:
    ring = DictKeyring()
    ring.set_password(KEYRING_SERVICE, ALMA.key, "stored")
    cache = PasswordCache(ring)
    assert cache.lookup(ALMA) == "stored" and cache.persists
    cache.remember(ALMA, "typed")
    assert cache.lookup(ALMA) == "typed"
    assert ring.data == {(KEYRING_SERVICE, ALMA.key): "stored"}  # remember() never writes the keyring
    cache.forget(ALMA)
    assert cache.lookup(ALMA) is None and ring.data == {}


def test_a_failing_keyring_falls_back_to_memory_and_says_so() -> None:
    cache = PasswordCache(BrokenKeyring())
    cache.store(ALMA, "pw")
    assert cache.lookup(ALMA) == "pw"
    assert not cache.persists and "keyring failed" in cache.where
    assert PasswordCache(BrokenKeyring()).lookup(ALMA) is None  # unreadable keyring: nothing stored


def test_dashboard_and_store_share_one_cache(tmp_path: Path) -> None:
    store = ProfileStore(tmp_path / "cfg" / "profiles.json", secrets=False)
    ctx = AppContext(MapsFolder(tmp_path / "maps"), store, config_dir=tmp_path / "cfg")
    try:
        profile = ChairProfile(name="alma", host="192.168.1.20", ssh_user="pmk")
        ctx.remember_password(profile, "typed")
        assert store.get_password(profile) == "typed"  # typed in a dialog, seen by the CLI-side store
        store.set_password(profile, "saved")
        assert ctx.ssh_password(profile) == "saved"
        moved = ChairProfile(name="alma", host="192.168.1.99", ssh_user="pmk")
        assert ctx.ssh_password(moved) is None  # the profile now names another chair
        assert not hasattr(ctx, "_session_passwords")
    finally:
        ctx.close()


@pytest.mark.parametrize("secrets", [False, DictKeyring()])
def test_profiles_file_is_private_and_holds_no_password(tmp_path: Path, secrets: object) -> None:
    store = ProfileStore(tmp_path / "cfg" / "profiles.json", secrets=secrets)  # type: ignore[arg-type]
    profile = ChairProfile(name="alma", host="192.168.1.20", ssh_user="pmk")
    store.save(profile)
    store.set_password(profile, "hunter2")
    assert stat.S_IMODE(store.path.stat().st_mode) == 0o600
    assert b"hunter2" not in store.path.read_bytes()
    assert sorted(p.name for p in store.path.parent.iterdir()) == ["profiles.json"]
