"""Campaign throughput: runs per minute for 1 and 2 workers, against separate processes.

Usage: ``python bench/bench_campaign.py [--runs 40] [--file examples/cut_in_and_stop.osc]``

Prints, for ``--runs`` runs of one scenario (seeds 0 .. runs-1, the local pool):

* the campaign's wall time and runs per minute with 1 worker and with 2, and
  the speed-up from 1 to 2 (target >= 1.8x on two free cores);
* the wall time of the same runs as ``runs`` separate ``osc2run FILE --seed k
  --out DIR -q`` processes one after the other, and the campaign's time with
  2 workers as a share of it (target <= 0.6);
* each worker's peak resident memory (target < 300 MB).

The campaign's time is the whole call: checking the file, planning, starting
the workers, every run with its files, and the report. Figures only: nothing
is asserted, and other work on shared cores moves them.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from osc2runner.campaign import CampaignOptions, run_campaign  # noqa: E402


def campaign(path: str, runs: int, jobs: int, out: Path) -> tuple[float, list[float]]:
    started = time.perf_counter()
    result = run_campaign(CampaignOptions(path, runs=runs, out=str(out), jobs=jobs))
    wall = time.perf_counter() - started
    assert result.summary["finished"] == runs, result.summary
    return wall, result.document["workers"]["peak_memory_mb"]


def separate(path: str, runs: int, out: Path) -> float:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    started = time.perf_counter()
    for seed in range(runs):
        subprocess.run(
            [sys.executable, "-m", "osc2runner", path, "--seed", str(seed), "-q",
             "--out", str(out / str(seed))],
            check=False, capture_output=True, env=env,
        )  # fmt: skip
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=40)
    parser.add_argument("--file", default=str(ROOT / "examples" / "cut_in_and_stop.osc"))
    parser.add_argument("--skip-separate", action="store_true")
    args = parser.parse_args()
    print(f"{args.runs} runs of {args.file} on {os.cpu_count()} processors")
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp)
        one, mem1 = campaign(args.file, args.runs, 1, base / "one")
        print(f"  1 worker : {one:7.1f} s  {60 * args.runs / one:6.1f} runs/min  "
              f"peak memory {', '.join(f'{m:.0f} MB' for m in mem1)}")  # fmt: skip
        two, mem2 = campaign(args.file, args.runs, 2, base / "two")
        print(f"  2 workers: {two:7.1f} s  {60 * args.runs / two:6.1f} runs/min  "
              f"peak memory {', '.join(f'{m:.0f} MB' for m in mem2)}")  # fmt: skip
        print(f"  speed-up 1 -> 2 workers: {one / two:.2f}x (target >= 1.8x)")
        if not args.skip_separate:
            alone = separate(args.file, args.runs, base / "alone")
            print(f"  {args.runs} separate osc2run processes: {alone:7.1f} s  "
                  f"{60 * args.runs / alone:6.1f} runs/min")  # fmt: skip
            print(f"  campaign (2 workers) / separate: {two / alone:.2f} (target <= 0.6)")


if __name__ == "__main__":
    main()
