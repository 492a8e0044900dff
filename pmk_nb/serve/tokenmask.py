"""Access tokens masked in the dashboard server's log: ``?token=SECRET`` is written ``?token=***``.

Tornado logs every 4xx and 5xx request with its full URL (``404 GET /api/kernels/.../channels?token=...``),
and an uncaught exception with the request, so the kiosk's token ended up in the terminal and in any
log file kept of it.  :class:`TokenMask` is a logging filter on every handler Voilà writes with
(:func:`logging_config`, merged into Voilà's own logging configuration from ``voila.json``).
"""

from __future__ import annotations

import logging
import re

MASK = "***"
#: ``token=`` in a query (also percent-encoded, as in a login page's ``next=`` URL), up to the next separator
TOKEN_VALUE = re.compile(r"(token(?:=|%3D))[^&\s'\"#,;)\]]+", re.IGNORECASE)
FILTER_NAME = "pmk_mask_tokens"


def mask_tokens(text: str) -> str:
    """``text`` with the value of every ``token=`` replaced by :data:`MASK`."""
    return TOKEN_VALUE.sub(rf"\g<1>{MASK}", text)


class TokenMask(logging.Filter):
    """Masks tokens in a record's message and traceback before any handler formats it (keeps every record)."""

    def filter(self, record: logging.LogRecord) -> bool:
        line = record.getMessage()
        masked = mask_tokens(line)
        if masked != line:
            record.msg, record.args = masked, None
        if record.exc_info and not record.exc_text:
            record.exc_text = logging.Formatter().formatException(record.exc_info)
        if record.exc_text:
            record.exc_text = mask_tokens(record.exc_text)
        return True


def logging_config() -> dict[str, object]:
    """Voilà's ``logging_config``: the filter on its console handler and on the root logger's handler,
    which takes tornado's access and error lines (they went to Python's last-resort handler: message
    only, stderr, warnings and up; the same here)."""
    return {
        "filters": {FILTER_NAME: {"()": f"{__name__}.{TokenMask.__name__}"}},
        "formatters": {"pmk_plain": {"format": "%(message)s"}},
        "handlers": {
            "console": {"filters": [FILTER_NAME]},
            "pmk_plain": {
                "class": "logging.StreamHandler",
                "formatter": "pmk_plain",
                "stream": "ext://sys.stderr",
                "filters": [FILTER_NAME],
            },
        },
        "root": {"level": "WARNING", "handlers": ["pmk_plain"]},
    }
