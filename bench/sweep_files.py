"""Robustness sweep of the command-line tools over other people's files.

Every ``.osc`` under the third-party folder (``OSC2_THIRD_PARTY``: ``carla``,
``scenario_execution``, ``py-osc2``, ``scena``) and the conformance folder
(``OSC2_CONFORMANCE``) is checked with ``osc2check`` (time-boxed); each file the checker
passes without errors is run with ``osc2run`` for a bounded simulated duration (each
root scenario when the file has several). One line per file, then a summary table.

What it looks for (the charter): a traceback or an internal error on stderr; a hang
(a command over its wall-clock box); a runner refusing a checked file with findings the
checker did not give (A308 in both, same code, place and message, is agreement); a run
that fails, to be read against what the scenario's author meant.

Usage: ``python bench/sweep_files.py [--jobs 2] [--duration 120] [--only SUBSTRING]
[--out /tmp/sweep]``. The figures are the machine's and the corpora's of the day; wall
times are not asserted anywhere.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
EXAMPLE_PLUGIN = REPO / "examples" / "plugins" / "example_plugin.py"
BIN = Path(sys.executable).parent
FINDING = re.compile(
    r"^(?P<path>.+?):(?P<line>\d+):(?P<col>\d+): (?P<code>[A-Z]\d{3}) \[\w+\] (?P<msg>.*)$"
)  # a finding of the runner's refusal, in the full format
CHOICES = re.compile(r"choose one with --scenario: ([^)]*)\)")
BROKEN = ("Traceback (most recent call last)", "internal error")


@dataclass
class Outcome:
    path: str
    kind: str  # the summary's column
    detail: str = ""
    runs: list[tuple[str, str, str]] = field(default_factory=list)  # (scenario, kind, detail)


def _call(argv: list[str], box: float) -> tuple[int | None, str, str]:
    """Exit status (None: over the box, killed), stdout, stderr."""
    proc = subprocess.Popen(
        argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
    )
    try:
        out, err = proc.communicate(timeout=box)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        return None, out, err
    return proc.returncode, out, err


def _broken(stderr: str) -> str | None:
    for line in stderr.splitlines():
        if any(b in line for b in BROKEN):
            return line.strip()[:200]
    return None


def _options(path: Path, third_party: Path | None, config: Path | None) -> list[str]:
    """The options a user of that project gives: CARLA's dialect, scenario_execution's
    module map and the example plug-in (its ``log`` action), DSL 2.2 for Scena's files
    (its scenarios, and its test cases in the conformance folder's ``scena-2.2``)."""
    if "scena-2.2" in path.parts:
        return ["--osc-version", "2.2"]
    if third_party is None or not path.is_relative_to(third_party):
        return []
    project = path.relative_to(third_party).parts[0]
    if project == "scena":
        return ["--osc-version", "2.2"]
    if project == "carla":
        return ["--dialect", "carla"]
    if project == "scenario_execution" and config is not None:
        return ["--config", str(config)]
    return []


def _module_map(root: Path, out: Path) -> Path:
    """scenario_execution's ``osc.<name>`` -> ``lib_osc/<name>.osc``, as its users map it."""
    modules = {f"osc.{p.stem}": str(p) for p in sorted(root.glob("**/lib_osc/*.osc"))}
    modules.pop("osc.standard", None)
    lines = ["[modules]"] + [f'"{k}" = "{v}"' for k, v in modules.items()]
    lines.append(f'plugins = ["{EXAMPLE_PLUGIN}"]')
    path = out / "scenario_execution.toml"
    # plugins is a top-level key: write it before the table
    path.write_text("\n".join([lines[-1], *lines[:-1]]) + "\n", encoding="utf-8")
    return path


def sweep_file(path: Path, options: list[str], args) -> Outcome:
    cache = ["--no-cache"] if args.no_cache else []
    argv = [str(BIN / "osc2check"), "--output-format", "json", *cache, *options, str(path)]
    rc, out, err = _call(argv, args.check_box)
    if rc is None:
        return Outcome(str(path), "hang", f"osc2check over {args.check_box:g} s")
    if broken := _broken(err):
        return Outcome(str(path), "internal", f"osc2check: {broken}")
    try:
        report = json.loads(out)
    except json.JSONDecodeError:
        return Outcome(str(path), "internal", f"osc2check rc={rc}, no JSON: {err.strip()[:200]}")
    findings = report.get("findings", [])
    errors = [f for f in findings if f["severity"] == "error"]
    if errors:
        codes = Counter(f["code"] for f in errors)
        return Outcome(str(path), "rejected", " ".join(f"{c}x{n}" for c, n in codes.items()))
    refusing = sorted(
        (f["code"], f["location"]["start"]["line"], f["location"]["start"]["column"], f["message"])
        for f in findings
        if f["code"] == "A308"
    )
    outcome = Outcome(str(path), "clean")
    pending: list[str | None] = [None]
    tried: set[str | None] = set()
    while pending:
        name = pending.pop(0)
        if name in tried:
            continue
        tried.add(name)
        outcome.runs.append(_run(path, name, options, refusing, args, pending))
    outcome.runs = [r for r in outcome.runs if r[1] != "choose"]
    return outcome


def _run(path: Path, name, options, refusing, args, pending) -> tuple[str, str, str]:
    label = name or "-"
    out_dir = Path(args.out) / re.sub(r"[^\w.-]", "_", f"{path.parent.name}_{path.stem}_{label}")
    shutil.rmtree(out_dir, ignore_errors=True)
    argv = [str(BIN / "osc2run"), str(path), "-q", "--duration", str(args.duration)]
    argv += ["--out", str(out_dir), *options] + (["--scenario", name] if name else [])
    argv += ["--no-cache"] if args.no_cache else []
    rc, out, err = _call(argv, args.run_box)
    if rc is None:
        return label, "hang", f"osc2run over {args.run_box:g} s"
    if broken := _broken(err):
        return label, "internal", broken
    if choices := CHOICES.search(err):
        pending.extend(c.strip() for c in choices.group(1).split(","))
        return label, "choose", ""
    if "declares no scenario" in err:
        return label, "library", ""
    run_json = out_dir / "run.json"
    if run_json.is_file():
        result = json.loads(run_json.read_text(encoding="utf-8"))["outcome"]
        status = result["status"]
        kinds = {"success": "success", "failure": "failed", "timeout": "timeout"}
        kind = kinds.get(status, "internal")  # `error`: non-finite physics or a bug
        return label, kind, f"{status} at {result.get('time')}: {result.get('reason', '')}"[:300]
    got = sorted(
        (m["code"], int(m["line"]), int(m["col"]), m["msg"])
        for m in map(FINDING.match, err.splitlines())
        if m
    )
    if got and got == refusing:
        return label, "refused", ",".join(sorted({g[0] for g in got}))
    return label, "mismatch", f"rc={rc}: {err.strip()[-300:]}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--duration", type=float, default=120.0, help="simulated seconds")
    parser.add_argument("--only", default="", help="only paths containing this")
    parser.add_argument("--out", default="/tmp/sweep")
    parser.add_argument("--no-cache", action="store_true")
    parser.add_argument("--check-box", type=float, default=60.0, help="wall-clock s per check")
    parser.add_argument("--run-box", type=float, default=120.0, help="wall-clock s per run")
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    third = os.environ.get("OSC2_THIRD_PARTY")
    third_party = Path(third) if third else None
    conformance = Path(os.environ.get("OSC2_CONFORMANCE", REPO.parent / "shared" / "conformance"))
    files: list[Path] = []
    if third_party is not None:
        files += sorted(third_party.rglob("*.osc"))
    if conformance.is_dir():
        files += sorted(conformance.rglob("*.osc"))
    files = [f for f in files if args.only in str(f)]
    if not files:
        print("no files: set OSC2_THIRD_PARTY and/or OSC2_CONFORMANCE", file=sys.stderr)
        return 2
    se = third_party / "scenario_execution" if third_party else None
    config = _module_map(se, out) if se is not None and se.is_dir() else None

    def one(path: Path) -> Outcome:
        return sweep_file(path, _options(path, third_party, config), args)

    table: Counter[str] = Counter()
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for o in pool.map(one, files):
            table["files"] += 1
            table[o.kind] += 1
            runs = "; ".join(f"{s}={k}{' ' + d if d else ''}" for s, k, d in o.runs)
            print(f"{o.kind:9} {o.path} {o.detail}{runs}", flush=True)
            for _, kind, _ in o.runs:
                table[f"run:{kind}"] += 1
    ran = sum(table[f"run:{k}"] for k in ("success", "failed", "timeout"))
    rows = [
        ("files", table["files"]),
        ("checked clean (no error)", table["clean"]),
        ("rejected by the checker", table["rejected"]),
        ("checker internal error", table["internal"]),
        ("checker over its box (hang)", table["hang"]),
        ("roots run", ran),
        ("  success", table["run:success"]),
        ("  failed (read each: ours or the scenario's)", table["run:failed"]),
        ("  time limit reached", table["run:timeout"]),
        ("refused with the checker's A308", table["run:refused"]),
        ("refused otherwise (mismatch)", table["run:mismatch"]),
        ("libraries (no scenario)", table["run:library"]),
        ("runner internal error", table["run:internal"]),
        ("runner over its box (hang)", table["run:hang"]),
    ]
    print("\nsummary")
    for name, count in rows:
        print(f"  {name:46} {count}")
    bad = sum(table[k] for k in ("internal", "hang", "run:internal", "run:hang", "run:mismatch"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
