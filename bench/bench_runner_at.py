"""Run another checkout's ``bench/bench_runner.py`` on that checkout's code, for paired runs.

Usage: ``python bench/bench_runner_at.py ROOT [bench_runner options]``, e.g. this
branch against a clone of ``main`` in ``../main``, the two run in turn (A B A B ...)::

    for i in 1 2 3 4 5; do
        /usr/bin/time -f "%e s %U user" python bench/bench_runner_at.py ../main --repeat 1 \\
            --scene cut-in+idle '20 vehicles'
        /usr/bin/time -f "%e s %U user" python bench/bench_runner_at.py . --repeat 1 \\
            --scene cut-in+idle '20 vehicles'
    done

``bench_runner.py`` takes the cut-in from ``../shared`` when that folder is beside the
checkout (a worktree elsewhere has none); here both take
``ROOT/examples/cut_in_and_stop.osc``, so that the two sides run the same scenes.
"""

from __future__ import annotations

import sys
from pathlib import Path

root = Path(sys.argv[1]).resolve()
sys.argv = [str(root / "bench" / "bench_runner.py"), *sys.argv[2:]]
sys.path[:0] = [str(root), str(root / "bench")]
import bench_runner  # noqa: E402

assert Path(bench_runner.__file__).resolve().parents[1] == root
bench_runner.SEED_CUT_IN = Path("/nonexistent")
bench_runner.main()
