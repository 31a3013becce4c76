"""The one guard around every handler: log, tell the client's log, answer empty."""

from __future__ import annotations

import asyncio
import logging

from osc2lsp.transport.guard import guarded


class _Client:
    def __init__(self):
        self.logged = []

    def window_log_message(self, params):
        self.logged.append(params.message)


def test_a_failing_handler_answers_its_default_and_logs(caplog):
    @guarded(list)
    def broken(ls, params):
        raise ValueError("boom")

    client = _Client()
    with caplog.at_level(logging.ERROR, logger="osc2lsp.server"):
        assert broken(client, None) == []
    assert "broken failed" in caplog.text
    assert client.logged == ["osc2lsp: internal error in broken (see the server log)"]


def test_a_failing_async_handler_answers_none():
    @guarded()
    async def broken(ls, params):
        raise KeyError("boom")

    assert asyncio.run(broken(_Client(), None)) is None


def test_a_working_handler_is_untouched():
    @guarded(list)
    def fine(ls, params):
        return [params]

    assert fine(_Client(), 1) == [1]
