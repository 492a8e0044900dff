"""The dashboard's one style sheet: touch sizes, colours, and the layouts for phone, tablet and JupyterLab.

The layout follows the width of the app itself, not of the browser window: the app root is a CSS
size container (``pmk-app``), so the same rules serve a phone, a portrait tablet and JupyterLab's
main area beside its file browser (a 700 px box in a wider window).  Wide (> 900 px): navigation
on the left.  Narrower: the navigation becomes a top bar and the content takes the full width;
at phone width (<= 600 px) the top bar is compact.  The screens' rows wrap instead of squeezing
(``flex-wrap``, ``min-width: 0``), so no control is cut off and nothing scrolls sideways.

Sizes are set here rather than in ipywidgets ``Layout`` objects where a narrow screen must change
them: a Layout is an inline style, which a media or container rule cannot override.
"""

from __future__ import annotations

from pmk_nb.ui.common.a11y_style import A11Y_CSS

TOUCH_PX = 56  # comfortably above the 44-48 px minimum touch target
BASE_FONT_PX = 18
NAV_PX = 270  # the navigation column on a wide screen
TOP_BAR_BELOW_PX = 900  # app width at or below which the navigation is a top bar
PHONE_PX = 600  # app width at or below which the compact phone layout applies

_F, _T = BASE_FONT_PX, TOUCH_PX

_BASE = f"""
.pmk-app {{ container: pmk-app / inline-size; width: 100%; min-width: 0; box-sizing: border-box;
            font-size: {_F}px; --jp-widgets-font-size: {_F}px;
            --jp-widgets-inline-height: {_T - 8}px; --jp-ui-font-size1: {_F}px; }}
.pmk-app .widget-label, .pmk-app .widget-html-content, .pmk-app .widget-inline-hbox .widget-label
   {{ font-size: {_F}px; line-height: 1.3; }}
.pmk-app .widget-html-content {{ overflow-wrap: break-word; }}
/* messages and the panel may hold long URLs and paths: break them anywhere rather than clip them */
.pmk-info .widget-html-content, .pmk-message, [class*="-status"] .widget-html-content,
.pmk-home-warning, .pmk-field-error {{ overflow-wrap: anywhere; }}
.pmk-app input, .pmk-app select, .pmk-app textarea, .pmk-app .widget-dropdown > select
   {{ font-size: {_F}px !important; min-height: {_T - 8}px; }}
.pmk-app button.jupyter-button, .pmk-app .jupyter-button
   {{ font-size: {_F}px; min-height: {_T}px; min-width: {_T}px; border-radius: 6px; flex-shrink: 0;
      max-width: 100%; }}
.pmk-app .widget-select select {{ font-size: {_F}px; }}
.pmk-app .widget-select option {{ padding: 10px 6px; }}
.pmk-app .widget-tab > .lm-TabBar, .pmk-app .widget-tab > .lm-TabBar .lm-TabBar-tab,
.pmk-app .widget-tab > .lm-TabBar .lm-TabBar-tabLabel
   {{ font-size: {_F}px !important; min-height: {_T - 8}px !important; line-height: {_T - 8}px !important; }}
.pmk-app .widget-tab > .lm-TabBar .lm-TabBar-tab {{ flex: 0 1 200px !important; }}
.pmk-app .widget-checkbox {{ min-height: {_T - 8}px; width: auto; }}
.pmk-app .widget-checkbox input[type="checkbox"] {{ width: 28px; height: 28px; margin: 0 8px 0 0; }}
.pmk-app .widget-checkbox label {{ display: flex; align-items: center; font-size: {_F}px;
   min-height: {_T - 8}px; }}
.pmk-app .widget-toggle-buttons .widget-toggle-button {{ height: {_T - 8}px; min-width: {_T}px; }}
.pmk-app .widget-toggle-buttons .widget-toggle-button-group {{ flex-wrap: wrap; }}
/* a field 100% wide plus ipywidgets' 2 px side margins would stick out of its column */
.pmk-app .widget-inline-hbox {{ min-width: 0; max-width: 100%; margin-left: 0; margin-right: 0; }}
.pmk-app .widget-inline-hbox input, .pmk-app .widget-inline-hbox select {{ min-width: 0; }}
.pmk-row {{ flex-wrap: wrap; gap: 8px 12px; min-width: 0; max-width: 100%; }}
"""

