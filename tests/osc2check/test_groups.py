"""A large file checked by groups of declarations (``osc2check.groups``): the findings
after every edit are the whole check's, and only the groups an edit reached are checked."""

from __future__ import annotations

import io
import os
import random
import re
import time
from contextlib import redirect_stdout
from pathlib import Path

import pytest

from osc2check import analysis, cache, groups, results
from osc2check.verify import check as verify_check

ROOT = Path(__file__).resolve().parents[2]


def _split(text: str) -> tuple[list[str], list[list[str]]]:
    """The shared chunks' and the groups' first words and names, for reading."""
    chunks = groups.split(text)
    assert chunks is not None
    everyone, found = groups.partition(chunks)

    def label(i: int) -> str:
        c = chunks[i]
        return f"{c.keyword} {sorted(c.declares)[0]}" if c.declares else c.keyword or "-"

    return [label(i) for i in everyone], [[label(i) for i in g] for g in found]


def test_declarations_that_name_each_other_are_one_group() -> None:
    text = (
        "import osc.standard\n"
        "\n"
        "enum mood: [calm, wild]\n"
        "\n"
        "# A robot.\n"
        "actor robot inherits vehicle:\n"
        "    m: mood\n"
        "\n"
        "scenario uses_robot:\n"
        "    r: robot\n"
        "\n"
        "scenario alone:\n"
        "    car: vehicle\n"
        "    keep(car.length < 5m)\n"
        "\n"
        "scenario wild_one:\n"
        "    x: bool = wild == calm  # an enum member, unqualified\n"
        "\n"
        "extend vehicle:\n"
        "    note: string = 'not a name: robot'\n"
    )
    shared, found = _split(text)
    assert shared == ["import", "extend vehicle"]
    assert found == [
        ["enum calm", "actor robot", "scenario uses_robot", "scenario wild_one"],
        ["scenario alone"],
    ]


def test_an_extend_of_a_declaration_of_the_file_is_in_its_group() -> None:
    text = "scenario a:\n    x: int\n\nextend a:\n    y: int\n\nscenario b:\n    z: int\n"
    shared, found = _split(text)
    assert shared == []
    assert found == [["scenario a", "extend a"], ["scenario b"]]


def test_an_enum_s_extension_declares_its_members_and_one_of_the_library_s_is_shared() -> None:
    text = (
        "enum mood: [calm]\n\nextend mood: [wild]\n\n"
        "extend vehicle_category: [calm_car]\n\n"
        "scenario a:\n    x: bool = wild == wild\n\nscenario b:\n    y: int\n"
    )
    shared, found = _split(text)
    assert shared == ["extend calm_car"]
    assert found == [["enum calm", "extend mood", "scenario a"], ["scenario b"]]


def test_namespace_statements_are_shared_where_they_are() -> None:
    text = "namespace n\n\nscenario a:\n    x: int\n\nnamespace m\n\nscenario b:\n    y: int\n"
    shared, found = _split(text)
    assert shared == ["namespace", "namespace"]
    assert found == [["scenario a"], ["scenario b"]]


def test_a_global_and_what_it_names_are_shared() -> None:
    text = "struct p:\n    x: int\n\nglobal g: p\n\nscenario a:\n    y: int\n"
    shared, found = _split(text)
    assert shared == ["struct p", "global"]
    assert found == [["scenario a"]]


@pytest.mark.parametrize(
    "text",
    [
        "scenario a:\n    keep(x <\n1)\nscenario b:\n    y: int\n",
        "scenario a:\n    x: int = 1 + \\\n        2\n",
        'scenario a:\n    s: string = "open\nscenario b:\n    y: int\n',
        "scenario |a b|:\n    x: int\n",
        "scenario a:\r\n    x: int\r\n",
        "    indented\nscenario a:\n    x: int\n",
    ],
    ids=["bracket", "backslash", "string", "bar-name", "cr", "indented-start"],
)
def test_text_that_cannot_be_split_exactly_is_checked_whole(text: str) -> None:
    assert groups.split(text) is None


