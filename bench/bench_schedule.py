"""Cost of the run schedule (``osc2check.verify.schedule``): building the timing plan
when a scenario is lowered, and evaluating it for each witness.

Usage: ``python bench/bench_schedule.py``. Uses bench_verify's 20-actor scenario.
Figures only; tests never assert on time.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from bench_verify import lowered, many_actors  # noqa: E402

from osc2check.verify.schedule import schedule  # noqa: E402
from osc2check.verify.z3_backend import check  # noqa: E402


def main() -> None:
    _, _, _, lower = lowered(many_actors(20), "convoy")
    problem = lower()
    values = check(problem).values
    times = []
    for _ in range(20):
        t0 = time.perf_counter()
        found = schedule(problem.timing, values)
        times.append((time.perf_counter() - t0) * 1000)
    times.sort()
    print(f"schedule of one witness ({len(found)} phases): median {times[10]:.2f} ms, "
          f"best {times[0]:.2f} ms")  # fmt: skip


if __name__ == "__main__":
    main()
