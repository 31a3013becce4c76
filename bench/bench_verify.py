"""Speed of the verification layer (constraints, placement, witnesses).

Prints, for inputs generated as OSC2 text:

* a 20-actor scenario of about 300 constraints: full analysis, lowering, deciding it
  (``z3_backend.check``: propagation first, z3 if needed) and solving it with z3 alone
  (target: median under 100 ms after the analysis);
* one conflict among about 1,000 constraints: finding the minimal core (target < 500 ms);
* witnesses: the first one, and each additional sample (target < 10 ms per sample).

Figures only; tests never assert on time.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from osc2check.analysis import AnalysisOptions, SourceInput, analyze  # noqa: E402
from osc2check.verify.check import source_text  # noqa: E402
from osc2check.verify.flow import scenarios_of  # noqa: E402
from osc2check.verify.pipeline import lower_scenario  # noqa: E402
from osc2check.verify.terms import member_declarations  # noqa: E402
from osc2check.verify.z3_backend import (  # noqa: E402
    Encoder,
    Sampler,
    SolverOutcome,
    active_constraints,
    check,
    load_z3,
    solve,
)


def many_actors(actors: int = 20) -> str:
    """A convoy in three lanes: every actor placed relative to the one ahead, with
    parameters for gaps and speeds and keeps between them."""
    lines = ["import osc.standard", "", "scenario convoy:"]
    for i in range(actors):
        lines.append(f"    a{i}: vehicle")
    for i in range(actors):
        lines += [
            f"    gap{i}: length with:",
            f"        keep(default it == {10 + i % 7}m)",
            f"    v{i}: speed",
            f"    keep(v{i} in [{40 + i % 5}kph..{110 - i % 9}kph])",
            f"    keep(v{i} != {60 + i}kph)",
            f"    keep(gap{i} in [5m..40m])",
            f"    keep(gap{i} >= {5 + i % 3}m)",
        ]
        if i:
            lines += [f"    keep(v{i} <= v{i - 1} + 5kph)", f"    keep(gap{i} + gap{i - 1} <= 70m)"]
    lines.append("    do parallel:")
    for i in range(actors):
        lines += [f"        a{i}.drive(duration: 30s) with:", f"            speed(v{i}, at: start)"]
        if i < 3:
            lines.append(f"            lane({i + 1}, at: start)")
        else:
            lines += [
                f"            lane(same_as: a{i - 3}, at: start)",
                f"            position(distance: gap{i}, behind: a{i - 3}, at: start)",
            ]
    return "\n".join(lines) + "\n"


def one_conflict(params: int = 100, keeps: int = 1000) -> str:
    """About ``keeps`` keeps over ``params`` speeds, and one pair that cannot hold."""
    lines = ["import osc.standard", "", "scenario crowded_constraints:", "    hero: vehicle"]
    lines += [f"    p{i}: speed" for i in range(params)]
    count = 0
    i = 0
    while count < keeps - 2:
        a, b = i % params, (i * 7 + 3) % params
        if i < params:
            lines.append(f"    keep(p{a} in [{i % 50}kph..{200 + i % 50}kph])")
        elif a != b:
            lines.append(f"    keep(p{a} + p{b} <= {400 + i % 100}kph)")
        else:
            lines.append(f"    keep(p{a} >= 0kph)")
        count += 1
        i += 1
    lines.insert(len(lines) - keeps // 2, "    keep(p17 >= 190kph)")  # the conflict...
    lines.append("    keep(p17 <= 150kph)")  # ...with this one
    lines += ["    do hero.drive(duration: 10s) with:", "        lane(1, at: start)"]
    return "\n".join(lines) + "\n"


def timed(fn, repeat: int = 7) -> tuple[float, float, object]:
    times = []
    result = None
    for _ in range(repeat):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times) * 1000, min(times) * 1000, result


def lowered(text: str, name: str):
    sources = [SourceInput(f"{name}.osc", text)]

    analysis = analyze(sources, AnalysisOptions(verify=False))
    program = analysis.programs[f"{name}.osc"]
    (scenario,) = scenarios_of(program)
    text_of = source_text(program)
    decls = member_declarations(program.model)
    return (
        sources,
        program,
        scenario,
        lambda: lower_scenario(program.model, scenario, text_of, "default", decls),
    )


def main() -> None:
    start = time.perf_counter()
    load_z3()
    print(
        f"import z3: {(time.perf_counter() - start) * 1000:.0f} ms (once per process, "
        "only when a scenario needs the solver)"
    )

    # --- 20 actors, about 300 constraints -------------------------------------------------
    text = many_actors()
    sources, program, scenario, lower = lowered(text, "convoy")
    problem = lower()
    user = [c for c in problem.constraints if c.kind not in ("domain", "placement")]
    print(
        f"\n20-actor scenario: {text.count(chr(10))} lines, {len(problem.variables)} variables, "
        f"{len(problem.constraints)} constraints ({len(user)} written, the rest the road, "
        "the vehicles and the types' domains)"
    )
    med, best, analysis = timed(lambda: analyze(sources), repeat=5)
    status = analysis.verified["convoy.osc"].scenarios[0].outcome
    print(
        f"  full analysis (parse, resolve, lower, decide): median {med:.1f} ms, "
        f"best {best:.1f} ms  [{status.status} by {status.method}]"
    )
    med, best, _ = timed(lower)
    print(f"  lowering to the IR:                     median {med:.1f} ms, best {best:.1f} ms")
    med, best, outcome = timed(lambda: check(problem))
    print(
        f"  decide (check: propagation, else z3):    median {med:.1f} ms, best {best:.1f} ms"
        f"  [{outcome.status} by {outcome.method}]   (target < 100 ms)"
    )
    med, best, outcome = timed(lambda: solve(problem))
    print(
        f"  solve with z3 alone (fresh context):    median {med:.1f} ms, best {best:.1f} ms"
        f"  [{outcome.status}]   (target < 100 ms)"
    )

    # --- witnesses -------------------------------------------------------------------------
    result = analysis.verified["convoy.osc"].scenarios[0]
    seeds = iter(range(1000))
    med, best, _ = timed(lambda: result.witness_for(next(seeds)), repeat=7)
    print(
        f"  a witness from the analysis (sample + tables): median {med:.1f} ms, best {best:.1f} ms"
    )
    med, best, _ = timed(lambda: solve(problem, seed=1), repeat=5)
    print(f"  a witness from z3 (solve + one sample):   median {med:.1f} ms, best {best:.1f} ms")
    active = active_constraints(problem, SolverOutcome("sat"))
    base = check(problem).values
    sampler = Sampler(problem, active, base)
    sampler.sample(0)
    seeds = iter(range(1000))
    med, best, _ = timed(lambda: sampler.sample(next(seeds)), repeat=20)
    spread = {sampler.sample(s)["a0@start.s"] for s in range(10)}
    print(
        f"  each additional sample (drawn by propagation): median {med:.1f} ms, "
        f"best {best:.1f} ms   (target < 10 ms; {len(spread)} distinct starts of a0 "
        "in 10 seeds)"
    )
    ctx = load_z3().Context()
    enc = Encoder(problem, ctx)
    fallback = Sampler(problem, active, base, enc=enc)
    fallback.TRIES = 0  # straight to z3.Optimize
    fallback.sample(0)
    seeds = iter(range(1000))
    med, best, _ = timed(lambda: fallback.sample(next(seeds)), repeat=10)
    print(
        f"  each additional sample when propagation fails (one Optimize, push/pop): "
        f"median {med:.1f} ms, best {best:.1f} ms"
    )

    # --- one conflict among 1,000 constraints ------------------------------------------------
    text = one_conflict()
    sources, program, scenario, lower = lowered(text, "crowded")
    problem = lower()
    print(
        f"\none conflict among {len(problem.constraints)} constraints "
        f"({len(problem.variables)} variables):"
    )
    med, best, outcome = timed(lambda: check(problem), repeat=5)
    (conflict,) = outcome.conflicts
    members = [conflict.primary, *conflict.others]
    print(
        f"  minimal core (check, z3 with tracked constraints): median {med:.0f} ms, "
        f"best {best:.0f} ms   (target < 500 ms) -> {len(members)} constraints: "
        + "; ".join(f"line {c.span.line} `{c.text}`" for c in members)
    )
    med, best, analysis = timed(lambda: analyze(sources), repeat=3)
    print(
        f"  full analysis of the file ({text.count(chr(10))} lines):     median {med:.0f} ms, "
        f"best {best:.0f} ms  "
        f"[{', '.join(d.code.code for d in analysis.diagnostics)}]"
    )


if __name__ == "__main__":
    main()
