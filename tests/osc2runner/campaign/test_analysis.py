"""What a campaign found, shown for every parameter it swept (issue 22).

One small campaign (a module fixture, 12 runs of 1.5 s): the ego drives at ``v``
in [20..60] kph for 1.5 s towards a standing target 15 m ahead whose lateral
offset ``o`` is in [0..3] m; it hits when it is fast enough and the target
overlaps its width. Both parameters must appear in every table and plot, the
pass/fail map, the failure boundary and the triage table in the report, the
JUnit names and the command's summary; a headless Chromium checks the page
(no horizontal scroll at 1280 px, every plot labelled, every link resolves).
The spread statistics are tested on the witnesses of the skewed-sampling
scenario without running it.
"""

from __future__ import annotations

import csv
import json
import os
import re
import subprocess
import sys
from pathlib import Path
from urllib.parse import unquote, urlparse
from xml.etree import ElementTree as ET

import numpy as np
import pytest

from osc2check.analysis import SourceInput, analyze
from osc2runner.campaign.charts import pass_fail_map
from osc2runner.campaign.failures import best_pair, boundary, grow, reason_class, triage
from osc2runner.campaign.outputs import read_records
from osc2runner.campaign.spread import ks_p_value, spread_of
from tests.docs_blocks import check_block
from tests.osc2runner.campaign.chromium import Chromium, find

HERE = Path(__file__).parent
ROOT = HERE.parents[2]
RUNS = 12

TWO = """\
import osc.standard

scenario two_params:
    ego: vehicle with:
        keep(it.vehicle_category == car)
    target: vehicle with:
        keep(it.vehicle_category == car)
    v: speed with:
        keep(it in [20kph..60kph])
    o: length with:
        keep(it in [0m..3m])
    gap: length = 15m
    do serial:
        setup: parallel:
            ego.assign_position() with:
                lane(2, at: start)
                speed(v, at: start)
            target.assign_position() with:
                lane(same_as: ego, at: start)
                lateral(distance: o, at: start)
                position(distance: gap, ahead_of: ego, at: start)
                speed(0kph, at: start)
        ego.drive(duration: 1.5s) with:
            speed(v)
"""


# under -n one worker builds the module fixtures for every test here (docs/testing.md)
pytestmark = pytest.mark.xdist_group("osc2runner/campaign/test_analysis")


@pytest.fixture(scope="module")
def campaign(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, str]:
    """The campaign's folder and the command's output."""
    folder = tmp_path_factory.mktemp("two")
    (folder / "two.osc").write_text(TWO, encoding="utf-8")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(
        [sys.executable, "-m", "osc2runner", "two.osc", "--runs", str(RUNS), "--jobs", "2",
         "--out", "c", "-q"],
        capture_output=True, text=True, env=env, cwd=folder, timeout=900,
    )  # fmt: skip
    assert done.returncode == 1, done.stderr + done.stdout  # some runs fail
    return folder / "c", done.stdout


@pytest.fixture(scope="module")
def document(campaign) -> dict:
    return json.loads((campaign[0] / "campaign.json").read_text())


@pytest.fixture(scope="module")
def records(campaign) -> list:
    found = read_records(campaign[0])
    return [found[s] for s in sorted(found)]


@pytest.mark.slow
def test_both_parameters_are_swept_and_the_constant_is_not(document) -> None:
    parameters = document["parameters"]
    assert sorted(parameters["swept"]) == ["o", "v"]
    assert parameters["domains"]["v"] == {
        "unit": "kph", "sort": "real", "low": 20.0, "high": 60.0, "values": None
    }  # fmt: skip
    assert "gap" not in parameters["swept"] and "gap" not in parameters["derived"]
    failed = [r for r in document["runs"] if r["outcome"]["status"] == "failure"]
    assert 0 < len(failed) < RUNS


@pytest.mark.slow
def test_both_parameters_are_in_every_table(campaign, document, records) -> None:
    folder, _ = campaign
    with (folder / "runs.csv").open() as f:
        header = next(csv.reader(f))
    assert {"v", "o"} <= set(header)
    page = (folder / "report.html").read_text()
    for section in ("worst", "runs"):
        table = page[page.index(f'id="{section}"') :]
        table = table[: table.index("</table>")]
        assert "<th>v</th>" in table and "<th>o</th>" in table, section
    suite = ET.parse(folder / "junit.xml").getroot().find("testsuite")
    names = [case.get("name") for case in suite.findall("testcase")]
    by_seed = {r.seed: r for r in records}
    first = by_seed[0]
    v, o = first.parameters["v"]["value"], first.parameters["o"]["value"]
    assert f"two_params[o={o:.3g}m,v={v:.3g}kph]" in names or (
        f"two_params[v={v:.3g}kph,o={o:.3g}m]" in names
    )
    failures = [
        c.find("failure") for c in suite.findall("testcase") if c.find("failure") is not None
    ]
    assert failures and all("relative_impact_speed_kph" in f.get("message") for f in failures)


