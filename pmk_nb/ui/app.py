"""The dashboard shell: navigation and information panel, and the active screen beside or below them.

Same layout as the original tablet app (thesis 4.2.1.1) on a wide screen: Home, Maps and Settings
buttons, below them an information panel (the active screen's info plus the latest message with
no place on the screen), and the screen's content filling the rest.  On a narrow app (portrait
tablet, phone, JupyterLab beside its file browser) the same panel becomes a top bar; see
:mod:`pmk_nb.ui.common.style`.  ``build_app()`` is all a notebook or the Voilà kiosk page needs.
"""

from __future__ import annotations

import atexit
import logging
from collections.abc import Callable
from pathlib import Path
from typing import Any, Protocol

import ipywidgets as w

from pmk_nb.errors import PmkError
from pmk_nb.ui.common.context import AppContext, Notification, autostart_from_env
from pmk_nb.ui.common.display_prefs import DisplayPrefs
from pmk_nb.ui.common.widgets import button, close_tree, escape, guard, style_widget

log = logging.getLogger(__name__)

SCREENS: tuple[str, ...] = ("home", "maps", "settings")
_NAV_LABELS = {"home": ("Home", "home"), "maps": ("Maps", "map"), "settings": ("Settings", "cog")}
NAV_ICONS = {name: icon for name, (_label, icon) in _NAV_LABELS.items()}  # the kiosk's lock swaps them


class Screen(Protocol):
    widget: w.Widget
    info_widget: w.Widget

    def close(self) -> None: ...


class Dashboard(w.VBox):
    """The whole app as one widget; ``show(name)`` switches screens like the navigation buttons.

    Args:
        ctx: the session state shared by the screens.
        autostart_preview: start Home's live preview whenever Home is shown (demo, kiosk).

    Attributes:
        ctx: the session state shared by the screens.
        screens: ``{"home": HomeScreen, "maps": MapsScreen, "settings": SettingsScreen}``.
    """

    def __init__(self, ctx: AppContext, *, autostart_preview: bool = False) -> None:
        from pmk_nb.ui.home.screen import HomeScreen
        from pmk_nb.ui.maps.screen import MapsScreen
        from pmk_nb.ui.settings.screen import SettingsScreen

        self.ctx = ctx
        self._builders: dict[str, Callable[[], Any]] = {
            "home": lambda: HomeScreen(ctx, autostart=autostart_preview),
            "maps": lambda: MapsScreen(ctx),
            "settings": lambda: SettingsScreen(ctx),
        }
        # Only Home is built with the page: Maps and Settings are built when first opened (their
        # ~500 widgets halved a page's start, and most pages, a rider's kiosk above all, never
        # open them). A locked kiosk page builds no screen behind the PIN: a widget that does not
        # exist cannot be reached by a page script speaking the widget protocol (``ctx.may_open``).
        self.screens: dict[str, Any] = {"home": self._builders["home"]()}
        self.current = "home"
        self.nav_buttons: dict[str, w.Button] = {}
        self.nav_icons = NAV_ICONS  # the kiosk's lock puts them back (kiosk.py does not import this module)
        for name in SCREENS:
            label, icon = _NAV_LABELS[name]
            btn = button(label, f"pmk-nav-{name}", icon=icon, width=None)
            btn.on_click(guard(ctx, f"Opening {label}")(lambda _b, n=name: self.show(n)))
            self.nav_buttons[name] = btn
        self.message = w.HTML("")
        self.message.add_class("pmk-message")
        self.info_slot = w.VBox([])
        info = w.VBox([self.info_slot, self.message])
        info.add_class("pmk-info")
        title = w.HTML("<div class='pmk-title'>PMK Wheelchair</div>")
        title.add_class("pmk-nav-title")
        # sizes come from the style sheet (pmk_nb.ui.common.style): a sidebar on a wide app, a top bar on
        # a narrow one; a Layout width here would be an inline style no container rule can change
        self.nav = w.VBox([title, *self.nav_buttons.values(), info])
        self.nav.add_class("pmk-nav")
        self.content = w.Box([])
        self.content.add_class("pmk-content")
        self.shell = w.Box([self.nav, self.content])
        self.shell.add_class("pmk-shell")
        # the root is the CSS size container: the layout follows the app's own width (a phone, a
        # portrait tablet, JupyterLab's main area beside the file browser), not the window's
        super().__init__([style_widget(), self.shell], layout=w.Layout(width="100%"))
        self.add_class("pmk-app")
        self.display = DisplayPrefs(self, ctx)  # high contrast, large text (pmk_nb/ui/common/display_prefs.py)
        self._unsubscribe = ctx.observe_notifications(self._on_notification)
        if ctx.notifications:  # problems found while the screens were built
            self._on_notification(ctx.notifications[-1])
        self._closed = False
        # kiosk hook (pmk_nb/ui/kiosk/mode.py): return False to keep a screen closed (e.g. behind a PIN)
        self.gate: Callable[[str], bool] | None = None
        self.show("home")

    def show(self, name: str) -> None:
        """Switch to a screen; leaving Home stops the live preview (as the Android app did)."""
        if name not in SCREENS:
            raise ValueError(f"unknown screen {name!r}; expected one of {', '.join(SCREENS)}")
        if self.gate is not None and not self.gate(name):
            return
        screen = self.screen(name)
        previous = self.current
        if previous == "home" and name != "home":
            self.screens["home"].stop_preview()
        self.current = name
        self.content.children = (screen.widget,)
        self.info_slot.children = (screen.info_widget,)
        for other, btn in self.nav_buttons.items():
            if other == name:
                btn.add_class("pmk-nav-active")
            else:
                btn.remove_class("pmk-nav-active")
        self.display.refresh()  # a profile saved by another page shows here on the next screen
        on_show = getattr(screen, "on_show", None)
        if on_show is not None:
            on_show()
        for other in [n for n in self.screens if not self.ctx.may_open(n)]:  # locked again: gone
            self.drop(other)

    def screen(self, name: str) -> Any:
        """The screen ``name``, built now if it was not (behind the kiosk PIN: only once unlocked)."""
        if not self.ctx.may_open(name):  # also a screen built before another page set the PIN
            self.ctx.require_unlocked(f"Opening {name.title()}")
        if name not in self.screens:
            self.screens[name] = self._builders[name]()
        return self.screens[name]

    def drop(self, name: str) -> None:
        """Stop a screen and close its whole widget tree: its models leave the kernel and the page."""
        screen = self.screens.pop(name, None)
        if screen is None:
            return
        try:
            screen.close()
        except Exception:
            log.exception("closing the %s screen failed", name)
        close_tree(screen.widget)
        close_tree(screen.info_widget)

    def _on_notification(self, note: Notification) -> None:
        """The latest message with no place of its own; any later one (even inline) clears it."""
        if note.inline:
            self.message.value = ""
            return
        self.message.value = f"<div class='pmk-msg-{note.level}'>{escape(note.message)}</div>"

    def close(self) -> None:
        """Stop every screen and close the chair link of this session.

        Also reached from ``Widget.__del__`` (garbage collection, interpreter exit): runs once.
        """
        if getattr(self, "_closed", True):
            super().close()
            return
        self._closed = True
        self._unsubscribe()
        self.display.close()
        for screen in self.screens.values():
            try:
                screen.close()
            except Exception:
                log.exception("closing a screen failed")
        self.ctx.close()
        super().close()


