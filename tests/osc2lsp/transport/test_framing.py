"""JSON-RPC frames: a frame with a wrong Content-Length costs that frame at most,
never the messages after it."""

from __future__ import annotations

import itertools
import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from osc2lsp.transport.framing import FrameReader, Garbled

MESSAGES = [
    {"jsonrpc": "2.0", "id": n, "method": "m", "params": {"text": "a\r\nb" * n}} for n in range(5)
]


def frame(message: dict, length_error: int = 0, content_type: bool = False) -> bytes:
    body = json.dumps(message).encode()
    header = b"Content-Type: application/vscode-jsonrpc; charset=utf-8\r\n" if content_type else b""
    return header + f"Content-Length: {len(body) + length_error}\r\n\r\n".encode() + body


def read(stream: bytes, chunk: int) -> tuple[list, list[Garbled]]:
    reader = FrameReader()
    events = []
    for i in range(0, len(stream), chunk):
        events += reader.feed(stream[i : i + chunk])
    return [e for e in events if not isinstance(e, Garbled)], [
        e for e in events if isinstance(e, Garbled)
    ]


@pytest.mark.parametrize("chunk", [1, 7, 64, 1 << 20])
@pytest.mark.parametrize("length_error", [-30, -1, 1, 25])
@pytest.mark.parametrize("content_type", [False, True])
def test_a_wrong_length_is_recovered_and_the_next_frames_read(chunk, length_error, content_type):
    stream = (
        frame(MESSAGES[0])
        + frame(MESSAGES[1], length_error, content_type)
        + frame(MESSAGES[2], 0, content_type)
        + frame(MESSAGES[3])
    )
    messages, garbled = read(stream, chunk)
    assert [m["id"] for m in messages] == [0, 1, 2, 3]
    assert len(garbled) == 1 and "Content-Length" in garbled[0].reason


@pytest.mark.parametrize("chunk", [1, 1 << 20])
def test_good_frames_are_read_whole_in_any_chunks(chunk):
    messages, garbled = read(
        b"".join(frame(m, 0, n % 2 == 1) for n, m in enumerate(MESSAGES)), chunk
    )
    assert messages == MESSAGES and garbled == []


def test_a_last_frame_that_claims_more_bytes_than_come_is_still_read():
    """The client waits for the answer: no more bytes will come."""
    messages, garbled = read(frame(MESSAGES[1]) + frame(MESSAGES[2], 40), 1 << 20)
    assert [m["id"] for m in messages] == [1, 2] and len(garbled) == 1


def test_bytes_between_frames_and_frames_without_length_are_skipped():
    stream = (
        b"garbage\r\n"
        + frame(MESSAGES[1])
        + b"xx"
        + b"Content-Type: text/plain\r\n\r\n{}"
        + frame(MESSAGES[2])
        + b"Content-Length: 4\r\n\r\nnope"
        + frame(MESSAGES[3])
    )
    messages, garbled = read(stream, 5)
    assert [m["id"] for m in messages] == [1, 2, 3]
    assert garbled and all(g.size > 0 for g in garbled)


def test_a_body_that_is_not_json_is_reported_once_the_next_frame_starts():
    reader = FrameReader()
    assert reader.feed(b"Content-Length: 5\r\n\r\nnot j") == []  # maybe more is coming
    events = reader.feed(b"son" + frame(MESSAGES[4]))
    assert isinstance(events[0], Garbled) and events[1] == MESSAGES[4]
    assert reader.pending == 0


class _Counted:
    """A compiled pattern that counts the bytes its searches and matches go over."""

    def __init__(self, pattern, counter: list[int]):
        self._pattern, self._counter = pattern, counter

    def search(self, data, pos=0, endpos=None):
        found = self._pattern.search(data, pos, len(data) if endpos is None else endpos)
        end = found.end() if found else (len(data) if endpos is None else endpos)
        self._counter[0] += end - pos
        return found

    def match(self, data, pos=0):
        found = self._pattern.match(data, pos)
        self._counter[0] += (found.end() if found else pos) - pos
        return found


