"""Shared look and behaviour of the dashboard widgets: touch-sized controls and safe callbacks.

The kiosk runs on a landscape tablet held at arm's length, so every control is at least 48 px high
and text is large.  Every callback goes through :func:`guard` so a failure becomes a message in the
information panel instead of a traceback in the page (Voilà hides tracebacks, leaving the user
with a button that silently does nothing).
"""

from __future__ import annotations

import functools
import html
import logging
import math
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TypeVar

import ipywidgets as w

from pmk_nb.errors import PmkError
from pmk_nb.progress import Progress, ProgressCallback

if TYPE_CHECKING:
    from pmk_nb.ui.context import AppContext

log = logging.getLogger(__name__)

F = TypeVar("F", bound=Callable[..., Any])

TOUCH_PX = 56  # comfortably above the 48 px minimum touch target
BASE_FONT_PX = 18

#: One stylesheet for the whole app, injected once per page by :func:`style_widget`.
APP_CSS = f"""
<style>
.pmk-app {{ font-size: {BASE_FONT_PX}px; --jp-widgets-font-size: {BASE_FONT_PX}px;
            --jp-widgets-inline-height: {TOUCH_PX - 8}px; --jp-ui-font-size1: {BASE_FONT_PX}px; }}
.pmk-app .widget-label, .pmk-app .widget-html-content, .pmk-app .widget-inline-hbox .widget-label
   {{ font-size: {BASE_FONT_PX}px; line-height: 1.3; }}
.pmk-app input, .pmk-app select, .pmk-app textarea, .pmk-app .widget-dropdown > select
   {{ font-size: {BASE_FONT_PX}px !important; min-height: {TOUCH_PX - 8}px; }}
.pmk-app button.jupyter-button, .pmk-app .jupyter-button
   {{ font-size: {BASE_FONT_PX}px; min-height: {TOUCH_PX}px; min-width: {TOUCH_PX}px; border-radius: 6px; }}
.pmk-app .widget-select select {{ font-size: {BASE_FONT_PX + 2}px; }}
.pmk-app .widget-select option {{ padding: 10px 6px; }}
.pmk-app .widget-tab > .lm-TabBar, .pmk-app .widget-tab > .lm-TabBar .lm-TabBar-tab,
.pmk-app .widget-tab > .lm-TabBar .lm-TabBar-tabLabel
   {{ font-size: {BASE_FONT_PX}px !important; min-height: {TOUCH_PX - 8}px !important;
      line-height: {TOUCH_PX - 8}px !important; }}
.pmk-app .widget-tab > .lm-TabBar .lm-TabBar-tab {{ flex: 0 1 200px !important; }}
.pmk-app .widget-checkbox input[type="checkbox"] {{ width: 28px; height: 28px; margin: 0 8px 0 0; }}
.pmk-app .widget-checkbox label {{ display: flex; align-items: center; font-size: {BASE_FONT_PX}px; }}
.pmk-nav {{ background: #263238; color: #eceff1; padding: 12px; border-radius: 8px; }}
.pmk-nav .pmk-title {{ color: #eceff1; font-size: 24px; font-weight: 600; margin-bottom: 8px; }}
.pmk-nav .widget-html-content {{ color: #eceff1; }}
.pmk-nav button.pmk-nav-active {{ background: #4fc3f7; color: #000; font-weight: 600; }}
.pmk-info {{ background: #37474f; border-radius: 6px; padding: 8px; margin-top: 12px; }}
.pmk-info .widget-html-content {{ color: #eceff1; font-size: {BASE_FONT_PX - 1}px; }}
.pmk-msg-info {{ color: #b3e5fc; }}
.pmk-msg-warning {{ color: #ffe082; font-weight: 600; }}
.pmk-msg-error {{ color: #ff8a80; font-weight: 600; }}
/* the same message classes on the white content area: dark text on a tinted band (the pale colours
   above are for the dark panel) */
.pmk-content .pmk-msg-warning {{ color: #6d4c00; background: #fff8e1; border-left: 5px solid #ffb300;
   padding: 6px 10px; border-radius: 4px; margin: 2px 0; }}
.pmk-content .pmk-msg-error {{ color: #b71c1c; background: #ffebee; border-left: 5px solid #e53935;
   padding: 6px 10px; border-radius: 4px; margin: 2px 0; }}
.pmk-content .pmk-msg-info {{ color: #01579b; }}
.pmk-field-error {{ color: #c62828; font-size: {BASE_FONT_PX - 2}px; }}
.pmk-content {{ padding: 0 16px; }}
.pmk-heading {{ font-size: 26px; font-weight: 600; margin: 4px 0 12px 0; }}
.pmk-confirm {{ background: #fff8e1; border: 2px solid #ffb300; border-radius: 6px; padding: 8px; }}
.pmk-app .widget-progress {{ height: 18px; }}
.pmk-home .pmk-heading {{ margin-bottom: 4px; }}
.pmk-home-preview-box {{ width: fit-content; max-width: 100%; gap: 8px; }}
.pmk-home-toolbar {{ min-height: {TOUCH_PX}px; }}
.pmk-home-zoom button.jupyter-button {{ min-width: 64px; }}
/* the canvas has the map's shape; on a smaller screen the page scales it down, keeping that shape
   (height auto), and never taller than the window below the toolbar */
.pmk-app canvas.pmk-live-canvas {{ max-width: 100%; height: auto; width: auto;
   max-height: calc(100vh - 200px); border: 1px solid #b0bec5; border-radius: 4px; }}
</style>
"""


