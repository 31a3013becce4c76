"""CARLA scenario_runner's dialect on a hand-written CARLA-style file (tests/data/
carla_style): every form is a warning with its own D code, the file runs as CARLA
means it, and `osc2check migrate` writes standard OSC2 that runs the same.

CARLA's own 17 examples are tested in ../end_to_end/test_carla_examples.py (OSC2_THIRD_PARTY)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from osc2check.analysis import SourceInput, analyze
from osc2check.cli import main as check_main
from osc2check.config import Config
from osc2check.diagnostics import Severity
from osc2check.dialects.migrate import migrate
from osc2check.dialects.rewrite import Edit, apply_edits
from osc2runner import run

FILE = Path(__file__).resolve().parents[2] / "data" / "carla_style" / "cut_in.osc"
TEXT = FILE.read_text(encoding="utf-8")


def findings(text: str = TEXT, **config: object) -> list:
    options = Config(**config).analysis_options()  # type: ignore[arg-type]
    return analyze([SourceInput(str(FILE), text)], options).diagnostics


def test_every_carla_form_is_a_warning_with_its_own_d_code():
    found = findings()
    assert {d.severity for d in found} == {Severity.WARNING}
    assert {d.code.code for d in found} == {
        "D807", "D811", "D815", "D816", "D817", "D818", "D820", "D821", "D831",
    }  # fmt: skip
    strict = findings(strict=True)
    assert {d.severity for d in strict} == {Severity.ERROR}


def test_findings_point_at_the_forms_as_written():
    lines = TEXT.splitlines()
    for d in findings():
        written = lines[d.span.line - 1][d.span.column - 1 : d.span.end_column - 1]
        if d.code.code == "D817":  # the arguments CARLA gives drive
            assert written.startswith("path")
        if d.code.code == "D811":
            assert written == "basic.osc"
        if d.code.code == "D807":
            assert written == "right_of"


def test_the_standard_dialect_reads_the_file_as_written():
    codes = {d.code.code for d in findings(dialect="standard")}
    assert "N105" in codes  # there is no basic.osc to import


def test_the_cut_in_runs_as_carla_means(tmp_path):
    result = run(FILE, out=tmp_path)
    assert result.outcome.status == "success", result.outcome.reason
    ego, npc = result.telemetry["ego_vehicle"], result.telemetry["npc"]
    # lane(1) is the leftmost of Town04's four lanes (telemetry counts from the right)
    assert ego["lane"][0] == 4 and npc["lane"][0] == 3  # the npc starts right of the ego
    assert npc["x"][0] < ego["x"][0]  # behind it
    get_ahead = int(20.0 / 0.05)
    assert npc["x"][get_ahead] - ego["x"][get_ahead] > 20.0  # ahead when the phase ends
    assert npc["lane"][-1] == ego["lane"][-1] == 4  # and then in the ego's lane: a cut-in
    assert np.all(npc["x"][-1] > ego["x"][-1])
    assert result.metadata["map"]["name"] == "Town04"
    assert result.metadata["actors"]["ego_vehicle"]["model"] == "vehicle.tesla.model3"
    assert result.metadata["actors"]["npc"]["model"] == "vehicle.jeep.wrangler_rubicon"


def test_migrate_writes_standard_osc2_that_runs_the_same(tmp_path):
    migrated = migrate(TEXT, str(FILE))
    assert migrated.dialect == "carla" and migrated.changed
    assert "import osc2toolkit.carla\n" in migrated.text and "import basic" not in migrated.text
    standard = tmp_path / "cut_in.osc"
    standard.write_text(migrated.text, encoding="utf-8")
    assert findings(migrated.text, dialect="standard") == []
    first = run(FILE, out=tmp_path / "carla")
    second = run(standard, out=tmp_path / "standard", config=Config(dialect="standard"))
    assert (tmp_path / "carla" / "telemetry.csv").read_bytes() == (
        tmp_path / "standard" / "telemetry.csv"
    ).read_bytes()
    assert first.outcome.status == second.outcome.status


def test_the_migrate_command_prints_or_writes(tmp_path, capsys):
    assert check_main(["migrate", str(FILE)]) == 0
    out, err = capsys.readouterr()
    assert out == migrate(TEXT, str(FILE)).text
    assert "D820 rewritten" in err
    assert check_main(["migrate", str(FILE), "--out", str(tmp_path)]) == 0
    assert (tmp_path / "cut_in.osc").read_text() == out
    plain = tmp_path / "plain.osc"
    plain.write_text("scenario s:\n    do serial:\n        emit end\n")
    assert check_main(["migrate", str(plain)]) == 0
    assert capsys.readouterr().out == plain.read_text()  # not CARLA's: unchanged


@pytest.mark.parametrize(
    ("edits", "offset", "end", "expected"),
    [
        ([Edit(2, 4, "XYZW")], 1, False, 1),  # before the edit
        ([Edit(2, 4, "XYZW")], 3, False, 2),  # inside the new text: the start it replaced
        ([Edit(2, 4, "XYZW")], 6, True, 4),  # the end of the new text: the end it replaced
        ([Edit(2, 4, "XYZW")], 7, False, 5),  # after: shifted back
        ([Edit(0, 0, "ab\n"), Edit(5, 6, "")], 8, False, 6),  # an insertion and a deletion
    ],
)
def test_positions_in_the_edited_text_map_back(edits, offset, end, expected):
    _, offsets = apply_edits("0123456789", edits)
    assert offsets.original(offset, end=end) == expected