@pytest.mark.parametrize("length_error", [0, 40])
def test_a_large_message_in_small_chunks_is_read_in_linear_work(monkeypatch, length_error):
    """Each chunk used to search the whole body again for the next header, and to parse
    it whole whenever it ended with a bracket: 20 MB took tens of seconds. The bytes
    searched and parsed are now a small multiple of the message's size."""
    import osc2lsp.transport.framing as framing

    work = [0]
    for name in ("_NEXT_FRAME", "_JSON_TOKEN", "_STRING_REST"):
        if hasattr(framing, name):
            monkeypatch.setattr(framing, name, _Counted(getattr(framing, name), work))
    parse = framing._parse

    def counted_parse(body: bytes):
        work[0] += len(body)
        return parse(body)

    monkeypatch.setattr(framing, "_parse", counted_parse)
    text = 'scenario s:\n    x: int = 1  # {"a": [1]}\n' * 50_000
    message = {"jsonrpc": "2.0", "method": "m", "params": {"text": text}}
    stream = frame(message, length_error)
    messages, garbled = read(stream, 4096)
    assert messages == [message] and len(garbled) == (1 if length_error else 0)
    assert work[0] <= 4 * len(stream)


def test_a_message_over_the_size_limit_is_skipped_and_the_next_read(monkeypatch):
    monkeypatch.setattr("osc2lsp.transport.framing.MAX_MESSAGE_BYTES", 10_000)
    big = {"jsonrpc": "2.0", "id": 1, "method": "m", "params": {"text": "x" * 20_000}}
    messages, garbled = read(frame(big) + frame(MESSAGES[2]), 1000)
    assert messages == [MESSAGES[2]]
    assert [g.too_large for g in garbled] == [True]
    assert "larger than the limit of" in garbled[0].reason


def test_a_body_without_end_is_skipped_once_past_the_size_limit(monkeypatch):
    """A length shorter than the body, and the body goes on: never held whole."""
    monkeypatch.setattr("osc2lsp.transport.framing.MAX_MESSAGE_BYTES", 10_000)
    reader = FrameReader()
    events = reader.feed(b"Content-Length: 10\r\n\r\n[")
    for _ in range(30):
        events += reader.feed(b"1, " * 1000)
        assert reader.pending < 20_000
    assert any(isinstance(e, Garbled) and e.too_large for e in events)
    assert reader.feed(frame(MESSAGES[3]))[-1] == MESSAGES[3]


_SEGMENT = st.one_of(
    st.tuples(st.just("good"), st.integers(0, 4)),
    st.tuples(st.just("wrong"), st.sampled_from([-30, -1, 1, 25, 400])),
    st.tuples(st.just("junk"), st.binary(min_size=1, max_size=40).map(lambda b: b.lower())),
    st.tuples(st.just("large"), st.integers(0, 1)),
)


@settings(max_examples=150, derandomize=True, deadline=None)
@given(segments=st.lists(_SEGMENT, max_size=12), chunks=st.lists(st.integers(1, 300), min_size=1))
def test_framing_storm_every_well_framed_message_is_read_and_none_invented(segments, chunks):
    """Good frames, frames of a wrong length, bytes outside any frame and messages over
    the size limit, in any order and cut anywhere: each well-framed message is read, in
    order, nothing else is taken for one, and the reader holds no more than the limit."""
    limit = 2_000
    stream, expected, sent_ids = b"", [], set()
    for n, (kind, value) in enumerate(segments):
        message = {"jsonrpc": "2.0", "id": n, "method": "m", "params": {"text": "a\r\nb" * n}}
        if kind == "good":
            stream += frame(message)
            expected.append(n)
        elif kind == "wrong":
            stream += frame(message, value)
        elif kind == "junk":  # never the start of a header: its bytes hold no "content-"
            stream += value.replace(b"c", b"k")
        else:
            message["params"]["text"] = "x" * (limit + 100 * value)
            stream += frame(message)
        sent_ids.add(n)
    import osc2lsp.transport.framing as framing

    original = framing.MAX_MESSAGE_BYTES
    framing.MAX_MESSAGE_BYTES = limit
    try:
        reader, events, at = FrameReader(), [], 0
        for size in itertools.cycle(chunks):
            if at >= len(stream):
                break
            events += reader.feed(stream[at : at + size])
            at += size
            assert reader.pending <= 2 * limit + 4096 + size
    finally:
        framing.MAX_MESSAGE_BYTES = original
    messages = [e for e in events if not isinstance(e, Garbled)]
    ids = [m["id"] for m in messages if isinstance(m, dict) and "id" in m]
    assert len(ids) == len(messages) and set(ids) <= sent_ids  # nothing invented
    assert ids == sorted(ids) and len(set(ids)) == len(ids)  # in order, each once
    assert set(expected) <= set(ids)  # every well-framed message
