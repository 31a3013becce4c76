"""The output README quotes is the runner's output now (a snapshot that fails on drift).

README's set-up command is run as written, its summary compared with the block
README shows: every line but the wall time and real-time factor, which depend on
the machine and are shown as ``…`` (docs/runner.md's *Measured* gives measured
figures). ``OSC2_UPDATE_DOCS=1`` rewrites the block.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from osc2runner.cli import main
from tests.docs_blocks import ROOT, check_block

COMMAND = ["osc2run", "examples/cut_in_and_stop.osc", "--out", "out", "--plot"]


def normalized(output: str) -> str:
    """The output with the machine's figures (wall time, real-time factor) left out."""
    return re.sub(
        r"wall time \(this machine\): [0-9.]+ s(, [0-9]+x real time)?",
        "wall time (this machine): … s, …x real time",
        output,
    )


@pytest.mark.slow
def test_readme_quotes_what_the_set_up_command_prints(tmp_path: Path, monkeypatch, capsys) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    assert main(COMMAND[1:]) == 0
    output = normalized(capsys.readouterr().out)
    assert "…x real time" in output
    check_block(ROOT / "README.md", "cut-in-output", "```text\n" + output + "```")
