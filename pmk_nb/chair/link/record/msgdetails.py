"""A message definition the bridge describes: rosapi's ``message_details`` -> the schema text of an MCAP.

A recording writes any type the chair's bridge can describe, not only the bundled ones
(:mod:`.msgdefs`, which need no round trip): rosapi answers ``/rosapi/message_details`` with one
``TypeDef`` per type (the type, then each type it uses: field names, field types, array lengths) and
this module writes them as the concatenated ``ros2msg`` text ``ros2 bag`` puts in a schema (the
type's fields, then ``===`` / ``MSG: pkg/Type`` sections, each dependency once, depth-first).

What differs between the bridges' answers and the ROS 2 text written:

* rosapi 2.x reports IDL names (``double``, ``float``, ``boolean``, ``octet``): written as ``.msg``
  primitives (``float64``, ``float32``, ``bool``, ``byte``); a bounded ``string<=N`` as ``string``.
* rosapi 1.x reports ``time`` / ``duration`` and a ``std_msgs/Header`` with ``seq``: written as
  ``builtin_interfaces/Time`` / ``Duration`` and the ROS 2 header, as :mod:`.record_convert`
  converts the messages (a recording is ROS 2 CDR whatever the chair runs).
* Constants (``constnames``) carry no type in a typedef and do not change the encoding: left out.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from pmk_nb.chair.link.record.msgdefs import FIELDS, concatenated
from pmk_nb.wire import normalise_type

if TYPE_CHECKING:
    from pmk_nb.chair.link.query.discovery import Discovery

#: rosapi 2.x's IDL spellings -> ``.msg`` primitives
IDL = {"double": "float64", "float": "float32", "boolean": "bool", "octet": "byte"}
#: rosapi 1.x's specials -> the ROS 2 types a recording writes
SPECIALS = {"time": "builtin_interfaces/Time", "duration": "builtin_interfaces/Duration"}
#: types written as ROS 2 defines them whatever the bridge says (ROS 1's header has ``seq``)
ROS2_FORM = ("std_msgs/Header", "builtin_interfaces/Time", "builtin_interfaces/Duration")


def _field_type(kind: str) -> str:
    kind = kind.strip()
    if kind.startswith("sequence<"):  # rosapi unwraps these; an older one may not
        kind = kind[len("sequence<") :].rstrip(">")
    kind = kind.split(",", 1)[0].strip()  # a bounded sequence unwrapped by rosapi: "int32, 5"
    if kind.startswith("string<=") or kind.startswith("wstring<="):
        kind = kind.split("<=", 1)[0]
    if kind in SPECIALS:
        return SPECIALS[kind]
    if "/" in kind:
        return normalise_type(kind)
    return IDL.get(kind, kind)


def _own_fields(typedef: dict[str, Any]) -> str:
    names = list(typedef.get("fieldnames") or ())
    kinds = list(typedef.get("fieldtypes") or ())
    sizes = list(typedef.get("fieldarraylen") or ()) or [-1] * len(names)
    if not (len(names) == len(kinds) == len(sizes)):
        raise ValueError(f"typedef of {typedef.get('type')} has fields, types and array lengths of unequal counts")
    lines = []
    for name, kind, size in zip(names, kinds, sizes, strict=True):
        suffix = "" if int(size) < 0 else ("[]" if int(size) == 0 else f"[{int(size)}]")
        lines.append(f"{_field_type(str(kind))}{suffix} {name}\n")
    return "".join(lines)


def definition_from_typedefs(type_name: str, typedefs: Sequence[dict[str, Any]]) -> str | None:
    """The concatenated ``ros2msg`` definition of ``type_name`` (any spelling) from rosapi's typedefs;
    None when they do not describe it whole (the type itself or a type it uses is missing, or a
    typedef is malformed)."""
    own: dict[str, str] = {}
    try:
        for typedef in typedefs:
            key = normalise_type(str(typedef.get("type", "")))
            if key in SPECIALS or key in ROS2_FORM:
                continue
            own[key] = _own_fields(typedef)
    except (ValueError, TypeError):
        return None
    own |= {key: FIELDS[key] for key in ROS2_FORM if key in FIELDS}
    own.setdefault("builtin_interfaces/Duration", FIELDS["builtin_interfaces/Time"])
    try:
        return concatenated(normalise_type(type_name), own)
    except KeyError:
        return None


def describe(discovery: Discovery, type_name: str, timeout: float | None = None) -> str | None:
    """Ask the bridge for ``type_name``'s definition (one rosapi call); None when it cannot describe it.

    Raises:
        RosapiMissing: the bridge has no rosapi; ChairTimeout: no answer in time.
    """
    return definition_from_typedefs(type_name, discovery.message_details(type_name, timeout))
