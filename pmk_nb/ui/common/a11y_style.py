"""WCAG 2.2 AA additions to the style sheet: visible focus, contrast fixes, high contrast, large text.

- Focus (2.4.7, 2.4.11/2.4.13): every control shows a ``:focus-visible`` ring of
  :data:`FOCUS_PX` px, dark blue on the light content, amber on the dark navigation panel, each
  at least 3:1 against what surrounds it.  ipywidgets' own focus style is a 1 px outline.
- Contrast (1.4.3): ipywidgets' coloured buttons (``button_style``) and Lumino's unselected tab
  labels (#6d6d6d on #eeeeee, 4.45:1) fall just under 4.5:1; they get darker colours here.
- ``pmk-sr-only``: visually hidden, still read by screen readers (the live regions).
- ``pmk-high-contrast`` and ``pmk-large-text`` on the app root (:mod:`pmk_nb.ui.common.display_prefs`
  puts them there from the chair profile): black on white with 2 px borders and a thicker ring;
  text a third larger (24 px), labels allowed to wrap rather than be cut.

Every colour pair is listed in :data:`CHECKED_PAIRS`; ``tests/ui/common/test_a11y.py`` checks each
against its WCAG minimum with :mod:`pmk_nb.ui.common.contrast`.
"""

from __future__ import annotations

from pmk_nb.ui.common.contrast import NON_TEXT_AA, TEXT_AA

FOCUS_PX = 3
HC_FOCUS_PX = 4
LARGE_FONT_PX = 24

# -- the palette (every pair below is checked) -------------------------------------------------------
WHITE, BLACK = "#ffffff", "#000000"
CONTENT_BG = WHITE
BUTTON_BG = "#eeeeee"  # ipywidgets' plain button
NAV_BG, INFO_BG = "#263238", "#37474f"  # pmk_nb/ui/common/style.py
FOCUS_LIGHT = "#0b3d91"  # on the content
FOCUS_DARK = "#ffd54f"  # on the navigation panel
TAB_TEXT = "#37474f"
#: ipywidgets ``button_style`` -> (background, text)
BUTTON_STYLES: dict[str, tuple[str, str]] = {
    "primary": ("#1565c0", WHITE),
    "success": ("#2e7d32", WHITE),
    "info": ("#00695c", WHITE),
    "warning": ("#ffb300", BLACK),
    "danger": ("#c62828", WHITE),
}
HC_ACTIVE = "#ffeb3b"  # the active navigation button in high contrast

#: (what, foreground, background, minimum ratio)
CHECKED_PAIRS: list[tuple[str, str, str, float]] = [
    ("focus ring on the content", FOCUS_LIGHT, CONTENT_BG, NON_TEXT_AA),
    ("focus ring on a plain button's grey", FOCUS_LIGHT, BUTTON_BG, NON_TEXT_AA),
    ("focus ring on the navigation", FOCUS_DARK, NAV_BG, NON_TEXT_AA),
    ("focus ring on the info panel", FOCUS_DARK, INFO_BG, NON_TEXT_AA),
    ("unselected tab label", TAB_TEXT, BUTTON_BG, TEXT_AA),
    *[(f"{name} button text", fg, bg, TEXT_AA) for name, (bg, fg) in BUTTON_STYLES.items()],
    ("high contrast: text", BLACK, WHITE, 7.0),
    ("high contrast: navigation text", WHITE, BLACK, 7.0),
    ("high contrast: active navigation", BLACK, HC_ACTIVE, 7.0),
    ("high contrast: focus ring on the navigation", HC_ACTIVE, BLACK, NON_TEXT_AA),
    ("stale value on the info panel (style.py)", "#b0bec5", INFO_BG, TEXT_AA),
]

_BUTTONS = "\n".join(
    f".pmk-app .jupyter-button.mod-{name}, .pmk-app .jupyter-button.mod-{name}:hover:enabled "
    f"{{ background-color: {bg}; color: {fg}; }}"
    for name, (bg, fg) in BUTTON_STYLES.items()
)

