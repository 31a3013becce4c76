"""The Ray engine gives what the local pool gives, for the same seeds (a local Ray instance).

Skipped where Ray is not installed (``pip install ".[ray]"``); CI installs it and
runs this against a local instance. ``OSC2_RAY_ADDRESS`` (``auto``) joins a
running one (``ray start --head``) instead of starting one.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

pytest.importorskip("ray")

from osc2runner.campaign import CampaignOptions, run_campaign  # noqa: E402

ROOT = Path(__file__).parents[3]
CCRS = ROOT / "examples" / "ncap" / "ccrs.osc"
AEB = ROOT / "examples" / "controllers" / "aeb.py"


def test_six_runs_on_ray_equal_the_local_pool(tmp_path: Path) -> None:
    from osc2runner.sut.loading import SutSpec

    common = {"runs": 6, "jobs": 2, "sut": SutSpec(f"{AEB}:Aeb").resolved(), "seed": 40}
    local = run_campaign(CampaignOptions(str(CCRS), out=str(tmp_path / "local"), **common))
    ray = run_campaign(
        CampaignOptions(
            str(CCRS), out=str(tmp_path / "ray"), engine="ray",
            address=os.environ.get("OSC2_RAY_ADDRESS"), **common,
        )
    )  # fmt: skip
    assert ray.document["workers"]["engine"] == "ray"
    assert [r.seed for r in ray.records] == [r.seed for r in local.records] == list(range(40, 46))
    for a, b in zip(local.records, ray.records, strict=True):
        assert (a.status, a.reason, a.parameters, a.kpis) == (
            b.status,
            b.reason,
            b.parameters,
            b.kpis,
        )
        for name in ("telemetry.csv", "events.csv", "coverage.json"):
            assert (tmp_path / "local" / a.folder / name).read_bytes() == (
                tmp_path / "ray" / b.folder / name
            ).read_bytes(), (a.seed, name)


def test_nothing_left_to_run_starts_no_actor(tmp_path: Path) -> None:
    import ray

    from osc2runner.campaign.ray_engine import RayEngine
    from osc2runner.campaign.worker import CampaignSetup

    setup = CampaignSetup(str(CCRS), CCRS.read_text(encoding="utf-8"), out=str(tmp_path))
    engine = RayEngine(setup, 2, None)
    records: list[object] = []
    engine.run([], records.append)
    assert engine.started_workers == 0 and not records and not ray.is_initialized()
