"""Driving settings (profile + Settings screen) and Home's drive panel, without a browser.

The panel is driven through its widgets exactly as the page does (the hidden channel's value),
against the real simulator and link.
"""

from __future__ import annotations

import json
import time
from typing import Any

import pytest

from pmk_nb.chair import ChairProfile
from pmk_nb.drive import StopReason
from pmk_nb.errors import SettingsError
from pmk_nb.sim import demo_grid
from pmk_nb.ui.common.context import AppContext
from pmk_nb.ui.drive.panel import DrivePanel, limits_of
from pmk_nb.ui.settings.screen import SettingsScreen
from tests.fixtures_sim import wait_until


def test_profile_has_drive_defaults_and_refuses_wild_speeds() -> None:
    profile = ChairProfile(name="a", host="127.0.0.1")
    assert (profile.cmd_vel_topic, profile.max_linear, profile.max_angular) == ("/cmd_vel", 0.5, 0.8)
    assert limits_of(profile).scale(slow=True) == pytest.approx((0.2, 0.32))
    for field, value in (("max_linear", 5.0), ("max_angular", 0), ("slow_factor", 1.5), ("cmd_vel_topic", "cmd")):
        with pytest.raises(SettingsError) as err:
            ChairProfile(name="a", host="127.0.0.1", **{field: value}).validate()
        assert err.value.field == field
    old = {"name": "old", "host": "127.0.0.1"}  # a profile saved before driving existed still loads
    assert ChairProfile.from_dict(old).max_linear == 0.5


def test_settings_edit_speed_limits_and_topic(ctx: AppContext) -> None:
    screen = SettingsScreen(ctx)
    for key, value in {"name": "Chair A", "host": "127.0.0.1", "ssh_user": "pmk"}.items():
        screen.fields[key].value = value
    assert screen.fields["max_linear"].value == "0.5"
    screen.fields["max_linear"].value = "fast"
    screen.save_button.click()
    assert "a number" in screen.errors["max_linear"].value and "Not saved" in screen.message.value
    screen.fields["max_linear"].value = "3"
    screen.save_button.click()
    assert "at most 2" in screen.errors["max_linear"].value
    screen.fields["max_linear"].value = "0,3"  # a decimal comma is what a tablet's keyboard gives
    screen.fields["slow_factor"].value = "0.25"
    screen.fields["cmd_vel_topic"].value = "/wheelchair/cmd_vel"
    screen.save_button.click()
    saved = ctx.profiles.get("Chair A")
    assert (saved.max_linear, saved.slow_factor, saved.cmd_vel_topic) == (0.3, 0.25, "/wheelchair/cmd_vel")
    assert SettingsScreen(ctx).fields["max_linear"].value == "0.3"


def hold(panel: DrivePanel, seq: int, press: int, until: Any, timeout: float = 5.0, renew: bool = False) -> int | None:
    """Keep the finger down on ``press`` (a page repeats its message every 50 ms) until ``until()``
    holds; the next free seq, or None when it did not within ``timeout`` s. ``renew``: after a
    safety stop (a starved test thread trips the keepalive) lift the finger and press anew."""
    deadline = time.monotonic() + timeout
    assert panel.session is not None
    stops = panel.session.gate.stop_count
    while time.monotonic() < deadline:
        if renew and panel.session.gate.stop_count != stops:
            press, stops = press + 1, panel.session.gate.stop_count
        panel.channel.value = page(seq, press)
        seq += 1
        if wait_until(until, 0.05):
            return seq
    return None


def page(seq: int, press: int, held: bool = True, **kw: Any) -> str:
    msg = {"page": "ui", "seq": seq, "press": press, "t": time.monotonic() * 1000.0, "x": 0.0, "y": 1.0}
    return json.dumps({**msg, "held": held, "hidden": False, **kw})