@pytest.mark.slow
def test_every_swept_parameter_has_its_kpi_plot_and_the_map_and_triage_are_there(campaign) -> None:
    page = (campaign[0] / "report.html").read_text()
    assert 'alt="KPIs over v, a point a run coloured by its outcome"' in page
    assert 'alt="KPIs over o, a point a run coloured by its outcome"' in page
    assert 'alt="pass/fail map over ' in page
    assert 'id="triage"' in page and "<th>representative</th>" in page
    assert 'id="boundary"' in page


@pytest.mark.slow
def test_the_failure_boundary_names_both_parameters(document, records) -> None:
    (region,) = document["failures"]["boundary"]["regions"]
    assert region["failed"] == region["runs"] >= 2
    text = region["text"]
    assert "v is above" in text and "o is below" in text, text
    # each threshold lies between the runs either side of it
    leaves, split = grow(records, ["v", "o"])
    assert split
    failing = [leaf for leaf in leaves if leaf.failed > leaf.passed]
    for split_, _ in failing[0].path:
        assert split_.below < split_.threshold < split_.above


@pytest.mark.slow
def test_the_map_shows_the_pair_and_every_run_where_its_values_are(document, records) -> None:
    pair, pairs = best_pair(records, document["parameters"]["swept"])
    assert sorted(pair) == ["o", "v"] and len(pairs) == 1
    fig = pass_fail_map(records, "v", "o", document["parameters"]["domains"])
    ax = fig.axes[0]
    assert ax.get_xlabel() == "v (kph)" and ax.get_ylabel() == "o (m)"
    drawn = {}
    for collection in ax.collections:
        if (gid := collection.get_gid() or "").startswith("runs-"):
            drawn[gid] = {tuple(np.round(p, 6)) for p in collection.get_offsets()}
    for status in ("success", "failure"):
        expected = {
            (round(r.parameters["v"]["value"], 6), round(r.parameters["o"]["value"], 6))
            for r in records
            if r.status == status
        }
        assert drawn[f"runs-{status}"] == expected
    (region,) = [p for p in ax.patches if p.get_gid() == "failure-region"]
    for x, y in drawn["runs-failure"]:
        assert region.contains_point(ax.transData.transform((x, y)))


@pytest.mark.slow
def test_triage_groups_the_failures_with_a_representative_to_replay(document, records) -> None:
    rows = document["failures"]["triage"]
    failed = sorted(r.seed for r in records if r.status == "failure")
    assert [row["reason"] for row in rows] == ["collision: ego and target"]
    assert rows[0]["seeds"] == failed and rows[0]["representative"] in failed
    assert rows[0]["replay"] == f"osc2run two.osc --seed {rows[0]['representative']}"
    assert "v is above" in rows[0]["region"]


@pytest.mark.slow
def test_the_summary_prints_the_spread_and_the_boundary(campaign) -> None:
    _, out = campaign
    assert "  swept v over [20..60] kph (constraints): " in out
    assert "  swept o over [0..3] m (constraints): " in out
    assert "  failure boundary: fails where " in out
    assert "warning:" not in out


@pytest.mark.slow
def test_campaigns_md_quotes_what_the_command_prints(campaign) -> None:
    _, out = campaign
    shown = re.sub(r"[0-9.]+ s wall, [0-9.]+ runs per minute", "… s wall, … runs per minute", out)
    check_block(ROOT / "docs" / "campaigns.md", "campaign-summary", f"```text\n{shown}```")


