"""The JSON-RPC side of the server: reading frames, checking params, answering errors.

pygls' ``LanguageServerProtocol`` does the dispatching; this subclass changes
what it does wrong for an editor that must never lose its server:

* **Frames** are read by ``framing.FrameReader`` (``serving.py``), on stdio and
  on ``--tcp`` alike, which re-synchronises after a frame with a wrong
  ``Content-Length`` (pygls' reader stays silent forever).
* **Invalid params** of a request are answered with ``-32602`` (pygls logs the
  error and never answers, so the client waits forever); a value of the wrong
  JSON type (``"newName": null``, a number for a URI) is invalid instead of
  being turned into the string ``"None"``.
* **After ``shutdown``** every request is answered with ``-32600`` (pygls drops
  them, again leaving the client waiting); notifications other than ``exit``
  are ignored.
* **Refusals** (``Refusal``: a rename of a library name, a keyword as new name)
  are answered with their message and logged at info level, without the
  traceback pygls logs for any exception of a handler.
* **Documents** are kept by ``osc2lsp.session`` with LSP's line semantics, so the
  built-in document handlers no longer update pygls' own copy (which splits
  lines with ``str.splitlines()``).
"""

from __future__ import annotations

import asyncio
import inspect
import json
import logging
import re
from collections.abc import Callable, Generator
from concurrent.futures import Future
from typing import TYPE_CHECKING, Any

from cattrs.errors import ClassValidationError, IterableValidationError
from cattrs.v import format_exception, transform_error
from lsprotocol import types
from pygls.exceptions import (
    JsonRpcException,
    JsonRpcInternalError,
    JsonRpcInvalidParams,
    JsonRpcInvalidRequest,
    JsonRpcParseError,
)
from pygls.protocol import LanguageServerProtocol, default_converter
from pygls.protocol.json_rpc import (
    JsonRPCNotification,
    JsonRPCRequestMessage,
    JsonRPCResponseMessage,
)
from pygls.protocol.language_server import lsp_method

from osc2lsp.transport.framing import Garbled

if TYPE_CHECKING:
    from cattrs import Converter

log = logging.getLogger(__name__)

REQUEST_FAILED = -32803


class Refusal(JsonRpcException):
    """An expected refusal (shown to the user), not a failure of the server."""

    CODE = REQUEST_FAILED


class InvalidParams(JsonRpcInvalidParams):
    """Params that are well-formed JSON but not what the method takes."""


# ---- params of the right JSON type ----------------------------------------------------


def _strict(kind: type, name: str) -> Callable[[Any, Any], Any]:
    def structure(value: Any, _: Any) -> Any:
        if isinstance(value, kind) and not (kind is int and isinstance(value, bool)):
            return value
        raise TypeError(f"expected {name}, got {_json_type(value)}")

    return structure