_SHELL = f"""
.pmk-shell {{ display: flex; flex-direction: row; width: 100%; min-width: 0; align-items: stretch;
              min-height: 600px; gap: 8px; }}
.pmk-app .pmk-nav {{ flex: 0 0 {NAV_PX}px; width: {NAV_PX}px; display: flex; flex-direction: column;
   gap: 8px; background: #263238; color: #eceff1; padding: 12px; border-radius: 8px; min-width: 0; }}
.pmk-nav .pmk-title {{ color: #eceff1; font-size: 24px; font-weight: 600; margin-bottom: 8px; }}
.pmk-app .pmk-nav-title {{ margin: 0; }}
.pmk-nav .widget-html-content {{ color: #eceff1; }}
.pmk-nav button.pmk-nav-active {{ background: #4fc3f7; color: #000; font-weight: 600; }}
.pmk-app .pmk-nav button.jupyter-button {{ width: 100%; }}
.pmk-info {{ background: #37474f; border-radius: 6px; padding: 8px; margin-top: 12px; min-width: 0;
   width: 100%; }}
.pmk-info .widget-html-content {{ color: #eceff1; font-size: {_F - 1}px; }}
.pmk-app .pmk-content {{ flex: 1 1 0; min-width: 0; width: auto; padding: 0 16px; overflow: visible; }}
.pmk-message:empty, .pmk-message .widget-html-content:empty {{ display: none; }}
.pmk-stale {{ color: #b0bec5 !important; }}  /* 5.1:1 on the info panel (#90a4ae was 3.7) */
"""

_MESSAGES = f"""
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
.pmk-field-error {{ color: #c62828; font-size: {_F - 2}px; }}
.pmk-heading {{ font-size: 26px; font-weight: 600; margin: 4px 0 12px 0; overflow-wrap: anywhere; }}
.pmk-confirm {{ background: #fff8e1; border: 2px solid #ffb300; border-radius: 6px; padding: 8px; }}
.pmk-app .widget-progress {{ height: 18px; }}
"""

_SCREENS = f"""
.pmk-home .pmk-heading {{ margin-bottom: 4px; }}
.pmk-home-title {{ flex-wrap: wrap; column-gap: 24px; align-items: baseline; }}
.pmk-home-preview-box {{ width: fit-content; max-width: 100%; gap: 8px; }}
.pmk-home-toolbar {{ min-height: {_T}px; flex-wrap: wrap; gap: 8px 12px; max-width: 100%; }}
.pmk-home-controls {{ flex-wrap: wrap; gap: 8px 12px; min-width: 0; }}
.pmk-record-row {{ gap: 8px 12px; min-width: 0; }}
.pmk-record .widget-html-content {{ overflow-wrap: anywhere; }}
.pmk-home-zoom {{ margin-left: auto; gap: 8px; flex-wrap: wrap; justify-content: flex-end; max-width: 100%; }}
.pmk-app .pmk-live-toolbar {{ flex-wrap: wrap; gap: 8px; max-width: 100%; }}
.pmk-home-zoom button.jupyter-button {{ min-width: 64px; }}
/* (live view, helper C) Chromium names a button by its FontAwesome glyph, so the icon-only zoom
   buttons had no name but a private-use character: an empty alternative text for these glyphs
   leaves the tooltip as the name ("Zoom in"), and "Follow" / "Centre" as their own */
.pmk-app .fa-search-plus::before {{ content: "\\f00e" / ""; }}
.pmk-app .fa-search-minus::before {{ content: "\\f010" / ""; }}
.pmk-app .fa-location-arrow::before {{ content: "\\f124" / ""; }}
.pmk-app .fa-crosshairs::before {{ content: "\\f05b" / ""; }}
/* the canvas has the map's shape; on a smaller screen the page scales it down, keeping that shape
   (height auto), and never taller than the window below the toolbar */
.pmk-app canvas.pmk-live-canvas {{ max-width: 100%; height: auto; width: auto;
   max-height: calc(100vh - 200px); border: 1px solid #b0bec5; border-radius: 4px; }}
.pmk-maps-listtab {{ display: flex; flex-wrap: wrap; gap: 16px; width: 100%; min-width: 0; }}
.pmk-maps-left {{ flex: 1 1 340px; min-width: 0; max-width: 100%; }}
.pmk-maps-right {{ flex: 2 1 380px; min-width: 0; max-width: 100%; }}
.pmk-app .pmk-maps-list {{ width: 100%; }}
.pmk-app .pmk-maps-list select {{ height: 420px; max-height: 60vh; }}
.pmk-maps-card {{ flex-wrap: wrap; gap: 8px 12px; }}
.pmk-app .pmk-maps-import {{ width: auto; }}
.pmk-maps-storeys {{ max-width: 100%; overflow-x: auto; }}
.pmk-settings-auth-row, .pmk-settings-loss-row {{ flex-wrap: wrap; align-items: center; gap: 4px 8px; }}
.pmk-settings-auth-label, .pmk-settings-loss-label {{ width: 208px; text-align: right; padding-right: 8px; }}
.pmk-settings-loss-row .widget-toggle-buttons {{ flex-wrap: wrap; max-width: 100%; }}
"""

