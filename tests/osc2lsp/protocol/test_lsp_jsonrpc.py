"""JSON-RPC robustness through raw pipes (what a well-behaved client cannot send):
wrong frame lengths, params of the wrong type, requests after ``shutdown``,
refusals logged quietly, the way the server ends."""

from __future__ import annotations

import pytest

from osc2lsp.transport.framing import MAX_MESSAGE_BYTES
from tests.osc2lsp.protocol.raw_client import TIMEOUT, RawClient

URI = "file:///tmp/osc2lsp-tests/jsonrpc.osc"
TEXT = "import osc.standard\nscenario s:\n    hero: vehicle\n    x: int = 1\n"
HOVER = {"textDocument": {"uri": URI}, "position": {"line": 3, "character": 5}}


@pytest.fixture
def server(tmp_path):
    client = RawClient(tmp_path / "stderr.log", "--log-level", "INFO", settings={"verify": False})
    client.initialize()
    client.open(URI, TEXT)
    client.diagnostics(URI, 1)
    yield client
    client.close()


@pytest.mark.parametrize("length_error", [-12, -1, 1, 30])
def test_a_frame_with_a_wrong_length_does_not_silence_the_server(server, length_error):
    server.request("textDocument/hover", HOVER, length_error=length_error)
    after = server.call("textDocument/hover", HOVER)
    assert "x" in after["result"]["contents"]["value"]
    assert "reading on from the next frame" in server.stderr()


def test_a_last_frame_claiming_too_many_bytes_is_answered(server):
    asked = server.request("textDocument/hover", HOVER, length_error=50)
    assert "result" in server.response(asked)


def test_bytes_that_are_no_frame_are_skipped(server):
    server.send_bytes(b"\r\nhello world\r\n")
    assert "result" in server.call("textDocument/hover", HOVER)


def test_invalid_params_are_answered_with_invalid_params(server):
    bad_line = dict(HOVER, position={"line": "3", "character": 5})
    answer = server.call("textDocument/hover", bad_line)
    assert answer["error"]["code"] == -32602
    assert "params.position.line" in answer["error"]["message"]
    missing = server.call("textDocument/definition", {"textDocument": {"uri": URI}})
    assert missing["error"]["code"] == -32602


def test_a_rename_to_null_is_invalid_params_not_a_rename_to_none(server):
    answer = server.call("textDocument/rename", dict(HOVER, newName=None))
    assert answer["error"]["code"] == -32602
    assert "newName" in answer["error"]["message"]


def test_a_notification_with_invalid_params_is_dropped_and_serving_goes_on(server):
    server.notify("textDocument/didChange", {"textDocument": {"uri": URI}, "contentChanges": 5})
    assert "result" in server.call("textDocument/hover", HOVER)
    assert "a notification: not answered" in server.stderr()


def test_an_error_for_a_message_whose_id_is_unknown_has_a_null_id(server):
    """JSON-RPC 2.0: "If there was an error in detecting the id ... it MUST be Null"."""
    server.send_bytes(b"Content-Length: 5\r\n\r\n{abc}")  # not JSON
    server.send_bytes(b"Content-Length: 3\r\n\r\n[1]")  # not an object
    bad_id = b'{"jsonrpc": "2.0", "id": [1], "method": "textDocument/hover"}'
    server.send_bytes(b"Content-Length: %d\r\n\r\n%s" % (len(bad_id), bad_id))
    server.call("textDocument/hover", HOVER)
    errors = [m for m in server.inbox if "error" in m]
    assert sorted(m["error"]["code"] for m in errors) == [-32700, -32600, -32600]
    assert all("id" in m and m["id"] is None for m in errors)


def test_a_message_over_the_size_limit_is_refused_with_a_clear_error(server):
    """The header says more than ``MAX_MESSAGE_BYTES``: the body is skipped as it comes
    (never held), the client gets an error and a message, and serving goes on."""
    server.send_bytes(b"Content-Length: %d\r\n\r\n" % (MAX_MESSAGE_BYTES + 1))
    server.send_bytes(b'{"jsonrpc": "2.0", "id": 99, "params": {"text": "' + b"x" * 100_000)
    assert "result" in server.call("textDocument/hover", HOVER)
    [error] = [m for m in server.inbox if "error" in m]
    assert error["id"] is None and "larger than the limit of 64 MiB" in error["error"]["message"]
    shown = server.wait_for(lambda m: m.get("method") == "window/showMessage")
    assert "out of date" in shown["params"]["message"]