@pytest.mark.slow
def test_drive_panel_drives_the_chair_through_its_channel(sim_factory: Any, link_factory: Any, tmp_path: Any) -> None:
    sim = sim_factory(grid=demo_grid(), start_pose=(2.0, 6.0, 0.0))
    link = link_factory(sim)
    link.start_streams()
    assert wait_until(lambda: link.latest_odom() is not None, 10.0)
    stops: list[StopReason] = []
    panel = DrivePanel(on_stop=stops.append, claims_dir=tmp_path)
    assert panel.widget.layout.display == "none"
    profile = ChairProfile(name="sim", host="127.0.0.1", port=sim.port, max_linear=0.3)
    session = panel.attach(link, profile)
    assert panel.widget.layout.display == "flex" and len(panel.page.outputs) == 1
    assert "pmk-drive-channel" in panel.page.outputs[0]["data"]["text/html"]
    panel.channel.value = "{not json"  # a page can send anything: ignored, counted
    panel.channel.value = page(1, 1, x=9.0)
    assert session.invalid == 2 and sim.velocity == (0.0, 0.0)
    for seq in range(2, 10):
        panel.channel.value = page(seq, 1)
        time.sleep(0.1)
    assert sim.velocity[0] == pytest.approx(0.3, abs=0.01)
    panel.refresh()
    assert "Driving" in panel.status.value
    panel.slow.value = True
    # renew: the gap before Slow can trip the 0.3 s keepalive on a loaded machine (seen in make test)
    seq = hold(panel, 10, 1, lambda: sim.velocity[0] == pytest.approx(0.12, abs=0.01), renew=True)
    assert seq is not None
    panel.stop_button.click()
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)
    panel.channel.value = page(seq, 1)  # the finger is still down: that press is over
    time.sleep(0.2)
    assert sim.velocity == (0.0, 0.0)
    panel.refresh()
    assert "Stopped" in panel.status.value and stops == [StopReason.STOP_BUTTON]
    # a new press drives, and hiding the panel stops it; the finger stays down as on a page (a
    # single message drives only until the 0.3 s keepalive, which a loaded machine can miss)
    assert hold(panel, seq + 1, 2, lambda: sim.velocity[0] > 0.05, renew=True) is not None
    panel.detach()
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)
    assert panel.widget.layout.display == "none"


@pytest.mark.slow
def test_the_drive_toggle_shows_the_stick_only_when_asked_and_stops_when_switched_off(
    sim_factory: Any, link_factory: Any, tmp_path: Any
) -> None:
    sim = sim_factory(grid=demo_grid(), start_pose=(2.0, 6.0, 0.0))
    link = link_factory(sim)
    link.start_streams()
    assert wait_until(lambda: link.latest_odom() is not None, 10.0)
    panel = DrivePanel(claims_dir=tmp_path)
    assert panel.toggle.layout.display == "none"  # no preview, no link: nothing to switch on
    panel.toggle.value = True  # a page can set the trait anyway: no link, so nothing drives
    assert panel.session is None and panel.widget.layout.display == "none"
    panel.toggle.value = False
    panel.offer(link, ChairProfile(name="sim", host="127.0.0.1", port=sim.port, max_linear=0.3))
    assert panel.toggle.layout.display == "" and panel.session is None  # offered, but off
    assert panel.widget.layout.display == "none"
    panel.toggle.value = True
    assert panel.session is not None and panel.widget.layout.display == "flex"
    seq = 0
    deadline = time.monotonic() + 10.0  # the page's keepalives every 100 ms until the chair moves (a busy
    while time.monotonic() < deadline:  # machine may take a few hundred ms to carry the first command)
        seq += 1
        panel.channel.value = page(seq, 1)
        if sim.velocity[0] == pytest.approx(0.3, abs=0.01):
            break
        time.sleep(0.1)
    assert sim.velocity[0] == pytest.approx(0.3, abs=0.01)
    panel.toggle.value = False  # switching Drive off while driving stops the chair
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)
    assert panel.session is None and panel.widget.layout.display == "none"
    panel.toggle.value = True
    panel.offer(None, None)  # the preview stops: Drive goes off and hides
    assert panel.toggle.value is False and panel.toggle.layout.display == "none" and panel.session is None


