"""The pygls methods the server overrides or relies on are the ones we read.

``osc2lsp.transport`` overrides some of pygls' methods, private ones included
(``_send_data``, ``_send_handler_result``), and calls others (``_send_response``).
Each is recorded below with a hash of its source in the pygls version it was read
in; when pygls changes one, the test names it: read the new method, adapt the
override (or the call) in ``osc2lsp/transport/``, then record the new hash and the
version. A method overridden without being recorded fails too.
"""

from __future__ import annotations

import hashlib
import inspect
import textwrap
from collections.abc import Callable
from importlib.metadata import version
from typing import Any

import pytest
from pygls import protocol as pygls_protocol
from pygls.lsp.server import LanguageServer
from pygls.protocol import JsonRPCProtocol, LanguageServerProtocol
from pygls.server import JsonRPCServer

from osc2lsp.language_server import Osc2LanguageServer
from osc2lsp.transport.protocol import Osc2Protocol
from osc2lsp.transport.serving import ServingLanguageServer

# The pygls versions whose sources the hashes below were read from (pyproject allows
# pygls>=2.0,<3: a version not listed passes as long as every method is unchanged).
CHECKED_WITH = ("2.1.1",)

# pygls method -> sha256 (first 16 hex digits) of its dedented source.
OVERRIDDEN = {
    "pygls.protocol.json_rpc.JsonRPCProtocol.structure_message": "f474677cc6876fa2",
    "pygls.protocol.json_rpc.JsonRPCProtocol._send_data": "1fc28d5c43c4c85b",
    "pygls.protocol.json_rpc.JsonRPCProtocol.handle_message": "16c6cdc3306bda77",
    "pygls.protocol.json_rpc.JsonRPCProtocol._send_handler_result": "a248db6fbc89dec3",
    "pygls.protocol.language_server.LanguageServerProtocol.lsp_text_document__did_open": (
        "47a06808b05783f4"
    ),
    "pygls.protocol.language_server.LanguageServerProtocol.lsp_text_document__did_change": (
        "3de47dba4785a65b"
    ),
    "pygls.protocol.language_server.LanguageServerProtocol.lsp_text_document__did_close": (
        "ba85bb5435285a3c"
    ),
    "pygls.lsp.server.LanguageServer.__init__": "a96a4470813e983f",
    "pygls.lsp.server.LanguageServer.report_server_error": "663c27df2c127e2a",
    "pygls.server.JsonRPCServer.start_io": "e858e563c2260f8a",
    "pygls.server.JsonRPCServer.start_tcp": "c42c704ef29c75c9",
}

# Called (not overridden): private methods, and what sets the private attributes the
# overrides read (``_result_types``, ``_request_futures``, ``_shutdown``,
# ``_include_headers``, ``_converter``, ``_server``, ``_stop_event``).
RELIED_ON: dict[str, tuple[Callable[..., Any], str]] = {
    "pygls.protocol.json_rpc.JsonRPCProtocol.__init__": (
        JsonRPCProtocol.__init__,
        "b255748a0d9979ab",
    ),
    "pygls.protocol.json_rpc.JsonRPCProtocol._send_response": (
        JsonRPCProtocol._send_response,
        "1402bff0b4719313",
    ),
    "pygls.protocol.json_rpc.JsonRPCProtocol.set_writer": (
        JsonRPCProtocol.set_writer,
        "384025e27de7afde",
    ),
    "pygls.protocol.language_server.LanguageServerProtocol.__init__": (
        LanguageServerProtocol.__init__,
        "76697c1025fa6d46",
    ),
    "pygls.protocol.language_server.LanguageServerProtocol.get_message_type": (
        LanguageServerProtocol.get_message_type,
        "fa5618cb59110386",
    ),
    "pygls.server.JsonRPCServer.__init__": (JsonRPCServer.__init__, "ee4bd4019f0e8425"),
    "pygls.server.JsonRPCServer._report_server_error": (
        JsonRPCServer._report_server_error,
        "4b8d5346c2c2fe22",
    ),
    "pygls.protocol.default_converter": (pygls_protocol.default_converter, "8e51b7df0d07a18d"),
}

OURS = (Osc2Protocol, ServingLanguageServer, Osc2LanguageServer)


def source_hash(function: Callable[..., Any]) -> str:
    source = textwrap.dedent(inspect.getsource(inspect.unwrap(function)))
    return hashlib.sha256(source.encode("utf-8")).hexdigest()[:16]


def overridden() -> dict[str, Callable[..., Any]]:
    """Every pygls method one of our classes defines again, by its pygls name."""
    found: dict[str, Callable[..., Any]] = {}
    for ours in OURS:
        for name in vars(ours):
            if name.startswith("__") and name != "__init__":
                continue
            for base in ours.__mro__[1:]:
                if base.__module__.startswith("pygls") and name in vars(base):
                    found[f"{base.__module__}.{base.__qualname__}.{name}"] = vars(base)[name]
                    break
    return found


def changed(name: str, recorded: str, function: Callable[..., Any]) -> str | None:
    now = source_hash(function)
    if now == recorded:
        return None
    return (
        f"pygls {version('pygls')} changed {name} (source hash {now}, recorded {recorded} "
        f"with pygls {', '.join(CHECKED_WITH)}): read it, adapt osc2lsp/transport/, then "
        "record the new hash and version in tests/osc2lsp/transport/test_pygls_contract.py"
    )


def test_every_override_of_a_pygls_method_is_recorded():
    unrecorded = sorted(set(overridden()) - set(OVERRIDDEN))
    assert not unrecorded, f"pygls methods overridden without a record: {unrecorded}"
    gone = sorted(set(OVERRIDDEN) - set(overridden()))
    assert not gone, f"recorded as overridden, no longer overridden (drop them): {gone}"


@pytest.mark.parametrize("name", sorted(OVERRIDDEN))
def test_an_overridden_pygls_method_is_the_one_we_read(name):
    problem = changed(name, OVERRIDDEN[name], overridden()[name])
    assert problem is None, problem


@pytest.mark.parametrize("name", sorted(RELIED_ON))
def test_a_pygls_method_we_rely_on_is_the_one_we_read(name):
    function, recorded = RELIED_ON[name]
    problem = changed(name, recorded, function)
    assert problem is None, problem


def test_the_private_attributes_the_overrides_read_exist():
    server = LanguageServer("contract", "1", protocol_cls=Osc2Protocol)
    protocol = server.protocol
    for attribute in (
        "_result_types",
        "_request_futures",
        "_shutdown",
        "_include_headers",
        "_converter",
        "_server",
        "fm",
        "writer",
    ):
        assert hasattr(protocol, attribute), f"pygls' protocol has no {attribute} any more"
    assert hasattr(server, "_stop_event"), "pygls' server has no _stop_event any more"
