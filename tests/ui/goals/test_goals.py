"""Tap-to-go without a browser: the picker's pixel -> goal maths, the gesture mode, the panel's texts
and a goal sent through the panel to the real simulated chair (real ChairLink, real roslibpy)."""

from __future__ import annotations

import math

import pytest

from pmk_nb.chair.link import GoalProgress, GoalStatus
from pmk_nb.ui.goals.panel import GoalPanel, status_html
from pmk_nb.ui.goals.picker import GoalPicker, goal_from_pixels
from pmk_nb.ui.live.view import LiveView
from pmk_nb.viewport import Viewport
from tests.fixtures_sim import wait_until
from tests.ui.live.test_live import sample_grid


def _view() -> Viewport:
    return Viewport(300, 200, 0.05, (-1.0, -2.0), 600, 400)  # 2 px per cell, the whole map


def test_a_drag_gives_the_heading_and_a_tap_faces_away_from_the_chair() -> None:
    view = _view()
    x, y = (float(v) for v in view.pixel_to_world(300.0, 200.0))
    right = goal_from_pixels(view, (300.0, 200.0), (360.0, 200.0))
    up = goal_from_pixels(view, (300.0, 200.0), (300.0, 140.0))
    assert right is not None and up is not None
    assert right[:2] == pytest.approx((x, y))
    assert right[2] == pytest.approx(0.0, abs=1e-9)  # screen right is +x
    assert up[2] == pytest.approx(math.pi / 2)  # screen up is +y (image rows grow downwards)
    tap = goal_from_pixels(view, (300.0, 200.0), (305.0, 203.0), chair=(x - 1.0, y - 1.0))
    assert tap is not None and tap[2] == pytest.approx(math.pi / 4)
    assert goal_from_pixels(view, (math.nan, 1.0), (2.0, 3.0)) is None


def test_picker_ignores_garbage_and_sends_one_goal_per_gesture() -> None:
    view = _view()
    goals: list[tuple[float, float, float]] = []
    picker = GoalPicker(lambda: view, lambda: None, goals.append)
    picker.release(None)  # no press: nothing
    picker.move((10.0, 10.0))
    assert goals == [] and picker.preview() is None
    picker.press((300.0, 200.0))
    picker.move(None)
    picker.move((300.0, 260.0))
    assert picker.preview() is not None and picker.preview()[2] == pytest.approx(-math.pi / 2)
    picker.release(None)  # the mouse left the canvas: the last point counts
    assert len(goals) == 1 and goals[0][2] == pytest.approx(-math.pi / 2)
    picker.release((1.0, 1.0))
    assert len(goals) == 1
    no_map = GoalPicker(lambda: None, lambda: None, goals.append)
    no_map.press((1.0, 1.0))
    no_map.release((1.0, 1.0))
    assert len(goals) == 1


def test_destination_mode_takes_the_drag_from_the_pan() -> None:
    live = LiveView(600, 400)
    live.set_map(sample_grid())
    panel = GoalPanel(live)
    sent: list[tuple[float, float, float]] = []
    panel.picker._on_goal = sent.append  # record instead of sending
    panel.attach(object())
    g = live.gestures
    live.set_zoom(3)  # zoomed in, so a pan can move the view
    before = live.viewport.center
    panel.toggle.value = True
    assert g.picker is panel.picker
    g.on_touch_end(None)  # nothing pressed: nothing sent
    g.on_mouse_up("?", [])
    assert sent == []
    g.on_mouse_down(300, 200)
    g.on_mouse_move("x", None)  # garbage from the page is ignored
    g.on_touch("not a list")  # ignored, the gesture goes on
    g.on_touch([[1, "y"]])
    g.on_mouse_move(340, 200)
    g.on_mouse_up(340, 200)
    assert live.viewport.center == before  # no pan
    assert len(sent) == 1 and sent[0][2] == pytest.approx(0.0, abs=1e-9)
    panel.toggle.value = False
    assert g.picker is None
    g.on_touch([[100, 100]])
    g.on_touch([[150, 100]])
    assert live.viewport.center != before  # panning again
    panel.attach(None)
    assert panel.toggle.disabled


