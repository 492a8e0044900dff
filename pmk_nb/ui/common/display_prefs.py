"""The rider's display settings from the chair profile, applied as CSS classes on the app root.

``high_contrast`` and ``large_text`` (Settings, kept in the chair profile like the drive limits)
become ``pmk-high-contrast`` / ``pmk-large-text`` on ``.pmk-app``; the rules are in
:mod:`pmk_nb.ui.common.a11y_style`.  The profile is read again whenever the app shows a screen and
whenever something is announced (a saved profile always is: "Saved settings for …"), so a change
shows at once without the Settings screen knowing about the app.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import ipywidgets as w

    from pmk_nb.ui.common.context import AppContext

#: profile field -> the class it puts on the app root
DISPLAY_CLASSES: dict[str, str] = {"high_contrast": "pmk-high-contrast", "large_text": "pmk-large-text"}


def display_classes(profile: Any) -> frozenset[str]:
    """The root classes a profile asks for (none without a profile; only a real True counts)."""
    if profile is None:
        return frozenset()
    return frozenset(css for field, css in DISPLAY_CLASSES.items() if getattr(profile, field, False) is True)


class DisplayPrefs:
    """Keeps ``root``'s display classes in step with ``ctx``'s current chair profile."""

    def __init__(self, root: w.DOMWidget, ctx: AppContext) -> None:
        self.root = root
        self.ctx = ctx
        self._unsubscribe = ctx.observe_notifications(lambda _note: self.refresh())
        self.refresh()

    def refresh(self) -> frozenset[str]:
        """Re-read the profile and set the classes; returns those now on."""
        wanted = display_classes(self.ctx.profile())
        for css in DISPLAY_CLASSES.values():  # add_class / remove_class sync only a change
            if css in wanted:
                self.root.add_class(css)
            else:
                self.root.remove_class(css)
        return wanted

    def close(self) -> None:
        self._unsubscribe()
