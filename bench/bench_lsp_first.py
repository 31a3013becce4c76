"""First diagnostics of a small document after ``initialize``, one server start.

``python bench/bench_lsp_first.py [ROOT]`` starts ``python -m osc2lsp`` from the
checkout ``ROOT`` (default: this one), answers ``initialize``, opens
``examples/cut_in_and_stop.osc`` and waits for its first ``publishDiagnostics``;
it prints both times and exits. One run per process, so that runs can be paired
with another checkout's, in turn::

    for i in $(seq 9); do
        python bench/bench_lsp_first.py
        python bench/bench_lsp_first.py /path/to/other/checkout
    done

``bench_lsp.py LINES`` reports the same figures as medians of five starts.
"""

from __future__ import annotations

import asyncio
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import bench_lsp  # noqa: E402


async def once(root: Path) -> None:
    bench_lsp.ROOT = root  # the server's PYTHONPATH and the workspace root
    small = (root / "examples" / "cut_in_and_stop.osc").read_text(encoding="utf-8")
    client, ready, first = await bench_lsp.start(small)
    await bench_lsp.stop(client)
    assert first is not None
    print(
        f"initialize answered {ready * 1000:.0f} ms, first diagnostics {first * 1000:.0f} ms, "
        f"initialize -> first diagnostics {(first - ready) * 1000:.0f} ms"
    )


if __name__ == "__main__":
    asyncio.run(once(Path(sys.argv[1]).resolve() if len(sys.argv) > 1 else bench_lsp.ROOT))
