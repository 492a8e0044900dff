"""Spoken feedback in the page: the browser's speech synthesis, or espeak-ng audio made in the kernel.

The kernel decides *what* to say (:class:`pmk_nb.speech.PhraseQueue`); the page says it. A hidden
widget carries the latest phrase (``.pmk-speech-say``, with a sequence number), and a small script
in the page speaks each new one with ``speechSynthesis`` (voice: the first whose language starts
with the chosen code; rate as set). A page without ``speechSynthesis`` says so through a hidden text
field (``.pmk-speech-caps``); from then on the kernel attaches a WAV made with espeak-ng, which the
script plays in an ``<audio class="pmk-speech-audio">`` element. The script runs from an Output
widget (its outputs are trusted, so the ``<script>`` runs) and installs itself once per page.
"""

from __future__ import annotations

import base64
import html
import logging
import threading
import time
from collections.abc import Callable

import ipywidgets as w
from IPython.display import HTML

from pmk_nb.speech import DEFAULT_VOICE, PhraseQueue, SpeechUnavailable, synthesize

log = logging.getLogger(__name__)
ESPEAK_WPM = 175  # espeak-ng's normal rate: rate 1.0
STALE_MS = 15_000  # a phrase older than this when a page first sees it is not said (a reloaded page)

SPEECH_SCRIPT = f"""<script>
(function () {{
  if (window.__pmkSpeech) return;
  window.__pmkSpeech = true;
  window.__pmkSpoken = window.__pmkSpoken || [];
  var last = 0;
  function canSpeak() {{
    return !!(window.speechSynthesis && typeof window.SpeechSynthesisUtterance === 'function');
  }}
  function report() {{
    var el = document.querySelector('.pmk-speech-caps input');
    if (!el) return;
    var v = canSpeak() ? 'speech' : 'audio';
    if (el.value === v) return;
    el.value = v;
    el.dispatchEvent(new Event('input', {{bubbles: true}}));
    el.dispatchEvent(new Event('change', {{bubbles: true}}));
  }}
  function speak(d) {{
    var via = d.audio ? 'audio' : 'speech';
    window.__pmkSpoken.push({{text: d.text, via: via, seq: d.seq}});
    if (!d.audio && canSpeak()) {{
      var u = new SpeechSynthesisUtterance(d.text);
      u.rate = parseFloat(d.rate) || 1;
      u.lang = d.voice || 'en';
      var code = (d.voice || 'en').toLowerCase();
      var voices = window.speechSynthesis.getVoices() || [];
      for (var i = 0; i < voices.length; i++) {{
        if ((voices[i].lang || '').toLowerCase().indexOf(code) === 0) {{ u.voice = voices[i]; break; }}
      }}
      window.speechSynthesis.speak(u);
      return;
    }}
    if (!d.audio) return;
    var el = document.querySelector('audio.pmk-speech-audio');
    if (!el) {{
      el = document.createElement('audio');
      el.className = 'pmk-speech-audio';
      document.body.appendChild(el);
    }}
    el.src = d.audio;
    var played = el.play();
    if (played && played.catch) played.catch(function (e) {{ el.dataset.error = String(e); }});
  }}
  setInterval(function () {{
    report();
    var item = document.querySelector('.pmk-speech-say [data-seq]');
    if (!item) return;
    var seq = parseInt(item.dataset.seq, 10);
    if (!(seq > last)) return;
    var fresh = last > 0 || Date.now() - parseFloat(item.dataset.t) < {STALE_MS};
    last = seq;
    if (fresh) speak(item.dataset);
  }}, 150);
}})();
</script>"""


class SpeechOutput:
    """The hidden speech widgets and the phrase queue behind them; call :meth:`pump` on a timer.

    Attributes:
        queue: what waits to be said (see :class:`pmk_nb.speech.PhraseQueue`).
        said: ``(text, "speech" | "audio")`` of every phrase handed to the page, for tests and logs.
        problem: why espeak-ng audio could not be made (None when fine): the screen shows it.
    """

    def __init__(self) -> None:
        self.queue = PhraseQueue()
        self.voice = DEFAULT_VOICE
        self.rate = 1.0
        self.said: list[tuple[str, str]] = []
        self.problem: SpeechUnavailable | None = None
        #: also told every phrase, spoken or not (the screen reader's live region: pmk_nb/ui/home/live_region.py)
        self.listeners: list[Callable[[tuple[str, str]], None]] = []
        self._seq = 0
        self._lock = threading.Lock()
        self.say_box = w.HTML("")
        self.say_box.add_class("pmk-speech-say")
        self.caps = w.Text("", continuous_update=True)
        self.caps.add_class("pmk-speech-caps")
        self.script = w.Output()
        self.script.append_display_data(HTML(SPEECH_SCRIPT))
        self.widget = w.Box([self.say_box, self.caps, self.script], layout=w.Layout(display="none"))
        self.widget.add_class("pmk-speech")

    @property
    def enabled(self) -> bool:
        return self.queue.enabled

    def configure(self, on: bool, voice: str = DEFAULT_VOICE, rate: float = 1.0) -> None:
        """Apply the profile's settings (Settings: spoken feedback, voice, rate)."""
        self.queue.enabled = bool(on)
        if not on:
            self.queue.clear()
        self.voice, self.rate = voice or DEFAULT_VOICE, float(rate)

    @property
    def browser_speaks(self) -> bool | None:
        """What the page reported: True (speechSynthesis), False (needs audio), None (not yet)."""
        value = str(self.caps.value or "")
        return None if not value else value == "speech"

    def say(self, phrase: tuple[str, str]) -> bool:
        """Queue a ``(key, text)`` phrase of :mod:`pmk_nb.speech.phrases` (any thread)."""
        for listener in self.listeners:
            listener(phrase)
        return self.queue.add(phrase)

    def pump(self) -> str | None:
        """Hand the next due phrase to the page; returns its text (None: nothing now)."""
        phrase = self.queue.take()
        if phrase is None:
            return None
        self.emit(phrase.text)
        return phrase.text

    def emit(self, text: str) -> None:
        """Put ``text`` in the page now, with espeak-ng audio when the page cannot speak."""
        audio = ""
        if self.browser_speaks is False:
            try:
                wav = synthesize(text, voice=self.voice, rate=round(ESPEAK_WPM * self.rate))
                audio = "data:audio/wav;base64," + base64.b64encode(wav).decode("ascii")
                self.problem = None
            except SpeechUnavailable as err:
                log.warning("no spoken feedback: %s", err)
                self.problem = err
        with self._lock:
            self._seq += 1
            attrs = {
                "data-seq": str(self._seq),
                "data-t": f"{time.time() * 1000:.0f}",
                "data-text": text,
                "data-voice": self.voice,
                "data-rate": f"{self.rate:g}",
                "data-audio": audio,
            }
            self.said.append((text, "audio" if audio else "speech"))
        body = " ".join(f'{k}="{html.escape(v, quote=True)}"' for k, v in attrs.items())
        self.say_box.value = f"<span {body}>{html.escape(text)}</span>"
