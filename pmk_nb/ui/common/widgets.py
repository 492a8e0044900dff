"""Shared look and behaviour of the dashboard widgets: touch-sized controls and safe callbacks.

The kiosk runs on a tablet or phone held at arm's length, so every control is at least 48 px high
and text is large (the style sheet is :mod:`pmk_nb.ui.common.style`).  Every callback goes through
:func:`guard` so a failure becomes a message in the page instead of a traceback (Voilà hides
tracebacks, leaving the user with a button that silently does nothing).

One place per message: work run by :func:`run_in_thread` with an ``on_error`` shows its failure
there (next to the control that started it) and the app's message line only clears; a failure
with no place of its own goes to the app's message line.  Errors are worded for the page by
:func:`error_text`, from their types and fields.
"""

from __future__ import annotations

import base64
import functools
import html
import logging
import math
import threading
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, TypeVar

import ipywidgets as w

from pmk_nb.errors import GridTooLarge, LibraryError, PmkError
from pmk_nb.progress import Progress, ProgressCallback
from pmk_nb.ui.common.style import APP_CSS, TOUCH_PX

if TYPE_CHECKING:
    from pmk_nb.ui.common.context import AppContext

log = logging.getLogger(__name__)

F = TypeVar("F", bound=Callable[..., Any])


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
    width: str | None = "auto",
) -> w.Button:
    """A touch-sized button with a stable CSS class for the browser tests.

    The tooltip is also the button's accessible name (the ``title`` attribute) when it shows only
    an icon; an icon-only button without a tooltip is refused.
    """
    if not description and not tooltip:
        raise ValueError(f"the icon-only button {css_class!r} needs a tooltip: it is its accessible name")
    btn = w.Button(
        description=description,
        icon=icon,
        button_style=style,
        tooltip=tooltip or description,
        # width None: the style sheet sizes it (an inline width would override its narrow-screen rules)
        layout=w.Layout(height=f"{TOUCH_PX}px", width=width) if width else w.Layout(height=f"{TOUCH_PX}px"),
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


def picture(
    png: bytes, alt: str, css_class: str, *, style: str = "max-width: 100%; height: auto", on_img: bool = False
) -> w.HTML:
    """A PNG with its text alternative (WCAG 1.1.1): ipywidgets' ``Image`` has no ``alt`` (and its
    ``tooltip`` breaks its view), so the image is an ``<img alt>`` in an HTML widget.

    ``css_class`` goes on the widget, or with ``on_img`` on the ``<img>`` itself (where a page
    script reads the picture, e.g. its ``naturalWidth``).
    """
    item = w.HTML(picture_html(png, alt, style=style, css_class=css_class if on_img else ""))
    if not on_img:
        item.add_class(css_class)
    return item


def picture_html(png: bytes, alt: str, *, style: str = "max-width: 100%; height: auto", css_class: str = "") -> str:
    """The ``<img alt>`` of :func:`picture`, for a slot that shows a picture that changes (a replay)."""
    data = base64.b64encode(png).decode("ascii")
    cls = f' class="{css_class}"' if css_class else ""
    alt_attr = html.escape(alt, quote=True)
    return f'<img{cls} src="data:image/png;base64,{data}" alt="{alt_attr}" style="{style}">'


def html_slot(css_class: str) -> w.HTML:
    """An empty HTML widget whose CSS class the style sheet and the browser tests find it by."""
    item = w.HTML("")
    item.add_class(css_class)
    return item


def checkbox(
    ctx: AppContext, label: str, value: bool, css_class: str, action: str, on_change: Callable[..., Any]
) -> w.Checkbox:
    """A checkbox labelled on its right, as wide as its label; ``on_change`` runs guarded as ``action``."""
    box = w.Checkbox(value=value, description=label, indent=False, layout=w.Layout(width="auto"))
    box.add_class(css_class)
    box.observe(guard(ctx, action)(on_change), names="value")
    return box


def tick_exactly(boxes: Sequence[w.Widget], names: Sequence[str], refusal: str) -> None:
    """Tick exactly the checkboxes labelled ``names`` (what clicking them does).

    Raises:
        LibraryError: a name that labels no box: ``refusal`` formatted with ``unknown`` and ``known``.
    """
    known = {str(b.description) for b in boxes}
    unknown = [n for n in names if n not in known]
    if unknown:
        raise LibraryError(refusal.format(unknown=", ".join(unknown), known=", ".join(sorted(known))))
    for b in boxes:
        b.value = b.description in names


def close_tree(widget: w.Widget) -> None:
    """Close ``widget`` and every widget it holds (children, layout, style): their models leave the
    kernel and the page, so no message can reach them any more (``Widget.close`` closes one model)."""
    seen: set[int] = set()
    todo: list[object] = [widget]
    while todo:
        item = todo.pop()
        if isinstance(item, list | tuple):
            todo.extend(item)
            continue
        if not isinstance(item, w.Widget) or id(item) in seen:
            continue
        seen.add(id(item))
        todo.extend(getattr(item, name, None) for name in item.keys if name != "comm")
        item.close()


def replace_children(box: w.Box, children: Sequence[w.Widget]) -> None:
    """Show ``children`` in ``box``, closing the widgets it drops (else their models stay live in the
    kernel, reachable by a page script); into a closed box (its screen was dropped while a thread
    worked), the new widgets are closed at once."""
    new = tuple(children)
    if box.comm is None:
        for child in new:
            close_tree(child)
        return
    keep = {id(c) for c in new}
    old = [c for c in box.children if id(c) not in keep]
    box.children = new
    for child in old:
        close_tree(child)


def field_error() -> w.HTML:
    """An (initially empty) error line shown under a form field."""
    err = w.HTML("")
    err.add_class("pmk-field-error")
    return err


def progress_bar(css_class: str) -> w.FloatProgress:
    """A hidden-until-used 0..1 progress bar."""
    bar = w.FloatProgress(value=0.0, min=0.0, max=1.0, layout=w.Layout(width="100%", max_width="720px", display="none"))
    bar.add_class(css_class)
    return bar


def set_progress(bar: w.FloatProgress, fraction: float | None, *, style: str = "info") -> None:
    """Show ``fraction`` (None removes the bar from the page); tolerant of NaN and out-of-range values.

    A finished job calls ``set_progress(bar, None)``: its status line says how it ended, and a full
    bar left on screen would look like work still under way.
    """
    if fraction is None:
        bar.layout.display = "none"
        return
    value = 0.0 if not math.isfinite(fraction) else min(1.0, max(0.0, float(fraction)))
    bar.bar_style = style
    bar.value = value
    bar.layout.display = ""


#: How the dashboard names the core's progress steps (other steps are shown capitalised).
STEP_WORDS = {
    "read": "Reading",
    "rasterise": "Rasterising",
    "write": "Saving",
    "done": "Done",
    "download": "Downloading",
    "upload": "Uploading",
}


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
    """An ``on_error`` for :func:`run_in_thread`: the bar goes, ``label`` shows the message."""

    def failed(err: BaseException) -> None:
        set_progress(bar, None)
        label.value = f"<span class='pmk-msg-error'>{escape(error_text(err))}</span>"

    return failed


def error_text(err: BaseException, action: str = "") -> str:
    """An error in the dashboard's words: "Converting failed: ...", from the error's type and fields.

    A grid too large for the resolution names the resolution that fits (the core's own hint may
    quote command-line options); an unexpected error names its type.
    """
    prefix = f"{action} failed: " if action else ""
    cause = err if isinstance(err, GridTooLarge) else err.__cause__
    if isinstance(cause, GridTooLarge):
        return f"{prefix}{too_fine_text(cause)}"
    if isinstance(err, PmkError):
        return f"{prefix}{err}"
    return f"{action or 'It'} failed unexpectedly ({type(err).__name__}: {err})."


def too_fine_text(err: GridTooLarge) -> str:
    """What to do when the map would be too large: the resolution that fits, in the page's words."""
    return (
        f"The map would be too large at this resolution ({err.cells:,} cells, limit {err.limit:,}). "
        f"Use {err.suggested_resolution:g} m per cell or coarser."
    )


def report_error(ctx: AppContext, err: BaseException, action: str, *, inline: bool = False) -> str:
    """Turn an exception into a user message; returns the message.

    ``inline``: the caller shows the message in its own place; the app's message line only clears
    (the error is still logged and kept in ``ctx.notifications``).
    """
    if not isinstance(err, PmkError | ValueError):
        log.error("%s failed", action, exc_info=err)
    message = error_text(err, action)
    ctx.notify(message, "error", inline=inline)
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
    on_error: Callable[[BaseException], object] | None = None,
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
        # the work is over before its outcome is shown: a question the outcome asks (a host key to
        # trust) may start the action again at once, and must not find it "already running"
        failure: Exception | None = None
        result: Any = None
        try:
            result = work()
        except Exception as err:
            failure = err
        finally:
            for widget in busy or []:
                widget.disabled = False
            if exclusive is not None:
                exclusive.release()
        if failure is not None:
            # with an on_error the failure is shown there: one place per message
            report_error(ctx, failure, action, inline=on_error is not None)
            if on_error is not None:
                guard(ctx, action)(on_error)(failure)
        elif on_done is not None:
            guard(ctx, action)(on_done)(result)

    thread = threading.Thread(target=target, name=f"pmk-{action}", daemon=True)
    try:
        thread.start()
    except BaseException:
        if exclusive is not None:
            exclusive.release()
        raise
    return thread


def buttons_in(widget: w.Widget) -> list[w.Button]:
    """Every button inside ``widget`` (to disable them while a job runs)."""
    if isinstance(widget, w.Button):
        return [widget]
    return [b for child in getattr(widget, "children", ()) for b in buttons_in(child)]


class ConfirmBox:
    """An explicit in-page "are you sure?" step (a Voilà page has no modal dialogs).

    ``ask(message, on_yes)`` shows the box; the yes button runs ``on_yes`` once, the no button hides it.
    """

    def __init__(self, ctx: AppContext, css_prefix: str, *, yes: str = "Overwrite", no: str = "Cancel") -> None:
        self._on_yes: Callable[[], object] | None = None
        self.message = w.HTML("")
        self.yes = button(yes, f"{css_prefix}-yes", style="warning", icon="check")
        self.no = button(no, f"{css_prefix}-no", icon="times")
        self.yes.on_click(guard(ctx, "Confirming")(lambda _b: self._answer(True)))
        self.no.on_click(guard(ctx, "Cancelling")(lambda _b: self._answer(False)))
        row = w.HBox([self.yes, self.no])
        row.add_class("pmk-row")
        self.widget = w.VBox([self.message, row], layout=w.Layout(display="none"))
        self.widget.add_class("pmk-confirm")
        self.widget.add_class(css_prefix)

    @property
    def visible(self) -> bool:
        return self.widget.layout.display != "none"

    def ask(self, message: str, on_yes: Callable[[], object]) -> None:
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
