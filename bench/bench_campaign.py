"""Campaign throughput: runs per minute and speed-up for 1..N workers; fixed overheads.

Usage: ``python bench/bench_campaign.py [--runs 40] [--jobs N] [--file FILE]``
(``--jobs`` defaults to the number of processors).

For ``--runs`` runs of one scenario (seeds 0 .. runs-1, the local pool), with 1, 2,
..., N workers, prints:

* the campaign's wall time (the whole call: checking the file, planning, starting
  the workers, every run with its files, the outputs and the report), runs per
  minute, and the speed-up over 1 worker (targets: >= 1.9x from 1 to 2 workers;
  linear while workers <= free cores);
* the campaign's fixed overhead per run (1 worker): the campaign's wall time less
  the sum of its runs' own wall times (each measured by its worker, from the task
  received to the record sent), divided by the number of runs, as a share of a
  run (target < 5 % of a cut-in run);
* inside a run (averaged): the tick loop (``run.json``'s ``wall_seconds``) and
  the rest (the witness, the compile, the world's construction and settling, the
  files and the record);
* each worker's peak resident memory.

``--separate`` also times the runs as ``osc2run FILE --seed k`` processes one after
the other. Figures only: nothing is asserted, and other work on shared cores moves
them (quote the machine's load with them).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from osc2runner.campaign import CampaignOptions, run_campaign  # noqa: E402


def campaign(path: str, runs: int, jobs: int, out: Path) -> dict[str, float | list[float]]:
    started = time.perf_counter()
    result = run_campaign(CampaignOptions(path, runs=runs, out=str(out), jobs=jobs))
    wall = time.perf_counter() - started
    assert result.summary["finished"] == runs, result.summary
    own = [r.wall_s for r in result.records]
    loops = [
        json.loads((out / r.folder / "run.json").read_text())["wall_seconds"]
        for r in result.records
    ]
    return {
        "wall": wall,
        "own": sum(own) / len(own),
        "loop": sum(loops) / len(loops),
        "fixed": (wall - sum(own) / jobs) / runs,
        "memory": result.document["workers"]["peak_memory_mb"],
    }


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
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--file", default=str(ROOT / "examples" / "cut_in_and_stop.osc"))
    parser.add_argument("--separate", action="store_true")
    args = parser.parse_args()
    print(
        f"{args.runs} runs of {args.file}; {os.cpu_count()} processors, "
        f"load average {os.getloadavg()[0]:.1f} at the start"
    )
    with tempfile.TemporaryDirectory() as tmp:
        base = Path(tmp)
        first: dict[str, float | list[float]] = {}
        for jobs in range(1, args.jobs + 1):
            got = campaign(args.file, args.runs, jobs, base / f"jobs{jobs}")
            first = first or got
            wall = float(got["wall"])
            memory = ", ".join(f"{m:.0f}" for m in got["memory"])  # type: ignore[union-attr]
            print(
                f"  {jobs:2d} worker(s): {wall:7.1f} s  {60 * args.runs / wall:7.1f} runs/min  "
                f"speed-up {float(first['wall']) / wall:5.2f}x  peak memory MB: {memory}"
            )
        own, loop, fixed = (float(first[k]) for k in ("own", "loop", "fixed"))
        print(
            f"  campaign fixed overhead per run (1 worker): {fixed:.3f} s = "
            f"{100 * fixed / own:.1f} % of a run ({own:.3f} s)   (target < 5 %)"
        )
        print(
            f"  inside a run: tick loop {loop:.3f} s, the rest {own - loop:.3f} s "
            f"({100 * (own - loop) / own:.1f} %: witness, compile, world and settling, files)"
        )
        if args.separate:
            alone = separate(args.file, args.runs, base / "alone")
            print(f"  {args.runs} separate osc2run processes: {alone:7.1f} s  "
                  f"{60 * args.runs / alone:6.1f} runs/min")  # fmt: skip
    print(f"(load average {os.getloadavg()[0]:.1f} at the end)")


if __name__ == "__main__":
    main()