def style_widget() -> w.HTML:
    """The stylesheet as a (zero-size) widget; put it once in the app's tree."""
    css = w.HTML(APP_CSS, layout=w.Layout(height="0px", width="0px", overflow="hidden"))
    css.add_class("pmk-style")
    return css


def button(
    description: str,
    css_class: str,
    *,
    icon: str = "",
    style: str = "",
    tooltip: str = "",
    width: str = "auto",
) -> w.Button:
    """A touch-sized button with a stable CSS class for the browser tests."""
    btn = w.Button(
        description=description,
        icon=icon,
        button_style=style,
        tooltip=tooltip or description,
        layout=w.Layout(height=f"{TOUCH_PX}px", width=width, min_width="120px"),
    )
    btn.add_class(css_class)
    return btn


def text(value: str, label: str, css_class: str, *, placeholder: str = "", password: bool = False) -> w.Text:
    """A labelled text box, wide enough for a URL and tall enough for a finger."""
    cls = w.Password if password else w.Text
    box = cls(
        value=value,
        description=label,
        placeholder=placeholder,
        style={"description_width": "200px"},
        layout=w.Layout(width="100%", max_width="720px", height=f"{TOUCH_PX - 8}px"),
    )
    box.add_class(css_class)
    return box


def heading(title: str) -> w.HTML:
    out = w.HTML(f"<div class='pmk-heading'>{escape(title)}</div>")
    return out


def escape(value: object) -> str:
    """HTML-escape anything shown inside an HTML widget (names come from files and users)."""
    return html.escape(str(value), quote=True)


def field_error() -> w.HTML:
    """An (initially empty) error line shown under a form field."""
    err = w.HTML("")
    err.add_class("pmk-field-error")
    return err


def progress_bar(css_class: str) -> w.FloatProgress:
    """A hidden-until-used 0..1 progress bar."""
    bar = w.FloatProgress(
        value=0.0, min=0.0, max=1.0, layout=w.Layout(width="100%", max_width="720px", visibility="hidden")
    )
    bar.add_class(css_class)
    return bar


def set_progress(bar: w.FloatProgress, fraction: float | None, *, style: str = "info") -> None:
    """Show ``fraction`` (None hides the bar); tolerant of NaN and out-of-range values."""
    if fraction is None:
        bar.layout.visibility = "hidden"
        return
    value = 0.0 if not math.isfinite(fraction) else min(1.0, max(0.0, float(fraction)))
    bar.bar_style = style
    bar.value = value
    bar.layout.visibility = "visible"


#: How the dashboard names the core's progress steps (other steps are shown capitalised).
STEP_WORDS = {"read": "Reading", "rasterise": "Rasterising", "write": "Saving", "done": "Done",
              "download": "Downloading", "upload": "Uploading"}  # fmt: skip


def progress_text(p: Progress) -> str:
    """A progress report in the dashboard's words: "Rasterising storey F1"."""
    word = STEP_WORDS.get(p.step, p.step.capitalize())
    return f"{word} {p.message}".strip()


def progress_callback(bar: w.FloatProgress, label: w.HTML | None = None) -> ProgressCallback:
    """A :data:`~pmk_nb.progress.ProgressCallback` that moves ``bar`` (and shows the step in ``label``).

    A report without a fraction (e.g. a download of unknown size) creeps the bar towards the end, one
    step per report, so the user still sees activity.
    """
    unknown = [0]

    def update(p: Progress) -> None:
        try:
            if p.fraction is None:
                unknown[0] += 1
                set_progress(bar, 0.9 - 0.8 / (1.0 + unknown[0] / 20))
            else:
                set_progress(bar, p.fraction)
            if label is not None:
                label.value = escape(progress_text(p)) + "…"
        except Exception:  # progress is cosmetic: never let it break the work
            log.debug("progress update failed", exc_info=True)

    return update


