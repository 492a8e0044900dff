"""The dashboard shell: navigation, info panel messages, session state, kiosk notebook and CLI."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import ipywidgets as w
import pytest

from pmk_nb.chair import ChairProfile, ProfileStore
from pmk_nb.chair.link import open_links
from pmk_nb.errors import LibraryError
from pmk_nb.library import MapsFolder
from pmk_nb.progress import Progress
from pmk_nb.serve.voila import DASHBOARD_SOURCE, dashboard_notebook, voila_command
from pmk_nb.ui import build_app
from pmk_nb.ui.app import SCREENS, Dashboard
from pmk_nb.ui.common.context import STATE_FILE, AppContext, CurrentMap
from pmk_nb.ui.common.widgets import TOUCH_PX, guard, progress_bar, progress_callback, set_progress

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture
def ctx(tmp_path: Path) -> Iterator[AppContext]:
    context = AppContext(
        MapsFolder(tmp_path / "maps"),
        ProfileStore(tmp_path / "cfg" / "profiles.json", secrets=False),
        config_dir=tmp_path / "cfg",
    )
    yield context
    context.close()


def test_build_app_uses_env_dirs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PMK_MAPS_DIR", str(tmp_path / "m"))
    monkeypatch.setenv("PMK_CONFIG_DIR", str(tmp_path / "c"))
    app = build_app()
    try:
        assert isinstance(app, Dashboard) and isinstance(app, w.Widget)
        assert app.ctx.maps.root == tmp_path / "m"
        assert app.ctx.config_dir == tmp_path / "c"
        assert app.ctx.profiles.path.parent == tmp_path / "c"
    finally:
        app.close()


def test_navigation_switches_content_and_info(ctx: AppContext) -> None:
    app = Dashboard(ctx)
    try:
        assert app.current == "home"
        for name in ("maps", "settings", "home", "settings"):
            app.nav_buttons[name].click()
            screen = app.screens[name]
            assert app.current == name
            assert app.content.children == (screen.widget,)
            assert app.info_slot.children == (screen.info_widget,)
            active = [n for n, b in app.nav_buttons.items() if "pmk-nav-active" in b._dom_classes]
            assert active == [name]
        assert set(app.nav_buttons) == set(SCREENS)
        with pytest.raises(ValueError, match="unknown screen"):
            app.show("nope")
    finally:
        app.close()


def test_touch_targets_and_stable_classes(ctx: AppContext) -> None:
    app = Dashboard(ctx)
    try:
        for name, btn in app.nav_buttons.items():
            assert int(btn.layout.height.removesuffix("px")) >= 48
            assert f"pmk-nav-{name}" in btn._dom_classes
        assert TOUCH_PX >= 48
        assert "pmk-app" in app._dom_classes
    finally:
        app.close()


def test_notifications_reach_the_info_panel_escaped(ctx: AppContext) -> None:
    app = Dashboard(ctx)
    try:
        ctx.notify("<b>boom</b> & co", "error")
        assert "pmk-msg-error" in app.message.value
        assert "&lt;b&gt;boom&lt;/b&gt; &amp; co" in app.message.value
        ctx.notify("fine", "bogus-level")  # type: ignore[arg-type]
        assert "pmk-msg-info" in app.message.value
    finally:
        app.close()


def test_guard_turns_exceptions_into_messages(ctx: AppContext) -> None:
    seen: list[str] = []
    ctx.observe_notifications(lambda note: seen.append(f"{note.level}:{note.message}"))

    @guard(ctx, "Doing X")
    def fails() -> None:
        raise LibraryError("the folder is gone")

    @guard(ctx, "Doing Y")
    def crashes() -> None:
        raise KeyError("k")

    assert fails() is None and crashes() is None
    assert seen[0] == "error:Doing X failed: the folder is gone"
    assert seen[1].startswith("error:Doing Y failed unexpectedly (KeyError")


def test_current_map_persists_and_notifies(tmp_path: Path, ctx: AppContext) -> None:
    seen: list[CurrentMap | None] = []
    unsubscribe = ctx.observe_current_map(seen.append)
    ctx.set_current_map("clinic", tmp_path / "clinic.yaml", tmp_path / "clinic-visualization.png")
    unsubscribe()
    ctx.set_current_map("other", tmp_path / "other.yaml", None)
    assert [c.name for c in seen if c] == ["clinic"]
    state = json.loads((tmp_path / "cfg" / STATE_FILE).read_text())
    assert state["current_map"]["name"] == "other"
    again = AppContext(ctx.maps, ctx.profiles, config_dir=tmp_path / "cfg")
    assert again.current_map == CurrentMap("other", tmp_path / "other.yaml", None)
    (tmp_path / "cfg" / STATE_FILE).write_text("{not json")
    assert AppContext(ctx.maps, ctx.profiles, config_dir=tmp_path / "cfg").current_map is None


def test_password_lookup_prefers_session_then_store(ctx: AppContext) -> None:
    chair = ChairProfile(name="Real chair", host="10.0.0.2")
    assert ctx.ssh_password(chair) is None
    ctx.profiles.set_password(chair, "stored")
    assert ctx.ssh_password(chair) == "stored"
    ctx.remember_password(chair, "typed")
    assert ctx.ssh_password(chair) == "typed"


def test_progress_adapter_takes_progress_reports() -> None:
    bar = progress_bar("x")
    assert bar.layout.display == "none"  # takes no room until used
    label = w.HTML("")
    update = progress_callback(bar, label)
    update(Progress("download", 0.25, "1 of 4 MiB"))
    assert bar.value == pytest.approx(0.25) and bar.layout.display != "none"
    assert label.value == "Downloading 1 of 4 MiB…"
    update(Progress("rasterise", 0.6, "storey <F1>"))
    assert bar.value == pytest.approx(0.6) and label.value == "Rasterising storey &lt;F1&gt;…"
    update(Progress("download", None))  # unknown total: still moves, stays below 1
    first = bar.value
    update(Progress("download", None))
    assert 0 < first < bar.value < 1
    set_progress(bar, None)  # finished: the bar leaves the screen
    assert bar.layout.display == "none"


def test_repo_notebook_matches_kiosk_notebook() -> None:
    repo_nb = json.loads((REPO / "notebooks" / "dashboard.ipynb").read_text())
    code = ["".join(c["source"]) for c in repo_nb["cells"] if c["cell_type"] == "code"]
    assert code == [DASHBOARD_SOURCE]
    assert dashboard_notebook()["metadata"]["kernelspec"]["name"] == "python3"


def test_voila_command_is_a_locked_down_kiosk(tmp_path: Path) -> None:
    cmd = voila_command(tmp_path / "d.ipynb", port=9999)
    assert "--port=9999" in cmd and "--no-browser" in cmd
    assert "--Voila.ip=127.0.0.1" in cmd and "--strip_sources=True" in cmd
    assert any(a.startswith("--MappingKernelManager.cull_idle_timeout=") and not a.endswith("=0") for a in cmd)


def test_cli_parses_dashboard_and_demo() -> None:
    from pmk_nb.cli import build_parser
    from pmk_nb.cli import dashboard as ui_cli
    from pmk_nb.cli import demo as cli_demo

    args = build_parser("dashboard").parse_args(["dashboard", "--port", "8870", "--no-browser"])
    assert args.run is ui_cli.run and args.port == 8870 and args.no_browser and args.ip == "127.0.0.1"
    assert not args.preview_on_start
    assert build_parser("dashboard").parse_args(["dashboard", "--preview-on-start"]).preview_on_start
    args = build_parser("demo").parse_args(["demo", "--dir", "x", "--ip", "0.0.0.0"])
    assert args.run is cli_demo.run and args.dir == Path("x") and args.port == 8866


def test_demo_makes_a_private_key_pair_and_a_key_only_chair(tmp_path: Path) -> None:
    import stat

    import paramiko

    from pmk_nb.cli.demo_setup import make_key_pair, sim_command

    private, public = make_key_pair(tmp_path / "cfg")
    assert stat.S_IMODE(private.stat().st_mode) == 0o600
    key = paramiko.PKey.from_path(private)
    assert public.read_text().split()[:2] == [key.get_name(), key.get_base64()] == ["ssh-ed25519", key.get_base64()]
    cmd = sim_command(tmp_path / "m.yaml", 1, 2, tmp_path / "chair", public)
    assert cmd[cmd.index("--sftp-authorized-key") + 1] == str(public)
    assert "--no-sftp-password" in cmd and "--sftp-password" not in cmd  # no secret on a command line
    again, _ = make_key_pair(tmp_path / "cfg")  # each demo run gets a new pair
    assert paramiko.PKey.from_path(again).get_base64() != key.get_base64()
    assert sorted(p.name for p in (tmp_path / "cfg").iterdir()) == ["chair_key", "chair_key.pub"]  # no temp left


def test_ssh_password_never_comes_from_the_environment(ctx: AppContext, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PMK_SIM_PROFILE", "Simulated chair")  # what earlier demos used
    monkeypatch.setenv("PMK_SIM_PASSWORD", "s3cret")
    profile = ChairProfile(name="Simulated chair", host="127.0.0.1")
    assert ctx.ssh_password(profile) is None
    ctx.remember_password(profile, "typed")
    assert ctx.ssh_password(profile) == "typed"


@pytest.mark.slow
def test_autostart_shows_the_chair_without_a_click_and_respects_disconnect(
    ctx: AppContext, sim_factory: Any, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from tests.fixtures_sim import room_grid, write_test_map

    sim = sim_factory(patrol=True)
    yaml = write_test_map(room_grid(), tmp_path / "maps", "room")
    ctx.profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port))
    ctx.set_current_map("room", yaml, None)
    monkeypatch.setenv("PMK_AUTOSTART_PREVIEW", "1")
    app = build_app(ctx=ctx)
    try:
        home = app.screens["home"]
        assert home.running  # nothing pressed
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and home.live.metrics.last_pose is None:
            time.sleep(0.05)
        assert home.live.metrics.last_pose is not None
        app.nav_buttons["maps"].click()
        assert not home.running
        app.nav_buttons["home"].click()
        assert home.running  # back on Home: live again
        home.disconnect_button.click()  # the user's choice wins over autostart ...
        app.nav_buttons["settings"].click()
        app.nav_buttons["home"].click()
        assert not home.running and home.preview_button.layout.display != "none"
        home.preview_button.click()  # ... until they press Preview again
        app.nav_buttons["maps"].click()
        app.nav_buttons["home"].click()
        assert home.running
    finally:
        app.close()
    monkeypatch.delenv("PMK_AUTOSTART_PREVIEW")
    other = AppContext(ctx.maps, ctx.profiles, config_dir=tmp_path / "cfg2")
    other.set_current_map("room", yaml, None)
    plain = build_app(ctx=other)
    try:
        assert not plain.screens["home"].running  # default: Preview is pressed by the user
    finally:
        plain.close()


@pytest.mark.slow
def test_leaving_home_stops_the_preview(ctx: AppContext, sim_factory: Any, tmp_path: Path) -> None:
    from tests.fixtures_sim import room_grid, write_test_map

    sim = sim_factory(patrol=True)
    yaml = write_test_map(room_grid(), tmp_path / "maps", "room")
    ctx.profiles.save(ChairProfile(name="sim", host="127.0.0.1", port=sim.port))
    ctx.set_current_map("room", yaml, None)
    app = Dashboard(ctx)
    try:
        home = app.screens["home"]
        assert home.start_preview()
        assert home.running
        app.nav_buttons["maps"].click()
        assert not home.running
        link = ctx.link()
        assert link.is_connected
    finally:
        app.close()
    assert not link.is_connected  # the page's chair connection ends with the app (kernel shutdown)


@pytest.mark.slow
@pytest.mark.realtime  # a real pmk dashboard process and its Voila child
def test_pmk_dashboard_serves_and_stops(tmp_path: Path) -> None:
    from pmk_nb.serve.procs import free_port, wait_for_port

    port = free_port()
    env = {**os.environ, "PMK_MAPS_DIR": str(tmp_path / "m"), "PMK_CONFIG_DIR": str(tmp_path / "c")}
    proc = subprocess.Popen(
        [sys.executable, "-m", "pmk_nb.cli", "dashboard", "--port", str(port), "--no-browser"],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        wait_for_port("127.0.0.1", port, proc, "pmk dashboard", 120)
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=120) as resp:
            page = resp.read().decode()
        assert resp.status == 200
        assert "build_app" not in page  # sources stripped: the kiosk shows the app, not code
        assert "application/vnd.jupyter.widget-view+json" in page
    finally:
        proc.send_signal(signal.SIGTERM)
        out, _ = proc.communicate(timeout=60)
    assert f"http://127.0.0.1:{port}/" in out
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:  # Voilà (the child) is gone too
        try:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=1):
                pass
        except OSError:
            break
        time.sleep(0.2)
    else:
        raise AssertionError("Voilà still serving after pmk dashboard was stopped")


def test_unusable_maps_folder_gives_a_message_not_a_traceback(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("PMK_MAPS_DIR", str(blocker / "maps"))
    out = build_app(config_dir=tmp_path / "c")
    assert not isinstance(out, Dashboard)
    assert "cannot start" in out.value and "maps folder" in out.value


def test_corrupt_profiles_file_is_reported_in_the_panel(tmp_path: Path) -> None:
    (tmp_path / "c").mkdir()
    (tmp_path / "c" / "profiles.json").write_text("{broken")
    app = build_app(maps_dir=tmp_path / "m", config_dir=tmp_path / "c")
    try:
        assert isinstance(app, Dashboard)
        assert "pmk-msg-error" in app.message.value and "profiles.json" in app.message.value
        before = len(app.ctx.notifications)
        assert app.ctx.profile() is None and app.ctx.profile() is None
        assert len(app.ctx.notifications) == before  # reported once, not on every poll
        app.show("settings")  # still usable: a new profile can be saved
    finally:
        app.close()


def test_exclusive_work_refuses_a_second_start_even_if_the_page_reenables_the_button(ctx: AppContext) -> None:
    import threading

    from pmk_nb.ui.common.widgets import button, run_in_thread

    release, lock, done = threading.Event(), threading.Lock(), []
    btn = button("Go", "x")
    first = run_in_thread(ctx, "Converting", release.wait, on_done=done.append, busy=[btn], exclusive=lock)
    assert first is not None and btn.disabled
    btn.disabled = False  # what a crafted page could do
    assert run_in_thread(ctx, "Converting", lambda: None, busy=[btn], exclusive=lock) is None
    assert ctx.notifications[-1].level == "warning" and "already running" in ctx.notifications[-1].message
    release.set()
    first.join(5)
    assert done == [True] and not btn.disabled and not lock.locked()


def test_the_outcome_of_exclusive_work_may_start_it_again(ctx: AppContext) -> None:
    """A failed Send asks to trust the host key; "Trust and send" starts Send again at once. The
    question comes after the work is over, so it never finds Send "already running" (seen in a
    full run: the retry was refused while the first thread had not yet released the lock)."""
    import threading

    from pmk_nb.ui.common.widgets import button, run_in_thread

    lock, retried, btn = threading.Lock(), [], button("Send", "x")

    def ask_and_retry(_err: BaseException) -> None:
        retried.append((btn.disabled, run_in_thread(ctx, "Sending", lambda: None, busy=[btn], exclusive=lock)))

    def fail() -> None:
        raise OSError("unknown host key")

    first = run_in_thread(ctx, "Sending", fail, on_error=ask_and_retry, busy=[btn], exclusive=lock)
    assert first is not None
    first.join(5)
    [(disabled_when_asked, again)] = retried
    assert not disabled_when_asked and again is not None  # the retry ran, not refused
    again.join(5)
    assert not lock.locked() and not any("already running" in n.message for n in ctx.notifications)


def test_one_chair_connection_per_page(ctx: AppContext) -> None:
    ctx.profiles.save(ChairProfile(name="a", host="127.0.0.1", port=9101))
    first = ctx.link()
    assert ctx.link() is first  # re-used, not one per screen
    ctx.profiles.save(ChairProfile(name="a", host="127.0.0.1", port=9101, odom_topic="/wheel_odom"))
    assert ctx.link() is first and first.config["odom_topic"] == "/wheel_odom"
    ctx.profiles.save(ChairProfile(name="b", host="127.0.0.1", port=9102))
    second = ctx.link()
    assert second is not first and second.port == 9102
    assert first not in open_links() and second in open_links()  # the old chair's link was dropped


def test_a_new_page_builds_home_only_and_the_other_screens_when_first_opened(ctx: AppContext) -> None:
    """Page start is what every rider waits for: Maps and Settings (more than half the widgets)
    are built when first opened, once."""
    app = Dashboard(ctx)
    try:
        assert set(app.screens) == {"home"}
        app.show("maps")
        maps = app.screens["maps"]
        app.show("settings")
        app.show("maps")
        assert set(app.screens) == {"home", "maps", "settings"} and app.screens["maps"] is maps
        assert app.screen("settings") is app.screens["settings"]
    finally:
        app.close()
