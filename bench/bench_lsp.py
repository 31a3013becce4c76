"""Latency and memory of the language server on generated documents.

``python bench/bench_lsp.py`` (the default) compares documents of 60, 2,000 and
10,000 lines through the real protocol (the server runs as a subprocess,
driven by pygls' client, with its default settings), typing words into names:
``OSC2LSP_BENCH_WORDS`` (20) words of 4 keystrokes 150 ms apart, a pause of
1.5 s after each word:

* first diagnostics after a keystroke: ``didChange`` sent → the first
  ``publishDiagnostics`` of that version (the server's default 100 ms
  debounce included; on slow documents it is the syntax-first preview);
* hover, definition and completion p95 while the re-analysis runs: asked
  right after that first push, at names away from the edit;
* the analysis of a word's last keystroke done (a request that needs the
  current version answered);
* memory: the server's resident set after each word's pause (first, last and
  highest).

``python bench/bench_lsp.py LINES`` prints the detailed report for one size
(what follows), unless marked "in process"; ``python bench/bench_lsp.py startup
[RUNS]`` the start-up alone, on the small example (RUNS new processes, default 5):

* start-up: process start → `initialize` answered, and → first diagnostics of
  the document (grammar, library and analysis included);
* completion: on an analysed document, and while typing (right after each
  keystroke, when the latest analysis is a version behind);
* hover and definition on names across the document;
* diagnostics after an edit: `didChange` sent → `publishDiagnostics` for that
  version received (the debounce included);
* the same features called in process, without the protocol.

Targets (issue): completion p95 < 50 ms, hover and definition p95 < 30 ms,
diagnostics < 300 ms after the last keystroke, start-up < 1 s. Figures only,
no assertions: `python bench/bench_lsp.py [lines]`.
"""

from __future__ import annotations

import asyncio
import os
import re
import sys
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

from generate import generate  # noqa: E402
from lsprotocol import types  # noqa: E402
from pygls.lsp.client import BaseLanguageClient  # noqa: E402

URI = "file:///tmp/osc2lsp-bench/generated.osc"
SERVER = [sys.executable, "-m", "osc2lsp"]
OPTIONS: dict = {}


def pct(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q * (len(ordered) - 1))))]


def report(name: str, values: list[float], target: str = "") -> None:
    ms = [v * 1000 for v in values]
    print(
        f"  {name:<44} p50 {pct(ms, 0.5):7.1f} ms   p95 {pct(ms, 0.95):7.1f} ms"
        f"   (n={len(ms)}){'   target ' + target if target else ''}"
    )


