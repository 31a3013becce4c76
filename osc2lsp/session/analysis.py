"""Snapshots of documents: the checker's analysis of their texts, one call."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from osc2check.config import Config
from osc2lsp.text import uri_to_key

if TYPE_CHECKING:
    from osc2check.syntax import ParseResult
    from osc2lsp.snapshot import Snapshot


def analyse(
    documents: list[tuple[str, str, int | None]],
    config: Any = None,
    verify: bool = True,
    parses: Mapping[str, ParseResult] | None = None,
) -> dict[str, Snapshot]:
    """Analyse documents given as ``(uri, text, version)``; a snapshot for each.

    Without ``verify`` the solver's checks (C, L and B codes) are left out.
    ``parses`` has parses of documents' texts by uri, to use instead of parsing.
    """
    # imported on first use: the analysis and the snapshot (163 ms measured after
    # osc2lsp.server) are not needed to answer `initialize`
    from osc2check.analysis import SourceInput, analyze
    from osc2lsp.snapshot import Snapshot

    keys = {uri: uri_to_key(uri) for uri, _, _ in documents}
    given = parses or {}
    inputs = [SourceInput(keys[uri], text, parse=given.get(uri)) for uri, text, _ in documents]
    config = config if config is not None else Config()
    # the budget is an address-space limit of the whole process: the server's own would
    # bound its transport too, so only the solver worker, a process of its own, has it
    analysis = analyze(inputs, config.analysis_options(verify=verify, memory_limit_mib=None))
    return {
        uri: Snapshot(uri, keys[uri], version, text, analysis, config, verify)
        for uri, text, version in documents
    }


def snapshot_of(
    text: str,
    uri: str = "file:///tmp/osc2lsp/document.osc",
    version: int | None = 1,
    config: Any = None,
) -> Snapshot:
    """A snapshot of one text (for tests and scripts)."""
    return analyse([(uri, text, version)], config)[uri]
