"""Spoken feedback for a user who cannot watch the screen: what is said, when, and the audio.

Pure (no widgets): :mod:`.phrases` (the short sentences: destination set, arrived, route blocked,
connection lost / regained, stopped), :mod:`.queue` (:class:`PhraseQueue`: de-duplication and rate
limiting, so a flapping link or a repeated tap does not chatter) and :mod:`.espeak` (speech made
in the kernel with espeak-ng, for browsers without speech synthesis).
"""

from pmk_nb.speech import phrases
from pmk_nb.speech.espeak import DEFAULT_VOICE, SpeechUnavailable, list_voices, synthesize, wav_stats
from pmk_nb.speech.queue import Phrase, PhraseQueue

__all__ = [
    "DEFAULT_VOICE",
    "Phrase",
    "PhraseQueue",
    "SpeechUnavailable",
    "list_voices",
    "phrases",
    "synthesize",
    "wav_stats",
]
