"""Speech made in the kernel with espeak-ng (the Debian package), for pages without speechSynthesis.

``espeak-ng --stdout`` writes a streaming WAV whose header gives no real length (0x7fff....); the
sizes are fixed here so every player knows the duration. The text goes through stdin, never the
command line (a phrase starting with "-" is not an option).
"""

from __future__ import annotations

import functools
import io
import shutil
import struct
import subprocess
import wave

import numpy as np

from pmk_nb.errors import PmkError

ESPEAK = "espeak-ng"
DEFAULT_VOICE = "en"
DEFAULT_RATE = 160  # words per minute (espeak's default is 175; slower is clearer for announcements)
TIMEOUT = 10.0


class SpeechUnavailable(PmkError):
    """espeak-ng is missing or failed.

    Attributes:
        tool: the program looked for.
        returncode: its exit code, or None when it was not found or timed out.
    """

    def __init__(self, message: str, *, tool: str = ESPEAK, returncode: int | None = None, hint: str = "") -> None:
        super().__init__(message, hint=hint)
        self.tool = tool
        self.returncode = returncode


def _espeak() -> str:
    path = shutil.which(ESPEAK)
    if path is None:
        raise SpeechUnavailable(
            f"{ESPEAK} is not installed, so the dashboard cannot make speech for this browser",
            hint="Install the Debian package espeak-ng (apt-get install espeak-ng), or use a browser with speech.",
        )
    return path


def _fix_sizes(data: bytes) -> bytes:
    """Set the RIFF and data chunk sizes to the real lengths (espeak streams with placeholder sizes)."""
    if len(data) < 12 or data[:4] != b"RIFF" or data[8:12] != b"WAVE":
        return data
    out = bytearray(data)
    pos = 12
    while pos + 8 <= len(out):
        tag, size = bytes(out[pos : pos + 4]), struct.unpack_from("<I", out, pos + 4)[0]
        if tag == b"data":
            struct.pack_into("<I", out, pos + 4, len(out) - pos - 8)
            break
        pos += 8 + size + (size & 1)
    struct.pack_into("<I", out, 4, len(out) - 8)
    return bytes(out)


def synthesize(text: str, *, voice: str = DEFAULT_VOICE, rate: int = DEFAULT_RATE) -> bytes:
    """``text`` spoken as a WAV file (16-bit mono PCM).

    Raises:
        SpeechUnavailable: espeak-ng is missing, timed out or failed (the voice may not exist).
    """
    rate = max(80, min(450, int(rate)))
    voice = voice or DEFAULT_VOICE
    if voice.split("+")[0].casefold() not in _known_voices(_espeak()):  # espeak-ng falls back silently
        raise SpeechUnavailable(f"{ESPEAK} has no voice {voice!r}", hint="Pick another voice in Settings.")
    cmd = [_espeak(), "--stdout", "-v", voice, "-s", str(rate)]
    try:
        done = subprocess.run(cmd, input=text.encode("utf-8"), capture_output=True, timeout=TIMEOUT, check=False)
    except subprocess.TimeoutExpired as err:
        raise SpeechUnavailable(f"{ESPEAK} took over {TIMEOUT:.0f} s to speak {text!r}") from err
    if done.returncode != 0 or len(done.stdout) <= 44:
        why = done.stderr.decode("utf-8", "replace").strip()[:200]
        raise SpeechUnavailable(
            f"{ESPEAK} could not speak with voice {voice!r}: {why or 'no audio'}",
            returncode=done.returncode,
            hint="Pick another voice in Settings.",
        )
    return _fix_sizes(done.stdout)


def wav_stats(wav: bytes) -> tuple[float, float]:
    """(seconds, RMS of the samples in 0..1) of a 16-bit PCM WAV: how long and how loud."""
    with wave.open(io.BytesIO(wav)) as f:
        frames = f.readframes(f.getnframes())
        seconds = f.getnframes() / float(f.getframerate())
    samples = np.frombuffer(frames, dtype="<i2").astype(np.float64) / 32768.0
    rms = float(np.sqrt(np.mean(samples**2))) if samples.size else 0.0
    return seconds, rms


@functools.lru_cache(maxsize=4)
def _voice_table(espeak: str) -> tuple[tuple[str, str, str], ...]:
    """(language code, name, file) per voice of the espeak-ng at ``espeak`` (asked once)."""
    try:
        done = subprocess.run([espeak, "--voices"], capture_output=True, timeout=TIMEOUT, check=False, text=True)
    except (OSError, subprocess.TimeoutExpired):
        return ()
    rows = [line.split() for line in done.stdout.splitlines()[1:]]
    return tuple((p[1], p[3], p[4]) for p in rows if len(p) >= 5)


def _known_voices(espeak: str) -> set[str]:
    """What ``-v`` accepts: codes, names, voice files and their last part ("gmw/en" is "en" too)."""
    names = {v.casefold() for row in _voice_table(espeak) for v in row}
    return names | {v.rsplit("/", 1)[-1] for v in names}


def list_voices() -> list[tuple[str, str]]:
    """espeak-ng's voices as ``(language code, name)``; empty when espeak-ng is missing."""
    try:
        espeak = _espeak()
    except SpeechUnavailable:
        return []
    return [(code, name.replace("_", " ")) for code, name, _ in _voice_table(espeak)]
