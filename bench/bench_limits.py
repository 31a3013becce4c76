"""Time and peak memory of each tool on the worst inputs we know (issue 26, docs/security.md).

Each input is made here, in a temporary folder, and each tool runs on it as a user runs
it: ``osc2check`` and ``osc2run`` as commands, ``osc2lsp`` over its pipes, a campaign
with ``--resume``. Printed per input: its size, the wall time, the peak resident memory
of the process (the language server's solver worker and a campaign's workers counted
too), and whether it stays within the acceptance of issue 26: no input under 1 MB
makes any tool use more than 1 GB or 60 s. A line ``OVER`` is a budget missing.

    python bench/bench_limits.py            # every input (a few minutes)
    python bench/bench_limits.py numbers    # the inputs whose name contains "numbers"

Figures depend on the machine and its load: quote them with the machine they came from.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.osc2check.world.maptext import road_xml, scenario_on, xodr  # noqa: E402
from tests.osc2lsp.lsp_helpers import CONFLICT  # noqa: E402

LIMIT_SECONDS, LIMIT_BYTES = 60.0, 2**30
MB = 1024 * 1024
NEAR_MB = MB - 4096  # the "1 MB" inputs are just under it: the acceptance is for those
PYTHON = sys.executable
ENV = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))


@dataclass
class Figure:
    name: str
    tool: str
    size: int  # bytes of input
    seconds: float
    peak: int  # bytes
    note: str = ""


def run(command: list[str], cwd: Path, timeout: float = 600) -> tuple[float, int, str]:
    """Wall seconds, peak RSS (bytes: the process's own, from ``wait4``) and what the
    command said: its exit status and first finding or error (else its last line)."""
    with tempfile.TemporaryFile() as out:
        start = time.perf_counter()
        proc = subprocess.Popen(command, cwd=cwd, env=ENV, stdout=out, stderr=subprocess.STDOUT)
        timer = threading.Timer(timeout, proc.kill)
        timer.start()
        _, status, usage = os.wait4(proc.pid, 0)
        timer.cancel()
        proc.returncode = os.waitstatus_to_exitcode(status)
        wall = time.perf_counter() - start
        out.seek(0)
        lines = out.read().decode(errors="replace").strip().splitlines()
    if proc.returncode == -9:
        return wall, usage.ru_maxrss * 1024, "killed: over the timeout"
    said = next((line for line in lines if _SAYS.search(line)), lines[-1] if lines else "")
    return wall, usage.ru_maxrss * 1024, f"exit {proc.returncode}: {said.strip()[:110]}"


_SAYS = re.compile(r": [A-Z]\d{3} |error")


# ---- the inputs ---------------------------------------------------------------------------


def scenario(field_value: str, extra: str = "") -> str:
    return (
        "import osc.standard\nscenario s:\n    hero: vehicle\n"
        f"    x: float = {field_value}\n{extra}"
        "    do hero.drive(duration: 3s) with:\n        speed(30kph)\n"
    )


def product(depth: int, leaf: str) -> str:
    return leaf if depth == 0 else f"({product(depth - 1, leaf)}*{product(depth - 1, leaf)})"


def checker_inputs() -> dict[str, str]:
    body = CONFLICT.split("\n", 1)[1]
    unclosed = "".join(f'    s{i}: string = "a\\"b \\n unclosed\n' for i in range(20_000))
    return {
        "numbers: 1e99999999": scenario("1e99999999"),
        "numbers: 3,000 literals of 300 digits": scenario(
            "1", "".join(f"    y{i}: float = {'7' * 299}.5\n" for i in range(3_000))
        ),
        "numbers: products nested 16 deep (65,536 factors of 1e300)": scenario(
            "1", f"    keep(x == {product(16, '1e300')})\n"
        ),
        "strings: a 1 MB string literal": scenario("1", f'    t: string = "{"a" * NEAR_MB}"\n'),
        "strings: 20,000 unclosed strings": "scenario s:\n" + unclosed,
        "nesting: 1 MB of brackets": scenario("(" * (NEAR_MB // 2) + "1" + ")" * (NEAR_MB // 2)),
        "scenarios: 5,000 conflicting scenarios": CONFLICT
        + "".join(body.replace("cruise_band", f"b{i}") for i in range(5_000)),
    }


def map_inputs() -> dict[str, str]:
    wide = '<width sOffset="0" a="3.5" b="0" c="0" d="0"/>'
    left = "".join(f'<lane id="{i}" type="driving">{wide}</lane>' for i in range(3, 0, -1))
    right = "".join(f'<lane id="{-i}" type="driving">{wide}</lane>' for i in range(1, 3))
    five = (
        f'<laneSection s="0"><left>{left}</left><center><lane id="0" type="none"/></center>'
        f"<right>{right}</right></laneSection>"
    )

    def apart(roads: list[str]) -> list[str]:
        return [r.replace('y="0"', f'y="{50 * i}"') for i, r in enumerate(roads)]

    return {
        "maps: an arc of curvature 1e6 (600 bytes)": xodr(
            road_xml(length=10, geometry='<arc curvature="1e6"/>')
        ),
        "maps: a road of 1e300 m": xodr(road_xml(length=1e300)),
        "maps: paramPoly3 coefficients of 1e300": xodr(
            road_xml(
                length=50,
                geometry='<paramPoly3 aU="0" bU="1" cU="0" dU="1e300" aV="0" bV="0" cV="0" '
                'dV="1e300" pRange="arcLength"/>',
            )
        ),
        "maps: the most road within the budget (2 x 99 km, 5 lanes)": xodr(
            *apart([road_xml(str(i), length=99_000, lanes=five) for i in range(2)])
        ),
        "maps: 1 MB of roads (beyond the surface budget)": xodr(
            *apart([road_xml(str(i), length=300) for i in range(2_000)])
        ),
    }


# ---- the tools ----------------------------------------------------------------------------


def check_and_run(folder: Path, figures: list[Figure], wanted: Callable[[str], bool]) -> None:
    for name, text in checker_inputs().items():
        if not wanted(name):
            continue
        path = folder / "input.osc"
        path.write_text(text, encoding="utf-8")
        wall, peak, last = run(["osc2check", "--output-format", "concise", str(path)], folder)
        figures.append(Figure(name, "osc2check", len(text.encode()), wall, peak, last))
    for name, text in map_inputs().items():
        if not wanted(name):
            continue
        (folder / "map.xodr").write_text(text, encoding="utf-8")
        (folder / "on_map.osc").write_text(scenario_on("map.xodr", "30kph"), encoding="utf-8")
        for tool in ("osc2check", "osc2run"):
            command = [tool, str(folder / "on_map.osc")] + (["-q"] if tool == "osc2run" else [])
            wall, peak, last = run(command, folder)
            figures.append(Figure(name, tool, len(text.encode()), wall, peak, last))


def server(folder: Path, figures: list[Figure], wanted: Callable[[str], bool]) -> None:
    from tests.osc2lsp.protocol.raw_client import RawClient, children

    cases = {
        "lsp: a 20 MB message": None,
        "lsp: 1e99999999 open": scenario("1e99999999"),
        "lsp: a 1 MB string literal open": scenario("1", f'    t: string = "{"a" * NEAR_MB}"\n'),
        "lsp: 1 MB of conflicting scenarios open": CONFLICT
        + "".join(CONFLICT.split("\n", 1)[1].replace("cruise_band", f"b{i}") for i in range(5_000)),
    }
    for name, text in cases.items():
        if not wanted(name):
            continue
        client = RawClient(folder / "lsp.log", settings={"diagnostics": {"verifyDelay": 0}})
        client.initialize()
        uri = (folder / "doc.osc").as_uri()
        start = time.perf_counter()
        if text is None:
            size = 20 * MB
            client.notify("$/osc2/bench", {"text": "x" * size})
            client.call("textDocument/hover", {"textDocument": {"uri": uri}, "position": {
                "line": 0, "character": 0}})  # fmt: skip
        else:
            size = len(text.encode())
            client.open(uri, text)
            client.diagnostics(uri, 1, timeout=300)
            # and the solver's, when it has any (the pushes stop changing)
            try:
                client.wait_for(lambda m: False, timeout=5)
            except TimeoutError:
                pass
        wall = time.perf_counter() - start
        pids = [client.process.pid, *children(client.process.pid)]
        peak = max(_hwm(pid) for pid in pids)
        client.close()
        figures.append(Figure(name, "osc2lsp", size, wall, peak, "answered"))


def _hwm(pid: int) -> int:
    try:
        for line in (Path("/proc") / str(pid) / "status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def campaign(folder: Path, figures: list[Figure], wanted: Callable[[str], bool]) -> None:
    name = "campaign: --resume with a 1 MB reason in a record"
    if not wanted(name):
        return
    (folder / "c.osc").write_text(scenario("1"), encoding="utf-8")
    out = folder / "campaign"
    run(["osc2run", str(folder / "c.osc"), "--runs", "2", "--jobs", "1", "--out", str(out), "-q"],
        folder)  # fmt: skip
    record = out / "runs" / "0" / "record.json"
    data = json.loads(record.read_text())
    data["outcome"]["reason"] = "<b>" * (NEAR_MB // 3)
    record.write_text(json.dumps(data))
    size = record.stat().st_size  # (the run is done again: its record is written anew)
    wall, peak, last = run(["osc2run", "--resume", str(out), "-q"], folder)
    figures.append(Figure(name, "osc2run", size, wall, peak, last))


def main() -> None:
    wanted_text = " ".join(sys.argv[1:])

    def wanted(name: str) -> bool:
        return not wanted_text or wanted_text in name

    figures: list[Figure] = []
    folder = Path(tempfile.mkdtemp(prefix="bench-limits-"))
    try:
        check_and_run(folder, figures, wanted)
        server(folder, figures, wanted)
        campaign(folder, figures, wanted)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    print(f"{'input':62} {'tool':9} {'size':>9} {'wall':>8} {'peak':>9}")
    for f in figures:
        over = f.seconds > LIMIT_SECONDS or f.peak > LIMIT_BYTES
        flag = "OVER" if over and f.size < MB else ""
        print(
            f"{f.name:62.62} {f.tool:9} {f.size / 1024:8.0f}K {f.seconds:7.1f}s "
            f"{f.peak / MB:8.0f}M {flag}"
        )
        if f.note:
            print(f"    {f.note}")
    print(
        "peak: the process's resident memory at its highest (osc2lsp: the server or its solver "
        "worker, whichever is larger); a figure over 1 GB or 60 s for an input under 1 MB is OVER"
    )


if __name__ == "__main__":
    main()
