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
JSON value: a strict prefix of a JSON document never does (where that value
ends is followed as the bytes arrive, each byte read once).

A message larger than ``MAX_MESSAGE_BYTES`` (64 MiB: the checker's 50 MiB cap on a
source file, JSON-escaped) is skipped as it arrives, never held, and reported
(``Garbled.too_large``): the server answers with an error and shows a message.

``FrameReader.feed(data)`` returns what the new bytes completed: parsed
messages and ``Garbled`` records (for logging; a request in a garbled frame
cannot be answered since its id is unknown). No asyncio here: the server's
loop (``serving.py``) feeds it.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from typing import Any

_LENGTH = re.compile(rb"Content-Length:[ \t]*(\d{1,15})[ \t]*\r\n", re.IGNORECASE)
# Where the next frame starts: a whole header line (raw CR LF: never inside JSON).
_NEXT_FRAME = re.compile(rb"Content-(?:Length|Type):[^\r\n]*\r\n", re.IGNORECASE)
_HEADER_WORD_AT = re.compile(rb"content-", re.IGNORECASE)
_HEADER_END = b"\r\n\r\n"
_HEADER_WORD = b"content-"
_MAX_HEADER = 4096  # bytes of header lines before the blank line
MAX_MESSAGE_BYTES = 64 * 1024 * 1024  # a body larger than this is skipped, with an error
# JSON outside strings: a string's opening quote or a bracket; inside a string: its text
# up to the closing quote (escapes included) or the end of what arrived.
_JSON_TOKEN = re.compile(rb'["{}\[\]]')
_STRING_REST = re.compile(rb'[^"\\]*(?:\\.[^"\\]*)*')


@dataclass(frozen=True, slots=True)
class Garbled:
    """Bytes that were not a well-formed frame, and what was wrong."""

    reason: str
    size: int
    too_large: bool = False  # a whole message skipped for its size (the client is told)


Event = Any  # a parsed JSON message (dict, list...) or a Garbled record


class _ValueEnd:
    """Where the JSON value that starts a body ends, found by reading each byte once:
    the depth of brackets outside strings, as the bytes arrive."""

    def __init__(self, start: int) -> None:
        self.start = start  # where the body starts in the buffer
        self.at = start  # how far the bytes have been read
        self.depth = 0
        self.in_string = False
        self.end: int | None = None  # just after the value's closing bracket

    def read(self, buf: bytearray) -> int | None:
        """The end of the value once its last bracket arrived, else None."""
        while self.end is None and self.at < len(buf):
            if self.in_string:
                rest = _STRING_REST.match(buf, self.at)
                stop = rest.end() if rest is not None else self.at  # (it matches "" at least)
                if stop >= len(buf) or buf[stop] == 0x5C:  # the end, or a backslash cut off
                    self.at = stop
                    return None
                self.at, self.in_string = stop + 1, False  # past the closing quote
                continue
            token = _JSON_TOKEN.search(buf, self.at)
            if token is None:
                self.at = len(buf)
                return None
            self.at = token.end()
            char = buf[token.start()]
            if char == 0x22:  # "
                self.in_string = True
            elif char in b"{[":
                self.depth += 1
            else:
                self.depth -= 1
                if self.depth <= 0:
                    self.end = self.at
        return self.end


