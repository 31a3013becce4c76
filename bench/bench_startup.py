"""Whole-process time of `osc2check`: one small file, a 10,000-line file; warm and cold cache.

Every figure is a whole process, interpreter start included, as a pre-commit hook
sees it: the median of RUNS runs (default 15), each paired with a run of the
yardstick `python -c pass` right before it (A B A B ...), so the ratio stays
meaningful when the machine's speed drifts. Printed per command: median wall and
CPU (user + system) seconds, and the median of the pairwise wall ratios to
`python -c pass`.

* warm: the start-up cache holds the parser's tables, the analysed standard
  library, the built-in map's facts and the classes' compiled code (one run first
  fills it), and the stored result of the same check (``osc2check.results``);
* unchanged: the file was last modified an hour ago and is checked again as it was,
  so its stored result is given (what a pre-commit hook or CI sees for the files a
  commit did not touch); edited: a comment line is added before every run, so the
  file is checked (what it sees for the files a commit changed); the large file is
  also edited at its top (every declaration after the edit moves) and in a scenario
  in its middle (a limit changed: that scenario's group is checked again, the
  others' findings are read from the last check, ``osc2check.groups``), and checked
  whole with ``--no-cache``;
* cold: a new, empty cache folder for every run (it is filled as it runs, and the
  next run does not see it): the first run after an install or an upgrade;
* --no-cache: neither read nor written.

Each file is checked unchanged and edited; the small file also cold and with
--no-cache (both checked in full).

* resident: ``OSC2_RESIDENT=1``, the resident process started and warm before the
  runs (``osc2check.resident``): each check is handed to it.

Targets (issue 23): one small file <= 0.15 s warm, the cold run no slower than
before the cache; the 10,000-line file <= 0.4 s warm. The note says which of
unchanged and edited meets them. The children get their
bytecode written (PYTHONDONTWRITEBYTECODE is unset for them, into a folder of their
own): an installed toolkit always has its .pyc files.

`python bench/bench_startup.py [RUNS]`
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "bench"))

from generate import generate  # noqa: E402

from osc2check import resident  # noqa: E402

SMALL = ROOT / "examples" / "cut_in_and_stop.osc"
_COMMAND = "import sys; from osc2check.results import run; sys.argv[0] = 'osc2check'; run()"


def run(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU seconds of one whole process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def paired(
    label: str,
    cmd: list[str],
    env: dict[str, str],
    runs: int,
    fresh: bool = False,
    before: Callable[[int], None] | None = None,
) -> None:
    """``before(i)``: called before run ``i`` (-1: the warm-up), e.g. to edit the file."""
    yardstick = [sys.executable, "-c", "pass"]
    if before is not None:
        before(-1)
    run(cmd, env if not fresh else {**env, "OSC2_CACHE_DIR": tempfile.mkdtemp()})  # warm-up
    walls, cpus, ratios = [], [], []
    for i in range(runs):
        if before is not None:
            before(i)
        base, _ = run(yardstick, env)
        this_env = env if not fresh else {**env, "OSC2_CACHE_DIR": tempfile.mkdtemp()}
        wall, cpu = run(cmd, this_env)
        walls.append(wall)
        cpus.append(cpu)
        ratios.append(wall / base)
    print(
        f"{label:<44} wall {statistics.median(walls):6.3f} s  cpu {statistics.median(cpus):6.3f} s"
        f"  (min {min(walls):.3f}, max {max(walls):.3f}; "
        f"{statistics.median(ratios):4.1f}x python -c pass)"
    )


def main() -> None:
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 15
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONDONTWRITEBYTECODE",)}
    env.pop("OSC2_NO_CACHE", None)
    work = Path(tempfile.mkdtemp(prefix="osc2-bench-startup-"))
    env["PYTHONPYCACHEPREFIX"] = str(work / "pycache")
    env["OSC2_CACHE_DIR"] = str(work / "cache")
    large = work / "generated.osc"
    text = generate(10_000)
    large.write_text(text, encoding="utf-8")
    os.utime(large, (time.time() - 3600,) * 2)  # as a file checked after a commit
    small = work / SMALL.name
    small_text = SMALL.read_text(encoding="utf-8")
    small.write_text(small_text, encoding="utf-8")
    os.utime(small, (time.time() - 3600,) * 2)
    # what the installed `osc2check` command runs
    check = [sys.executable, "-c", _COMMAND, "--output-format", "concise"]
    subprocess.run([*check, str(SMALL)], env=env, capture_output=True, check=False)  # .pyc

    base = [run([sys.executable, "-c", "pass"], env)[0] for _ in range(runs)]
    print(f"python -c pass: median wall {statistics.median(base):.3f} s ({runs} runs)")
    print(f"one small file: {SMALL.relative_to(ROOT)} ({SMALL.read_text().count(chr(10))} lines)")
    paired("  warm cache, unchanged (its stored result)", [*check, str(small)], env, runs)

    def edit_small(i: int) -> None:
        small.write_text(f"{small_text}# edit {i}\n", encoding="utf-8")

    paired(
        "  warm cache, edited before each run", [*check, str(small)], env, runs, before=edit_small
    )
    paired("  cold cache (a new folder every run)", [*check, str(small)], env, runs, fresh=True)
    paired("  --no-cache", [*check, "--no-cache", str(small)], env, runs)
    lines = text.count("\n")
    few = max(runs // 3, 3)
    print(f"large file: {lines} lines generated by bench/generate.py")
    paired("  warm cache, unchanged (its stored result)", [*check, str(large)], env, few)

    def edit(i: int) -> None:
        large.write_text(f"{text}# edit {i}\n", encoding="utf-8")

    def edit_top(i: int) -> None:
        large.write_text(f"# edit {i}\n{text}", encoding="utf-8")

    middle = text.index("keep(top_", len(text) // 2)
    number = middle + text[middle:].index("< ") + 2
    digits = len(text[number:].split("kph", 1)[0])

    def edit_scenario(i: int) -> None:  # a limit of the scenario in the middle of the file
        large.write_text(f"{text[:number]}{121 + i % 79}{text[number + digits :]}", "utf-8")

    large_edits = {
        "edited before each run": edit,
        "edited at its top before each run": edit_top,
        "a scenario in its middle edited before each run": edit_scenario,
    }
    for label, before in large_edits.items():
        paired(f"  warm cache, {label}", [*check, str(large)], env, few, before=before)
    paired("  --no-cache (checked whole)", [*check, "--no-cache", str(large)], env, few)
    # the resident checker (OSC2_RESIDENT=1): a warm process checks, forked per check
    served = {**env, "OSC2_RESIDENT": "1", "XDG_RUNTIME_DIR": str(work / "run")}
    (work / "run").mkdir(mode=0o700)
    _resident_ready([*check, str(small)], served, work / "run" / "osc2check")
    print("resident checker (OSC2_RESIDENT=1), started before:")
    paired(
        "  small file, edited before each run",
        [*check, str(small)],
        served,
        runs,
        before=edit_small,
    )
    for label, before in large_edits.items():
        paired(f"  large file, {label}", [*check, str(large)], served, few, before=before)
    resident.stop(str(work / "run" / "osc2check"))
    print("(machine: `nproc` =", os.cpu_count(), "; load average", os.getloadavg(), ")")


def _resident_ready(cmd: list[str], env: dict[str, str], folder: Path) -> None:
    """Run ``cmd`` once (it starts the resident process) and wait until the process
    answers at its socket in ``folder``."""
    subprocess.run(cmd, env=env, capture_output=True, check=False)
    if not resident.answering(str(folder), wait=120):
        raise SystemExit("the resident checker did not start")


if __name__ == "__main__":
    main()