def test_status_words_and_remaining_distance() -> None:
    assert "Set destination" in status_html(None, None)
    goal = (1.0, 2.0, 0.0)
    assert "sending" in status_html(goal, None)
    progress = GoalProgress(GoalStatus.MOVING, goal, 3.25, "Nav2 NavigateToPose (/navigate_to_pose)")
    text = status_html(goal, progress)
    assert "moving" in text and "3.2 m to go" in text and "(1.00, 2.00)" in text
    assert "&lt;b&gt;" in status_html(goal, GoalProgress(GoalStatus.ABORTED, goal, None, "<b>")), "escaped"


@pytest.mark.parametrize(("ros", "bridge"), [("ros1", "official"), ("ros2", "rs")])
def test_the_panel_sends_a_goal_and_cancels_it(sim_factory, link_factory, ros: str, bridge: str) -> None:
    sim = sim_factory(ros=ros, start_pose=(1.0, 6.0, 0.0), bridge=bridge)
    link = link_factory(sim)
    live = LiveView(600, 400)
    live.set_map(sim.grid)
    panel = GoalPanel(live)
    said: list[tuple[str, str]] = []
    panel.speak = said.append
    panel.attach(link)
    panel.send((12.0, 6.0, 0.0))
    assert said == [("goal", "Going to the destination.")]
    assert panel.overlay.goal == (12.0, 6.0, 0.0)
    assert wait_until(lambda: panel.handle is not None and panel.handle.progress().status is GoalStatus.MOVING, 10.0)
    panel.refresh()
    assert panel.cancel_button.layout.display == ""
    panel.cancel()
    assert panel.handle.wait(3.0).status is GoalStatus.CANCELLED
    assert wait_until(lambda: sim.velocity[0] == 0.0, 1.0)
    panel.refresh()
    assert "cancelled" in panel.status.value and panel.cancel_button.layout.display == "none"
    assert panel.overlay.goal is None
    panel.refresh()  # the ending is said once, not at every refresh
    assert said[1:] == [("stop", "Stopped, goal cancelled.")]


@pytest.mark.slow
def test_the_panel_says_the_official_bridge_ignored_the_cancel(sim_factory, link_factory) -> None:
    """rosbridge_suite holds the cancel behind the goal: the panel says "cancel sent", then "cancel
    not honoured" (the chair still moves); the cancel sent again on a second connection stops it."""
    from pmk_nb.chair.link.goals.navigate import GoalPolicy

    sim = sim_factory(ros="ros2", start_pose=(1.0, 6.0, 0.0), bridge="official")
    link = link_factory(sim)
    link.goal_policy = GoalPolicy(verify_s=0.5)
    panel = GoalPanel(LiveView(600, 400))
    panel.speak = lambda _said: None
    panel.attach(link)
    panel.send((6.0, 6.0, 0.0))
    moving = GoalStatus.MOVING
    # on its way (not merely accepted): the cancel is judged against a chair that is really driving
    assert wait_until(lambda: panel.handle is not None and panel.handle.progress().status is moving, 10.0)
    assert wait_until(lambda: sim.velocity[0] > 0.1, 10.0)
    texts: list[str] = []
    panel.handle.on_update(lambda _p: texts.append(panel.status.value))  # what a refresh then showed
    panel.handle.on_update(lambda _p: panel.refresh())
    panel.cancel()
    assert "pmk-goal-cancel-sent" in panel.status.value
    assert panel.handle.wait(5.0).status is GoalStatus.CANCELLED and sim.pose[0] < 5.0
    shown = [t for t in texts if "data-status='cancel_ignored'" in t]
    assert shown and "cancel not honoured" in shown[0] and "did not honour the cancel" in shown[0], texts
    assert "pmk-goal-cancel-sent" not in shown[0] and panel.handle.zero_bursts == 1