def position(text: str, offset: int) -> types.Position:
    line = text.count("\n", 0, offset)
    start = text.rfind("\n", 0, offset) + 1
    return types.Position(line=line, character=len(text[start:offset].encode("utf-16-le")) // 2)


class Client(BaseLanguageClient):
    """A pygls client that records when each version's diagnostics arrive."""

    def __init__(self):
        super().__init__("osc2lsp-bench", "1")
        self.arrived: dict[int | None, float] = {}  # the first push of each version
        self.event = asyncio.Event()

        @self.feature(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
        def _diagnostics(params: types.PublishDiagnosticsParams):
            self.arrived.setdefault(params.version, time.perf_counter())
            self.event.set()

    async def wait_version(self, version: int, timeout: float = 30) -> float:
        deadline = time.perf_counter() + timeout
        while version not in self.arrived:
            self.event.clear()
            await asyncio.wait_for(self.event.wait(), max(deadline - time.perf_counter(), 0.01))
        return self.arrived[version]


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")])
    return env


async def start(text: str | None) -> tuple[Client, float, float | None]:
    """Start a server; returns the client, seconds to `initialize`, to first diagnostics."""
    client = Client()
    began = time.perf_counter()
    await client.start_io(*SERVER, env=_env())
    await client.initialize_async(
        types.InitializeParams(
            capabilities=types.ClientCapabilities(),
            root_uri=ROOT.as_uri(),
            initialization_options=OPTIONS,
        )
    )
    ready = time.perf_counter() - began
    client.initialized(types.InitializedParams())
    first = None
    if text is not None:
        client.text_document_did_open(
            types.DidOpenTextDocumentParams(
                text_document=types.TextDocumentItem(
                    uri=URI, language_id="osc2", version=1, text=text
                )
            )
        )
        first = await client.wait_version(1) - began
    return client, ready, first


async def stop(client: Client) -> None:
    await client.shutdown_async(None)
    client.exit(None)
    await client.stop()


def _doc(uri: str) -> types.TextDocumentIdentifier:
    return types.TextDocumentIdentifier(uri=uri)


def completion_points(text: str) -> list[int]:
    """Offsets right after `hero.`, inside `lane(`/`speed(`, after a number, in a block."""
    points = [m.end() for m in re.finditer(r"hero\.", text)][:30]
    points += [m.end() for m in re.finditer(r"(lane|speed)\(", text)][:30]
    points += [m.end() - 1 for m in re.finditer(r"elapsed\(\d+\.\d+s", text)][:20]
    points += [m.start() for m in re.finditer(r"(?m)^        \S", text)][:20]
    return points


def name_points(text: str) -> list[int]:
    return [
        m.start() + 1 for m in re.finditer(r"\b(gap_\d+|top_\d+|hero|change_lane|drive)\b", text)
    ][::7][:100]


async def protocol(text: str, debounce_note: str) -> None:
    client, ready, first = await start(text)
    print(f"\nthrough the protocol ({text.count(chr(10))} lines, {debounce_note}):")
    doc = _doc(URI)
    comp = []
    for offset in completion_points(text):
        t = time.perf_counter()
        await client.text_document_completion_async(
            types.CompletionParams(text_document=doc, position=position(text, offset))
        )
        comp.append(time.perf_counter() - t)
    report("completion (analysed document)", comp, "p95 < 50 ms")
    hov, dfn = [], []
    for offset in name_points(text):
        t = time.perf_counter()
        await client.text_document_hover_async(
            types.HoverParams(text_document=doc, position=position(text, offset))
        )
        hov.append(time.perf_counter() - t)
        t = time.perf_counter()
        await client.text_document_definition_async(
            types.DefinitionParams(text_document=doc, position=position(text, offset))
        )
        dfn.append(time.perf_counter() - t)
    report("hover", hov, "p95 < 30 ms")
    report("definition", dfn, "p95 < 30 ms")

    # typing: write `hero.drive()` on a new line before a do-block statement, one
    # keystroke at a time, completing after the `.`; then wait for the diagnostics of
    # the last version
    typing, diag = [], []
    version = 1
    snippet = "hero.drive()"
    anchors = [
        text.count("\n", 0, m.start())
        for m in re.finditer(r"(?m)^        hero\.change_speed", text)
    ][:30]
    for done, anchor in enumerate(anchors):
        line = anchor + done  # each earlier edit added a line above
        for i, ch in enumerate(snippet):
            version += 1
            _insert(client, version, types.Position(line=line, character=8 + i), ch)
            if ch == ".":
                t = time.perf_counter()
                await client.text_document_completion_async(
                    types.CompletionParams(
                        text_document=doc, position=types.Position(line=line, character=9 + i)
                    )
                )
                typing.append(time.perf_counter() - t)
        version += 1
        _insert(client, version, types.Position(line=line, character=8 + len(snippet)), "\n")
        version += 1
        _insert(client, version, types.Position(line=line + 1, character=0), " " * 8)
        sent = time.perf_counter()
        arrived = await client.wait_version(version)
        diag.append(arrived - sent)
    report("completion right after a keystroke", typing, "p95 < 50 ms")
    report("diagnostics after the last keystroke", diag, "< 300 ms")
    await stop(client)
    print(
        f"  start-up: initialize answered after {ready * 1000:.0f} ms; first diagnostics "
        f"of the document after {first * 1000:.0f} ms"
    )


def _insert(client: Client, version: int, at: types.Position, text: str) -> None:
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=version),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=at, end=at), text=text
                )
            ],
        )
    )


async def startup(runs: int = 5) -> None:
    ready, first = [], []
    small = (ROOT / "examples" / "cut_in_and_stop.osc").read_text(encoding="utf-8")
    for _ in range(runs):
        client, r, f = await start(small)
        ready.append(r)
        first.append(f)
        await stop(client)
    print("\nstart-up (new process each time, small example document):")
    report("process start -> initialize answered", ready, "< 1 s")
    report("process start -> first diagnostics", first)
    after = [f - r for f, r in zip(first, ready, strict=True) if f is not None]
    report("initialize answered -> first diagnostics", after, "< 300 ms")