def _json_type(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "an array"
    return "an object"


def converter() -> Converter:
    """pygls' converter, but a string, an integer or a boolean must be one in the JSON.

    cattrs' defaults call ``str(value)``, ``int(value)`` and ``bool(value)``: a
    ``null`` new name became the name ``"None"``, the string ``"false"`` became
    true.
    """
    conv: Converter = default_converter()  # type: ignore[no-untyped-call]  # pygls: unannotated
    conv.register_structure_hook(str, _strict(str, "a string"))
    conv.register_structure_hook(int, _strict(int, "an integer"))
    conv.register_structure_hook(bool, _strict(bool, "a boolean"))
    return conv


def _problems(exc: BaseException) -> str:
    """What is wrong with the params, one ``<what> at <where>`` per problem."""
    if isinstance(exc, (ClassValidationError, IterableValidationError)):

        def describe(error: BaseException, kind: Any) -> str:
            return str(error) if isinstance(error, TypeError) else format_exception(error, kind)

        try:
            found = transform_error(exc, path="$", format_exception=describe)
        except Exception:  # a nesting cattrs cannot describe
            return str(exc)
        return "; ".join(_camel(problem).replace(" @ $.", " at ") for problem in found)
    return str(exc)


def _camel(text: str) -> str:
    """``params.new_name`` as the JSON spells it: ``params.newName``."""
    return re.sub(r"(?<=[a-z0-9])_([a-z])", lambda m: m.group(1).upper(), text)


# ---- the protocol -------------------------------------------------------------------


class Osc2Protocol(LanguageServerProtocol):
    """pygls' protocol with checked params, answers after shutdown and quiet refusals."""

    def structure_message(self, data: dict[str, Any]) -> Any:
        """A message from its JSON (the whole message: nested objects are left to cattrs).

        As pygls' own, without its error log and traceback for a client's mistake.
        """
        if "jsonrpc" not in data:
            return data
        method = data.get("method")
        if "id" in data and "error" in data:
            kind: Any = types.ResponseErrorMessage
        elif "id" in data and method is None:
            kind = self._result_types.pop(data["id"], None) or JsonRPCResponseMessage
        elif "id" in data:
            kind = self.get_message_type(method) or JsonRPCRequestMessage
        else:
            kind = self.get_message_type(method or "") or JsonRPCNotification
        try:
            return self._converter.structure(data, kind)
        except Exception as exc:
            raise InvalidParams(f"invalid params of {method!r}: {_problems(exc)}") from None

    def dispatch(self, data: Any) -> None:
        """Handle one parsed JSON message; malformed ones are answered when they can be."""
        if not isinstance(data, dict):
            log.warning("ignoring a JSON-RPC message that is not an object: %.200r", data)
            self._send_error(None, JsonRpcInvalidRequest("a message must be a JSON object"))
            return
        if "id" in data and not _valid_id(data["id"]):
            log.warning("ignoring a JSON-RPC message whose id is %.200r", data["id"])
            self._send_error(None, JsonRpcInvalidRequest("an id must be a string or a number"))
            return
        try:
            message = self.structure_message(data)
        except JsonRpcException as exc:
            request = "id" in data and "method" in data
            log.warning("%s%s", exc.message, "" if request else " (a notification: not answered)")
            if request:
                self._send_error(data["id"], exc)
            return
        self.handle_message(message)

    def garbled(self, event: Garbled) -> None:
        if event.too_large:
            log.error("skipped %s; reading on from the next frame", event.reason)
            self._send_error(None, JsonRpcInvalidRequest(f"skipped {event.reason}"))
            self._send_data(
                {
                    "jsonrpc": "2.0",
                    "method": types.WINDOW_SHOW_MESSAGE,
                    "params": {
                        "type": types.MessageType.Error.value,
                        "message": f"osc2lsp: skipped {event.reason}; a document it changed "
                        "may be out of date until it is opened again",
                    },
                }
            )
            return
        log.warning(
            "skipped %s (%d bytes); reading on from the next frame", event.reason, event.size
        )
        if "not JSON" in event.reason:
            self._send_error(None, JsonRpcParseError("a frame whose body is not JSON"))

    def _send_data(self, data: Any) -> None:
        """As pygls' own, without logging each body and with a broken pipe logged once,
        without a traceback (the client left)."""
        if not data:
            return
        if self.writer is None:
            log.error("no transport to send data to")
            return
        body = json.dumps(data, default=self._serialize_message)
        if self._include_headers:
            body = (
                f"Content-Length: {len(body)}\r\n"
                f"Content-Type: {self.CONTENT_TYPE}; charset={self.CHARSET}\r\n\r\n" + body
            )
        try:
            result = self.writer.write(body.encode(self.CHARSET))
            if inspect.isawaitable(result):
                asyncio.ensure_future(result)
        except BrokenPipeError:
            log.error("the client closed the connection")
            raise
        except Exception as error:
            log.exception("sending data failed")
            self._server._report_server_error(error, JsonRpcInternalError)

    def _send_error(self, msg_id: Any, error: JsonRpcException) -> None:
        """An error answer; ``"id": null`` when the id is unknown (JSON-RPC 2.0 wants
        the member present, and lsprotocol's converter leaves a None out)."""
        self._send_data(
            {
                "jsonrpc": "2.0",
                "id": msg_id if _valid_id(msg_id) else None,
                "error": {"code": error.code, "message": error.message},
            }
        )

    def handle_message(self, message: Any) -> None:
        if self._shutdown and getattr(message, "method", None) not in (None, types.EXIT):
            if hasattr(message, "id"):
                log.info("request %r after shutdown: refused", message.method)
                self._send_error(message.id, JsonRpcInvalidRequest("the server is shutting down"))
            return
        super().handle_message(message)

    def _send_handler_result(self, future: Future[Any], *, msg_id: Any) -> None:
        if not future.cancelled():
            exc = future.exception()
            if isinstance(exc, (Refusal, InvalidParams)):
                self._request_futures.pop(msg_id, None)
                log.info("request %s refused: %s", msg_id, exc.message)
                self._send_response(msg_id, error=exc.to_response_error())
                return
        super()._send_handler_result(future, msg_id=msg_id)

    # ---- documents: kept by osc2lsp.session, not by pygls' workspace --------------------

    @lsp_method(types.TEXT_DOCUMENT_DID_OPEN)
    def lsp_text_document__did_open(self, params: Any) -> Generator[Any, Any, None]:
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_OPEN)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_CHANGE)
    def lsp_text_document__did_change(self, params: Any) -> Generator[Any, Any, None]:
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CHANGE)) is not None:
            yield handler, (params,), None

    @lsp_method(types.TEXT_DOCUMENT_DID_CLOSE)
    def lsp_text_document__did_close(self, params: Any) -> Generator[Any, Any, None]:
        if (handler := self.fm.features.get(types.TEXT_DOCUMENT_DID_CLOSE)) is not None:
            yield handler, (params,), None


def _valid_id(value: Any) -> bool:
    """Whether ``value`` can be a request's id (a string or a number, not a boolean)."""
    return isinstance(value, (str, int, float)) and not isinstance(value, bool)


__all__ = [
    "InvalidParams",
    "Osc2Protocol",
    "REQUEST_FAILED",
    "Refusal",
    "converter",
]