@pytest.mark.slow
@pytest.mark.skipif(find() is None, reason="no Chromium (apt-get install chromium)")
def test_the_report_in_a_browser(campaign) -> None:
    folder, _ = campaign
    page = folder / "report.html"
    with Chromium(find()) as browser:  # type: ignore[arg-type]
        browser.open(page, width=1280)
        browser.evaluate("document.querySelectorAll('details').forEach(d => d.open = true)")
        width = browser.evaluate("[document.documentElement.scrollWidth, window.innerWidth]")
        assert width[0] <= width[1], width  # no horizontal scroll at 1280 px
        images = browser.evaluate(
            "[...document.images].map(i => [i.alt, i.naturalWidth, "
            "i.closest('figure')?.querySelector('figcaption')?.textContent || ''])"
        )
        assert images and all(alt and natural > 0 and caption for alt, natural, caption in images)
        links = browser.evaluate("[...document.querySelectorAll('a[href]')].map(a => a.href)")
        anchors = browser.evaluate("[...document.querySelectorAll('[id]')].map(e => e.id)")
        assert links
        for link in links:
            url = urlparse(link)
            if url.fragment and unquote(url.path) == str(page.resolve()):
                assert url.fragment in anchors, link
            else:
                assert url.scheme == "file" and Path(unquote(url.path)).is_file(), link


def test_witnesses_of_the_skewed_scenario_spread_and_a_pile_is_told() -> None:
    """The issue's scenario (``ttc0: time = 4s``): 40 seeds' speeds and offsets have no
    pile; the same statistics flag the pile the sampler used to make."""
    text = (HERE.parents[1] / "osc2check" / "verify" / "test_witness_spread.py").read_text()
    namespace: dict = {}
    exec(compile(text.split("BOUNDS = ")[0], "spread", "exec"), namespace)  # the scenario texts
    source = namespace["CCRM"].format(factors=namespace["CONSTANT_FIELD"])
    analysis = analyze([SourceInput("ccrm.osc", source)])
    result = analysis.verified["ccrm.osc"].scenarios[0]
    domains = {
        "ego_speed": {"unit": "kph", "sort": "real", "low": 30.0, "high": 80.0},
        "offset": {"unit": "m", "sort": "real", "low": -0.45, "high": 0.45},
    }
    witnesses = [result.witness_for(seed) for seed in range(40)]
    speeds = [float(w.parameter("ego_speed").value) * 3.6 for w in witnesses]
    offsets = [float(w.parameter("offset").value) for w in witnesses]
    for name, values in (("ego_speed", speeds), ("offset", offsets)):
        spread = spread_of(name, values, domains[name])
        assert not spread.piles and spread.on_low <= 4 and spread.on_high <= 4
        assert spread.ks is not None and spread.ks_p > 0.01, spread
    skewed = spread_of("ego_speed", [30.0] * 22 + speeds[:18], domains["ego_speed"])
    assert skewed.piles and skewed.on_low == 22
    assert skewed.warning == "`ego_speed` piles up: 22 of 40 runs at 30 kph, its lower bound"


def test_a_discrete_parameter_piles_up_only_when_improbably_uneven() -> None:
    domain = {"unit": "", "sort": "int", "values": [-75, -50, 50, 75, 100]}
    even = spread_of("overlap", [-75, -50, 50, 75, 100] * 8, domain)
    assert not even.piles and (even.hit, even.allowed) == (5, 5)
    uneven = spread_of("overlap", [100] * 25 + [-75, -50, 50, 75, 50] * 3, domain)
    assert uneven.piles and "25 of 40 runs at 100 of its 5 values" in uneven.warning


def test_the_ks_p_value_of_the_kolmogorov_distribution() -> None:
    assert ks_p_value(0.0, 40) == 1.0
    assert ks_p_value(0.21, 40) == pytest.approx(0.05, abs=0.01)  # the 5 % critical value
    assert ks_p_value(0.6, 40) < 1e-10


def test_reasons_group_without_their_numbers_but_with_their_places() -> None:
    assert reason_class("collision: ego and target") == "collision: ego and target"
    a = reason_class("f.osc:12:9: `ego.drive` did not complete within its duration 3.5 s")
    assert a == "f.osc:12:9: `ego.drive` did not complete within its duration # s"
    assert reason_class("the physics diverged at tick 31 (1.55 s)") == (
        "the physics diverged at tick # (# s)"
    )


@pytest.mark.slow
def test_no_boundary_when_every_run_fails_or_none_does(records) -> None:
    passing = [r for r in records if r.passed]
    assert boundary(passing, ["v", "o"], {})["why"] == "no run failed"
    failing = [r for r in records if not r.passed]
    assert boundary(failing, ["v", "o"], {})["why"] == "every run failed"
    assert triage(passing, ["v", "o"], {}, {}) == []
