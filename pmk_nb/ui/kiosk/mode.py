"""Kiosk mode: a tablet on the chair shows Home with big targets; Maps and Settings need the PIN.

``apply(app)`` turns a :class:`~pmk_nb.ui.app.Dashboard` into the kiosk page when
``PMK_KIOSK=1`` (``pmk dashboard --kiosk``, ``pmk demo``): the navigation asks for the PIN before
Maps or Settings (:class:`KioskGate`, through the Dashboard's ``gate`` hook), going back Home locks
again, and the page asks the browser to keep the screen on (Screen Wake Lock API) and says so
where the browser cannot.  The PIN is set in Settings (:func:`pin_section`); until one is set,
Maps and Settings stay open and say how to lock them.

The prompt is only the face of the lock: the kernel decides (:class:`~pmk_nb.ui.kiosk.pin.KioskLock`
in ``AppContext.kiosk``).  While locked, the Maps and Settings widgets do not exist (the Dashboard
builds them once the PIN is accepted and closes them on the way back Home), and each of their
actions checks the lock itself (``AppContext.require_unlocked``).
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING, Any

import ipywidgets as w

from pmk_nb.errors import SettingsError
from pmk_nb.ui.common.widgets import button, escape, guard, heading, text
from pmk_nb.ui.kiosk.pin import LOCKED, PIN_MAX, PIN_MIN, KioskLock, PinStore

if TYPE_CHECKING:
    from pmk_nb.ui.common.context import AppContext

log = logging.getLogger(__name__)

__all__ = ["LOCKED", "KioskGate", "apply", "pin_section", "wake_lock_html"]
# !important: the app's own sheet (style.py) sets the 56 px touch size with a more specific selector
KIOSK_CSS = """<style>
.pmk-kiosk button.jupyter-button, .pmk-kiosk .jupyter-button { min-height: 64px !important; font-size: 1.25em; }
.pmk-kiosk button.pmk-nav-home { min-height: 96px !important; font-size: 1.5em; }
.pmk-kiosk-pin-box input { font-size: 1.5em; letter-spacing: 0.3em; }
.pmk-wakelock { position: fixed; left: 8px; bottom: 4px; font-size: 12px; color: #455a64; z-index: 10;
   background: rgba(255,255,255,0.85); padding: 2px 6px; border-radius: 4px; pointer-events: none; }
