"""The start-up cache: entries keyed, checked and rebuilt; findings never depend on it."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from osc2check import cache, fingerprint
from osc2check.semantics.profile import OSC_VERSIONS
from osc2check.semantics.stdlib import standard_library

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
# a clean file, one with findings of several kinds, one with a syntax error (the recovering
# parser), one on a built-in map other than the default
FILES = [
    EXAMPLES / "cut_in_and_stop.osc",
    EXAMPLES / "unsafe_typos.osc",
    EXAMPLES / "red_light_stop.osc",
]


@pytest.fixture
def folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("OSC2_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("OSC2_NO_CACHE", raising=False)
    return tmp_path / "cache"


def _check(
    folder: Path | None, *paths: Path, no_cache: bool = False, version: str | None = None
) -> tuple[int, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("OSC2_CACHE_DIR", "OSC2_NO_CACHE")}
    if folder is not None:
        env["OSC2_CACHE_DIR"] = str(folder)
    args = [sys.executable, "-m", "osc2check.cli", "--output-format", "concise"]
    if no_cache:
        args.append("--no-cache")
    if version is not None:
        args += ["--osc-version", version]
    done = subprocess.run(
        [*args, *map(str, paths)], env=env, capture_output=True, text=True, timeout=300
    )
    assert "Traceback" not in done.stderr, done.stderr
    return done.returncode, done.stdout


def test_an_entry_is_read_back_under_its_key_only(folder: Path) -> None:
    cache.store("probe", {"a": "1"}, {"value": (1, "two")})
    assert cache.load("probe", {"a": "1"}) == {"value": (1, "two")}
    assert cache.load("probe", {"a": "2"}) is None
    assert cache.load("other", {"a": "1"}) is None


def test_a_damaged_entry_is_ignored_and_written_again(folder: Path) -> None:
    cache.store("probe", {}, [1, 2, 3])
    (entry,) = folder.glob("probe-*.bin")
    data = entry.read_bytes()
    for damaged in (b"", data[: len(data) // 2], data[:-1] + bytes([data[-1] ^ 1]), b"x" * 999):
        entry.write_bytes(damaged)
        assert cache.load("probe", {}) is None
        assert cache.cached("probe", {}, lambda: [1, 2, 3]) == [1, 2, 3]
        assert cache.load("probe", {}) == [1, 2, 3]


def test_an_entry_independent_of_the_toolkit_outlives_a_new_version(
    folder: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    cache.store("probe", {}, "toolkit's")
    cache.store("probe-lark", {}, "lark's", toolkit=False)
    monkeypatch.setattr(fingerprint, "_toolkit", "another version of the toolkit")
    assert cache.load("probe", {}) is None
    assert cache.load("probe-lark", {}, toolkit=False) == "lark's"
    assert cache.load("probe-lark", {}) is None  # the two kinds of key never meet


def test_the_cache_off_neither_reads_nor_writes(folder: Path) -> None:
    cache.store("probe", {}, "stored")
    cache.set_enabled(False)
    try:
        assert cache.load("probe", {}) is None
        assert cache.cached("probe", {}, lambda: "built") == "built"
        assert os.environ["OSC2_NO_CACHE"] == "1"  # processes started now inherit it
    finally:
        cache.set_enabled(True)
    assert cache.load("probe", {}) == "stored"
    assert "OSC2_NO_CACHE" not in os.environ


def test_an_unwritable_folder_only_means_no_cache(tmp_path: Path, monkeypatch) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("OSC2_CACHE_DIR", str(blocker / "cache"))
    assert cache.cached("probe", {}, lambda: 42) == 42
    assert cache.load("probe", {}) is None


def test_old_entries_of_a_kind_are_pruned(folder: Path) -> None:
    for version in range(8):
        cache.store("probe", {"v": str(version)}, version)
    cache.store("probe-other", {}, "kept")  # a kind whose name begins like another's
    assert len(list(folder.glob("probe-????????????????.bin"))) <= 5
    assert cache.load("probe", {"v": "7"}) == 7
    assert cache.load("probe-other", {}) == "kept"


@pytest.mark.parametrize("version", OSC_VERSIONS)
def test_the_library_from_the_cache_is_the_library_built(folder: Path, version: str) -> None:
    built = standard_library(version)  # this process's, whichever way it came
    stored = cache.load("stdlib", _stdlib_key(version))
    if stored is None:  # this process built it with the cache elsewhere: store a copy
        cache.store("stdlib", _stdlib_key(version), built)
        stored = cache.load("stdlib", _stdlib_key(version))
    assert stored is not built
    assert [_symbol_row(s) for s in stored.model.symbols] == [
        _symbol_row(s) for s in built.model.symbols
    ]
    for table in dataclasses.fields(stored.model):  # every side table, those added later too
        value = getattr(stored.model, table.name)
        if hasattr(value, "__len__"):
            assert len(value) == len(getattr(built.model, table.name)), table.name
    assert sorted(stored.parses) == sorted(built.parses)
    for uri, result in built.parses.items():
        assert stored.parses[uri].text == result.text
        assert len(stored.parses[uri].ast.declarations) == len(result.ast.declarations)
    # identities the analysis relies on: a symbol's declaration is the AST node of the parse
    symbol = next(s for s in stored.model.symbols if s.decl is not None)
    assert stored.model.declarations[symbol.decl] is symbol


def _stdlib_key(version: str) -> dict[str, str]:
    from osc2check.resources import stdlib_dir
    from osc2check.semantics.stdlib import LIBRARY_FILES, VERSION_FILES
    from osc2check.syntax.grammar import grammar_key

    names = [*LIBRARY_FILES, *VERSION_FILES.get(version, {}).values()]
    texts = {str(stdlib_dir() / n): (stdlib_dir() / n).read_text("utf-8") for n in names}
    return {**grammar_key(), "version": version, "library": cache.digest(*texts, *texts.values())}


def _symbol_row(symbol) -> tuple[object, ...]:
    return (
        symbol.kind,
        symbol.qualified_name,
        symbol.uri,
        symbol.name_span,
        str(symbol.type) if symbol.type is not None else None,
        symbol.parent.qualified_name if symbol.parent is not None else None,
        symbol.doc,
    )


def test_garbage_and_eight_checkers_at_once_never_change_a_finding(tmp_path: Path) -> None:
    expected = _check(None, *FILES, no_cache=True)
    assert expected[0] == 1 and expected[1].count("\n") > 3  # findings to compare
    folder = tmp_path / "cache"
    # a cold cache, filled by eight checkers at once
    with ThreadPoolExecutor(8) as pool:
        results = list(pool.map(lambda _: _check(folder, *FILES), range(8)))
    assert results == [expected] * 8
    entries = sorted(folder.glob("*.bin"))
    assert {p.name.rsplit("-", 1)[0] for p in entries} >= {"stdlib", "parse-tables"}
    assert not list(folder.glob(".*.tmp"))  # every temporary file was renamed or removed
    # garbage in every entry: each checker reads it, rebuilds, writes it again
    for number, entry in enumerate(entries):
        entry.write_bytes(os.urandom(64 + number) if number % 2 else b"OSC2CACHE\n1 2 3\nxx")
    with ThreadPoolExecutor(8) as pool:
        results = list(pool.map(lambda _: _check(folder, *FILES), range(8)))
    assert results == [expected] * 8
    assert _check(folder, *FILES) == expected  # the rewritten entries, read back


def test_a_large_imported_file_is_parsed_again_only_where_it_changed(
    folder: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from osc2check import analysis
    from osc2check.analysis import IMPORT_CACHE_SIZE, SourceInput, analyze

    structs = [
        f"struct pose_{i}:\n    x: length = {i}m\n    y: length = 2 * x\n" for i in range(400)
    ]
    library = tmp_path / "lib.osc"
    library.write_text("import osc.standard\n\n" + "\n".join(structs))
    assert len(library.read_text()) >= IMPORT_CACHE_SIZE
    root = tmp_path / "root.osc"
    text = 'import "lib.osc"\n\nscenario s:\n    p: pose_7\n    q: pose_999\n'
    root.write_text(text)
    parsed: list[str] = []
    real_parse = analysis.parse
    monkeypatch.setattr(analysis, "parse", lambda t, u: parsed.append(u) or real_parse(t, u))

    def findings() -> list[tuple[int, str]]:
        found = analyze([SourceInput(str(root), text)]).diagnostics
        return [(d.span.line, d.code.code) for d in found if d.span.uri == str(root)]

    first = findings()
    assert first == [(5, "N101")] and str(library) in parsed
    assert len(list(folder.glob("parse-*.bin"))) == 1
    parsed.clear()
    assert findings() == first and str(library) not in parsed  # its parse, read back
    library.write_text(library.read_text().replace("pose_7:", "pose_seven:"))
    # the struct that changed is parsed again, into the last version's parse
    assert findings() == [(4, "N101"), (5, "N101")] and str(library) not in parsed
    assert len(list(folder.glob("parse-*.bin"))) == 1  # the newest version of each file


def test_a_large_checked_file_as_saved_is_parsed_again_only_where_it_changed(
    folder: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from osc2check import analysis
    from osc2check.analysis import IMPORT_CACHE_SIZE, SourceInput, analyze

    structs = [f"struct pose_{i}:\n    x: length = {i}m\n" for i in range(600)]
    text = "import osc.standard\n\n" + "\n".join(structs) + "\nscenario s:\n    p: pose_x\n"
    assert len(text) >= IMPORT_CACHE_SIZE
    root = str(tmp_path / "root.osc")
    parsed: list[str] = []
    real_parse = analysis.parse
    # (the parse of "" is what each check makes first: analysis._load_once)
    monkeypatch.setattr(analysis, "parse", lambda t, u: u and parsed.append(u) or real_parse(t, u))

    def findings(given: str, on_disk: bool) -> list[tuple[int, str]]:
        found = analyze([SourceInput(root, given, on_disk=on_disk)]).diagnostics
        return [(d.span.line, d.code.code) for d in found]

    first = findings(text, on_disk=True)
    assert first == [(text.count("\n"), "N101")] and parsed == [root]
    parsed.clear()
    assert findings(text, on_disk=True) == first and parsed == []  # its parse, read back
    edited = text.replace("pose_x", "pose_7")
    assert findings(edited, on_disk=True) == [] and parsed == []  # the last line, again
    # an editor's buffer (not on disk) is parsed each time and not kept
    before = sorted((p, p.stat().st_mtime_ns) for p in folder.glob("parse-*.bin"))
    assert findings(text + "\n", on_disk=False) == first and parsed == [root]
    assert sorted((p, p.stat().st_mtime_ns) for p in folder.glob("parse-*.bin")) == before


def test_a_parse_made_from_the_last_version_is_the_whole_parse(
    folder: Path, tmp_path: Path
) -> None:
    """Whatever changed between two versions of a large file (a line, the top, the end,
    everything, the file emptied, a bracket left open), the parse made from the last
    version's is the parse of the new text, node for node and finding for finding."""
    from osc2check.analysis import IMPORT_CACHE_SIZE, _parse_saved
    from osc2check.syntax import parse
    from osc2check.syntax.walk import dump

    structs = [f"struct pose_{i}:\n    x: length = {i}m\n" for i in range(600)]
    text = "import osc.standard\n\n" + "\n".join(structs)
    assert len(text) >= IMPORT_CACHE_SIZE
    middle = text.index("struct pose_300")
    versions = [
        text,
        text.replace("x: length = 300m", "x: length = 301m + 2"),
        "# a comment on top\n" + text,
        text + "scenario s:\n    p: pose_1\n",
        text[:middle] + "struct broken(\n" + text[middle:],
        text[:middle] + text[middle + 500 :],
        "".join(reversed(structs)),
        "",
        text,
    ]
    uri = str(tmp_path / "big.osc")
    for version in versions:
        made, whole = _parse_saved(version, uri), parse(version, uri)
        assert made.text == version
        assert dump(made.ast) == dump(whole.ast)
        assert made.diagnostics == whole.diagnostics
        assert made.comment_spans() == whole.comment_spans()