def in_process(text: str) -> None:
    from osc2lsp.features.completion import complete
    from osc2lsp.features.hover import hover
    from osc2lsp.features.navigation import definition
    from osc2lsp.session.analysis import analyse, snapshot_of

    print("\nin process (the feature functions alone):")
    analysis = []
    for _ in range(5):
        t = time.perf_counter()
        snap = snapshot_of(text, URI)
        analysis.append(time.perf_counter() - t)
    report("analysis with the solver (both phases)", analysis)
    quick = []
    for _ in range(5):
        t = time.perf_counter()
        analyse([(URI, text, 1)], None, verify=False)
        quick.append(time.perf_counter() - t)
    report("analysis without the solver (first phase)", quick)
    report("  after a keystroke (incremental parse)", _after_keystroke(snap, text))
    comp, hov, dfn = [], [], []
    for offset in completion_points(text):
        t = time.perf_counter()
        complete(snap, text, offset)
        comp.append(time.perf_counter() - t)
    for offset in name_points(text):
        t = time.perf_counter()
        hover(snap, offset)
        hov.append(time.perf_counter() - t)
        t = time.perf_counter()
        definition(snap, offset)
        dfn.append(time.perf_counter() - t)
    report("completion", comp)
    report("hover", hov)
    report("definition", dfn)


def _after_keystroke(snap, text: str) -> list[float]:
    """The first phase after one letter typed into names across the document, the parse
    made from the snapshot's as the server makes it (``Revision.parse``)."""
    from osc2lsp.session.analysis import analyse
    from osc2lsp.session.documents import Revision

    times = []
    for m in list(re.finditer(r"keep\(top_", text))[::7][:10]:
        at = m.end() - 1
        new = text[:at] + "x" + text[at:]
        t = time.perf_counter()
        revision = Revision(URI, snap.key, new, 2, False, snap)
        parsed = revision.parse()
        analyse([(URI, new, 2)], None, False, {URI: parsed} if parsed is not None else None)
        times.append(time.perf_counter() - t)
    return times