_FOCUS = f"""
.pmk-app :focus-visible, .pmk-app .jupyter-button:focus-visible, .pmk-app input:focus-visible,
.pmk-app select:focus-visible, .pmk-app .lm-TabBar-tab:focus-visible
   {{ outline: {FOCUS_PX}px solid {FOCUS_LIGHT} !important; outline-offset: 2px !important; }}
.pmk-app .pmk-nav :focus-visible, .pmk-app .pmk-nav .jupyter-button:focus-visible
   {{ outline-color: {FOCUS_DARK} !important; }}
.pmk-sr-only {{ position: absolute !important; width: 1px !important; height: 1px !important;
   overflow: hidden !important; clip: rect(0 0 0 0) !important; clip-path: inset(50%) !important;
   white-space: nowrap !important; margin: -1px !important; padding: 0 !important; border: 0 !important; }}
.pmk-app .widget-tab > .lm-TabBar .lm-TabBar-tab:not(.lm-mod-current) {{ color: {TAB_TEXT}; }}
{_BUTTONS}
"""

_HC = f"""
.pmk-app.pmk-high-contrast {{ background: {WHITE}; color: {BLACK}; }}
.pmk-high-contrast .pmk-content, .pmk-high-contrast .pmk-content .widget-html-content,
.pmk-high-contrast .pmk-content .widget-label, .pmk-high-contrast .pmk-content label,
.pmk-high-contrast .lm-TabBar-tab {{ color: {BLACK} !important; }}
.pmk-high-contrast .pmk-nav, .pmk-high-contrast .pmk-info {{ background: {BLACK} !important; }}
.pmk-high-contrast .pmk-nav .widget-html-content, .pmk-high-contrast .pmk-nav .pmk-title
   {{ color: {WHITE} !important; }}
.pmk-high-contrast .pmk-nav .jupyter-button {{ background: {BLACK}; color: {WHITE}; border: 2px solid {WHITE}; }}
.pmk-high-contrast .pmk-nav .jupyter-button.pmk-nav-active {{ background: {HC_ACTIVE}; color: {BLACK}; }}
.pmk-high-contrast .pmk-content .jupyter-button {{ border: 2px solid {BLACK}; }}
.pmk-high-contrast .pmk-content .jupyter-button:not([class*="mod-"]) {{ background: {WHITE}; color: {BLACK}; }}
.pmk-high-contrast .pmk-content .jupyter-button.mod-active {{ background: {BLACK}; color: {WHITE}; }}
.pmk-high-contrast input, .pmk-high-contrast select, .pmk-high-contrast textarea
   {{ border: 2px solid {BLACK} !important; color: {BLACK} !important; background: {WHITE} !important; }}
.pmk-high-contrast canvas.pmk-live-canvas {{ border: 2px solid {BLACK}; }}
.pmk-high-contrast .pmk-content .pmk-msg-warning, .pmk-high-contrast .pmk-content .pmk-msg-error
   {{ color: {BLACK} !important; border-left-width: 8px; }}
.pmk-high-contrast .pmk-stale {{ color: {WHITE} !important; font-style: italic; }}
.pmk-app.pmk-high-contrast :focus-visible, .pmk-app.pmk-high-contrast .jupyter-button:focus-visible,
.pmk-app.pmk-high-contrast input:focus-visible, .pmk-app.pmk-high-contrast select:focus-visible
   {{ outline: {HC_FOCUS_PX}px solid {BLACK} !important; }}
.pmk-app.pmk-high-contrast .pmk-nav :focus-visible, .pmk-app.pmk-high-contrast .pmk-nav .jupyter-button:focus-visible
   {{ outline-color: {HC_ACTIVE} !important; }}
"""

_F = LARGE_FONT_PX
_LARGE = f"""
.pmk-app.pmk-large-text {{ font-size: {_F}px; --jp-widgets-font-size: {_F}px; --jp-ui-font-size1: {_F}px; }}
.pmk-large-text .widget-label, .pmk-large-text .widget-html-content, .pmk-large-text input,
.pmk-large-text select, .pmk-large-text textarea, .pmk-large-text .jupyter-button,
.pmk-large-text .lm-TabBar-tabLabel, .pmk-large-text .widget-checkbox label, .pmk-large-text .pmk-title
   {{ font-size: {_F}px !important; }}
.pmk-large-text .pmk-info .widget-html-content {{ font-size: {_F - 2}px !important; }}
.pmk-large-text .pmk-heading {{ font-size: {_F + 8}px !important; }}
/* a label cut to "Wheelchair IP…" loses words: let it wrap instead (1.4.4 Resize Text) */
.pmk-large-text .widget-label {{ white-space: normal !important; line-height: 1.15 !important;
   height: auto !important; overflow: visible !important; }}
.pmk-large-text .jupyter-button {{ height: auto !important; white-space: normal; }}
"""

A11Y_CSS = _FOCUS + _HC + _LARGE
