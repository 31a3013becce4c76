"""Scheduling of analyses: debounce, newer edits win, importers are re-checked."""

from __future__ import annotations

import asyncio
import gc
import weakref

import pytest

from osc2lsp.options import Options
from osc2lsp.session.memory import MAX_REPLACED
from osc2lsp.session.scheduler import State
from tests.osc2lsp.cli_findings import cli_findings
from tests.osc2lsp.lsp_helpers import CONFLICT


def _run(coro):
    return asyncio.run(coro)


def test_fresh_returns_the_analysis_of_the_current_version():
    async def scenario():
        published = []
        state = State(Options(debounce=5000), lambda trigger, snaps: published.append(snaps))
        state.open("file:///tmp/s.osc", "scenario a:\n", 1)
        state.change("file:///tmp/s.osc", "scenario b:\n", 2)
        state.change("file:///tmp/s.osc", "scenario c:\n", 3)
        snap = await state.fresh("file:///tmp/s.osc")  # does not wait out the debounce
        await state.shutdown()
        return snap, published

    snap, published = _run(scenario())
    assert snap.version == 3 and snap.text == "scenario c:\n"
    assert all(s.version in (1, 3) for batch in published for s in batch)


def test_a_change_re_checks_the_open_importers(tmp_path):
    lib, main = tmp_path / "lib.osc", tmp_path / "main.osc"
    lib.write_text("actor robot\n", encoding="utf-8")

    async def scenario():
        published: list[tuple[str, list[int]]] = []
        state = State(
            Options(debounce=0),
            lambda trigger, snaps: published.append((trigger, sorted(s.uri for s in snaps))),
        )
        state.open(lib.as_uri(), "actor robot\n", 1)
        state.open(main.as_uri(), 'import "lib.osc"\nscenario s:\n    r: robot\n', 1)
        first = await state.fresh(main.as_uri())
        state.change(lib.as_uri(), "actor droid\n", 2)
        second = await state.fresh(main.as_uri())
        await state.shutdown()
        return first, second

    first, second = _run(scenario())
    assert first.diagnostics == []
    assert [d.code.code for d in second.diagnostics] == ["N101"]


def test_closing_releases_waiters_and_state():
    async def scenario():
        state = State(Options(debounce=5000))
        state.open("file:///tmp/c.osc", "scenario a:\n", 1)
        waiter = asyncio.ensure_future(state.fresh("file:///tmp/c.osc"))
        state.close("file:///tmp/c.osc")
        result = await waiter
        await state.shutdown()
        return result, state.latest("file:///tmp/c.osc")

    assert _run(scenario()) == (None, None)


def test_closed_workspace_files_that_mention_a_name_are_analysed(tmp_path):
    (tmp_path / "lib.osc").write_text("actor robot\n", encoding="utf-8")
    (tmp_path / "user.osc").write_text(
        'import "lib.osc"\nscenario u:\n    r: robot\n', encoding="utf-8"
    )
    (tmp_path / "other.osc").write_text("actor robotic\n", encoding="utf-8")
    (tmp_path / ".hidden").mkdir()
    (tmp_path / ".hidden" / "x.osc").write_text("actor robot\n", encoding="utf-8")

    async def scenario():
        state = State(Options(), root=str(tmp_path))
        state.open((tmp_path / "lib.osc").as_uri(), "actor robot\n", 1)
        found = await state.closed_files("robot")
        again = await state.closed_files("robot")
        await state.shutdown()
        return found, again

    found, again = _run(scenario())
    assert [s.key.rsplit("/", 1)[-1] for s in found] == ["user.osc"]
    assert again[0] is found[0]  # cached until the file changes


@pytest.mark.slow
def test_the_solver_phase_adds_its_findings_after_the_first():
    async def scenario():
        batches: list[list] = []
        done = asyncio.Event()

        def publish(trigger, snaps):
            batches.append(
                [(s.verified, sorted({d.code.code for d in s.diagnostics})) for s in snaps]
            )
            if any(s.verified for s in snaps):
                done.set()

        state = State(Options(debounce=0, verify_delay=0), publish)
        state.open("file:///tmp/conflict.osc", CONFLICT, 1)
        await asyncio.wait_for(done.wait(), 600)  # a hang guard
        await state.shutdown()
        return batches

    batches = _run(scenario())
    assert batches[0] == [(False, [])]
    assert batches[-1][0][0] is True and "C401" in batches[-1][0][1]