def rss_mb(pid: int) -> float:
    """Resident set of process ``pid`` in MB (Linux; 0 elsewhere)."""
    try:
        with open(f"/proc/{pid}/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return 0.0


@dataclass
class Keystrokes:
    lines: int
    first: list[float]  # keystroke -> first diagnostics of its version
    analysed: list[float]  # a word's last keystroke -> its analysis done
    hover: list[float]
    definition: list[float]
    completion: list[float]
    memory: list[float]  # server RSS after each word (and its pause)


async def keystrokes(
    text: str, words: int, per_word: int = 4, interval: float = 0.15, pause: float = 1.5
) -> Keystrokes:
    """Typing into names of the document: ``words`` words of ``per_word`` keystrokes,
    ``interval`` seconds apart (letters typed, then deleted by the next word), with a
    ``pause`` after each word. After each keystroke's first diagnostics, the questions
    an editor asks while the re-analysis runs."""
    client, _, _ = await start(text)
    doc = _doc(URI)
    lines = text.split("\n")
    targets = [i for i, line in enumerate(lines) if line.startswith("    keep(top_")]
    names = [i for i, line in enumerate(lines) if line.startswith("    hero: vehicle")]
    result = Keystrokes(text.count("\n"), [], [], [], [], [], [])
    pid = client._server.pid if client._server is not None else 0
    version, n = 1, 0
    for word in range(words):
        line = targets[(word // 2 * 7) % len(targets)]
        column = len("    keep(top")
        for k in range(per_word):
            version, n = version + 1, n + 1
            sent = time.perf_counter()
            if word % 2 == 0:  # type "xxxx" into `top_5`, one letter at a time
                _insert(client, version, types.Position(line=line, character=column + k), "x")
            else:  # and delete it again, backwards
                at = types.Position(line=line, character=column + per_word - 1 - k)
                _delete(client, version, at)
            result.first.append(await client.wait_version(version) - sent)
            # While the analysis runs: questions about other lines.
            other = names[(n * 13 + len(names) // 2) % len(names)]
            name = types.Position(line=other, character=5)
            t = time.perf_counter()
            await client.text_document_hover_async(
                types.HoverParams(text_document=doc, position=name)
            )
            result.hover.append(time.perf_counter() - t)
            t = time.perf_counter()
            await client.text_document_definition_async(
                types.DefinitionParams(text_document=doc, position=name)
            )
            result.definition.append(time.perf_counter() - t)
            t = time.perf_counter()
            await client.text_document_completion_async(
                types.CompletionParams(
                    text_document=doc, position=types.Position(line=other + 1, character=4)
                )
            )
            result.completion.append(time.perf_counter() - t)
            await asyncio.sleep(max(0.0, sent + interval - time.perf_counter()))
        # documentSymbol answers from the current version's analysis: it is done then.
        await client.text_document_document_symbol_async(
            types.DocumentSymbolParams(text_document=doc)
        )
        result.analysed.append(time.perf_counter() - sent)
        await asyncio.sleep(pause)
        result.memory.append(rss_mb(pid))
    await stop(client)
    return result


def _delete(client: Client, version: int, at: types.Position) -> None:
    end = types.Position(line=at.line, character=at.character + 1)
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            text_document=types.VersionedTextDocumentIdentifier(uri=URI, version=version),
            content_changes=[
                types.TextDocumentContentChangePartial(
                    range=types.Range(start=at, end=end), text=""
                )
            ],
        )
    )


def compare(sizes: list[int], words: int) -> None:
    """The keystroke figures of documents of each size, side by side."""
    print(
        f"osc2lsp typing: {words} words of 4 keystrokes 150 ms apart, a 1.5 s pause after "
        f"each (letters typed into a name, then deleted); server defaults (debounce 100 ms, "
        f"preview after 50 ms); {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}"
    )
    runs = [asyncio.run(keystrokes(generate(size), words)) for size in sizes]
    header = "".join(f"{r.lines:>14,} lines" for r in runs)
    print(f"\n  {'':<46}{header}")

    def row(name: str, pick, q: float = 0.95, unit: str = "ms") -> None:
        cells = "".join(f"{pct([v * 1000 for v in pick(r)], q):>17.1f} {unit}" for r in runs)
        print(f"  {name:<46}{cells}")

    row("first diagnostics after a keystroke, p50", lambda r: r.first, 0.5)
    row("first diagnostics after a keystroke, p95", lambda r: r.first)
    row("analysis done after a word's last keystroke, p50", lambda r: r.analysed, 0.5)
    row("hover while re-analysis runs, p95", lambda r: r.hover)
    row("definition while re-analysis runs, p95", lambda r: r.definition)
    row("completion while re-analysis runs, p95", lambda r: r.completion)
    memory = "".join(
        f"{r.memory[0]:>6.0f} -> {r.memory[-1]:>4.0f} ({max(r.memory):.0f}) MB" for r in runs
    )
    print(f"  {'server memory, word 1 -> ' + str(words) + ' (highest)':<46}{memory}")
    base = pct([v * 1000 for v in runs[0].first], 0.95)
    for r in runs[1:]:
        ratio = pct([v * 1000 for v in r.first], 0.95) / base
        print(f"  first diagnostics p95, {r.lines:,} lines / {runs[0].lines:,} lines: {ratio:.1f}x")


def main() -> None:
    if sys.argv[1:2] == ["startup"]:  # start-up alone: `bench_lsp.py startup [RUNS]`
        asyncio.run(startup(int(sys.argv[2]) if len(sys.argv) > 2 else 5))
        return
    if len(sys.argv) > 1:
        if not sys.argv[1].isdigit():
            print(__doc__)
            print("usage: python bench/bench_lsp.py [LINES | startup [RUNS]]")
            sys.exit(0 if sys.argv[1] in ("-h", "--help") else 2)
        lines = int(sys.argv[1])
        text = generate(lines)
        print(
            f"osc2lsp latency, generated document of {text.count(chr(10))} lines, "
            f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}"
        )
        asyncio.run(startup())
        asyncio.run(protocol(text, "server default debounce 100 ms"))
        in_process(text)
        return
    compare([60, 2000, 10_000], int(os.environ.get("OSC2LSP_BENCH_WORDS", "20")))


if __name__ == "__main__":
    main()
