"""The words a person reads about a goal's state: one place, used by the goal handle's messages
and Home's goal panel. Every sentence says only what the chair said or what is known for sure
(issue 24: the dashboard never shows more certainty than it has)."""

from __future__ import annotations

Point = tuple[float, float]


def at(goal: Point) -> str:
    return f"({goal[0]:.2f}, {goal[1]:.2f})"


def link_lost(goal: Point) -> str:
    return f"link lost: the chair may still be driving to {at(goal)}"


def link_back_asking() -> str:
    return "link back: asking the chair about the goal"


def link_back_cancelling() -> str:
    return "link back: cancel sent (setting: cancel goals when the dashboard loses the chair)"


def link_back_still_driving() -> str:
    return "link back: the chair says it is still driving to the goal"


def link_back_outcome(word: str) -> str:
    return f"link back: the chair says the goal {word} while the link was down"


def link_back_at_goal() -> str:
    return "link back: the chair no longer reports the goal; its pose is at the goal"


def link_back_unknown(pose: Point | None) -> str:
    where = f"; it is at {at(pose)}" if pose is not None else ""
    return f"link back: the chair no longer reports this goal, its outcome is not known{where}"


def no_answer(seconds: float) -> str:
    return f"no answer within {seconds:g} s: the chair may have started; a cancel was sent"


def quiet(seconds: float) -> str:
    return f"no word from the chair about this goal for {seconds:.0f} s"


def cancel_ignored(seconds: float) -> str:
    return f"the chair did not honour the cancel: still moving {seconds:g} s later; zero velocity sent"


def cancel_sent() -> str:
    return "cancel sent; waiting for the chair to confirm"


# Home panel: the status word shown for each state (GoalStatus value -> words)
def stop_latched() -> str:
    return "Stopped: no destination until the Stop is released on the page where it was pressed."


STATUS_WORDS = {
    "pending": "sending",
    "accepted": "accepted",
    "moving": "moving",
    "arrived": "arrived",
    "aborted": "aborted",
    "cancelled": "cancelled",
    "rejected": "rejected",
    "link_lost": "link lost",
    "no_answer": "no answer",
    "cancel_ignored": "cancel not honoured",
    "unknown": "outcome unknown",
}


def bridge_ignores_cancels(new_thread: bool | None) -> str:
    """The chair-test / Settings note for rosbridge_suite (see :mod:`pmk_nb.chair.link.query.bridge_kind`)."""
    if new_thread:
        return (
            "The chair runs rosbridge_suite: it does not cancel the dashboard's goals when the link drops "
            "(run pmk robot goal-watchdog on the chair), and never answers a goal the chair rejects."
        )
    return (
        "The chair runs rosbridge_suite with send_action_goals_in_new_thread off (its default): it ignores "
        "Cancel until the goal has ended and holds the dashboard's other commands (even Stop) behind a running "
        "goal (the dashboard then sends Cancel and Stop again over a second connection), and keeps driving "
        "when the link drops. Start it with send_action_goals_in_new_thread:=true and run pmk robot "
        "goal-watchdog on the chair."
    )