.pmk-wakelock.pmk-wakelock-off { color: #b71c1c; font-size: 14px; }
</style>"""
WAKE_ON = "Screen kept on."
WAKE_MISSING = "This browser cannot keep the screen on: set the tablet's screen timeout to Never."
WAKE_REFUSED = "The browser did not allow keeping the screen on: set the tablet's screen timeout to Never."

#: Enter in the PIN box presses Unlock (capture phase: the text box stops its key events).  Not
#: ``Text.on_submit`` (deprecated), nor ``continuous_update=False`` + observing the value: that
#: submits on every blur too, so a typed PIN would be tried (and a wrong one counted) on a tap on
#: "Back to Home", and a tap on Unlock would submit it twice.
PIN_ENTER_SCRIPT = """<script>
(function () {
  if (window.__pmkPinEnter) return;
  window.__pmkPinEnter = true;
  document.addEventListener('keydown', function (e) {
    if (e.key !== 'Enter' || e.isComposing || !e.target.closest || !e.target.closest('.pmk-kiosk-pin')) return;
    var unlock = document.querySelector('button.pmk-kiosk-unlock');
    if (unlock) { e.preventDefault(); unlock.click(); }
  }, true);
})();
</script>"""


def wake_lock_html() -> str:
    """A status line and the script that holds a screen wake lock (again after the page was hidden)."""
    return f"""<div class="pmk-wakelock" role="status"></div>
<script>
(function () {{
  if (window.__pmkWakeLock) return;
  window.__pmkWakeLock = true;
  function say(text, off) {{
    document.querySelectorAll('.pmk-wakelock').forEach(function (el) {{
      el.textContent = text; el.classList.toggle('pmk-wakelock-off', !!off);
      el.dataset.state = off ? 'off' : 'on';
    }});
  }}
  async function hold() {{
    if (!('wakeLock' in navigator)) {{ say({WAKE_MISSING!r}, true); return; }}
    try {{
      var sentinel = await navigator.wakeLock.request('screen');
      say({WAKE_ON!r}, false);
      sentinel.addEventListener('release', function () {{ if (!document.hidden) hold(); }});
    }} catch (err) {{ say({WAKE_REFUSED!r}, true); }}
  }}
  document.addEventListener('visibilitychange', function () {{ if (!document.hidden) hold(); }});
  hold();
}})();
</script>"""


class KioskGate:
    """Asks for the PIN before Maps or Settings; unlocked until the user goes back Home."""

    def __init__(self, app: Any, lock: KioskLock) -> None:
        self.app = app
        self.lock = lock
        self.pins = lock.pins
        self._target = ""
        self.title = w.HTML("")
        self.pin = text("", "PIN", "pmk-kiosk-pin", password=True)
        self.status = w.HTML("")
        self.status.add_class("pmk-kiosk-pin-status")
        self.unlock_button = button("Unlock", "pmk-kiosk-unlock", icon="unlock", style="primary")
        self.cancel_button = button("Back to Home", "pmk-kiosk-cancel", icon="home")
        # the one way a PIN is submitted; Enter in the box presses it (PIN_ENTER_SCRIPT)
        self.unlock_button.on_click(guard(app.ctx, "Checking the PIN")(lambda _b: self.submit()))
        self.cancel_button.on_click(guard(app.ctx, "Going back Home")(lambda _b: app.show("home")))
        row = w.HBox([self.unlock_button, self.cancel_button])
        row.add_class("pmk-row")
        self.widget = w.VBox([self.title, self.pin, row, self.status], layout=w.Layout(width="100%"))
        self.widget.add_class("pmk-kiosk-pin-box")

    def allows(self, name: str) -> bool:
        """The Dashboard's gate: True lets ``show(name)`` go on; False shows the PIN prompt instead."""
        show_lock_icons(self.app, self.lock)  # a PIN set or removed meanwhile (here or on another page)
        if name not in self.lock.screens:
            self.lock.lock()  # back Home (or elsewhere): lock again; the Dashboard drops the screens
            return True
        if self.lock.allows(name):
            return True
        self._target = name
        self.app.screens["home"].stop_preview()
        self.title.value = f"<div class='pmk-heading'>Enter the PIN to open {escape(name.title())}</div>"
        self.pin.value = ""
        self.status.value = ""
        self.app.content.children = (self.widget,)
        return False

    def submit(self) -> bool:
        """Check the typed PIN; open the screen asked for, or say why not."""
        typed = str(self.pin.value or "").strip()
        self.pin.value = ""
        if not typed:
            return self._say("Type the PIN first.")
        if not typed.isdigit() or not PIN_MIN <= len(typed) <= PIN_MAX:
            return self._say(f"Wrong PIN: a PIN has {PIN_MIN} to {PIN_MAX} digits.")
        try:
            answer = self.pins.check(typed)
        except SettingsError as err:
            return self._say(str(err))
        if answer.wait_s > 0:
            return self._say(f"Too many wrong PINs: try again in {answer.wait_s:.0f} s.")
        if not answer.ok:
            return self._say("Wrong PIN.")
        self.lock.unlock()
        self.status.value = ""
        self.app.show(self._target or "settings")
        return True

    def _say(self, message: str) -> bool:
        self.status.value = f"<div class='pmk-msg-error'>{escape(message)}</div>"
        return False


def pin_section(ctx: AppContext) -> w.Widget:
    """The Settings block that sets or removes the kiosk PIN (validated here, stored hashed)."""
    pins = PinStore(ctx.config_dir)
    new = text("", "New PIN", "pmk-kiosk-pin-new", password=True)
    repeat = text("", "Repeat the PIN", "pmk-kiosk-pin-repeat", password=True)
    state = w.HTML("")
    state.add_class("pmk-kiosk-pin-state")
    message = w.HTML("")
    message.add_class("pmk-kiosk-pin-message")
    set_button = button("Set PIN", "pmk-kiosk-pin-set", icon="lock")
    remove_button = button("Remove PIN", "pmk-kiosk-pin-remove", icon="unlock")

    def show_state() -> None:
        state.value = (
            "A PIN protects Maps and Settings on the kiosk page."
            if pins.is_set()
            else "No PIN yet: on the kiosk page anyone can open Maps and Settings."
        )

    def set_pin(_b: object) -> None:
        ctx.require_unlocked("Setting the kiosk PIN")  # changing a PIN needs it; the first one does not
        try:
            pins.set_pin(str(new.value or ""), str(repeat.value or ""))
        except SettingsError as err:
            message.value = f"<div class='pmk-msg-error'>{escape(err)}</div>"
            return
        finally:
            new.value, repeat.value = "", ""
        if ctx.kiosk is not None:
            ctx.kiosk.unlock()  # who just set the PIN knows it: this page stays open until back Home
        message.value = "<div class='pmk-msg-info'>PIN saved.</div>"
        show_state()

    def remove_pin(_b: object) -> None:
        ctx.require_unlocked("Removing the kiosk PIN")
        pins.clear()
        message.value = "<div class='pmk-msg-info'>PIN removed.</div>"
        show_state()

    set_button.on_click(guard(ctx, "Setting the kiosk PIN")(set_pin))
    remove_button.on_click(guard(ctx, "Removing the kiosk PIN")(remove_pin))
    show_state()
    row = w.HBox([set_button, remove_button])
    row.add_class("pmk-row")
    box = w.VBox([heading("Kiosk PIN"), state, new, repeat, row, message], layout=w.Layout(width="100%"))
    box.add_class("pmk-kiosk-pin-section")
    return box


def show_lock_icons(app: Any, lock: KioskLock) -> None:
    """A lock on the navigation buttons of the screens behind the PIN, only while a PIN is set: with
    no PIN those screens open freely (Settings says how to lock them), a lock icon would say otherwise."""
    pin = lock.pins.is_set()
    for name in lock.screens:
        btn = app.nav_buttons.get(name)
        if btn is not None:
            btn.icon = "lock" if pin else app.nav_icons.get(name, "")


def apply(app: Any) -> KioskGate | None:
    """Make ``app`` the kiosk page when its session has a kiosk lock (``build_app`` sets one when
    ``PMK_KIOSK`` asks for it); returns the gate (None: not a kiosk)."""
    lock = app.ctx.kiosk
    if lock is None:
        return None
    from IPython.display import HTML, display

    gate = KioskGate(app, lock)
    app.gate = gate.allows
    app.add_class("pmk-kiosk")
    show_lock_icons(app, lock)
    display(HTML(KIOSK_CSS + wake_lock_html() + PIN_ENTER_SCRIPT))
    return gate