_TOP_BAR = f"""
@container pmk-app (max-width: {TOP_BAR_BELOW_PX}px) {{
  .pmk-shell {{ flex-direction: column; min-height: 0; }}
  .pmk-app .pmk-nav {{ flex: 0 0 auto; width: 100%; flex-direction: row; flex-wrap: wrap;
     align-items: center; padding: 8px; }}
  .pmk-nav .pmk-title {{ font-size: 20px; margin: 0 8px 0 0; }}
  .pmk-app .pmk-nav-title {{ flex: 0 0 auto; }}
  .pmk-app .pmk-nav button.jupyter-button {{ flex: 1 1 auto; width: auto; }}
  .pmk-info {{ flex: 1 1 100%; margin-top: 0; }}
  .pmk-app .pmk-content {{ padding: 0 8px; }}
}}
@container pmk-app (max-width: {PHONE_PX}px) {{
  .pmk-app .pmk-nav-title {{ flex: 1 1 100%; }}
  .pmk-nav .pmk-title {{ font-size: 18px; }}
  .pmk-app .pmk-nav button.jupyter-button {{ flex: 1 1 auto; padding: 0 6px; }}
  .pmk-info .pmk-home-info {{ flex-direction: row; flex-wrap: wrap; column-gap: 12px; }}
  .pmk-info .widget-html-content {{ font-size: {_F - 3}px; }}
  .pmk-heading {{ font-size: 22px; }}
  .pmk-app .pmk-content {{ padding: 0 4px; }}
  /* labels above their fields: the whole width is left for the value */
  .pmk-app .widget-text, .pmk-app .widget-password, .pmk-app .widget-dropdown, .pmk-app .widget-combobox
     {{ flex-wrap: wrap; height: auto !important; }}
  .pmk-app .widget-text > .widget-label, .pmk-app .widget-password > .widget-label,
  .pmk-app .widget-dropdown > .widget-label, .pmk-app .widget-combobox > .widget-label
     {{ width: 100% !important; max-width: 100% !important; text-align: left; line-height: 1.3;
        height: auto; margin: 4px 0 2px 0; }}
  .pmk-settings-auth-label, .pmk-settings-loss-label {{ width: 100%; text-align: left; }}
  .pmk-maps-right {{ flex-basis: 100%; }}
  .pmk-app .pmk-maps-list select {{ height: 260px; }}
}}
"""


def _app_css() -> str:
    # last: WCAG 2.2 focus rings, contrast fixes, high contrast and large text (pmk_nb/ui/common/a11y_style.py)
    from pmk_nb.ui.home.style import home_css  # Home's map screen (issue 28)

    return f"<style>{_BASE}{_SHELL}{_MESSAGES}{_SCREENS}{_TOP_BAR}{home_css(PHONE_PX)}{A11Y_CSS}</style>"


APP_CSS = _app_css()
