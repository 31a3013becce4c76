"""Parse and analysis speed and memory of osc2check.

Prints, for the bundled standard library and for a generated 10,000-line
scenario file: parse time (and lines per second), the parse's stages, full analysis
time, peak memory; and the wall time of `osc2check` on one small file, interpreter
start included. `--parse` prints the generated file's parse figures only.
Targets (issue 2): 10,000 lines parsed < 0.5 s, analysed < 1.0 s; one small
file < 0.5 s wall.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from generate import generate  # noqa: E402

from osc2check.analysis import AnalysisOptions, SourceInput, analyze  # noqa: E402
from osc2check.semantics.stdlib import standard_library  # noqa: E402
from osc2check.syntax import parse  # noqa: E402


def timed(fn, repeat: int = 5) -> tuple[float, float]:
    """Median and best CPU-independent wall time of ``fn`` over ``repeat`` runs."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times)


def peak_memory(fn) -> float:
    tracemalloc.start()
    fn()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / 2**20


def stages(text: str) -> None:
    """The parse's stages on ``text``: the lexer, the indentation post-lexer (layout), the
    LALR automaton over the cached tables with the AST builder, and that automaton with
    callbacks that only group children (so the builder's share shows). The collector is
    paused, as ``parse`` pauses it: otherwise its passes over the objects made would be
    most of each stage's time."""
    from osc2check.gc_pause import gc_paused
    from osc2check.syntax import parser as syntax_parser
    from osc2check.syntax.indent import indent
    from osc2check.syntax.lexer import tokenize
    from osc2check.syntax.tables import automaton, drive, finish, lark_parser, parse_tables

    lexed = tokenize(text)
    tokens, layout = indent(lexed.tokens, text)
    with gc_paused():
        lex, _ = timed(lambda: tokenize(text))
        lay, _ = timed(lambda: indent(lexed.tokens, text))
        seg, _ = timed(
            lambda: syntax_parser.parse_segments("g", text, tokens, lexed.errors, layout, 0, 1)
        )
    tables = parse_tables()
    starts = [*syntax_parser.segment_starts(tokens), len(tokens)]
    grouping = automaton(tables, object())  # no methods: every rule's value is an Inline

    def bare() -> None:
        for a, b in zip(starts, starts[1:], strict=False):
            states, values = [tables.start], []
            drive(grouping, states, values, tokens[a:b])
            finish(grouping, states, values)

    with gc_paused():
        alone, _ = timed(bare)
    print(
        f"  stages: lexer {lex * 1000:.0f} ms, layout (indentation) {lay * 1000:.0f} ms, "
        f"LALR with the AST builder {seg * 1000:.0f} ms, of which the automaton alone "
        f"{alone * 1000:.0f} ms ({len(tokens)} tokens; lark is not imported)"
    )
    lark = lark_parser(syntax_parser._BUILDER)

    def larks() -> None:
        for a, b in zip(starts, starts[1:], strict=False):
            interactive = lark.parse_interactive(start="start")
            for tok in tokens[a:b]:
                interactive.feed_token(tok)
            interactive.feed_eof()

    with gc_paused():
        theirs, _ = timed(larks)
    print(
        f"  lark's own LALR parser over the same tokens, with the same builder: "
        f"{theirs * 1000:.0f} ms (the tables' driver with the builder: {seg * 1000:.0f} ms)"
    )


def parse_figures(text: str) -> None:
    """The parse of ``text``: median and best of five, lines per second, its stages."""
    med, best = timed(lambda: parse(text, "generated.osc"))
    print(
        f"  parse:    median {med * 1000:.0f} ms, best {best * 1000:.0f} ms, "
        f"{text.count(chr(10)) / med:,.0f} lines/s   (target < 500 ms)"
    )
    stages(text)


def main() -> None:
    if sys.argv[1:] == ["--parse"]:
        text = generate(10_000)
        print(f"generated file: {text.count(chr(10))} lines, {len(text) / 1024:.0f} KiB")
        parse(text, "generated.osc")  # the tables, from the cache, and the first parse
        parse_figures(text)
        return
    start = time.perf_counter()
    standard_library()
    print(
        f"standard library: parse + resolve once per process: "
        f"{(time.perf_counter() - start) * 1000:.0f} ms (includes grammar load)"
    )
    lib_text = "\n".join(p.read_text() for p in sorted((ROOT / "stdlib").glob("*.osc")))
    med, best = timed(lambda: parse(lib_text, "stdlib"))
    print(
        f"standard library text ({lib_text.count(chr(10))} lines): parse median "
        f"{med * 1000:.0f} ms, best {best * 1000:.0f} ms"
    )

    text = generate(10_000)
    lines = text.count("\n")
    sources = [SourceInput("generated.osc", text)]
    core = AnalysisOptions(verify=False)  # names, types, units, arguments: no solver
    check = analyze(sources, core)
    errors = [d for d in check.diagnostics if d.severity.name == "ERROR"]
    scenarios = text.count("\nscenario ")
    print(
        f"generated file: {lines} lines, {len(text) / 1024:.0f} KiB, {scenarios} scenarios, "
        f"{len(check.diagnostics)} findings ({len(errors)} errors) before verification"
    )
    parse_figures(text)
    med, best = timed(lambda: analyze(sources, core), repeat=3)
    print(
        f"  analysis: median {med * 1000:.0f} ms, best {best * 1000:.0f} ms   "
        "(parse, names, types, units, arguments; target < 1000 ms)"
    )
    print(
        f"  peak memory of one analysis: {peak_memory(lambda: analyze(sources, core)):.0f} MiB "
        "(traced Python allocations)"
    )
    med, best = timed(lambda: analyze(sources), repeat=1)
    print(
        f"  with verification of all {scenarios} scenarios (z3): {med * 1000:.0f} ms "
        f"({med / max(scenarios, 1) * 1000:.1f} ms per scenario; see bench_verify.py)"
    )

    example = ROOT / "examples" / "cut_in_and_stop.osc"
    cmd = [sys.executable, "-m", "osc2check.cli", "--output-format", "concise", str(example)]
    walls = []
    for _ in range(5):
        start = time.perf_counter()
        subprocess.run(cmd, cwd=ROOT, capture_output=True, check=False)
        walls.append(time.perf_counter() - start)
    print(
        f"osc2check on one small file, interpreter start included: median "
        f"{statistics.median(walls) * 1000:.0f} ms, best {min(walls) * 1000:.0f} ms "
        "(target < 500 ms)"
    )


if __name__ == "__main__":
    main()
