"""What a ``FileUpload`` widget received, checked: a page can set any synced trait, so its value is
read as untrusted data (a list of dicts with a ``name`` and bytes) and anything else counts as nothing."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any


def uploaded_file(change: Mapping[str, Any]) -> tuple[str, bytes] | None:
    """The first file of an upload's new value as (name as the user's device gave it, bytes), or None."""
    files = change.get("new") or ()
    if not isinstance(files, tuple | list) or not files or not isinstance(files[0], Mapping):
        return None
    name, content = files[0].get("name"), files[0].get("content")
    if not isinstance(name, str):
        return None
    if isinstance(content, memoryview):
        return name, content.tobytes()
    if isinstance(content, bytes | bytearray):
        return name, bytes(content)
    return None