def test_a_slow_documents_edit_is_previewed_before_it_is_analysed():
    text = "scenario a:\n    x: int = 1\n\nscenario b:\n    hreo: vehicle\n"
    edited = text.replace("x: int = 1", "x: int = (1")

    async def scenario():
        published: list[tuple[int | None, bool, list[str]]] = []
        analysed = asyncio.Event()

        def publish(trigger, found):
            for f in found:
                published.append((f.version, f.final, sorted(d.code.code for d in f.diagnostics)))
                if f.version == 2 and f.final:
                    analysed.set()

        state = State(Options(debounce=1, verify=False, preview_after=0), publish)
        uri = "file:///tmp/preview.osc"
        state.open(uri, text, 1)
        await state.fresh(uri)
        state.change(uri, edited, 2)
        await asyncio.wait_for(analysed.wait(), 600)  # a hang guard
        await state.shutdown()
        return [p for p in published if p[0] == 2]

    second = _run(scenario())
    preview, analysis = second[0], second[-1]
    assert preview[1] is False and analysis[1] is True
    assert "N101" in preview[2] and any(code.startswith("P") for code in preview[2])
    # the final analysis is what the checker finds in the edited text
    assert analysis[2] == [f[0] for f in cli_findings("file:///tmp/preview.osc", edited)]


def test_the_latest_snapshot_answers_outside_the_edited_text():
    v1 = "scenario s:\n    x: int = 1\n    keep(x > 0)\n"
    v2 = v1.replace("int = 1", "float = 1.5")

    async def scenario():
        state = State(Options(debounce=60_000, verify=False))
        uri = "file:///tmp/view.osc"
        state.open(uri, v1, 1)
        first = await state.fresh(uri)
        state.change(uri, v2, 2)
        outside = await state.view(uri, v2.index("x > 0"))
        inside = await state.view(uri, v2.index("float"))
        await state.shutdown()
        return first, outside, inside

    first, outside, inside = _run(scenario())
    assert outside is not None and outside[0] is first and outside[1] is not None
    assert inside is not None and inside[0].version == 2 and inside[1] is None


def test_replaced_snapshots_are_freed_without_the_cyclic_collector():
    """With automatic collection off, reference counting alone frees the replaced
    snapshots: at most ``MAX_REPLACED`` are kept while edits keep coming, none once
    the documents are quiet."""

    async def scenario():
        state = State(Options(debounce=0, verify=False))
        uri = "file:///tmp/garbage.osc"
        state.open(uri, "scenario s:\n    x: int = 1\n", 1)
        models = [weakref.ref((await state.fresh(uri)).model)]
        alive = []
        for version in range(2, 7):
            state.change(uri, f"scenario s:\n    x: int = {version}\n", version)
            models.append(weakref.ref((await state.fresh(uri)).model))
            await state.analysed()
            alive.append(sum(m() is not None for m in models))
        await state.quiet()
        freed = [m() is None for m in models]
        await state.shutdown()
        return alive, freed

    gc.disable()
    try:
        alive, freed = _run(scenario())
    finally:
        gc.enable()
    assert max(alive) == MAX_REPLACED + 1 and alive[-1] == MAX_REPLACED + 1
    assert freed == [True] * 5 + [False]


def test_requests_only_see_snapshots_whose_indexes_are_built():
    """A new snapshot becomes the latest once the analysis thread has built what requests
    use (names by position, line starts); while it does, the previous one answers, also
    when the new findings are already published."""
    text = "scenario s:\n    x: int = {}\n    keep(x > 0)\n"
    uri = "file:///tmp/indexes.osc"
    seen = []

    async def scenario():
        def publish(trigger, found):
            seen.append(state.latest(uri))

        state = State(Options(debounce=0, verify=False), publish)
        state.open(uri, text.format(1), 1)
        seen.append(await state.fresh(uri))
        for version in range(2, 5):
            state.change(uri, text.format(version), version)
            seen.append(await state.fresh(uri))
        await state.shutdown()

    _run(scenario())
    later = [snap for snap in seen if snap is not None and snap.version != 1]
    assert {snap.version for snap in later} == {2, 3, 4}
    assert all("_name_starts" in vars(snap) for snap in later)


def test_the_solvers_snapshot_keeps_the_built_indexes():
    from osc2lsp.session.analysis import snapshot_of

    snap = snapshot_of("scenario s:\n    x: int = 1\n").prepare()
    verified = snap.with_findings([])
    assert verified.verified and verified.diagnostics == []
    assert verified.lines is snap.lines and verified._name_starts is snap._name_starts
