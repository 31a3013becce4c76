"""The language server object: the session it owns, the client's abilities, findings
published to the client and the client's settings applied.

The handlers (``server.py``) ask it for the current text and offsets; the
session (``osc2lsp.session``) hands it findings to publish; serving is
``transport.serving``.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any

from lsprotocol import types
from pygls.workspace.position_codec import PositionCodec

from osc2lsp import __version__, convert
from osc2lsp.options import Options, from_settings
from osc2lsp.session.documents import Findings
from osc2lsp.session.scheduler import State
from osc2lsp.text import LineIndex, key_to_uri, uri_to_key
from osc2lsp.transport.protocol import Osc2Protocol, converter
from osc2lsp.transport.serving import ServingLanguageServer

log = logging.getLogger(__name__)


class Osc2LanguageServer(ServingLanguageServer):
    """pygls server holding the open documents' state and the client's abilities."""

    def __init__(self) -> None:
        self.state = State(Options(), self.publish)
        super().__init__(
            self.state,
            "osc2lsp",
            __version__,
            protocol_cls=Osc2Protocol,
            converter_factory=converter,
        )
        self.pull = False  # the client pulls diagnostics (textDocument/diagnostic)
        self.refresh = False  # ... and accepts workspace/diagnostic/refresh
        self.configuration = False  # the client answers workspace/configuration

    @property
    def codec(self) -> PositionCodec:
        return self.workspace.position_codec

    @property
    def options(self) -> Options:
        return self.state.options

    def library(self, uri: str) -> bool:
        """Whether ``uri`` is an open file of the bundled library (read-only here)."""
        doc = self.state.documents.get(uri)
        return doc is not None and doc.library

    def uri_of(self, key: str) -> str:
        for doc in self.state.documents.values():
            if doc.key == key:
                return doc.uri
        return key_to_uri(key)

    def current(self, uri: str) -> tuple[str, LineIndex]:
        """The document's text now and its lines (a closed file is read from disk; an
        unknown one is empty)."""
        doc = self.state.documents.get(uri)
        if doc is not None:
            return doc.text, doc.lines
        if not uri.startswith("file:"):
            return "", LineIndex("")
        try:
            text = Path(uri_to_key(uri)).read_text(encoding="utf-8", errors="replace")
        except OSError:
            text = ""
        return text, LineIndex(text)

    def offset(self, lines: LineIndex, position: types.Position) -> int:
        return convert.from_lsp_position(lines, position, self.codec)

    def publish(self, trigger: str, found: list[Findings]) -> None:
        """Send findings the client does not have: pushed, or a refresh request to a
        pulling client that holds older ones (its own document's next version it pulls
        by itself)."""
        if self.pull:
            if self.refresh and any(self._outdated(f, trigger) for f in found):
                self.workspace_diagnostic_refresh(None)
            return
        for f in found:
            items = convert.to_lsp_diagnostics(
                f.lines_of, f.diagnostics, self.uri_of, self.codec, self.options.docs_url
            )
            self.text_document_publish_diagnostics(
                types.PublishDiagnosticsParams(uri=f.uri, diagnostics=items, version=f.version)
            )
            self.state.pushed(f)

    def _outdated(self, found: Findings, trigger: str) -> bool:
        """Whether a pulling client holds other findings for ``found``'s version."""
        if not found.final:
            return False
        doc = self.state.documents.get(found.uri)
        pulled = doc.delivered if doc is not None else None
        return (
            found.uri != trigger
            or found.verified
            or (pulled is not None and pulled[0] == found.version)
        )

    def configure(self, settings: Any, refresh: bool = True) -> None:
        """Apply the client's `osc2` settings; re-check every document (and ask the
        client to re-request inlay hints when ``refresh`` and they changed)."""
        log.debug("settings: %r", settings)
        previous = self.options
        options, problems = from_settings(settings, previous)
        for problem in problems:
            self.window_show_message(
                types.ShowMessageParams(
                    type=types.MessageType.Warning, message=f"osc2lsp: {problem}"
                )
            )
        self.state.reconfigure(options)
        workspace = self.client_capabilities.workspace
        if (
            refresh
            and options.inlay_hints != previous.inlay_hints
            and workspace
            and workspace.inlay_hint
            and workspace.inlay_hint.refresh_support
        ):
            self.workspace_inlay_hint_refresh(None)
