"""Home's style: the map fills the screen, everything else floats over it (issue 28).

The canvas takes the whole width and the window's height below it (its pixel size comes from the
page's measurement, :mod:`pmk_nb.ui.home.fit`, so it is drawn 1:1 and never stretched).  Over it:
the tool bar (``.pmk-home-toolbar``) along the top, translucent, wrapping on a narrow screen; the
one-line status (``.pmk-home-statusline``) at the bottom; the Details card above it; and, while
Drive is on, the joystick column (``.pmk-drive``) docked at the rider's side (``pmk-drive-left`` /
``pmk-drive-right``, from the chair profile's ``drive_hand``).  Every button on Home is at least
48 x 48 CSS px (WCAG 2.2 target size, and a gloved or shaky finger); on a phone the bar's buttons
show their icon only (the text stays their accessible name).
"""

from __future__ import annotations

TARGET_PX = 48  # the smallest touch target on Home
BAR_BG = "rgba(255, 255, 255, 0.78)"
PANEL_BG = "rgba(255, 255, 255, 0.6)"


#: The map and its canvas have square corners: rounded ones clipped the live canvas's layer with a mask,
#: an extra render pass at every frame (software compositing, a classroom page at 12 fps: the GPU
#: process's draw 53 -> 14 ms a second, 9 -> 4 % of a core).
#: Details' first row: the heading keeps its width (a heading may break anywhere: beside a long map name it
#: was squeezed to one letter a line, issue 40); the map's name takes the rest of the row, or the next row.
DETAILS_HEAD_CSS = """
.pmk-app .pmk-home-details-head { flex-wrap: wrap; align-items: baseline; column-gap: 12px; }
.pmk-app .pmk-home-details-head > .pmk-home-details-title { flex: 0 0 auto; }
.pmk-app .pmk-home-details-head > .pmk-home-map { flex: 1 1 12em; min-width: 0; }
"""