# ---- the findings, edit after edit ------------------------------------------------


def _scenario(i: int, limit: int = 200) -> str:
    return (
        f"scenario s{i}:\n"
        f"    car{i}: vehicle\n"
        f"    top{i}: speed = {30 + i}kph\n"
        f"    keep(top{i} < {limit}kph)\n"
        f"    do car{i}.drive() with:\n"
        f"        speed(top{i})\n"
        f"\n"
    )


def _struct(i: int) -> str:
    return f"# Limits {i}.\nstruct limits{i}:\n    low: speed = {i}kph\n\n"


def _file(count: int) -> str:
    parts = ["import osc.standard\n\n"]
    for i in range(count):
        parts.append(_scenario(i) if i % 3 else _struct(i))
    return "".join(parts)


class _Checker:
    """Runs ``osc2check`` in this process as the command does (its result recorded) and
    the whole check (``--no-cache``), and counts the groups checked one by one."""

    def __init__(self, path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
        self.path = path
        self.parts = 0
        self.grouped = 0
        part, check = analysis._check_part, groups.check

        def counting_part(*args, **kwargs):  # type: ignore[no-untyped-def]
            self.parts += 1
            return part(*args, **kwargs)

        def counting_check(*args, **kwargs):  # type: ignore[no-untyped-def]
            found = check(*args, **kwargs)
            self.grouped += found is not None
            return found

        monkeypatch.setattr(analysis, "_check_part", counting_part)
        monkeypatch.setattr(groups, "check", counting_check)

    def write(self, text: str) -> None:
        self.path.write_text(text, encoding="utf-8")
        settled = time.time() - 10  # older than the check's two seconds of doubt
        os.utime(self.path, (settled, settled))

    def _run(self, *args: str) -> str:
        cache.set_enabled(True)
        out = io.StringIO()
        try:
            with redirect_stdout(out):
                status = results.check_here(["--output-format", "concise", *args])
        finally:
            cache.set_enabled(True)
        return f"exit {status}\n{out.getvalue()}"

    def edit(self, text: str) -> tuple[int, bool]:
        """Writes ``text`` and checks it by groups and whole (``same_as_whole``)."""
        self.write(text)
        return self.same_as_whole()

    def same_as_whole(self) -> tuple[int, bool]:
        """Checks the file by groups and whole; asserts the same output; returns the
        groups checked one by one and whether the groups were used at all."""
        self.parts, self.grouped = 0, 0
        by_groups = self._run(str(self.path))
        parts, grouped = self.parts, bool(self.grouped)
        whole = self._run("--no-cache", str(self.path))
        assert by_groups == whole
        return parts, grouped


@pytest.fixture
def checker(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> _Checker:
    monkeypatch.setenv("OSC2_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("OSC2_NO_CACHE", raising=False)
    monkeypatch.setattr(groups, "MIN_SIZE", 0)
    monkeypatch.setattr(verify_check, "MAX_SCENARIOS", 12)  # some past the budget (C408)
    # a test module edited a moment ago is one of what the check read: not in doubt here
    monkeypatch.setattr(results, "_RACY_NS", 0)
    return _Checker(tmp_path / "large.osc", monkeypatch)


def test_each_edit_gives_the_whole_check_s_findings(checker: _Checker) -> None:
    text = _file(30)
    assert checker.edit(text) == (0, True)  # checked whole, kept group by group
    assert "C408" in checker._run("--no-cache", str(checker.path))

    text += "# a comment at the end\n"
    assert checker.edit(text) == (1, True)  # the last group alone

    text = text.replace(_scenario(10), _scenario(10, limit=20))  # a conflict: 40 < 20 kph
    assert checker.edit(text) == (1, True)
    assert "C401" in checker._run("--no-cache", str(checker.path))

    # an error before the flow: the whole check runs neither the flow nor the solver
    text = text.replace("    top13: speed = 43kph\n", "    top13: speed = 43\n")
    assert checker.edit(text) == (1, True)
    assert "C401" not in checker._run("--no-cache", str(checker.path))

    text = text.replace("    top13: speed = 43\n", "    top13: speed = 43kph\n")
    assert checker.edit(text) == (0, True)  # as it was: every group kept

    # a name misspelt may be like one of any group ("did you mean"): checked whole
    text = text.replace("    car13: vehicle\n", "    car13: vehicel\n")
    assert checker.edit(text) == (1, False)
    text = text.replace("    car13: vehicel\n", "    car13: vehicle\n")
    assert checker.edit(text) == (0, True)

    # suppressions, on a line and file-wide, are read from every group's comments
    text = text.replace("    keep(top10 < 20kph)\n", "    keep(top10 < 20kph)  # noqa\n")
    text += "# osc2check: file-ignore[C408]\n"
    assert checker.edit(text) == (2, True)

    # a scenario added near the top renumbers those after it: checked whole
    text = text.replace("import osc.standard\n\n", "import osc.standard\n\n" + _scenario(99), 1)
    assert checker.edit(text) == (0, True)

    # lines added above a group move its findings
    text = text.replace("struct limits3:", "\n\n\nstruct limits3:")
    assert checker.edit(text) == (1, True)

    # a syntax error: the file is checked whole, not by groups
    text = text.replace("    keep(top4 < 200kph)\n", "    keep(top4 < 200kph\n")
    assert checker.edit(text) == (0, False)


def test_an_edit_of_what_a_group_shares_checks_every_group_again(checker: _Checker) -> None:
    text = _file(12)
    checker.edit(text)
    text += "extend vehicle:\n    keep(length < 1m)\n"  # every scenario's car: a conflict
    assert checker.edit(text) == (12, True)  # each of the 12 groups again


def test_a_changed_import_checks_every_group_again(checker: _Checker, tmp_path: Path) -> None:
    library = tmp_path / "units.osc"
    library.write_text("unit furlong of length is SI(m: 1, factor: 201.168)\n", encoding="utf-8")
    settled = time.time() - 10
    os.utime(library, (settled, settled))
    text = _file(12).replace("import osc.standard\n", 'import osc.standard\nimport "units.osc"\n')
    text += "scenario uses_it:\n    d: length = 2furlong\n"
    checker.edit(text)
    assert "T201" not in checker._run("--no-cache", str(checker.path))
    library.write_text("unit furlong of time is SI(s: 1, factor: 201.168)\n", encoding="utf-8")
    os.utime(library, (settled + 1, settled + 1))
    # the file itself unchanged: every group's text is, and each one is checked again
    assert checker.same_as_whole() == (13, True)
    assert "T201" in checker._run("--no-cache", str(checker.path))  # a time, not a length


def test_a_damaged_entry_of_groups_never_changes_a_finding(checker: _Checker) -> None:
    text = _file(12)
    checker.edit(text)
    entries = list(Path(os.environ["OSC2_CACHE_DIR"]).glob("groups-*"))
    assert entries
    for entry in entries:
        entry.write_bytes(b"not an entry" + entry.read_bytes()[40:])
    assert checker.edit(text + "# touched\n") == (12, True)  # each group again, and kept
    assert checker.edit(text + "# touched again\n") == (1, True)


def test_a_file_under_the_size_is_checked_whole(checker: _Checker, monkeypatch) -> None:
    monkeypatch.setattr(groups, "MIN_SIZE", 10**9)
    assert checker.edit(_file(12)) == (0, False)


def test_the_generated_large_file_checked_by_parts_is_the_whole_check(
    checker: _Checker, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every group of a varied file checked on its own, against the whole check."""
    import sys

    sys.path.insert(0, str(ROOT / "bench"))
    from generate import generate

    monkeypatch.setattr(groups, "MOST_PARTS", 10**9)
    checker.write(generate(700))
    parts, grouped = checker.same_as_whole()
    assert grouped and parts > 30


def test_comments_above_the_first_declaration_are_in_no_group(checker: _Checker) -> None:
    text = _file(12).replace("import osc.standard\n", "import osc.standard\n\n" + _scenario(50))
    text = text.replace("    keep(top50 < 200kph)\n", "    keep(top50 < 20kph)\n")  # C401
    checker.edit(text)
    text = "# osc2check: file-ignore[C401]\n" + text  # every group as it was
    assert checker.edit(text) == (0, True)
    assert "C401" not in checker._run("--no-cache", str(checker.path))
    assert groups.split(text)[0].keyword == ""  # type: ignore[index]


def test_a_file_in_carla_s_dialect_is_checked_whole(checker: _Checker) -> None:
    """Its reading is the whole file's: an import or a modifier decides it for every line."""
    text = _file(12) + "modifier Path.set_map:\n    map_name: string\n"
    assert checker.edit(text) == (0, False)


CONFORMANCE = ROOT.parent / "shared" / "conformance"
THIRD_PARTY = os.environ.get("OSC2_THIRD_PARTY")


def _other_projects_files() -> list[Path]:
    folders = [CONFORMANCE] + ([Path(THIRD_PARTY)] if THIRD_PARTY else [])
    return sorted(p for folder in folders if folder.is_dir() for p in folder.rglob("*.osc"))


@pytest.mark.slow
@pytest.mark.skipif(
    not _other_projects_files(), reason="no ../shared/conformance, no OSC2_THIRD_PARTY"
)
def test_other_projects_files_checked_group_by_group_are_the_whole_check(
    checker: _Checker, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every file of the conformance folder and of other projects, each group checked on
    its own (however small the file), against the whole check."""
    monkeypatch.setattr(groups, "MOST_PARTS", 10**9)
    grouped, differ = 0, []
    for path in _other_projects_files():
        for entry in (Path(os.environ["OSC2_CACHE_DIR"])).glob("*"):
            entry.unlink()  # no group and no result from the file's last check
        checker.path = path
        try:
            grouped += checker.same_as_whole()[1]
        except AssertionError:
            differ.append(str(path))
    assert not differ
    assert grouped >= 50  # files of two groups or more were checked by groups


def _edited(text: str, rng: random.Random) -> str:
    """``text`` with one random edit: a number changed, a name misspelt, a declaration
    removed, doubled or moved, a comment or a broken line added."""
    chunks = groups.split(text) or []
    lines = text.split("\n")
    kind = rng.randrange(7)
    if kind == 6:  # a name misspelt: an unknown name, member, type or argument
        i = rng.randrange(len(lines))
        lines[i] = re.sub(r"([a-z])([a-z_]*\d)", r"\2\1", lines[i], count=1)
        return "\n".join(lines)
    if kind == 0 or len(chunks) < 3:
        i = rng.randrange(len(lines))
        lines[i] = re.sub(
            r"\d+", lambda m: str(int(m.group()) + rng.randint(1, 90)), lines[i], count=1
        )
        return "\n".join(lines)
    c = chunks[rng.randrange(1, len(chunks))]
    before, after = text[: c.start], text[c.start + len(c.text) :]
    if kind == 1:
        return before + after
    if kind == 2:
        return before + c.text + c.text + after
    if kind == 3:
        return before + after + c.text
    if kind == 4:
        return before + "# a note\n" + c.text + after
    return before + c.text.replace(":\n", ":\n    keep(\n", 1) + after


@pytest.mark.slow
def test_random_edits_give_the_whole_check_s_findings(checker: _Checker) -> None:
    """Edit after random edit of a varied file, every check by groups is the whole one."""
    import sys

    sys.path.insert(0, str(ROOT / "bench"))
    from generate import generate

    rng = random.Random(7)
    original = generate(600, seed=3)
    text = original
    grouped = 0
    for step in range(24):
        text = original if step % 8 == 7 else _edited(text, rng)
        checker.write(text)
        grouped += checker.same_as_whole()[1]
    assert grouped >= 12