def show_failure(bar: w.FloatProgress, label: w.HTML) -> Callable[[BaseException], None]:
    """An ``on_error`` for :func:`run_in_thread`: the bar turns red, ``label`` shows the message."""

    def failed(err: BaseException) -> None:
        set_progress(bar, 1.0, style="danger")
        label.value = f"<span class='pmk-field-error'>{escape(err)}</span>"

    return failed


def report_error(ctx: AppContext, err: BaseException, action: str) -> str:
    """Turn an exception into a user message in the info panel; returns the message."""
    if isinstance(err, PmkError):
        message = f"{action} failed: {err}"
    else:
        log.exception("%s failed", action, exc_info=err)
        message = f"{action} failed unexpectedly ({type(err).__name__}: {err})."
    ctx.notify(message, "error")
    return message


def guard(ctx: AppContext, action: str) -> Callable[[F], F]:
    """Decorator for widget callbacks: any exception becomes a message in the app, not a traceback."""

    def wrap(fn: F) -> F:
        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            try:
                return fn(*args, **kwargs)
            except Exception as err:
                report_error(ctx, err, action)
                return None

        return wrapper  # type: ignore[return-value]

    return wrap


def run_in_thread(
    ctx: AppContext,
    action: str,
    work: Callable[[], Any],
    *,
    on_done: Callable[[Any], None] | None = None,
    on_error: Callable[[BaseException], None] | None = None,
    busy: list[w.Widget] | None = None,
    exclusive: threading.Lock | None = None,
) -> threading.Thread | None:
    """Run slow work (download, convert, send) off the kernel's main thread.

    ipywidgets state changes made from a thread are sent to the page by ipykernel, so progress bars
    move while the work runs.  ``busy`` widgets are disabled until the work ends; since a page can
    re-enable a button by itself, ``exclusive`` (a lock held while the work runs) is what really
    refuses a second start.  Returns the thread, or None when refused.
    """
    if exclusive is not None and not exclusive.acquire(blocking=False):
        ctx.notify(f"{action} is already running: wait for it to finish.", "warning")
        return None
    for widget in busy or []:
        widget.disabled = True

    def target() -> None:
        try:
            result = work()
        except Exception as err:
            report_error(ctx, err, action)
            if on_error is not None:
                guard(ctx, action)(on_error)(err)
        else:
            if on_done is not None:
                guard(ctx, action)(on_done)(result)
        finally:
            for widget in busy or []:
                widget.disabled = False
            if exclusive is not None:
                exclusive.release()

    thread = threading.Thread(target=target, name=f"pmk-{action}", daemon=True)
    try:
        thread.start()
    except BaseException:
        if exclusive is not None:
            exclusive.release()
        raise
    return thread


class ConfirmBox:
    """An explicit in-page "are you sure?" step (a Voilà page has no modal dialogs).

    ``ask(message, on_yes)`` shows the box; the yes button runs ``on_yes`` once, the no button hides it.
    """

    def __init__(self, ctx: AppContext, css_prefix: str, *, yes: str = "Overwrite", no: str = "Cancel") -> None:
        self._on_yes: Callable[[], None] | None = None
        self.message = w.HTML("")
        self.yes = button(yes, f"{css_prefix}-yes", style="warning", icon="check")
        self.no = button(no, f"{css_prefix}-no", icon="times")
        self.yes.on_click(guard(ctx, "Confirming")(lambda _b: self._answer(True)))
        self.no.on_click(guard(ctx, "Cancelling")(lambda _b: self._answer(False)))
        self.widget = w.VBox([self.message, w.HBox([self.yes, self.no])], layout=w.Layout(display="none"))
        self.widget.add_class("pmk-confirm")
        self.widget.add_class(css_prefix)

    @property
    def visible(self) -> bool:
        return self.widget.layout.display != "none"

    def ask(self, message: str, on_yes: Callable[[], None]) -> None:
        self.message.value = f"<b>{escape(message)}</b>"
        self._on_yes = on_yes
        self.widget.layout.display = "flex"

    def hide(self) -> None:
        self._on_yes = None
        self.widget.layout.display = "none"

    def _answer(self, yes: bool) -> None:
        action = self._on_yes
        self.hide()
        if yes and action is not None:
            action()
