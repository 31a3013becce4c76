"""References and rename reach into the workspace's closed files: they are found and read
as ``osc2check`` finds and reads them, off the event loop. A FIFO named ``*.osc`` froze
the server (opened for reading on the event loop); a ``*.osc`` link to ``/dev/zero`` was
read until memory ran out."""

from __future__ import annotations

import os
import sys

import pytest

from osc2check.inputs import MAX_SOURCE_BYTES
from tests.osc2lsp.protocol.raw_client import RawClient

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="FIFOs, /dev/zero")

LIBRARY = "actor robot\n"
USER = 'import "lib.osc"\nscenario u:\n    r: robot\n'


def test_references_skip_fifos_devices_and_files_over_the_size_cap(tmp_path):
    (tmp_path / "lib.osc").write_text(LIBRARY, encoding="utf-8")
    (tmp_path / "user.osc").write_text(USER, encoding="utf-8")
    os.mkfifo(tmp_path / "pipe.osc")  # opened for reading, it blocks until a writer comes
    (tmp_path / "zero.osc").symlink_to("/dev/zero")  # never ends
    with open(tmp_path / "huge.osc", "wb") as huge:  # sparse: no disk used
        huge.truncate(MAX_SOURCE_BYTES + 1)
    (tmp_path / "later.osc").write_text(USER.replace("u:", "later:"), encoding="utf-8")
    client = RawClient(tmp_path / "stderr.log", settings={"verify": False})
    try:
        client.initialize(rootUri=tmp_path.as_uri())
        uri = (tmp_path / "lib.osc").as_uri()
        client.open(uri, LIBRARY)
        client.diagnostics(uri, 1)
        asked = client.request(
            "textDocument/references",
            {
                "textDocument": {"uri": uri},
                "position": {"line": 0, "character": 7},
                "context": {"includeDeclaration": False},
            },
        )
        found = client.response(asked)["result"]
        assert sorted(loc["uri"].rsplit("/", 1)[-1] for loc in found) == ["later.osc", "user.osc"]
        assert "result" in client.call("shutdown")
    finally:
        client.close()
