"""JSON-RPC frames from a byte stream, re-synchronised after a bad frame.

A frame is ``Content-Length: N`` (other header lines may come too), an empty
line, then N bytes of JSON. pygls' own reader trusts N: with a wrong length
it reads into the next message or stops halfway through one, and from then on
every header lands in the middle of a body and the server never answers
again. This reader checks each frame and, when it is wrong, starts again at
the next header it finds.

Why that is safe: JSON text never holds a raw carriage return inside a string
and never a bare ``Content-Length`` outside one, so ``Content-Length: 12\\r\\n``
in the stream always starts a header. A body whose length is wrong is
recovered too: the bytes between its header and the next one are the real
body (too short: the rest follows; too long: the next message was swallowed).
A body that claims more bytes than ever arrive (the last message, the client
waiting for its answer) is taken as soon as what arrived parses as a whole
JSON value: a strict prefix of a JSON document never does.

``FrameReader.feed(data)`` returns what the new bytes completed: parsed
messages and ``Garbled`` records (for logging; a request in a garbled frame
cannot be answered since its id is unknown). No asyncio here: the server's
loop (``protocol.py``) feeds it.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from typing import Any

_LENGTH = re.compile(rb"Content-Length:[ \t]*(\d+)[ \t]*\r\n", re.IGNORECASE)
# Where the next frame starts: a whole header line (raw CR LF: never inside JSON).
_NEXT_FRAME = re.compile(rb"Content-(?:Length|Type):[^\r\n]*\r\n", re.IGNORECASE)
_HEADER_END = b"\r\n\r\n"
_HEADER_WORD = b"content-"
_MAX_HEADER = 4096  # bytes of header lines before the blank line
_MAX_BODY = 512 * 1024 * 1024


@dataclass(frozen=True, slots=True)
class Garbled:
    """Bytes that were not a well-formed frame, and what was wrong."""

    reason: str
    size: int


Event = Any  # a parsed JSON message (dict, list...) or a Garbled record


class FrameReader:
    """Split a byte stream into JSON-RPC messages; re-synchronise after a bad frame."""

    def __init__(self) -> None:
        self._buffer = bytearray()

    def feed(self, data: bytes) -> list[Event]:
        """The messages (and garbled parts) completed by ``data``."""
        self._buffer += data
        events: list[Event] = []
        while self._next(events):
            pass
        return events

    @property
    def pending(self) -> int:
        """Bytes held back, waiting for the rest of a frame."""
        return len(self._buffer)

    def _next(self, events: list[Event]) -> bool:
        """Take one frame (or skip bytes) from the buffer; False: wait for more bytes."""
        buf = self._buffer
        if not buf:
            return False
        if not _header_prefix(buf):
            return self._skip(events, 0)
        end = buf.find(_HEADER_END)
        if end < 0:
            return self._skip(events, 1) if len(buf) > _MAX_HEADER else False
        length_line = _LENGTH.search(buf, 0, end + 2)
        if length_line is None or end > _MAX_HEADER:
            return self._skip(events, 1)
        length = int(length_line.group(1))
        start = end + len(_HEADER_END)
        if length > _MAX_BODY:
            return self._skip(events, start)
        following = _NEXT_FRAME.search(buf, start)
        if len(buf) - start >= length:
            body = _parse(bytes(buf[start : start + length]))
            if body is not _INVALID:  # a prefix of a JSON text never parses: the length was right
                del buf[: start + length]  # stray bytes after it are skipped next
                events.append(body)
                return True
            if following is not None:  # the real body ends where the next frame starts
                return self._salvage(events, start, following.start(), length)
            whole = _parse(bytes(buf[start:]))  # too short, and nothing after it yet
            if whole is _INVALID:
                return False
            del buf[:]
            events += [Garbled("a Content-Length shorter than its body", length), whole]
            return True
        if following is not None:  # too long: it swallowed the next frame's header
            return self._salvage(events, start, following.start(), length)
        tail = bytes(buf[start:]).rstrip()
        if tail.endswith((b"}", b"]")):  # too long, and nothing more will come
            whole = _parse(tail)
            if whole is not _INVALID:
                del buf[:]
                events += [Garbled("a Content-Length longer than its body", length), whole]
                return True
        return False

    def _salvage(self, events: list[Event], start: int, stop: int, length: int) -> bool:
        """Take ``buffer[start:stop]`` as the body of a frame whose length was wrong."""
        raw = bytes(self._buffer[start:stop])
        del self._buffer[:stop]
        body = _parse(raw)
        if body is _INVALID:
            events.append(Garbled("a frame whose body is not JSON", len(raw)))
            return True
        what = "longer" if len(raw.rstrip()) < length else "shorter"
        events += [Garbled(f"a Content-Length {what} than its body", length), body]
        return True

    def _skip(self, events: list[Event], start: int) -> bool:
        """Drop the bytes before the next header found at or after ``start``."""
        buf = self._buffer
        lowered = bytes(buf).lower()
        at = lowered.find(_HEADER_WORD, start)
        if at < 0:  # keep what may be the beginning of a header still arriving
            at = len(buf)
            for cut in range(min(len(buf) - start, len(_HEADER_WORD) - 1), 0, -1):
                if _HEADER_WORD.startswith(lowered[-cut:]):
                    at = len(buf) - cut
                    break
        dropped = bytes(buf[:at])
        del buf[:at]
        if dropped.strip():
            events.append(Garbled("bytes outside a frame", len(dropped)))
        return len(buf) >= len(_HEADER_WORD)  # a whole header word is in front: go on


_INVALID = object()


def _parse(body: bytes) -> Any:
    try:
        return json.loads(body)
    except ValueError:  # JSONDecodeError and UnicodeDecodeError
        return _INVALID


def _header_prefix(data: bytes | bytearray) -> bool:
    """Whether ``data`` starts like a header line (``Content-…``), maybe cut short."""
    prefix = bytes(data[: len(_HEADER_WORD)]).lower()
    return _HEADER_WORD.startswith(prefix)
