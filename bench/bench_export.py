"""Export of one run: time and size of the OpenSCENARIO XML and OSI files.

    python bench/bench_export.py [examples/cut_in_and_stop.osc] [--repeat 5]

Runs the scenario once (not timed), then times the exports of that run — the import of
the writers (once per process, first), the OpenSCENARIO file with its road network, and
the OSI trace — and prints the best of ``--repeat`` and each file's size.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("file", nargs="?", default="examples/cut_in_and_stop.osc")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    from osc2runner.runner import check_file, execute, prepare_checked

    prepared = prepare_checked(check_file(args.file))
    result = execute(prepared)
    started = time.perf_counter()
    import osi_utilities  # noqa: F401
    import scenariogeneration.xosc  # noqa: F401
    from osi3 import osi_groundtruth_pb2  # noqa: F401

    imported = time.perf_counter() - started
    from osc2runner.export.osi import write_osi
    from osc2runner.export.recording import run_recording
    from osc2runner.export.xosc import write_xosc

    folder = Path(tempfile.mkdtemp(prefix="bench-export-"))
    best = {"recording": float("inf"), "xosc": float("inf"), "osi": float("inf")}
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        recording = run_recording(prepared, result)
        t1 = time.perf_counter()
        written = write_xosc(recording, folder / "run.xosc")
        t2 = time.perf_counter()
        trace = write_osi(recording, folder / "run.osi")
        t3 = time.perf_counter()
        for key, value in (("recording", t1 - t0), ("xosc", t2 - t1), ("osi", t3 - t2)):
            best[key] = min(best[key], value)
    ticks = len(recording.ticks)
    print(f"{args.file}: {ticks} ticks, {len(recording.actors)} actors")
    print(f"  import of the writers (once a process): {imported * 1000:.0f} ms")
    print(f"  recording: {best['recording'] * 1000:.1f} ms (best of {args.repeat})")
    for path in written:
        print(f"  {path.name}: {path.stat().st_size / 1024:.1f} KiB")
    print(f"  OpenSCENARIO + road network: {best['xosc'] * 1000:.1f} ms")
    print(f"  {trace.name}: {trace.stat().st_size / 1024:.1f} KiB, {best['osi'] * 1000:.1f} ms")


if __name__ == "__main__":
    main()