# vehicle_category!van is 2.2's (N106 under 2.1); speed_range a parameter 2.2 adds
ONLY_2_2 = """\
import osc.standard

scenario top:
    delivery: vehicle with:
        keep(it.vehicle_category == vehicle_category!van)
    do delivery.drive(duration: 5s) with:
        speed(speed_range: [20kph..40kph])
"""


def test_each_osc_version_has_its_own_library_in_the_cache(tmp_path: Path) -> None:
    scenario = tmp_path / "van.osc"
    scenario.write_text(ONLY_2_2)
    expected = {v: _check(None, scenario, no_cache=True, version=v) for v in ("2.1", "2.2")}
    assert "N106" in expected["2.1"][1] and "N106" not in expected["2.2"][1]
    folder = tmp_path / "cache"
    # 2.1 fills the cache; 2.2 then finds a library entry that is not its own, and back
    for version in ("2.1", "2.2", "2.2", "2.1"):
        assert _check(folder, scenario, version=version) == expected[version], version


def test_a_map_file_is_never_taken_from_the_cache(folder: Path, tmp_path: Path) -> None:
    """Built-in maps' facts are cached; a file is read each time, so its limits
    (``world.budget``) refuse it each time, whatever the cache holds."""
    from osc2check.world.errors import MapError
    from osc2check.world.maps import find_map
    from tests.osc2check.world.maptext import road_xml, xodr

    bad = tmp_path / "Town04.xodr"  # a file of a built-in map's name wins over the name
    bad.write_text(xodr(road_xml(length=1e300)), encoding="utf-8")
    assert find_map("Town04").facts.numbering == "from_left"  # the built-in one, cached
    for _ in range(2):
        with pytest.raises(MapError, match="longer than a road can be"):
            find_map("Town04.xodr", tmp_path)
    assert find_map("Town03").network.junctions  # the stand-in with a junction, by name


def test_the_toolkit_fingerprint_covers_a_checkout_s_grammar_and_library(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """In a checkout the grammar and the standard library are beside the package (where
    ``resources.data_dir`` finds them): editing them is a new toolkit, as editing a
    module is."""
    package = tmp_path / "osc2check"
    package.mkdir()
    (package / "module.py").write_text("x = 1\n")
    (tmp_path / "stdlib").mkdir()
    library = tmp_path / "stdlib" / "domain.osc"
    library.write_text("struct a:\n    x: int\n")
    (tmp_path / "grammar").mkdir()
    (tmp_path / "grammar" / "osc2.lark").write_text("start: NAME\n")

    def fingerprint_now() -> str:
        monkeypatch.setattr(fingerprint, "_PACKAGE", str(package))
        monkeypatch.setattr(fingerprint, "_toolkit", None)
        return fingerprint.toolkit_fingerprint()

    before = fingerprint_now()
    library.write_text("struct a:\n    x: int\nstruct b:\n    y: int\n")
    after_library = fingerprint_now()
    (package / "module.py").write_text("x = 22\n")
    after_module = fingerprint_now()
    assert len({before, after_library, after_module}) == 3
