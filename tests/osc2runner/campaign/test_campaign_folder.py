"""A campaign folder is data, never code (``osc2runner.campaign.schema``).

It used to be trusted: ``--resume DIR`` imported the system under test its
``campaign.json`` named (and its "same options" check compared the file with itself); a
``record.json`` with markup in its status went raw into ``report.html``, its ``folder``
could point the report outside the campaign; ``--out`` on a folder of other files wrote
over them and linked a stray ``runs/0/myplot.png`` as a plot; a ``campaign.json`` of the
wrong shape was a traceback; a NaN KPI left ``campaign.json`` "running"; a reason
beginning with ``=`` went raw into ``runs.csv``. A seeded storm of damaged folders ends,
every time, in records that hold what a run writes or in a clear error.
"""

from __future__ import annotations

import contextlib
import copy
import csv
import io
import json
import random
import re
import shutil
from html.parser import HTMLParser
from pathlib import Path

import pytest

from osc2runner.campaign import CampaignOptions, run_campaign
from osc2runner.campaign.outputs import read_campaign, read_records, write_runs_csv
from osc2runner.campaign.schema import STATUSES, FolderError, file_name
from osc2runner.cli import main
from osc2runner.sut.loading import SutSpec

SHORT = """\
import osc.standard

scenario short:
    ego: vehicle
    do ego.drive(duration: 1s) with:
        speed(30kph)
"""
PASS = "class Pass:\n    def step(self, obs):\n        return obs.driver\n"
EVIL = 'import pathlib\npathlib.Path(__file__).with_name("IMPORTED").write_text("yes")\n' + PASS


@pytest.fixture(scope="module")
def made(tmp_path_factory) -> Path:
    """A finished campaign of two runs with a system under test (made once)."""
    base = tmp_path_factory.mktemp("made")
    (base / "short.osc").write_text(SHORT, encoding="utf-8")
    (base / "pass.py").write_text(PASS, encoding="utf-8")
    result = run_campaign(
        CampaignOptions(
            str(base / "short.osc"),
            runs=2,
            out=str(base / "campaign"),
            jobs=1,
            sut=SutSpec(f"{base / 'pass.py'}:Pass").resolved(),
        )
    )
    assert result.status == "complete" and result.summary["passed"] == 2
    return base


@pytest.fixture
def folder(made, tmp_path) -> Path:
    """A copy of the finished campaign (with its scenario and SUT) to damage."""
    for name in ("short.osc", "pass.py"):
        shutil.copy(made / name, tmp_path / name)
    shutil.copytree(made / "campaign", tmp_path / "campaign")
    text = (tmp_path / "campaign" / "campaign.json").read_text().replace(str(made), str(tmp_path))
    (tmp_path / "campaign" / "campaign.json").write_text(text)
    return tmp_path / "campaign"


def _edit(path: Path, change) -> None:
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))


def _main(*argv: str) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main(list(argv))
    return status, err.getvalue()


# ---- --resume: the SUT comes from the command line ------------------------------------------


def test_resume_never_imports_the_sut_the_folder_names(folder):
    evil = folder.parent / "evil.py"
    evil.write_text(EVIL, encoding="utf-8")
    _edit(folder / "campaign.json", lambda d: d["options"]["sut"].update(target=f"{evil}:Pass"))
    status, err = _main("--resume", str(folder), "-q")
    assert status == 2 and not (folder.parent / "IMPORTED").exists()
    assert f"`{evil}:Pass`" in err and "--trust-folder" in err and "Traceback" not in err
    # the command line names another SUT: the folder's is compared, never imported
    status, err = _main("--resume", str(folder), "--sut", f"{folder.parent / 'pass.py'}:Pass")
    assert status == 2 and "other options (sut)" in err
    assert not (folder.parent / "IMPORTED").exists()
    # the user trusts the folder: it says what it imports
    status, err = _main("--resume", str(folder), "--trust-folder", "-q")
    assert status == 0 and (folder.parent / "IMPORTED").exists()
    assert f"--trust-folder: importing the system under test `{evil}:Pass`" in err


def test_resume_with_the_same_sut_keeps_the_finished_runs(folder):
    status, err = _main("--resume", str(folder), "--sut", f"{folder.parent / 'pass.py'}:Pass")
    assert status == 0, err
    assert json.loads((folder / "campaign.json").read_text())["plan"]["resumed"] == [0, 1]


