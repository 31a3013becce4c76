"""The Euro NCAP examples: the protocol's grids, each test runnable alone, the AEB against them."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2runner import run
from osc2runner.campaign.plan import item_plans
from osc2runner.campaign.steering import BinRef, cover_items
from osc2runner.campaign.worker import CampaignSetup, RunTask, Worker
from osc2runner.runner import check_file
from osc2runner.sut.loading import SutSpec

ROOT = Path(__file__).parents[3]
NCAP = ROOT / "examples" / "ncap"
AEB = SutSpec(f"{ROOT / 'examples' / 'controllers' / 'aeb.py'}:Aeb")

# the protocol's grids (Euro NCAP AEB C2C / VRU 2023; ncap-xosc Variations)
GRIDS = {
    "ccrs.osc": (9 * 5, {"test_speed": 9, "overlap": 5}),
    "ccrm.osc": (11 * 5, {"test_speed": 11, "overlap": 5}),
    "ccrb.osc": (2 * 2, {"headway": 2, "deceleration": 2}),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(GRIDS))
def test_the_grid_is_the_protocols(name: str) -> None:
    checked = check_file(NCAP / name)
    items = cover_items(checked)
    reachable = {p.name: p.status.count("reachable") for p in item_plans(checked, items)}
    cells, parts = GRIDS[name]
    assert reachable.pop("grid") == cells
    assert reachable == parts


@pytest.mark.slow
@pytest.mark.parametrize("name", ["ccrs.osc", "ccrm.osc", "ccrb.osc", "cpna25.osc"])
def test_each_test_runs_alone_and_without_braking_it_hits(name: str) -> None:
    result = run(NCAP / name, seed=1)
    assert result.outcome.status == "failure"
    assert result.outcome.reason.startswith("collision: ego and ")


@pytest.mark.slow
def test_the_example_aeb_avoids_at_low_speed_and_mitigates_at_50_kph(tmp_path: Path) -> None:
    path = NCAP / "ccrs.osc"
    worker = Worker(
        CampaignSetup(str(path), path.read_text(), sut=AEB.resolved(), out=str(tmp_path))
    )
    slow = worker.run(RunTask(5, BinRef("test_speed", 0)))  # 10 kph
    fast = worker.run(RunTask(6, BinRef("test_speed", 8)))  # 50 kph
    assert slow.parameters["test_speed"]["value"] == 10.0 and slow.status == "success"
    assert 0.0 < slow.kpis["min_gap_m"] < 3.0
    assert fast.parameters["test_speed"]["value"] == 50.0 and fast.status == "failure"
    assert 0.0 < fast.kpis["relative_impact_speed_kph"] < 5.0  # 50 kph reduced to under 5
    assert fast.kpis["speed_reduction_kph"] > 45.0