@pytest.mark.slow
def test_two_panels_one_driver_take_over_needs_two_taps_and_stop_holds_for_both(
    sim_factory: Any, link_factory: Any, tmp_path: Any
) -> None:
    """Two pages = two panels (two kernels) on one settings folder, each with its own link."""
    sim = sim_factory(grid=demo_grid(), start_pose=(2.0, 6.0, 0.0))
    links = [link_factory(sim), link_factory(sim)]
    for link in links:
        link.start_streams()
        assert wait_until(lambda link=link: link.latest_odom() is not None, 10.0)
    profile = ChairProfile(name="sim", host="127.0.0.1", port=sim.port, max_linear=0.3)
    a, b = DrivePanel(claims_dir=tmp_path), DrivePanel(claims_dir=tmp_path)
    a.attach(links[0], profile)
    b.attach(links[1], profile)

    seqs = {id(a): 0, id(b): 0}
    presses = {id(a): 0, id(b): 0}
    handled: dict[int, int] = {}  # per panel, the safety stops its holds have answered so far

    def hold(panel: DrivePanel, press: int, until: Any, timeout: float = 5.0, least: int = 2) -> bool:
        """Hold the stick as a page does (a message every 0.1 s) until ``until()`` holds, at least ``least`` ticks.

        Waits on the chair's state, not a fixed count, so a loaded machine's lag is no failure; a
        safety stop from a starved test thread (no message for 0.3 s) is answered by a new press, as
        a rider would lift and press again, also when it came between two holds (the test's own steps
        between them can take over 0.3 s). ``press`` 0 keeps the panel's current press."""
        deadline = time.monotonic() + timeout
        assert panel.session is not None
        if press:
            presses[id(panel)] = max(presses[id(panel)] + 1, press)
        stops = handled.setdefault(id(panel), panel.session.gate.stop_count)
        ticks = 0
        try:
            while True:
                if panel.session.gate.stop_count != stops and until is not stopped:
                    presses[id(panel)] += 1
                    stops = panel.session.gate.stop_count
                seqs[id(panel)] += 1
                panel.channel.value = page(seqs[id(panel)], presses[id(panel)])
                time.sleep(0.1)
                ticks += 1
                if ticks >= least and until():
                    return True
                if time.monotonic() > deadline:
                    return False
        finally:
            handled[id(panel)] = stops

    def driving() -> bool:
        return bool(sim.velocity[0] == pytest.approx(0.3, abs=0.01))

    def stopped() -> bool:
        return sim.velocity == (0.0, 0.0)

    try:
        assert hold(a, 1, driving)
        seqs[id(b)] += 1
        presses[id(b)] = 1
        b.channel.value = page(seqs[id(b)], 1, y=-1.0)  # B's stick while A drives: refused, A drives on
        time.sleep(0.1)
        b.refresh()
        assert b.session is not None and not b.session.driving
        assert b.status.value.startswith("Driven from another page (since ")
        assert "pmk-drive-locked" in b.pad._dom_classes and b.claim_button.layout.display == ""
        assert b.claim_button.description == "Take over driving"
        b.claim_button.click()  # one tap only arms it
        assert hold(a, 0, driving)
        assert b.claim_button.description == "Tap again to confirm"
        b.claim_button.click()  # the second tap takes over: A stops at its next tick
        assert a.session is not None
        assert hold(a, 0, lambda: stopped() and a.session is not None and not a.session.driving, least=3)
        a.refresh()
        assert a.status.value.startswith("Driven from another page") and "pmk-drive-locked" in a.pad._dom_classes
        assert hold(b, 2, driving)  # B drives now; A's Stop stops B and holds until A releases it
        a.stop_button.click()
        assert wait_until(stopped, 2.0)
        assert not hold(b, 3, driving, timeout=0.4)  # a new press on B: still stopped
        assert stopped()
        b.refresh()
        a.refresh()
        assert b.status.value.startswith("Stopped from another page (since ")
        assert b.claim_button.layout.display == "none"  # B's own page is still open: released there only
        assert a.claim_button.description == "Release the Stop"
        a.claim_button.click()
        assert hold(b, 4, driving)
    finally:
        a.detach()
        b.detach()
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)


def test_the_stick_takes_the_panels_lanes_in_turn(sim_factory: Any, link_factory: Any, tmp_path: Any) -> None:
    """ipywidgets holds a widget's next update until the kernel answered its last: one channel carried
    one message per round trip, and a round trip over 300 ms stopped the chair (classroom soak at load
    10: "the connection is too slow"). The page's script takes the panel's lanes in turn."""
    from pmk_nb.ui.drive.script import CHANNEL_CLASS, LANES, SCRIPT

    sim = sim_factory(grid=demo_grid(), start_pose=(2.0, 6.0, 0.0))
    link = link_factory(sim)
    link.start_streams()
    assert wait_until(lambda: link.latest_odom() is not None, 10.0)
    panel = DrivePanel(claims_dir=tmp_path)
    session = panel.attach(link, ChairProfile(name="sim", host="127.0.0.1", port=sim.port, max_linear=0.3))
    assert LANES >= 3 and len(panel.lanes) == LANES and panel.channel is panel.lanes[0]
    assert all(CHANNEL_CLASS in lane._dom_classes and lane in panel.widget.children for lane in panel.lanes)
    assert "els[lane % els.length]" in SCRIPT  # the page rotates over them
    for seq in range(1, 10):  # a press whose messages come on every lane in turn drives
        panel.lanes[seq % LANES].value = page(seq, 1)
        time.sleep(0.05)
    assert wait_until(lambda: sim.velocity[0] == pytest.approx(0.3, abs=0.01), 2.0)
    ignored = session.gate.stats.ignored
    panel.lanes[1].value = page(9, 1, held=False)  # an older message held back on its lane: ignored
    assert session.gate.stats.ignored == ignored + 1 and session.driving
    panel.lanes[2].value = page(10, 1, held=False)  # the release
    assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)
    panel.detach()
