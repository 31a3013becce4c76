"""The garbage collector's pause is counted: threads that pause at once never turn
the collector on under each other, nor leave it off."""

from __future__ import annotations

import gc
import subprocess
import sys
import threading

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.gc_pause import gc_paused, pauses
from osc2check.syntax import parse

TEXT = "scenario s:\n    hero: vehicle\n    x: int = 1\n    keep(x > 0)\n" * 40


def _in_thread(target) -> threading.Thread:
    thread = threading.Thread(target=target)
    thread.start()
    return thread


def test_the_collector_stays_off_until_the_last_of_two_threads_ends_its_pause():
    gc.enable()
    a_in, b_in, a_out = threading.Event(), threading.Event(), threading.Event()
    seen: list[bool] = []

    def first():
        with gc_paused():
            a_in.set()
            b_in.wait(10)
        a_out.set()  # the first pause ended while the second runs

    def second():
        a_in.wait(10)
        with gc_paused():
            b_in.set()
            a_out.wait(10)
            seen.append(gc.isenabled())

    threads = [_in_thread(first), _in_thread(second)]
    for t in threads:
        t.join(10)
    assert seen == [False]
    assert gc.isenabled() and pauses() == 0


def test_a_pause_leaves_a_disabled_collector_disabled():
    gc.disable()
    try:
        with gc_paused(), gc_paused():
            assert not gc.isenabled()
        assert not gc.isenabled() and pauses() == 0
    finally:
        gc.enable()


def test_a_pause_ends_when_its_body_raises():
    gc.enable()
    try:
        with gc_paused():
            raise KeyError("x")
    except KeyError:
        pass
    assert gc.isenabled() and pauses() == 0


def test_no_collection_runs_while_threads_parse_and_analyse_at_once():
    """Automatic collections while any parse or analysis runs would mean one thread
    turned the collector on under another."""
    gc.enable()
    during: list[int] = []

    def watch(phase: str, info: dict) -> None:
        if phase == "start" and pauses():
            during.append(info["generation"])

    def parsing():
        for _ in range(30):
            parse(TEXT[: len(TEXT) // 4], "/tmp/a.osc")

    def analysing():
        for _ in range(3):
            analyze([SourceInput("/tmp/b.osc", TEXT)], AnalysisOptions(verify=False))

    gc.callbacks.append(watch)
    try:
        threads = [_in_thread(parsing), _in_thread(analysing), _in_thread(parsing)]
        for t in threads:
            t.join(120)
    finally:
        gc.callbacks.remove(watch)
    assert during == []
    assert gc.isenabled() and pauses() == 0


def test_the_command_runs_with_the_collector_off_and_a_pause_leaves_it_off(tmp_path):
    """The ``osc2check`` process ends with its command: its collector stays off before and
    after the analysis's pause (the time spent reading and writing the cache)."""
    path = tmp_path / "case.osc"
    path.write_text(TEXT, encoding="utf-8")
    code = (
        "import atexit, gc, sys\n"
        "atexit.register(lambda: print('collector on:', gc.isenabled()))\n"
        "from osc2check.results import run\n"
        f"sys.argv[1:] = ['--no-cache', {str(path)!r}]\n"
        "run()\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert proc.stdout.splitlines()[-1] == "collector on: False", proc.stderr
