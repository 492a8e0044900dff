"""The page side of the page-drawn chair (issue 41): an overlay canvas drawn at the display's rate.

Why not ipycanvas alone: its batched commands are still one kernel message per frame (60 frames a
second would double the kernel's bytes and CPU), and its animation ``sleep`` replays a sequence the
kernel sent ahead, which would mean guessing the chair's future poses.  So a ``<script>`` shown once
in a hidden Output (as the drive stick's, :mod:`pmk_nb.ui.drive.script`) reads the feed
(:mod:`pmk_nb.ui.live.page_feed`, a hidden Text widget), puts a transparent ``<canvas
class="pmk-live-page">`` over the live canvas (same box, no pointer events: gestures still reach the
ipycanvas) and draws the chair and its heading dot there on every ``requestAnimationFrame`` whose
picture changed, at the pose interpolated between the kernel's recent ones, one update behind
(never carried on more than one update past the newest).  When the next update is overdue a
``role="status"`` note over the map says "Link slow" until one comes.  The functions mirror
:mod:`pmk_nb.viewport.glide` line for line.

For tests and the benchmark it keeps ``window.__pmkLive``: ``frames`` (pictures drawn),
``updates`` (feed messages read) and ``trace`` (the recent frames' ``[kernel seq, x, y, kernel time
shown, page wall time ms]``).
"""

from __future__ import annotations

from pmk_nb.ui.live.chair_layer import CHAIR_RGB, HEADING_RGB, STALE_RGB
from pmk_nb.ui.live.page_feed import FEED_CLASS
from pmk_nb.viewport import LATE_GRACE_S, OFFSET_WINDOW, STILL_SPEED

OVERLAY_CLASS = "pmk-live-page"
LINK_CLASS = "pmk-live-link"
LINK_SLOW = "Link slow: the chair is shown where it was last reported"
TRACE = 600  # frames kept in window.__pmkLive.trace

STYLE = f"""<style>
/* bottom right of the map: the tool bar floats at the top, the status line bottom left */
.{LINK_CLASS} {{ position: absolute; bottom: 6px; right: 6px; z-index: 9; max-width: 60%; padding: 4px 10px;
  border-radius: 4px; background: #fff3cd; color: #5c4200; border: 2px solid #b58100; font-weight: bold; }}
.{LINK_CLASS}:empty {{ display: none; }}
</style>"""

