"""JSON-RPC frames: a frame with a wrong Content-Length costs that frame at most,
never the messages after it."""

from __future__ import annotations

import json

import pytest

from osc2lsp.framing import FrameReader, Garbled

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
