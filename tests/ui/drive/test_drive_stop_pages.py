"""Issue 38 on the pages' side, without a browser: another page's Stop ends this page's goal and greys
Set destination and Go to; on a kiosk, Take over driving needs the PIN (Stop never does).

Pages are two kernels' worth of widgets: two DrivePanels (two members), two links, one settings folder.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from pmk_nb.chair import ChairProfile
from pmk_nb.chair.link import GoalStatus
from pmk_nb.drive import Hold
from pmk_nb.ui.drive.panel import DrivePanel
from pmk_nb.ui.goals.panel import GoalPanel
from pmk_nb.ui.home.stop_latch import StopLatch
from pmk_nb.ui.kiosk.pin import KioskLock, PinStore
from pmk_nb.ui.live.view import LiveView
from tests.fixtures_sim import wait_until

START = (1.0, 6.0, 0.0)
FAR = (14.0, 6.0, 0.0)


class StillLink:
    """A connected chair link as a drive session sees it (nothing moves; no goals)."""

    host, port, is_connected = "localhost", 9090, True

    def latest_odom(self) -> None:
        return None

    def publish_cmd_vel(self, v: float, w: float, topic: str | None = None) -> bool:
        return True

    def stop_goals(self, topic: str | None = None) -> list[Any]:
        return []


@pytest.mark.slow
def test_page_b_stop_ends_page_a_goal_and_greys_its_destination(sim_factory, link_factory, tmp_path: Path) -> None:
    sim = sim_factory(ros="ros2", start_pose=START)
    link_a, link_b = link_factory(sim), link_factory(sim)
    folder = tmp_path / "drive"
    drive_a, drive_b = DrivePanel(claims_dir=folder), DrivePanel(claims_dir=folder)
    latch_a = StopLatch(folder, drive_a.member)
    latch_a.attach(link_a)
    goals_a = GoalPanel(LiveView(600, 400))
    goals_a.attach(link_a)
    try:
        goals_a.send(FAR)  # A's Set destination
        assert wait_until(lambda: goals_a.handle is not None and sim.velocity[0] > 0.2, 10.0)
        profile_b = ChairProfile(name="b", host="localhost", port=sim.port)  # B spells the chair otherwise
        drive_b.attach(link_b, profile_b)
        drive_b.stop_button.click()
        assert wait_until(lambda: sim.velocity == (0.0, 0.0), 2.0)
        handle = goals_a.handle
        assert handle is not None and wait_until(lambda: handle.progress().status is GoalStatus.CANCELLED, 3.0)
        assert wait_until(lambda: latch_a.latched, 2.0)
        goals_a.set_stopped(latch_a.latched)  # Home's tick
        assert goals_a.toggle.disabled and "released on the page where it was pressed" in goals_a.status.value
        goals_a.toggle.value = True  # a page script clicks the greyed button: refused
        assert goals_a.toggle.value is False
        goals_a.send(FAR)  # and a goal that gets through anyway is refused by the link's gate
        assert wait_until(lambda: goals_a.goal is None and "not sent" in goals_a._note, 5.0)
        assert sim.goal_status == "cancelled"
        drive_b.refresh()
        assert drive_b.claim_button.description == "Release the Stop"  # released where it was pressed
        drive_b.claim_button.click()
        assert wait_until(lambda: not latch_a.latched, 2.0)
        goals_a.set_stopped(latch_a.latched)
        assert not goals_a.toggle.disabled
    finally:
        latch_a.close()
        drive_b.detach()
    assert link_a.goal_gate is None


def test_on_a_kiosk_take_over_needs_the_pin_and_stop_does_not(tmp_path: Path) -> None:
    folder = tmp_path / "drive"
    pins = PinStore(tmp_path)
    pins.set_pin("2468", "2468")
    driver, kiosk = DrivePanel(claims_dir=folder), DrivePanel(claims_dir=folder, kiosk=KioskLock(pins))
    driver.attach(StillLink(), None)  # type: ignore[arg-type]
    kiosk.attach(StillLink(), None)  # type: ignore[arg-type]
    try:
        assert driver.session is not None and kiosk.session is not None
        assert driver.session.claim is not None and driver.session.claim.acquire().hold is Hold.MINE
        assert wait_until(lambda: (kiosk.refresh(), kiosk.claim_button.description)[1] == "Take over driving", 3.0)
        assert kiosk.pin.layout.display == ""
        kiosk.claim_button.click()
        kiosk.claim_button.click()  # two taps without the PIN: nothing taken
        assert driver.session.claim.view().hold is Hold.MINE and "Type the kiosk PIN" in kiosk.status.value
        kiosk.pin.value = "1357"
        kiosk.claim_button.click()
        assert kiosk.pin.value == "" and "Wrong PIN" in kiosk.status.value
        assert driver.session.claim.view().hold is Hold.MINE
        kiosk.pin.value = "2468"
        kiosk.claim_button.click()
        assert driver.session.claim.view().hold is Hold.OTHER_DRIVER  # the kiosk drives now
        assert wait_until(lambda: (kiosk.refresh(), kiosk.pin.layout.display)[1] == "none", 3.0)
        driver.refresh()
        driver.stop_button.click()  # Stop without a PIN, from anywhere, and on the kiosk too
        assert kiosk.session.claim is not None and kiosk.session.claim.view().hold is Hold.STOPPED_ELSEWHERE
        kiosk.stop_button.click()
        assert kiosk.session.claim.view().hold is Hold.STOPPED_HERE
    finally:
        driver.detach()
        kiosk.detach()


def test_another_pages_stop_cancels_here_only_when_goals_run_here() -> None:
    """Ten pages, one Stop: the pressing page cancelled all goals natively; a page that runs none sends
    nothing more (no burst per page), a page that runs one cancels it."""
    from pmk_nb.ui.home.stop_latch import on_latch

    class Link:
        def __init__(self, goals: list[str]) -> None:
            self.goals, self.stops = goals, []  # type: ignore[var-annotated]

        def running_goals(self) -> list[str]:
            return self.goals

        def stop_goals(self, topic: str | None = None) -> list[str]:
            self.stops.append(topic)
            return self.goals

    idle, busy = Link([]), Link(["goal"])
    on_latch(idle, "/cmd_vel")
    on_latch(busy, "/chair/cmd_vel")
    assert idle.stops == [] and busy.stops == ["/chair/cmd_vel"]
