"""How evenly the witnesses of many seeds cover a scenario's swept parameters.

Usage: ``python bench/bench_spread.py [--seeds 40]``

For the CCRm-style scenario of issue 22 (ego speed in [30..80] kph, target offset
in [-0.45..0.45] m, the start gap following from the speed) written three ways —
with a constant field (``ttc0: time = 4s``), with a product of two unknowns and
with a division — prints, per swept parameter over ``--seeds`` witnesses (no
simulation), what a campaign prints (``osc2runner.campaign.spread``): the runs on
each bound, the most runs at one value, the Kolmogorov-Smirnov statistic against
a uniform spread, and whether it piles up; and the time per witness. Figures
only: nothing is asserted (``tests/osc2check/verify/test_witness_spread.py`` asserts).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from osc2check.analysis import SourceInput, analyze  # noqa: E402
from osc2runner.campaign.spread import spread_of  # noqa: E402
from tests.osc2check.verify import test_witness_spread as cases  # noqa: E402

DOMAINS = {
    "ego_speed": {"unit": "kph", "sort": "real", "low": 30.0, "high": 80.0},
    "offset": {"unit": "m", "sort": "real", "low": -0.45, "high": 0.45},
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=40)
    seeds = parser.parse_args().seeds
    for label, factors in (
        ("constant field", cases.CONSTANT_FIELD),
        ("product", cases.PRODUCT),
        ("division", cases.DIVISION),
    ):
        analysis = analyze([SourceInput("ccrm.osc", cases.CCRM.format(factors=factors))])
        result = analysis.verified["ccrm.osc"].scenarios[0]
        started = time.perf_counter()
        witnesses = [result.witness_for(seed) for seed in range(seeds)]
        per_witness = (time.perf_counter() - started) / seeds * 1000.0
        print(f"{label}: {seeds} witnesses, {per_witness:.1f} ms each")
        for name, scale in (("ego_speed", 3.6), ("offset", 1.0)):
            values = [float(w.parameter(name).value) * scale for w in witnesses if w is not None]
            print(f"  {spread_of(name, values, DOMAINS[name]).text()}")


if __name__ == "__main__":
    main()