@pytest.mark.parametrize(
    ("damage", "says"),
    [
        (lambda d: d.clear(), "campaign.json.format"),
        (lambda d: d["options"].update(sut=5), "campaign.json.options.sut: not an object"),
        (lambda d: d["options"].update(seed=-1), "options.seed: not a whole number"),
        (lambda d: d["options"].update(dt_control="fast"), "options.dt_control: not a number"),
        (lambda d: d["plan"].update(seeds=["x"]), "plan.seeds[0]: not a whole number"),
        (lambda d: d.update(source_sha256="<b>"), "source_sha256: not a SHA-256"),
    ],
)
def test_a_campaign_json_of_another_shape_is_a_clear_error(folder, damage, says):
    _edit(folder / "campaign.json", damage)
    status, err = _main("--resume", str(folder), "--sut", f"{folder.parent / 'pass.py'}:Pass")
    assert status == 2 and says in err, err
    assert err.startswith("osc2run: error: --resume") and "Traceback" not in err


def test_a_campaign_json_that_is_no_object_is_a_clear_error(folder):
    (folder / "campaign.json").write_text("[]")
    status, err = _main("--resume", str(folder))
    assert status == 2 and "campaign.json: not an object" in err


# ---- record.json: checked, then escaped ---------------------------------------------------


