"""Helpers of the protocol tests: open, change and close documents, wait for
diagnostics (pushed or pulled), positions in the client's encoding."""

from __future__ import annotations

import asyncio

from lsprotocol import types
from pytest_lsp import LanguageClient

#: guards against a hang only: an answer takes seconds, minutes on a loaded machine
TIMEOUT = 300


def pulls(client: LanguageClient) -> bool:
    caps = client.capabilities
    return bool(caps and caps.text_document and caps.text_document.diagnostic is not None)


def open_document(client: LanguageClient, uri: str, text: str, version: int = 1) -> None:
    client.diagnostics.pop(uri, None)
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            text_document=types.TextDocumentItem(
                uri=uri, language_id="osc2", version=version, text=text
            )
        )
    )


def close_document(client: LanguageClient, uri: str) -> None:
    client.text_document_did_close(
        types.DidCloseTextDocumentParams(text_document=types.TextDocumentIdentifier(uri=uri))
    )


def replace_text(client: LanguageClient, uri: str, text: str, version: int) -> None:
    """Replace the whole text with an incremental change (every client supports that)."""
    client.diagnostics.pop(uri, None)
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            content_changes=[types.TextDocumentContentChangeWholeDocument(text=text)],
        )
    )


async def diagnostics(client: LanguageClient, uri: str, until=None) -> list[types.Diagnostic]:
    """The document's diagnostics: pulled, or the next push (that satisfies ``until``)."""
    if pulls(client):
        # A pull answers for the current version at once; a setting sent just before may
        # not have been applied yet, so ask again (a bounded number of times) until it is.
        for _ in range(200):
            report = await asyncio.wait_for(
                client.text_document_diagnostic_async(
                    types.DocumentDiagnosticParams(
                        text_document=types.TextDocumentIdentifier(uri=uri)
                    )
                ),
                TIMEOUT,
            )
            items = list(report.items)
            if until is None or until(items):
                break
        return items

    async def pushed():
        # the client stores each push as it arrives; polling it leaves no future behind in
        # the client's protocol (pytest-lsp sets the result of a notification's future that
        # a timeout cancelled, which stops the client shared by every later test)
        while True:
            found = client.diagnostics.get(uri)
            if found is not None and (until is None or until(found)):
                return list(found)
            await asyncio.sleep(0.01)

    return await asyncio.wait_for(pushed(), TIMEOUT)


def position(text: str, offset: int, client: LanguageClient | None = None) -> types.Position:
    """The LSP position of a code-point offset, in the client's position encoding."""
    line = text.count("\n", 0, offset)
    start = text.rfind("\n", 0, offset) + 1
    before = text[start:offset]
    encoding = _encoding(client)
    if encoding == "utf-8":
        character = len(before.encode("utf-8"))
    elif encoding == "utf-32":
        character = len(before)
    else:
        character = len(before.encode("utf-16-le")) // 2
    return types.Position(line=line, character=character)


def _encoding(client: LanguageClient | None) -> str:
    caps = client.capabilities if client is not None else None
    encodings = caps.general.position_encodings if caps and caps.general else None
    for encoding in encodings or ():
        if encoding in ("utf-8", "utf-16", "utf-32"):
            return str(encoding)
    return "utf-16"


def text_document(uri: str) -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(uri=uri)


def internal_errors(client: LanguageClient) -> list[str]:
    """Errors the server's guard reported to the client's log."""
    return [m.message for m in client.log_messages if "internal error" in m.message]