SCRIPT = """<script>
(function () {
  if (window.__pmkLive) return;
  var S = window.__pmkLive = { frames: 0, updates: 0, trace: [], views: {} };
  var GRACE = __GRACE__, STILL = __STILL__, WINDOW = __WINDOW__, KEEP = 8, TRACE = __TRACE__;
  function wrap(a) {
    a = (a + Math.PI) % (2 * Math.PI);
    if (a <= 0) a += 2 * Math.PI;
    return a - Math.PI;
  }
  function between(a, b, f, t) {
    return { t: t, x: a.x + f * (b.x - a.x), y: a.y + f * (b.y - a.y),
             yaw: wrap(a.yaw + f * wrap(b.yaw - a.yaw)), v: b.v };
  }
  // viewport/glide.py pose_at: interpolate; past the newest at most one update interval, then hold
  function poseAt(s, t) {
    if (!s.length) return null;
    var first = s[0], last = s[s.length - 1];
    if (t <= first.t || s.length === 1) return t <= first.t ? first : last;
    if (t >= last.t) {
      var prev = s[s.length - 2], step = last.t - prev.t, ahead = Math.min(t - last.t, step);
      return step > 0 ? between(prev, last, 1 + ahead / step, last.t + ahead) : last;
    }
    var lo = 0, hi = s.length - 1;
    while (hi - lo > 1) { var mid = (lo + hi) >> 1; if (s[mid].t <= t) lo = mid; else hi = mid; }
    var a = s[lo], b = s[hi], span = b.t - a.t;
    return between(a, b, span > 0 ? (t - a.t) / span : 1, t);
  }
  // viewport/glide.py merge: by stamp, the newer message wins, the last KEEP; an older clock restarts
  function merge(s, fresh) {
    var byT = {};
    if (fresh.length && s.length && fresh[fresh.length - 1].t < s[0].t) s = [];
    s.forEach(function (p) { byT[p.t] = p; });
    fresh.forEach(function (p) { if ([p.t, p.x, p.y, p.yaw, p.v].every(isFinite)) byT[p.t] = p; });
    return Object.keys(byT).map(Number).sort(function (a, b) { return a - b; })
      .map(function (t) { return byT[t]; }).slice(-KEEP);
  }
  function late(now, arrived, next) { return next != null && now - arrived > Math.max(next, 0) + GRACE; }
  function read(now) {
    document.querySelectorAll('.__FEED__ input, input.__FEED__').forEach(function (input) {
      var text = input.value;
      if (!text) return;
      var m;
      try { m = JSON.parse(text); } catch (e) { return; }
      var V = S.views[m.id] || (S.views[m.id] = { text: '', samples: [], offsets: [], frames: 0, key: '' });
      if (V.text === text) return;
      V.text = text; V.msg = m; V.arrived = now;
      V.offsets.push(now - m.now);
      if (V.offsets.length > WINDOW) V.offsets.shift();
      V.samples = merge(V.samples, m.poses.map(function (p) {
        return { t: p[0], x: p[1], y: p[2], yaw: p[3], v: p[4] };
      }));
      S.updates += 1;
    });
  }
  function overlayFor(V, id, canvas) {
    if (V.overlay && V.overlay.isConnected && V.canvas === canvas && V.overlay.parentNode === canvas.parentNode)
      return V.overlay;
    if (V.overlay) { V.overlay.remove(); V.status.remove(); }
    var o = document.createElement('canvas');
    o.className = '__OVERLAY__';
    o.setAttribute('aria-hidden', 'true');
    o.dataset.view = id;
    o.style.cssText = 'position:absolute;pointer-events:none;z-index:1;';
    canvas.parentNode.insertBefore(o, canvas.nextSibling);
    var st = document.createElement('div');
    st.className = '__LINK__';
    st.setAttribute('role', 'status');
    st.setAttribute('aria-live', 'polite');
    canvas.parentNode.insertBefore(st, o.nextSibling);
    V.overlay = o; V.status = st; V.canvas = canvas; V.key = '';
    return o;
  }
  function draw(V, id, now) {
    var m = V.msg, canvas = document.querySelector('canvas.pmk-live-canvas.pmk-live-' + id);
    if (!canvas || !canvas.parentNode) return;
    var o = overlayFor(V, id, canvas);
    if (o.width !== canvas.width) o.width = canvas.width;
    if (o.height !== canvas.height) o.height = canvas.height;
    var place = [canvas.offsetLeft, canvas.offsetTop, canvas.offsetWidth, canvas.offsetHeight].join(',');
    if (o.dataset.place !== place) {
      o.style.left = canvas.offsetLeft + 'px'; o.style.top = canvas.offsetTop + 'px';
      o.style.width = canvas.offsetWidth + 'px'; o.style.height = canvas.offsetHeight + 'px';
      o.dataset.place = place; V.key = '';
    }
    var slow = late(now, V.arrived, m.next) ? '__SLOW__' : '';
    if (V.status.textContent !== slow) V.status.textContent = slow;
    var off = Math.min.apply(null, V.offsets);
    var p = poseAt(V.samples, now - off - Math.max(m.behind, 0));
    var key = '';
    if (p) {
      var x = m.px[0] * p.x + m.px[1], y = m.px[2] * p.y + m.px[3];
      var still = !isFinite(p.v) || Math.abs(p.v) < STILL, d = still ? Math.abs(m.m) : p.v;
      var hx = m.px[0] * (p.x + d * Math.cos(p.yaw)) + m.px[1], hy = m.px[2] * (p.y + d * Math.sin(p.yaw)) + m.px[3];
      key = [x.toFixed(1), y.toFixed(1), hx.toFixed(1), hy.toFixed(1), m.r, m.dot, m.stale, o.width, o.height]
        .join(',');
    }
    if (key === V.key) return;
    V.key = key;
    var g = o.getContext('2d');
    g.clearRect(0, 0, o.width, o.height);
    if (!p) return;
    g.fillStyle = m.stale ? '__STALE__' : '__CHAIR__';
    g.beginPath(); g.arc(x, y, m.r, 0, 2 * Math.PI); g.fill();
    g.fillStyle = '__HEADING__';
    g.beginPath(); g.arc(hx, hy, m.dot, 0, 2 * Math.PI); g.fill();
    V.frames += 1; S.frames += 1;
    S.trace.push([m.seq, x, y, p.t, performance.timeOrigin + performance.now()]);
    if (S.trace.length > TRACE) S.trace.shift();
  }
  function tick() {
    try {
      var now = performance.now() / 1000;
      read(now);
      Object.keys(S.views).forEach(function (id) { if (S.views[id].msg) draw(S.views[id], id, now); });
    } catch (e) { if (!S.error) { S.error = String(e); console.error('pmk live page layer', e); } }
    requestAnimationFrame(tick);
  }
  requestAnimationFrame(tick);
})();
</script>"""


def _rgb(rgb: tuple[int, int, int]) -> str:
    return f"rgb({rgb[0]}, {rgb[1]}, {rgb[2]})"


_TOKENS = {
    "__GRACE__": repr(LATE_GRACE_S),
    "__STILL__": repr(STILL_SPEED),
    "__WINDOW__": str(OFFSET_WINDOW),
    "__TRACE__": str(TRACE),
    "__FEED__": FEED_CLASS,
    "__OVERLAY__": OVERLAY_CLASS,
    "__LINK__": LINK_CLASS,
    "__SLOW__": LINK_SLOW,
    "__STALE__": _rgb(STALE_RGB),
    "__CHAIR__": _rgb(CHAIR_RGB),
    "__HEADING__": _rgb(HEADING_RGB),
}
for _token, _value in _TOKENS.items():
    SCRIPT = SCRIPT.replace(_token, _value)


def page_html() -> str:
    """The style sheet and the script, for the live view's hidden output."""
    return STYLE + SCRIPT