def build_app(
    maps_dir: str | Path | None = None,
    config_dir: str | Path | None = None,
    *,
    ctx: AppContext | None = None,
    autostart_preview: bool | None = None,
) -> w.Widget:
    """Build the dashboard; display the returned widget (a notebook cell's last line does that).

    Args:
        maps_dir: the maps folder (default: ``PMK_MAPS_DIR`` or the user data dir).
        config_dir: where chair profiles and UI state live (default: ``PMK_CONFIG_DIR`` or user config).
        ctx: an existing session state (tests); overrides both directories.
        autostart_preview: start the live preview when Home is shown; None reads
            ``PMK_AUTOSTART_PREVIEW`` (set by ``pmk demo``).

    Returns:
        The :class:`Dashboard`, or, when even the folders cannot be opened, a message saying why
        (a kiosk page must not show a traceback).
    """
    try:
        if ctx is None and config_dir is None:  # a classroom page (PMK_CLASSROOM): its own chair, issue 26
            from pmk_nb.ui.classroom_page import classroom_context

            ctx = classroom_context(maps_dir)
        if ctx is None:
            from pmk_nb.chair import PROFILES_FILE, ProfileStore
            from pmk_nb.library import MapsFolder

            cfg = Path(config_dir) if config_dir is not None else None
            profiles = ProfileStore(cfg / PROFILES_FILE) if cfg is not None else ProfileStore()
            maps = MapsFolder(Path(maps_dir) if maps_dir is not None else None)
            ctx = AppContext(maps, profiles, config_dir=cfg)
        if ctx.kiosk is None:  # a kiosk page (PMK_KIOSK): locked before any screen is built
            from pmk_nb.ui.kiosk.pin import kiosk_lock

            ctx.kiosk = kiosk_lock(ctx.config_dir)
        if autostart_preview is None:
            autostart_preview = autostart_from_env()
        app = Dashboard(ctx, autostart_preview=autostart_preview)
    except PmkError as err:
        box = w.HTML(f"<div class='pmk-msg-error'><b>The dashboard cannot start:</b> {escape(err)}</div>")
        box.add_class("pmk-app-error")
        return box
    # One chair connection per page: closed when the kernel goes (Voilà culls idle kernels).
    atexit.register(app.ctx.close)
    # Kiosk mode and the page's lifecycle (pmk_nb/ui/kiosk/mode.py, pmk_nb/ui/common/page_lifecycle.py): both do
    # nothing outside a Voilà page / without a kiosk lock (PMK_KIOSK).
    from pmk_nb.ui.common import page_lifecycle
    from pmk_nb.ui.kiosk import mode as kiosk

    kiosk.apply(app)
    page_lifecycle.attach(app)
    return app