class _Page(HTMLParser):
    """The tags and links of a page."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[str] = []
        self.links: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        self.links += [v for k, v in attrs if k in ("href", "src") and v]


def test_records_are_checked_and_what_they_say_is_escaped(folder):
    def markup(d):
        d["outcome"]["reason"] = "<img src=x onerror=alert(1)><script>alert(2)</script>"
        d["kpis"]["min_ttc_s"] = float("nan")
        d["folder"] = "../../.."  # the folder is runs/<seed>, whatever the record says

    _edit(folder / "runs" / "0" / "record.json", markup)
    _edit(folder / "runs" / "1" / "record.json", lambda d: d["outcome"].update(status="<b>x"))
    (folder / "runs" / "0" / "myplot.png").write_bytes(b"not the run's")
    kept = read_records(folder)
    assert sorted(kept) == [0]  # seed 1's record is no record: that run is done again
    assert kept[0].folder == "runs/0" and kept[0].kpis["min_ttc_s"] is None
    status, err = _main("--resume", str(folder), "--sut", f"{folder.parent / 'pass.py'}:Pass")
    assert status == 0, err
    page = _Page()
    page.feed((folder / "report.html").read_text())
    assert "script" not in page.tags and "x" not in page.links
    assert all(link.startswith(("#", "runs/", "data:image/png")) for link in page.links)
    assert not any(".." in link or "myplot" in link for link in page.links)
    assert json.loads((folder / "campaign.json").read_text())["status"] == "complete"


@pytest.mark.parametrize(
    "damage",
    [
        lambda d: d.update(seed=True),
        lambda d: d.update(seed=7),  # not the seed of its folder
        lambda d: d["outcome"].update(status="passed"),
        lambda d: d["outcome"].update(tick=-3),
        lambda d: d.update(files=["../../../etc/passwd"]),
        lambda d: d.update(files=[".hidden"]),
        lambda d: d["kpis"].update(collision={"nested": True}),
        lambda d: d["parameters"].update(v={"text": "x", "script": "<b>"}),
        lambda d: d.update(bin={"item": "v", "index": "zero"}),
        lambda d: d.update(coverage={"v": [1, "2"]}),
    ],
)
def test_a_record_of_another_shape_is_a_run_done_again(folder, damage):
    _edit(folder / "runs" / "1" / "record.json", damage)
    assert sorted(read_records(folder)) == [0]


def test_runs_csv_cells_a_spreadsheet_would_run_are_neutralised(folder):
    records = read_records(folder)
    for text, r in zip(("=1+1", "@SUM(A1:A2)"), records.values(), strict=True):
        r.reason = text
        r.kpis["subject"] = "+cmd|' /C calc'!A0"
        r.kpis["min_gap_m"] = -2.5
    write_runs_csv(folder, list(records.values()), {0: "-2+3", 1: "\tx"})
    rows = list(csv.DictReader((folder / "runs.csv").open(newline="")))
    for row in rows:
        texts = [row["reason"], row["subject"], row["replay"]]
        assert all(t.startswith("'") for t in texts), texts
        assert row["min_gap_m"] == "-2.5"  # a number stays a number


# ---- --out: a folder of other files is never written over by mistake ------------------------


def test_out_refuses_a_folder_that_holds_no_campaign_of_the_scenario(folder, tmp_path):
    scenario = str(folder.parent / "short.osc")
    other = tmp_path / "mine"
    (other / "runs" / "0").mkdir(parents=True)
    (other / "notes.txt").write_text("my notes")
    status, err = _main(scenario, "--runs", "1", "--out", str(other), "-q")
    assert status == 2 and "not empty and holds no campaign" in err and "--force" in err
    assert sorted(p.name for p in other.iterdir()) == ["notes.txt", "runs"]
    renamed = (folder.parent / "short.osc").read_text().replace("scenario short", "scenario long")
    (folder.parent / "long.osc").write_text(renamed)
    status, err = _main(str(folder.parent / "long.osc"), "--runs", "1", "--out", str(folder))
    assert status == 2 and "holds a campaign of scenario `short`, not `long`" in err
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "campaign.json").write_text('{"format": 1}')
    status, err = _main(scenario, "--runs", "1", "--out", str(bad))
    assert status == 2 and "is not a campaign" in err


def test_out_with_force_writes_and_links_only_what_its_runs_wrote(folder, tmp_path):
    other = tmp_path / "mine"
    (other / "runs" / "0").mkdir(parents=True)
    (other / "runs" / "0" / "myplot.png").write_bytes(b"mine")
    (other / "notes.txt").write_text("my notes")
    scenario = str(folder.parent / "short.osc")
    status, err = _main(scenario, "--runs", "1", "--jobs", "1", "--out", str(other), "--force")
    assert status == 0, err
    assert (other / "notes.txt").read_text() == "my notes"
    page = _Page()
    page.feed((other / "report.html").read_text())
    assert not any("myplot" in link for link in page.links)
    assert "runs/0/run.json" in page.links


# ---- NaN, and the interrupted report's count ----------------------------------------------


def test_a_nan_kpi_is_written_as_null_and_the_campaign_ends(folder):
    from osc2runner.campaign.outputs import write_record

    record = read_records(folder)[0]
    record.kpis["min_ttc_s"] = float("nan")
    write_record(folder, record)
    assert (
        json.loads((folder / "runs" / "0" / "record.json").read_text())["kpis"]["min_ttc_s"] is None
    )


def test_the_interrupted_report_counts_the_runs_that_did_not_finish(folder):
    _edit(
        folder / "runs" / "1" / "record.json", lambda d: d["outcome"].update(status="interrupted")
    )
    from osc2runner.campaign.campaign import finish
    from osc2runner.campaign.plan import CoverPlan
    from osc2runner.campaign.worker import RunTask

    document = json.loads((folder / "campaign.json").read_text())
    records = read_records(folder)
    plan = CoverPlan([RunTask(0), RunTask(1), RunTask(2)], [])

    class _Engine:
        name = "local"

    finish(folder, document, plan, records, {}, 1.0, "interrupted", _Engine())
    text = (folder / "report.html").read_text()
    assert "2 planned runs did not finish" in text  # seed 1 interrupted, seed 2 not run


# ---- a seeded storm of damaged folders ----------------------------------------------------

_VALUES = [None, True, -1, 0, 7, 1e308, float("nan"), "", "<script>x</script>", "=1+1",
           "../..", [], [1, "a"], {}, {"a": {"b": 1}}]  # fmt: skip


def _mutate(data, rng: random.Random):
    """``data`` with one field (at any depth) replaced, deleted or added."""
    node = data
    while isinstance(node, (dict, list)) and node and rng.random() < 0.6:
        key = rng.choice(list(node) if isinstance(node, dict) else range(len(node)))
        if not isinstance(node[key], (dict, list)) or not node[key]:
            break
        node = node[key]
    if isinstance(node, dict) and node:
        key = rng.choice(list(node))
        if rng.random() < 0.3:
            del node[key]
        else:
            node[key] = copy.deepcopy(rng.choice(_VALUES))
    elif isinstance(node, list) and node:
        node[rng.randrange(len(node))] = copy.deepcopy(rng.choice(_VALUES))
    return data


@pytest.mark.parametrize("seed", range(4))
def test_folder_storm_records_hold_what_a_run_writes_or_are_left_out(folder, seed):
    rng = random.Random(seed)
    originals = {p: json.loads(p.read_text()) for p in folder.glob("runs/*/record.json")}
    document = json.loads((folder / "campaign.json").read_text())
    for _ in range(60):
        for path, data in originals.items():
            path.write_text(json.dumps(_mutate(copy.deepcopy(data), rng)))
        for r in read_records(folder).values():
            assert r.folder == f"runs/{r.seed}" and r.status in STATUSES
            assert all(file_name(f) for f in r.files)
            assert all(not isinstance(v, (dict, list)) for v in r.kpis.values())
        (folder / "campaign.json").write_text(json.dumps(_mutate(copy.deepcopy(document), rng)))
        try:
            found = read_campaign(folder)
        except FolderError as error:
            assert "campaign.json" in str(error)
        else:
            assert found is not None and re.fullmatch(r"[0-9a-f]{64}", found["source_sha256"])
