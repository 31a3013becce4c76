"""``cover``/``record`` (§7.5): ``coverage.json`` value by value against telemetry.

``scenarios/coverage.osc`` samples at ``sample_now`` (1 s and 3 s), at
``every(1s)`` and at the scenario's end.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from osc2runner import run
from osc2runner.execution.coverage import RunCoverage
from osc2runner.output.coverage import read_coverage

SCENARIOS = Path(__file__).parents[1] / "scenarios"
KPH = 5 / 18  # the library's factor of kph


@pytest.fixture(scope="module")
def covered(tmp_path_factory):
    out = tmp_path_factory.mktemp("coverage")
    result = run(SCENARIOS / "coverage.osc", out=out)
    assert result.outcome.status == "success", result.outcome.reason
    return result, out


def test_coverage_json_is_written_and_is_what_the_run_returns(covered):
    result, out = covered
    assert (out / "coverage.json") in result.outputs
    document = json.loads((out / "coverage.json").read_text())
    assert document == result.coverage.to_json()
    assert read_coverage(out).to_json() == document
    assert RunCoverage.from_json(document).to_json() == document  # round trip
    assert [i["name"] for i in document["items"]] == [
        "end_speed", "speed_log", "periodic", "fast", "spd", "side", "quiet",
    ]  # fmt: skip
    assert {i["kind"] for i in document["items"]} == {"cover", "record"}


def test_samples_are_the_telemetry_values_at_their_event_in_the_unit_asked(covered):
    result, _ = covered
    speed = result.telemetry["hero"]["speed"]
    log = result.coverage.item("speed_log")
    assert log.unit == "kph" and log.si_unit == "m*s^-1" and log.event == "sample_now"
    assert [s.tick for s in log.samples] == result.event_ticks("emit", "sample_now") == [20, 60]
    for sample in log.samples:
        assert sample.value == pytest.approx(speed[sample.tick] / KPH, rel=1e-12)
        assert sample.time == pytest.approx(sample.tick * 0.05)
    periodic = result.coverage.item("periodic")  # every(1s) from the scenario's start, SI
    assert periodic.unit is None
    assert [s.tick for s in periodic.samples] == list(range(0, result.outcome.tick + 1, 20))
    assert [s.value for s in periodic.samples] == [speed[s.tick] for s in periodic.samples]


def test_the_default_sampling_event_is_the_end_of_the_scenario(covered):
    result, _ = covered
    item = result.coverage.item("end_speed")
    assert item.event == "end" and item.text == "speed at the end"
    [sample] = item.samples
    assert sample.tick == result.outcome.tick == result.event_ticks("end", "end")[0]
    value = result.telemetry["hero"]["speed"][sample.tick] / KPH
    assert sample.value == pytest.approx(value, rel=1e-12)
    # range [0..60] every 10 (plain numbers in kph): six buckets, the sample in its own
    assert item.range == (0.0, 60.0) and item.every == 10.0
    assert [b.label for b in item.buckets] == [
        "[0..10)", "[10..20)", "[20..30)", "[30..40)", "[40..50)", "[50..60]",
    ]  # fmt: skip
    assert sample.bucket == int(value // 10)
    assert [b.hits for b in item.buckets] == [int(i == sample.bucket) for i in range(6)]


def test_physical_bounds_ignore_enum_and_boolean_buckets(covered):
    result, _ = covered
    speed = result.telemetry["hero"]["speed"]
    spd = result.coverage.item("spd")  # range [0kph..20mps] every 5mps, in SI, target 2
    assert spd.unit is None and spd.range == (0.0, 20.0) and spd.target == 2
    assert [s.value for s in spd.samples] == [speed[20], speed[60]]
    assert [s.bucket for s in spd.samples] == [int(speed[20] // 5), int(speed[60] // 5)]
    # ignore: spd < 10kph holds for the first sample only: kept, counted in no bucket
    assert [s.ignored for s in spd.samples] == [speed[20] < 10 * KPH, speed[60] < 10 * KPH]
    assert [s.ignored for s in spd.samples] == [True, False]
    assert sum(b.hits for b in spd.buckets) == 1
    fast = result.coverage.item("fast")  # a boolean: a bucket per value
    assert [b.value for b in fast.buckets] == [False, True]
    assert [s.value for s in fast.samples] == [bool(speed[t] > 30 * KPH) for t in (20, 60)]
    side = result.coverage.item("side")  # the field it is named after; an enum
    assert [b.label for b in side.buckets] == ["left", "right"]
    assert [s.value for s in side.samples] == ["left", "left"]
    assert result.coverage.item("quiet").disabled
    assert result.coverage.item("quiet").samples == []


def test_an_illegal_value_is_recorded_and_fails_the_run():
    result = run(SCENARIOS / "coverage_illegal.osc")
    assert result.outcome.status == "failure"
    assert "record `too_fast`: illegal value" in result.outcome.reason
    item = result.coverage.item("too_fast")
    speed = result.telemetry["hero"]["speed"]
    first_bad = next(s for s in item.samples if s.illegal)
    assert first_bad.value > 20.0
    assert all(s.value <= 20.0 for s in item.samples if not s.illegal)
    assert first_bad.value == pytest.approx(speed[first_bad.tick] / KPH, rel=1e-12)
    assert result.outcome.tick == first_bad.tick