class FrameReader:
    """Split a byte stream into JSON-RPC messages; re-synchronise after a bad frame.

    Each byte is examined a bounded number of times, however the stream is cut into
    chunks: the search for the next header and for the end of a body that claims more
    bytes than came go on from where they stopped (reading a 20 MB message took tens of
    seconds when every chunk searched the body again from its start).
    """

    def __init__(self) -> None:
        self._buffer = bytearray()
        self._searched = 0  # the next header was looked for up to here (in this frame)
        self._value: _ValueEnd | None = None  # the end of the body's value (in this frame)
        self._skipping = False  # the body of a message too large is being skipped

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

    def _drop(self, size: int) -> None:
        """Forget the first ``size`` bytes (and what was learnt of the frame there)."""
        del self._buffer[:size]
        self._searched = 0
        self._value = None

    def _next(self, events: list[Event]) -> bool:
        """Take one frame (or skip bytes) from the buffer; False: wait for more bytes."""
        buf = self._buffer
        if not buf:
            return False
        if not _header_prefix(buf):
            return self._skip(events, 0)
        end = buf.find(_HEADER_END, 0, _MAX_HEADER + len(_HEADER_END))
        if end < 0:
            return self._skip(events, 1) if len(buf) > _MAX_HEADER else False
        length_line = _LENGTH.search(buf, 0, end + 2)
        if length_line is None:
            return self._skip(events, 1)
        length = int(length_line.group(1))
        start = end + len(_HEADER_END)
        self._skipping = False  # a header: whatever was skipped before has ended
        if length > MAX_MESSAGE_BYTES:
            return self._too_large(events, start, f"it says {length:,} bytes")
        following = self._following(start)
        if len(buf) - start >= length:
            body = _parse(bytes(buf[start : start + length]))
            if body is not _INVALID:  # a prefix of a JSON text never parses: the length was right
                self._drop(start + length)  # stray bytes after it are skipped next
                events.append(body)
                return True
            if following is not None:  # the real body ends where the next frame starts
                return self._salvage(events, start, following, length)
            whole = self._whole_value(start)  # too short, and nothing after it yet
            if whole is _INVALID:
                if len(buf) - start > MAX_MESSAGE_BYTES:  # and it goes on and on
                    return self._too_large(events, start, "its body goes on past it")
                return False
            self._drop(len(buf))
            events += [Garbled("a Content-Length shorter than its body", length), whole]
            return True
        if following is not None:  # too long: it swallowed the next frame's header
            return self._salvage(events, start, following, length)
        whole = self._whole_value(start)  # too long, and nothing more will come
        if whole is not _INVALID:
            self._drop(len(buf))
            events += [Garbled("a Content-Length longer than its body", length), whole]
            return True
        return False

    def _following(self, start: int) -> int | None:
        """Where the next frame's header starts after ``start``, if it has arrived.

        What was searched before is not searched again, but for the last header's
        length (a header cut short then may have been completed since)."""
        buf = self._buffer
        found = _NEXT_FRAME.search(buf, max(start, self._searched))
        if found is not None:
            return found.start()
        self._searched = max(start, len(buf) - _MAX_HEADER)
        return None

    def _whole_value(self, start: int) -> Any:
        """The body from ``start`` to the end of the buffer as JSON, when it holds a whole
        JSON value and nothing after it but blanks; else ``_INVALID``."""
        buf = self._buffer
        if self._value is None or self._value.start != start:
            self._value = _ValueEnd(start)
        end = self._value.read(buf)
        if end is None or buf[end:].strip():
            return _INVALID
        return _parse(bytes(buf[start:end]))

    def _too_large(self, events: list[Event], start: int, size: str) -> bool:
        """Skip a message larger than ``MAX_MESSAGE_BYTES`` (its header ends at ``start``):
        what of its body came and what is still to come, up to the next header."""
        limit = f"{MAX_MESSAGE_BYTES // (1024 * 1024)} MiB"
        events.append(
            Garbled(f"a message larger than the limit of {limit} ({size})", start, too_large=True)
        )
        self._drop(start)
        self._skipping = True  # its body goes as bytes outside a frame, unreported
        return True

    def _salvage(self, events: list[Event], start: int, stop: int, length: int) -> bool:
        """Take ``buffer[start:stop]`` as the body of a frame whose length was wrong."""
        raw = bytes(self._buffer[start:stop])
        self._drop(stop)
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
        found = _HEADER_WORD_AT.search(buf, start)
        at = found.start() if found is not None else len(buf)
        if found is None:  # keep what may be the beginning of a header still arriving
            for cut in range(min(len(buf) - start, len(_HEADER_WORD) - 1), 0, -1):
                if _HEADER_WORD.startswith(bytes(buf[-cut:]).lower()):
                    at = len(buf) - cut
                    break
        dropped = len(buf[:at].strip()) if not self._skipping else 0
        self._drop(at)
        if dropped:
            events.append(Garbled("bytes outside a frame", at))
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
