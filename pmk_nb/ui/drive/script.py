"""The page side of the joystick: a DOM stick, arrow keys, keepalives, release on every way out.

A ``<script>`` shown once in the drive panel's hidden output (scripts in an ipywidgets Output run
in JupyterLab and in Voilà alike; an HTML widget's would not). It binds every ``.pmk-drive-pad``
on the page, now and after Home is shown again, and posts each stick state as JSON into the
hidden Text widget ``.pmk-drive-channel`` (setting its value and dispatching ``input``, which is
how the Text view sends a value to the kernel). No custom widget, nothing to install.

While held it re-sends the position every :data:`KEEPALIVE_MS` (the kernel stops the chair when
they stop coming), in turn on :data:`LANES` hidden Text widgets of the panel: ipywidgets keeps one
update per widget in flight and holds the next until the kernel has answered the last (its "idle"
back on the page), so one channel carried at most one message per round trip, and a round trip over
300 ms on a loaded machine stopped the chair (the classroom soak: "the connection is too slow").
It releases on pointer up or cancel, lost capture, window blur, page hidden
(``hidden: true``) and page hide. Arrow keys drive while the pad has the focus, or, in a Voilà
page, anywhere outside a text field; the pad carries ``data-lm-suppress-shortcuts`` so that
JupyterLab's own arrow-key shortcuts stay out of the way.
"""

from __future__ import annotations

KEEPALIVE_MS = 100
LANES = 3  # channels the stick's messages take in turn: up to three in flight
PANEL_CLASS = "pmk-drive"
MOVE_MS = 40  # at most one message per this many ms while the finger moves
CHANNEL_CLASS = "pmk-drive-channel"
PAD_CLASS = "pmk-drive-pad"

PAD_HTML = f"""<div class="{PAD_CLASS}" tabindex="0" role="application" data-lm-suppress-shortcuts="true"
 aria-label="Joystick: hold and drag to drive the chair, or use the arrow keys; let go to stop">
<div class="pmk-drive-knob"></div></div>"""

STYLE = f"""<style>
/* where the panel docks (the rider's side) and how translucent it is: pmk_nb/ui/home/style.py */
.pmk-drive .pmk-drive-pad-box {{ order: -1; width: 176px; min-width: 0; margin: 0; }}
.{PAD_CLASS} {{ width: 170px; height: 170px; border-radius: 50%; background: #cfd8dc; position: relative;
  touch-action: none; user-select: none; -webkit-user-select: none; cursor: grab; outline: none;
  border: 3px solid #90a4ae; box-sizing: border-box; }}
.{PAD_CLASS}:focus-visible {{ border-color: #1565c0; }}
.{PAD_CLASS}.pmk-drive-held {{ background: #b3e5fc; border-color: #0277bd; cursor: grabbing; }}
.pmk-drive-knob {{ position: absolute; left: 50%; top: 50%; width: 64px; height: 64px; margin: -32px 0 0 -32px;
  border-radius: 50%; background: #1f6feb; box-shadow: 0 2px 6px rgba(0,0,0,.35); pointer-events: none; }}
.pmk-drive-locked .{PAD_CLASS} {{ opacity: 0.4; cursor: not-allowed; }}
.pmk-drive-claim button, button.pmk-drive-claim {{ white-space: normal; height: auto; min-height: 48px; }}
.pmk-drive-stop button, button.pmk-drive-stop {{ min-height: 72px; font-size: 1.4em; font-weight: bold; }}
.pmk-drive-status {{ max-width: 180px; text-align: center; font-size: 0.9em; line-height: 1.25; }}
.pmk-drive .pmk-drive-status, .pmk-drive .pmk-drive-status .widget-html-content {{ white-space: normal !important;
  line-height: 1.25; }}
</style>"""

