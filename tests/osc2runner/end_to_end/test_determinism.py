"""Same file, seed and versions: byte-identical telemetry."""

from __future__ import annotations

from pathlib import Path

from osc2runner import run

ROOT = Path(__file__).resolve().parents[3]


def test_two_runs_with_the_same_seed_give_identical_telemetry(tmp_path):
    source = ROOT / "examples" / "cut_in_and_stop.osc"
    first = run(source, seed=7, out=tmp_path / "a", duration=15.0)
    second = run(source, seed=7, out=tmp_path / "b", duration=15.0)
    for name in ("telemetry.csv", "events.csv"):
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
    for actor, channels in first.telemetry.items():
        for channel, values in channels.items():
            assert values.tobytes() == second.telemetry[actor][channel].tobytes(), (actor, channel)
