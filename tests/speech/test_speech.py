"""Spoken feedback: the phrase queue's rules, the phrases, and espeak-ng audio made in the kernel."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pmk_nb.speech import PhraseQueue, SpeechUnavailable, list_voices, phrases, synthesize, wav_stats


class Clock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def test_queue_drops_repeats_and_keeps_the_newest_news() -> None:
    clock = Clock()
    q = PhraseQueue(repeat_after=5.0, min_gap=1.0, clock=clock)
    assert q.add(phrases.destination_set("Office"))
    assert not q.add(phrases.destination_set("Office"))  # waiting already
    assert q.take() is not None and q.take() is None  # said; the next waits for min_gap
    assert not q.add(phrases.destination_set("Office"))  # said just now
    clock.t += 6.0
    assert q.add(phrases.destination_set("Office"))  # long enough ago
    assert q.add(phrases.connection_lost())
    assert q.add(phrases.connection_regained())  # replaces "lost", not yet said
    assert q.waiting == ["Going to Office.", "Connection to the chair restored."]
    first = q.take()
    assert first is not None and first.text == "Going to Office."
    assert q.take() is None  # min_gap: not cut off
    clock.t += 1.0
    second = q.take()
    assert second is not None and second.key == phrases.LINK


def test_queue_is_bounded_and_can_be_muted() -> None:
    clock = Clock()
    q = PhraseQueue(max_waiting=2, clock=clock)
    q.say("a", "one")
    q.say("b", "two")
    q.say("c", "three")
    assert q.waiting == ["two", "three"]  # the oldest dropped
    q.enabled = False
    assert not q.say("d", "four")
    q.clear()
    assert q.take() is None


def test_phrases_are_short_and_name_the_room() -> None:
    assert phrases.arrived("Exam room 2") == (phrases.GOAL, "Arrived at Exam room 2.")
    key, text = phrases.route_blocked("Treatment room", ["Door Treatment room"])
    assert key == phrases.GOAL and text == "No accessible route to Treatment room. Door Treatment room is too narrow."
    assert phrases.route_blocked("X", ["A", "B", "C"])[1].endswith("A and B are too narrow.")
    assert phrases.stopped("released")[1] == "Stopped."  # the deadman
    assert phrases.stopped("link stale")[1] == "Stopped, no data from the chair."
    assert all(len(f()[1]) < 40 for f in (phrases.connection_lost, phrases.connection_regained))


def test_espeak_makes_audible_speech_of_plausible_length() -> None:
    short = synthesize("Stopped.")
    long = synthesize("Arrived at Exam room 2. Connection to the chair restored.")
    assert short[:4] == b"RIFF" and long[8:12] == b"WAVE"
    s_sec, s_rms = wav_stats(short)
    l_sec, l_rms = wav_stats(long)
    assert 0.3 < s_sec < 2.5 and 2.0 < l_sec < 8.0 and l_sec > 2 * s_sec
    assert s_rms > 0.02 and l_rms > 0.02  # not silent
    fast, _ = wav_stats(synthesize("Arrived at Exam room 2.", rate=300))
    slow, _ = wav_stats(synthesize("Arrived at Exam room 2.", rate=100))
    assert slow > 1.8 * fast  # the rate setting is applied
    assert ("en", "English") in [(c, n.split(" (")[0]) for c, n in list_voices()] or any(
        c.startswith("en") for c, _ in list_voices()
    )


def test_espeak_missing_or_bad_voice_is_a_typed_error(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    with pytest.raises(SpeechUnavailable) as err:
        synthesize("Stopped.", voice="no-such-voice-xx")
    assert "no-such-voice-xx" in err.value.message
    monkeypatch.setenv("PATH", str(tmp_path))  # no espeak-ng on this PATH
    assert not (tmp_path / "espeak-ng").exists() and os.environ["PATH"] == str(tmp_path)
    with pytest.raises(SpeechUnavailable) as missing:
        synthesize("Stopped.")
    assert missing.value.returncode is None and "espeak-ng" in missing.value.hint
    assert list_voices() == []
