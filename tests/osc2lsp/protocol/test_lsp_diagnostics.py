"""``textDocument/publishDiagnostics`` (VS Code) and ``textDocument/diagnostic`` (Neovim)."""

from __future__ import annotations

import pytest
from lsprotocol import types
from pytest_lsp import LanguageClient

from tests.osc2lsp.lsp_helpers import CONFLICT, REPO, seed_text
from tests.osc2lsp.protocol.lsp_session import (
    close_document,
    diagnostics,
    open_document,
    pulls,
    replace_text,
)

pytestmark = pytest.mark.asyncio(loop_scope="session")

TYPOS = (REPO / "examples" / "unsafe_typos.osc").read_text(encoding="utf-8")


async def test_diagnostics_have_the_checkers_codes_and_links(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, TYPOS)
    found = await diagnostics(client, doc_uri)
    assert {d.code for d in found} == {"T201", "A301", "N106", "N104"}
    unit = next(d for d in found if d.code == "N104")
    assert unit.message == "unknown unit `kmph2`; did you mean `kmph`?"
    assert unit.source == "osc2check"
    assert unit.severity == types.DiagnosticSeverity.Error
    assert unit.code_description.href.endswith("#n104-unknown-unit")
    assert unit.range.start == types.Position(line=13, character=20)
    assert unit.data["suggestion"] == "kmph"
    close_document(client, doc_uri)


async def test_diagnostics_carry_related_locations(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, "scenario twice:\n    x: int\n    x: int\n")
    found = await diagnostics(client, doc_uri)
    duplicate = next(d for d in found if d.code == "N102")
    assert duplicate.related_information
    assert duplicate.related_information[0].location.range.start.line == 1
    close_document(client, doc_uri)


async def test_diagnostics_follow_edits(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, TYPOS)
    assert await diagnostics(client, doc_uri)
    fixed = (
        TYPOS.replace("drvie", "drive")
        .replace("rigth", "right")
        .replace("kmph2", "kmph")
        .replace("20kph", "20m")
    )
    replace_text(client, doc_uri, fixed, 2)
    typos = {"T201", "A301", "N106", "N104"}
    found = await diagnostics(
        client, doc_uri, until=lambda ds: not any(d.code in typos for d in ds)
    )
    assert not any(d.code in typos for d in found)
    close_document(client, doc_uri)


async def test_diagnostics_of_the_seed_are_dialect_warnings(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, seed_text())
    found = await diagnostics(client, doc_uri)
    assert found and all(d.severity == types.DiagnosticSeverity.Warning for d in found)
    assert {d.code for d in found} >= {"D801", "D802", "D804", "D806"}
    close_document(client, doc_uri)


async def test_diagnostics_strict_setting_makes_dialect_forms_errors(
    client: LanguageClient, doc_uri
):
    open_document(client, doc_uri, seed_text())
    await diagnostics(client, doc_uri)
    try:
        client.workspace_did_change_configuration(
            types.DidChangeConfigurationParams(settings={"osc2": {"strict": True}})
        )
        found = await diagnostics(
            client,
            doc_uri,
            until=lambda ds: ds and all(d.severity == types.DiagnosticSeverity.Error for d in ds),
        )
        assert all(d.severity == types.DiagnosticSeverity.Error for d in found)
    finally:
        client.workspace_did_change_configuration(
            types.DidChangeConfigurationParams(settings={"osc2": {"strict": False}})
        )
    found = await diagnostics(
        client,
        doc_uri,
        until=lambda ds: ds and all(d.severity == types.DiagnosticSeverity.Warning for d in ds),
    )
    assert all(d.severity == types.DiagnosticSeverity.Warning for d in found)
    close_document(client, doc_uri)


async def test_diagnostics_recheck_an_importer_when_its_import_changes(
    client: LanguageClient, tmp_path
):
    lib = tmp_path / "lib.osc"
    main = tmp_path / "main.osc"
    lib_text = "actor robot\n"
    main_text = 'import "lib.osc"\n\nscenario s:\n    r: robot\n'
    lib.write_text(lib_text, encoding="utf-8")
    main.write_text(main_text, encoding="utf-8")
    open_document(client, lib.as_uri(), lib_text)
    open_document(client, main.as_uri(), main_text)
    assert await diagnostics(client, main.as_uri()) == []
    replace_text(client, lib.as_uri(), "actor droid\n", 2)
    found = await diagnostics(
        client, main.as_uri(), until=lambda ds: any(d.code == "N101" for d in ds)
    )
    assert [d.code for d in found] == ["N101"]
    close_document(client, main.as_uri())
    close_document(client, lib.as_uri())


async def test_diagnostics_are_cleared_when_a_document_closes(client: LanguageClient, doc_uri):
    if pulls(client):
        pytest.skip("a pulling client asks for diagnostics itself")
    open_document(client, doc_uri, TYPOS)
    assert await diagnostics(client, doc_uri)
    client.diagnostics.pop(doc_uri, None)
    close_document(client, doc_uri)
    assert await diagnostics(client, doc_uri) == []


async def test_diagnostics_of_a_document_that_does_not_parse(client: LanguageClient, doc_uri):
    open_document(client, doc_uri, "scenario s:\n    x: int = (1 +\n    do serial:\n")
    found = await diagnostics(client, doc_uri)
    assert any(d.code.startswith("P") for d in found)
    close_document(client, doc_uri)


@pytest.mark.slow
async def test_diagnostics_of_the_solver_follow_the_first_ones(client: LanguageClient, doc_uri):
    if pulls(client):
        pytest.skip("this client cannot be asked to pull again (no refresh support)")
    open_document(client, doc_uri, CONFLICT)
    found = await diagnostics(client, doc_uri, until=lambda ds: any(d.code == "C401" for d in ds))
    conflict = next(d for d in found if d.code == "C401")
    assert conflict.range.start.line == 6
    close_document(client, doc_uri)
