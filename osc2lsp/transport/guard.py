"""One guard for every handler: no exception escapes to the client as a failure.

A handler's exception is logged, reported to the client's log, and answered with
an empty result; expected refusals and invalid params (``JsonRpcException``) and
cancellations go on to the protocol, which answers them as errors.
"""

from __future__ import annotations

import asyncio
import functools
import logging
from collections.abc import Callable
from typing import Any, TypeVar

from lsprotocol import types
from pygls.exceptions import JsonRpcException
from pygls.lsp.server import LanguageServer

log = logging.getLogger(__name__)

H = TypeVar("H", bound=Callable[..., Any])


def guarded(default: Any = None) -> Callable[[H], H]:
    """Log any exception of a handler and answer ``default()`` (or ``default``)."""

    def empty() -> Any:
        return default() if callable(default) else default

    def wrap(fn: H) -> H:
        def report(ls: LanguageServer) -> None:
            log.exception("%s failed", fn.__name__)
            try:
                ls.window_log_message(
                    types.LogMessageParams(
                        type=types.MessageType.Error,
                        message=f"osc2lsp: internal error in {fn.__name__} (see the server log)",
                    )
                )
            except Exception:  # the transport itself may be gone
                pass

        if asyncio.iscoroutinefunction(fn):

            @functools.wraps(fn)
            async def run_async(ls: LanguageServer, params: Any) -> Any:
                try:
                    return await fn(ls, params)
                except (asyncio.CancelledError, JsonRpcException):
                    raise
                except Exception:
                    report(ls)
                    return empty()

            return run_async  # type: ignore[return-value]

        @functools.wraps(fn)
        def run(ls: LanguageServer, params: Any) -> Any:
            try:
                return fn(ls, params)
            except JsonRpcException:
                raise
            except Exception:
                report(ls)
                return empty()

        return run  # type: ignore[return-value]

    return wrap