SCRIPT = """<script>
(function () {
  if (window.__pmkDrive) return;
  window.__pmkDrive = { sent: 0 };
  var page = Math.random().toString(36).slice(2, 10) + Date.now().toString(36);
  var seq = 0, press = 0, held = false, via = null, x = 0, y = 0, keys = {}, last = 0, lane = 0;
  var KEYS = { ArrowUp: [0, 1], ArrowDown: [0, -1], ArrowLeft: [-1, 0], ArrowRight: [1, 0] };
  function send(hidden) {
    var first = document.querySelector('.__CHANNEL__');  // the first panel's lanes, in turn
    var box = (first && first.closest('.__PANEL__')) || document;
    var els = box.querySelectorAll('.__CHANNEL__ input, input.__CHANNEL__');
    if (!els.length) return;
    var el = els[lane % els.length];
    lane += 1;
    seq += 1;
    el.value = JSON.stringify({ page: page, seq: seq, press: press, t: performance.now(),
                                x: x, y: y, held: held, hidden: !!hidden });
    el.dispatchEvent(new Event('input', { bubbles: true }));
    last = performance.now();
    window.__pmkDrive.sent = seq;
  }
  function draw() {
    document.querySelectorAll('.__PAD__').forEach(function (pad) {
      var r = pad.clientWidth / 2 - 32;
      pad.firstElementChild.style.transform = 'translate(' + (x * r) + 'px,' + (-y * r) + 'px)';
      pad.classList.toggle('pmk-drive-held', held);
    });
  }
  function start(how) { press += 1; held = true; via = how; }
  function release(hidden) {
    if (!held && !hidden) return;
    held = false; via = null; x = 0; y = 0; keys = {};
    send(hidden); draw();
  }
  function fromPointer(pad, e) {
    var box = pad.getBoundingClientRect(), r = box.width / 2;
    var dx = (e.clientX - box.left - r) / r, dy = -(e.clientY - box.top - r) / r;
    var d = Math.hypot(dx, dy);
    if (d > 1) { dx /= d; dy /= d; }
    x = dx; y = dy;
  }
  function fromKeys() {
    var kx = 0, ky = 0;
    Object.keys(keys).forEach(function (k) { kx += KEYS[k][0]; ky += KEYS[k][1]; });
    var d = Math.hypot(kx, ky) || 1;
    x = kx / d; y = ky / d;
  }
  function bind(pad) {
    pad.dataset.pmkBound = '1';
    pad.addEventListener('pointerdown', function (e) {
      e.preventDefault();
      if (pad.closest('.__LOCKED__')) return;  // another page drives: the kernel refuses it too
      try { pad.setPointerCapture(e.pointerId); } catch (err) { /* synthetic pointer */ }
      pad.focus({ preventScroll: true });
      start('pointer'); fromPointer(pad, e); send(false); draw();
    });
    pad.addEventListener('pointermove', function (e) {
      if (!held || via !== 'pointer') return;
      fromPointer(pad, e); draw();
      if (performance.now() - last >= __MOVE__) send(false);
    });
    ['pointerup', 'pointercancel', 'lostpointercapture'].forEach(function (name) {
      pad.addEventListener(name, function () { if (via === 'pointer') release(false); });
    });
    pad.addEventListener('contextmenu', function (e) { e.preventDefault(); });
  }
  function keysAllowed(e) {
    var t = e.target;
    if (t && t.closest && t.closest('.__PAD__')) return true;
    if (document.querySelector('.jp-LabShell')) return false;  // JupyterLab: only on the focused pad
    var tag = t && t.tagName;
    return !(tag === 'INPUT' || tag === 'TEXTAREA' || tag === 'SELECT' || (t && t.isContentEditable))
      && !!document.querySelector('.__PAD__');
  }
  document.addEventListener('keydown', function (e) {
    if (!KEYS[e.key] || e.altKey || e.ctrlKey || e.metaKey || !keysAllowed(e)) return;
    e.preventDefault(); e.stopPropagation();
    if (keys[e.key]) return;  // auto-repeat: the keepalive carries on
    if (!held && document.querySelector('.__LOCKED__ .__PAD__')) return;
    if (!held) start('keys');
    if (via !== 'keys') return;
    keys[e.key] = true; fromKeys(); send(false); draw();
  }, true);
  document.addEventListener('keyup', function (e) {
    if (!KEYS[e.key] || via !== 'keys') return;
    delete keys[e.key];
    if (Object.keys(keys).length === 0) release(false); else { fromKeys(); send(false); draw(); }
  }, true);
  document.addEventListener('visibilitychange', function () {
    if (document.visibilityState === 'hidden') release(true);
  });
  window.addEventListener('blur', function () { release(false); });
  window.addEventListener('pagehide', function () { release(true); });
  setInterval(function () { if (held) send(false); }, __KEEPALIVE__);
  function bindAll() {
    document.querySelectorAll('.__PAD__:not([data-pmk-bound])').forEach(bind);
  }
  bindAll();
  setInterval(bindAll, 300);
})();
</script>"""
LOCKED_CLASS = "pmk-drive-locked"  # on the pad's box while another page drives or a Stop holds
_TOKENS = {
    "__LOCKED__": LOCKED_CLASS,
    "__CHANNEL__": CHANNEL_CLASS,
    "__PANEL__": PANEL_CLASS,
    "__PAD__": PAD_CLASS,
    "__MOVE__": MOVE_MS,
    "__KEEPALIVE__": KEEPALIVE_MS,
}
for _token, _value in _TOKENS.items():
    SCRIPT = SCRIPT.replace(_token, str(_value))


def page_html() -> str:
    """The style sheet and the script, for the drive panel's hidden output."""
    return STYLE + SCRIPT
