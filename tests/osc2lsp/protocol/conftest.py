"""A pytest-lsp client connected to ``python -m osc2lsp``, once per session for each of
the VS Code and Neovim capability sets (every protocol test runs with both)."""

from __future__ import annotations

import os
import sys

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient, client_capabilities

from tests.osc2lsp.lsp_helpers import REPO
from tests.osc2lsp.protocol.lsp_session import internal_errors

CLIENTS = ["visual-studio-code", "neovim"]


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(REPO), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env


@pytest_lsp.fixture(
    scope="session",
    params=CLIENTS,
    config=ClientServerConfig(server_command=[sys.executable, "-m", "osc2lsp"], server_env=_env()),
)
async def client(lsp_client: LanguageClient, request):
    @lsp_client.feature(types.WORKSPACE_INLAY_HINT_REFRESH)
    def inlay_hint_refresh(params):  # Neovim asks for hints again; the test client needn't
        return None

    params = types.InitializeParams(
        capabilities=client_capabilities(request.param),
        root_uri=REPO.as_uri(),
        initialization_options={
            "osc2": {"diagnostics": {"debounce": 10}, "inlayHints": {"enabled": True}}
        },
    )
    lsp_client.initialize_result = await lsp_client.initialize_session(params)
    yield
    errors = internal_errors(lsp_client)
    await lsp_client.shutdown_session()
    assert errors == [], "a handler failed (its guard logged it); see the server's stderr"


@pytest.fixture
def doc_uri(request) -> str:
    """A document URI of its own for each test (the server session is shared)."""
    name = "".join(ch if ch.isalnum() else "_" for ch in request.node.name)
    return f"file:///tmp/osc2lsp-tests/{name}.osc"
