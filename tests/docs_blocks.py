"""Text in the docs that the tools produce: blocks a test writes and checks.

A Markdown file marks a generated block with two HTML comments::

    <!-- generated: cut-in-output (tests/osc2runner/test_docs_output.py) -->
    ...
    <!-- end: cut-in-output -->

:func:`check_block` asserts the block's text equals what the test produced now, so
a change that moves a quoted figure fails until the docs say the new one; with
``OSC2_UPDATE_DOCS=1`` it writes the text instead (then review the diff).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def check_block(doc: Path, name: str, text: str) -> None:
    """The block ``name`` of ``doc`` is ``text`` (see the module docstring)."""
    source = doc.read_text(encoding="utf-8")
    pattern = re.compile(
        rf"(<!-- generated: {re.escape(name)} [^\n]*-->\n)(.*?)(<!-- end: {re.escape(name)} -->)",
        re.DOTALL,
    )
    found = pattern.search(source)
    assert found is not None, f"{doc.name} has no generated block `{name}`"
    body = text if text.endswith("\n") else text + "\n"
    if os.environ.get("OSC2_UPDATE_DOCS"):
        updated = source[: found.start(2)] + body + source[found.end(2) :]
        doc.write_text(updated, encoding="utf-8")
        return
    assert found.group(2) == body, (
        f"{doc.relative_to(ROOT)}: block `{name}` is not what the runner gives now; "
        "OSC2_UPDATE_DOCS=1 rewrites it"
    )