def home_css(phone_px: int) -> str:
    """The rules; ``phone_px`` is the app width at or below which the phone layout applies."""
    return (
        f"""
.pmk-home {{ width: 100%; min-width: 0; }}
.pmk-home .pmk-heading {{ margin: 0 12px 4px 0; font-size: 22px; }}
.pmk-home-preview-box {{ width: 100%; max-width: 100%; gap: 8px; }}
.pmk-home-map-stack {{ position: relative; width: 100%; max-width: 100%; min-width: 0; overflow: hidden; }}
.pmk-app .pmk-home-map-stack canvas.pmk-live-canvas, .pmk-app .pmk-home-map-stack .pmk-live-canvas
   {{ max-width: 100%; max-height: none; height: auto; width: auto; border: none; }}
.pmk-app .pmk-home-toolbar {{ position: absolute; top: 6px; left: 6px; z-index: 6; width: max-content;
   max-width: calc(100% - 12px); box-sizing: border-box; display: flex; flex-wrap: wrap; gap: 6px;
   align-items: center; padding: 4px; background: {BAR_BG}; border-radius: 12px;
   box-shadow: 0 1px 6px rgba(0, 0, 0, .2); }}
.pmk-app .pmk-home-controls, .pmk-app .pmk-home-zoom, .pmk-app .pmk-home-toolbar .pmk-live-toolbar
   {{ display: flex; flex-wrap: wrap; gap: 6px; margin: 0; min-width: 0; align-items: center; }}
.pmk-app .pmk-home-toolbar button.jupyter-button, .pmk-app .pmk-home-toolbar .jupyter-button
   {{ min-height: {TARGET_PX}px; min-width: {TARGET_PX}px; margin: 0; }}
.pmk-app .pmk-home-zoom button.jupyter-button {{ min-width: {TARGET_PX + 8}px; }}
.pmk-app .pmk-home-statusline {{ position: absolute; left: 6px; bottom: 6px; z-index: 6; max-width: calc(100% - 12px);
   box-sizing: border-box; background: {BAR_BG}; border-radius: 10px; padding: 2px 12px;
   box-shadow: 0 1px 6px rgba(0, 0, 0, .2); pointer-events: none; }}
.pmk-app .pmk-home-statusline .widget-html-content {{ white-space: nowrap; overflow: hidden; text-overflow: ellipsis;
   line-height: 36px; font-weight: 600; }}
.pmk-app .pmk-home-statusline:has(.widget-html-content:empty) {{ display: none; }}
.pmk-app .pmk-home-details {{ position: absolute; left: 6px; bottom: 54px; z-index: 7; box-sizing: border-box;
   max-width: min(440px, calc(100% - 12px)); max-height: calc(100% - 130px); overflow: auto;
   background: rgba(38, 50, 56, 0.92); color: #eceff1; border-radius: 12px; padding: 8px 12px; }}
.pmk-home-details .widget-html-content, .pmk-home-details .pmk-heading {{ color: #eceff1; }}
.pmk-home-details .pmk-content .pmk-msg-info, .pmk-home-details .pmk-msg-info {{ color: #b3e5fc; }}
.pmk-info:has(.pmk-home-info-slot) .pmk-message:empty {{ display: none; }}
.pmk-info:has(.pmk-home-info-slot):not(:has(.pmk-message .widget-html-content:not(:empty)))
   {{ display: none; }}
/* the joystick column at the rider's side, translucent: the map shows through */
.pmk-app .pmk-home-map-stack .pmk-drive.widget-box {{ position: absolute; bottom: 54px; top: auto; z-index: 5;
   display: flex; flex-direction: column; flex-wrap: nowrap; align-items: center; gap: 8px; width: 196px;
   height: auto; box-sizing: border-box; padding: 10px; background: {PANEL_BG}; border-radius: 14px;
   box-shadow: 0 2px 8px rgba(0, 0, 0, .25); overflow: visible; margin: 0; }}
.pmk-app .pmk-home-map-stack .pmk-drive.pmk-drive-right {{ right: 6px; left: auto; }}
.pmk-app .pmk-home-map-stack .pmk-drive.pmk-drive-left {{ left: 6px; right: auto; }}
.pmk-app .pmk-home-map-stack .pmk-drive .pmk-drive-pad-box {{ order: 0; }}
/* the same height whatever the status says: the stick must not move under a finger */
.pmk-app .pmk-home-map-stack .pmk-drive-status {{ min-height: 3.8em; display: flex; align-items: center; }}
.pmk-app .pmk-home-map-stack .pmk-drive-pad {{ background: rgba(207, 216, 220, 0.7); }}
.pmk-app .pmk-home-map-stack .pmk-drive button.jupyter-button, .pmk-app .pmk-home-map-stack .pmk-drive .jupyter-button
   {{ width: 176px !important; }}
/* Go to: the rooms as big buttons over the map, favourites and recent ones first */
.pmk-app .pmk-home-goto-card {{ position: absolute; top: 6px; left: 6px; z-index: 8; box-sizing: border-box;
   width: min(440px, calc(100% - 12px)); max-height: calc(100% - 12px); overflow: auto; gap: 6px;
   background: rgba(255, 255, 255, 0.96); border-radius: 12px; padding: 8px 12px;
   box-shadow: 0 2px 10px rgba(0, 0, 0, .3); }}
.pmk-app .pmk-goto-row {{ gap: 6px; align-items: center; }}
.pmk-app .pmk-goto-row button.pmk-goto-room {{ flex: 1 1 auto; min-width: 0; justify-content: flex-start;
   text-align: left; overflow: hidden; text-overflow: ellipsis; }}
/* Set destination: the heading buttons over the map's bottom, clear of the tool bar */
.pmk-app .pmk-home-goal-card {{ position: absolute; left: 6px; bottom: 54px; z-index: 7; box-sizing: border-box;
   max-width: calc(100% - 12px); background: rgba(255, 255, 255, 0.92); border-radius: 12px; padding: 6px 10px;
   box-shadow: 0 2px 10px rgba(0, 0, 0, .3); }}
.pmk-app .pmk-heading-buttons .widget-toggle-button {{ min-width: {TARGET_PX}px; height: {TARGET_PX}px;
   font-size: 22px; }}
.pmk-app .pmk-heading-buttons .widget-toggle-button-group {{ flex-wrap: wrap; gap: 4px; }}
/* icon-only buttons are named by their tooltip, not by the icon font's private glyph */
.pmk-app .fa-star::before {{ content: "\\f005" / ""; }}
.pmk-app .fa-star-o::before {{ content: "\\f005" / ""; font-weight: 400; }}
@container pmk-app (max-width: {phone_px}px) {{
  /* icon-only bar buttons: the text stays the accessible name, the bar stays one or two rows */
  .pmk-app .pmk-home-toolbar button.jupyter-button {{ font-size: 0 !important; padding: 0;
     width: {TARGET_PX}px !important; min-width: {TARGET_PX}px !important; height: {TARGET_PX}px !important; }}
  .pmk-app .pmk-home-toolbar button.jupyter-button i {{ font-size: 20px; margin: 0 !important; }}
  .pmk-app .pmk-home-map-stack .pmk-drive.widget-box {{ width: 156px; padding: 6px; gap: 6px; }}
  .pmk-app .pmk-home-map-stack .pmk-drive .pmk-drive-pad-box {{ width: 140px; }}
  .pmk-app .pmk-home-map-stack .pmk-drive-pad {{ width: 140px; height: 140px; }}
  .pmk-app .pmk-home-map-stack .pmk-drive button.jupyter-button, .pmk-app .pmk-home-map-stack .pmk-drive .jupyter-button
     {{ width: 144px !important; }}
  .pmk-app .pmk-home-map-stack .pmk-drive-status {{ max-width: 144px; font-size: 14px; }}
}}
"""
        + DETAILS_HEAD_CSS
    )