@pytest.mark.parametrize(
    ("status", "word"),
    [
        (GoalStatus.LINK_LOST, "link lost"),
        (GoalStatus.NO_ANSWER, "no answer"),
        (GoalStatus.CANCEL_IGNORED, "cancel not honoured"),
        (GoalStatus.UNKNOWN, "outcome unknown"),
    ],
)
def test_the_states_the_link_cannot_vouch_for_are_shown_as_warnings(status: GoalStatus, word: str) -> None:
    goal = (1.0, 2.0, 0.0)
    text = status_html(goal, GoalProgress(status, goal, None, "Nav2: x"))
    assert f"data-status='{status.value}'" in text and f">{word}</b>" in text and "pmk-warn" in text
    assert "pmk-goal-quiet" not in text and "pmk-goal-cancel-sent" not in text
    quiet = status_html(goal, GoalProgress(GoalStatus.MOVING, goal, 2.0, "Nav2: x", quiet_s=31.0))
    assert "pmk-goal-quiet" in quiet and "for 31 s" in quiet and "pmk-warn'>moving" not in quiet
    waiting = status_html(goal, GoalProgress(GoalStatus.MOVING, goal, 2.0, "Nav2: x"), cancel_pending=True)
    assert "pmk-goal-cancel-sent" in waiting


def test_how_a_tapped_goal_ends_is_said_in_words() -> None:
    from pmk_nb.ui.goals.panel import _ending

    assert _ending(GoalStatus.ARRIVED)[1] == "Arrived at the destination."
    assert _ending(GoalStatus.CANCELLED)[1] == "Stopped, goal cancelled."
    assert _ending(GoalStatus.ABORTED)[1] == _ending(GoalStatus.REJECTED)[1] == "Could not reach the destination."
    assert _ending(GoalStatus.UNKNOWN) is None  # not known: shown, never announced as failed


def test_an_error_note_is_escaped_not_markup() -> None:
    """Issue 30: a failed send put the error's text into the panel's HTML unescaped."""
    from pmk_nb.errors import ChairLinkError

    class _Failing:
        def navigate_to(self, *_goal: float) -> None:
            raise ChairLinkError("bad answer <img src=x onerror=alert(1)>")

    panel = GoalPanel(LiveView(600, 400))
    errors: list[str] = []
    panel.on_error = errors.append
    panel.speak = lambda _said: None
    panel._send(_Failing(), (1.0, 2.0, 0.0))
    panel.refresh()
    assert "<img" not in panel.status.value and "&lt;img src=x onerror=alert(1)&gt;" in panel.status.value
    assert errors and "<img" in errors[0]  # the message itself is plain text; its renderer escapes it


def test_a_go_to_is_named_instead_of_no_destination() -> None:
    """Issue 29 item 9: while a Go to… drives, the tap-to-go panel names its room, not "No destination"."""
    assert "No destination" in status_html(None, None)
    text = status_html(None, None, elsewhere="Kitchen <2>")
    assert "No destination" not in text and "Going to <b>Kitchen &lt;2&gt;</b>" in text
    done = GoalProgress(GoalStatus.ARRIVED, (1.0, 2.0, 0.0), 0.0, "arrived")
    assert "Kitchen" in status_html((1.0, 2.0, 0.0), done, elsewhere="Kitchen")  # a finished tap gives way


class _Done:
    """A goal handle whose goal has arrived."""

    cancel_requested = False
    cancel_honoured = None

    def progress(self) -> GoalProgress:
        return GoalProgress(GoalStatus.ARRIVED, (1.0, 2.0, 0.0), 0.0, "arrived")


def test_a_finished_destination_is_not_shown_again_after_a_go_to_or_a_new_map() -> None:
    """Issue 40, item 5: after a tapped goal arrived, a Go to… arrived too, and the panel showed the old
    destination again."""
    from types import SimpleNamespace

    panel = GoalPanel(LiveView(600, 400))
    panel.speak = lambda _said: None
    here = SimpleNamespace(x=1.0, y=2.0)
    panel.goal, panel.handle = (1.0, 2.0, 0.0), _Done()  # type: ignore[assignment]
    panel.tick(here)
    assert "Destination (1.00, 2.00)" in panel.status.value  # how it ended stays shown meanwhile
    panel.tick(here, "Kitchen")
    assert "Going to <b>Kitchen</b>" in panel.status.value
    panel.tick(here, None)  # the Go to… arrived
    assert "Destination (1.00, 2.00)" not in panel.status.value and "No destination" in panel.status.value

    panel.goal, panel.handle = (1.0, 2.0, 0.0), _Done()  # type: ignore[assignment]
    panel.forget_finished()  # Home, when a new map is current
    panel.refresh()
    assert "Destination (1.00, 2.00)" not in panel.status.value