def test_a_rename_to_an_implicit_name_is_refused(server):
    """``it`` and ``actor`` are names the language gives: a field renamed to ``it``
    would be read as the subject of a ``with:`` block."""
    for implicit in ("it", "actor"):
        answer = server.call("textDocument/rename", dict(HOVER, newName=implicit))
        assert answer["error"]["code"] == -32803
        assert f"`{implicit}`" in answer["error"]["message"]


def test_a_refused_rename_is_an_error_answer_logged_without_traceback(server):
    vehicle = {"textDocument": {"uri": URI}, "position": {"line": 2, "character": 12}}
    answer = server.call("textDocument/rename", dict(vehicle, newName="car"))
    assert answer["error"]["code"] == -32803
    assert "standard library" in answer["error"]["message"]
    keyword = server.call("textDocument/rename", dict(HOVER, newName="keep"))
    assert "keyword" in keyword["error"]["message"]
    log = server.stderr()
    assert "refused" in log
    assert "Traceback" not in log and " ERROR " not in log


def test_requests_after_shutdown_are_refused_and_exit_ends_the_server(server):
    assert server.call("shutdown")["result"] is None
    late = server.call("textDocument/hover", HOVER)
    assert late["error"]["code"] == -32600
    server.notify("textDocument/didChange", {})  # ignored
    server.notify("exit")
    assert server.wait_exit() == 0


def test_exit_without_shutdown_ends_with_code_1(server):
    server.notify("exit")
    assert server.wait_exit() == 1


def test_the_end_of_input_ends_the_server(server):
    assert server.process.stdin is not None
    server.process.stdin.close()
    assert server.wait_exit() in (0, 1)


# ---- the same frames on `--tcp` -------------------------------------------------------


@pytest.fixture
def tcp_server(tmp_path):
    client = RawClient(
        tmp_path / "stderr.log", "--log-level", "INFO", settings={"verify": False}, tcp=True
    )
    client.initialize()
    client.open(URI, TEXT)
    client.diagnostics(URI, 1)
    yield client
    client.close()


@pytest.mark.parametrize("length_error", [-12, 30])
def test_on_tcp_a_frame_with_a_wrong_length_does_not_silence_the_server(tcp_server, length_error):
    tcp_server.request("textDocument/hover", HOVER, length_error=length_error)
    tcp_server.send_bytes(b"\r\nhello world\r\n")
    after = tcp_server.call("textDocument/hover", HOVER)
    assert "x" in after["result"]["contents"]["value"]
    assert "reading on from the next frame" in tcp_server.stderr()
    bad_line = dict(HOVER, position={"line": "3", "character": 5})
    assert tcp_server.call("textDocument/hover", bad_line)["error"]["code"] == -32602


def test_on_tcp_shutdown_and_exit_end_the_server(tcp_server):
    assert tcp_server.call("shutdown")["result"] is None
    tcp_server.notify("exit")
    assert tcp_server.wait_exit() == 0


def test_on_tcp_the_end_of_the_connection_ends_the_server(tcp_server):
    assert tcp_server._socket is not None
    tcp_server._socket.close()
    assert tcp_server.wait_exit() in (0, 1)


def test_on_tcp_the_port_stops_listening_once_a_client_connects(tcp_server):
    import socket

    assert tcp_server._socket is not None
    port = tcp_server._socket.getpeername()[1]
    with pytest.raises(ConnectionRefusedError):
        socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT).close()
    assert "x" in tcp_server.call("textDocument/hover", HOVER)["result"]["contents"]["value"]


def test_on_tcp_a_port_in_use_is_a_clear_error_with_exit_2():
    import socket
    import subprocess
    import sys

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        server = subprocess.run(
            [sys.executable, "-m", "osc2lsp", "--tcp", "--port", str(port)],
            capture_output=True,
            text=True,
            timeout=TIMEOUT,  # a hang guard
            stdin=subprocess.DEVNULL,
        )
    assert server.returncode == 2
    assert f"cannot listen on 127.0.0.1:{port}" in server.stderr
    assert "Traceback" not in server.stderr
