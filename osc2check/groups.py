"""A large file checked again after an edit: the findings of the declarations the edit
did not reach are read from the last check instead of being worked out again.

A file's top-level declarations are split into *groups* that cannot affect one
another: two declarations are in one group when one names what the other declares
(read from their text: every name outside strings and comments counts, so a group is
never smaller than what the resolver would bind). What every declaration may depend
on without naming it is *shared* and in every group: the imports, `global`
parameters, the `namespace`, `use` and `export` statements (at their places: a
declaration is in the namespace last named above it), `extend` of what the file does
not declare (a type of the standard library), and whatever those name.

Each group is checked as the file with every other group's lines blanked (the same
offsets, lines and columns: a finding's place is the one the whole check gives), and
its findings are kept in the start-up cache under a digest of its declarations' text,
each place stored relative to the declaration it is in. Checked again, a group whose
text is unchanged takes its findings from there, moved to where its declarations now
are; the others are checked. The file's findings are the union, as the whole check
gives them:

* the behaviour flow and the solver run only when no group has an error (the whole
  check runs them only for a file without one);
* a scenario keeps its number among the file's scenarios (the solver's budget, C408);
* the entry holds only while nothing else the check read has changed (the imports,
  the standard library, the configuration, maps: ``results.Recording``), and it is
  written only when the whole result could be stored too.

A file this cannot split exactly is checked whole: a line continued by a backslash, or
inside brackets or a string, at the start of a line; a name written `|like this|`; a
carriage return; a syntax error in any group; fewer than two groups; a file that may
be read in CARLA's dialect (its reading is the whole file's); a finding that may
suggest a name ("did you mean", ``codes.SUGGESTING``: the name may be any group's); or
a finding of one group placed in a declaration of another. ``tests/osc2check/
test_groups.py`` compares the findings with the whole check's, edit after edit.
"""

from __future__ import annotations

import os
import re
from bisect import bisect_right
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from functools import cache as once
from hashlib import blake2b

from osc2check import cache, results
from osc2check.diagnostics import Diagnostic, Fix, Related, Severity, TextEdit
from osc2check.source import Span

__all__ = ["Chunk", "Outcome", "PartCheck", "WholeCheck", "check", "partition", "split"]

#: a file at least this long (characters) read from disk is checked by groups
MIN_SIZE = 20_000

_KIND = "groups"
_HEADER = re.compile(r"^[^\s#][^\n]*", re.M)
_NAME = re.compile(r"[^\W\d]\w*")
_QUALIFIED = re.compile(r"([^\W\d]\w*)\s+([^\W\d]\w*)(?:\s*\.\s*([^\W\d]\w*))?")
_CONTINUED = re.compile(r"\\[ \t\f]*\n")
_DECLARING = frozenset({"type", "unit", "struct", "actor", "scenario", "action", "modifier"})
# statements every group has: what the file imports, its global parameters, and the
# namespace statements (a declaration is in the namespace last named above it)
_SHARED = frozenset({"import", "global", "namespace", "use", "export"})
_SLOT = "\x00slot:"  # a stored place's file: the declaration it is in, by its slot


@dataclass(frozen=True, slots=True)
class Chunk:
    """A top-level declaration's lines (with the comments and blank lines above it),
    or the file's first lines before any declaration."""

    line: int  # 1-based line of its first line
    start: int  # offset of its first character
    text: str
    keyword: str  # its first word ("" for the file's first lines)
    declares: frozenset[str]
    names: frozenset[str]
    scenario_at: int | None  # the offset of the scenario's name, for a scenario
    extends: str | None = None  # what an `extend` extends


def split(text: str) -> list[Chunk] | None:
    """The file's top-level declarations, or None when its text cannot be split exactly."""
    if "\r" in text or _CONTINUED.search(text):
        return None
    heads = [m.start() for m in _HEADER.finditer(text)]
    if not heads:
        return None
    # the comments above the first declaration are the file's first lines, in no group
    starts = [heads[0]] + [_with_comments_above(text, h) for h in heads[1:]]
    bounds: list[tuple[int, int | None]] = [(0, None)] if starts[0] > 0 else []
    bounds += zip(starts, heads, strict=True)
    chunks: list[Chunk] = []
    line = 1
    for i, (begin, head) in enumerate(bounds):
        end = bounds[i + 1][0] if i + 1 < len(bounds) else len(text)
        found = _chunk(text, begin, end, head, line)
        if found is None:
            return None
        chunks.append(found)
        line += found.text.count("\n")
    return chunks


def _with_comments_above(text: str, head: int) -> int:
    """Where a declaration's chunk begins: its header, or the comment lines (at the
    start of a line) and blank lines right above it."""
    begin = head
    while begin > 0:
        previous = text.rfind("\n", 0, begin - 1) + 1
        line = text[previous : begin - 1]
        if line.strip() and not line.startswith("#"):
            break
        begin = previous
    # blank lines above the comments belong to the declaration before
    while begin < head and not text[begin : text.index("\n", begin)].strip():
        begin = text.index("\n", begin) + 1
    return begin


def _code(text: str) -> str | None:
    """The text without strings and comments; None when a string is not closed."""
    if "#" in text or '"' in text or "'" in text:
        text = _strings_and_comments().sub(" ", text)
        if '"' in text or "'" in text:
            return None
    return text


@once
def _strings_and_comments() -> re.Pattern[str]:
    from osc2check.syntax.tables import parse_tables

    return re.compile(f"{parse_tables().patterns['STRING']}|#[^\\n]*")


def _chunk(text: str, begin: int, end: int, head: int | None, line: int) -> Chunk | None:
    own = text[begin:end]
    code = _code(own)
    if code is None or "|" in code:  # an unclosed string; a name written `|like this|`
        return None
    for opening, closing in ("()", "[]", "{}"):
        if code.count(opening) != code.count(closing):
            return None  # the next line at the start of a line continues this one
    names = frozenset(_NAME.findall(code))
    if head is None:
        return Chunk(line, begin, own, "", frozenset(), names, None) if not names else None
    line_end = text.find("\n", head, end)
    header = _code(text[head : line_end if line_end >= 0 else end])
    first = _NAME.match(header or "")
    if first is not None and first.group() in _SHARED:
        return Chunk(line, begin, own, first.group(), frozenset(), names, None)
    match = _QUALIFIED.match(header or "")
    if match is None:
        return None
    keyword = match.group(1)
    name = match.group(3) or match.group(2)
    if keyword == "enum":
        return Chunk(line, begin, own, keyword, names - {"enum"}, names, None)
    if keyword not in _DECLARING and keyword != "extend":
        return None  # namespace, use, export, or not a declaration: the whole check
    if keyword == "extend":
        # an enum's extension declares its members too (a use may name them alone)
        declares = names - {"extend"} if "[" in (header or "") else frozenset({name})
        return Chunk(line, begin, own, keyword, declares, names, None, name)
    at = None
    if keyword == "scenario":
        at = head + match.start(3 if match.group(3) else 2)
    return Chunk(line, begin, own, keyword, frozenset({name}), names, at)


def partition(chunks: list[Chunk]) -> tuple[list[int], list[list[int]]]:
    """The shared chunks and the groups (chunk indexes, in file order). The file's first
    lines, comments above its first declaration, are in neither: they have no findings,
    and the suppressions they hold are read from the whole file's comments."""
    shared = len(chunks)  # the node every shared chunk joins
    parent = list(range(len(chunks) + 1))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    def join(a: int, b: int) -> None:
        ra, rb = root(a), root(b)
        if ra != rb:
            if ra == shared:  # the shared node stays a root
                ra, rb = rb, ra
            parent[ra] = rb

    declared_here = {n for c in chunks if c.keyword != "extend" for n in c.declares}
    declared_by: dict[str, list[int]] = {}
    for i, c in enumerate(chunks):
        if c.keyword in _SHARED:
            join(i, shared)
        elif c.extends is not None and c.extends not in declared_here:
            join(i, shared)  # extends what the file does not declare: every group's
            continue  # (what names that declaration is with the shared chunks anyway)
        for name in c.declares:
            declared_by.setdefault(name, []).append(i)
    for i, c in enumerate(chunks):
        for name in c.names:
            for j in declared_by.get(name, ()):
                join(i, j)
    members: dict[int, list[int]] = {}
    for i, c in enumerate(chunks):
        if c.keyword:  # the file's first lines (comments) are no declaration's
            members.setdefault(root(i), []).append(i)
    everyone = members.pop(shared, [])
    return everyone, sorted(members.values())


@dataclass
class Outcome:
    """What one check of a file (or of one group of it) found: the findings before the
    behaviour flow (syntax, names, types), those after it, whether the first have no
    error, the constraints the solver left out (span, reason) and the comments."""

    before: list[Diagnostic]
    after: list[Diagnostic]
    clean: bool
    unverified: set[tuple[Span, str]]
    comments: list[tuple[Span, str]]


#: checks the file with only the given chunks (the others' lines blank: ``text``), whose
#: scenarios have the given numbers (by the offset of each one's name); None when that
#: check cannot stand for the group's (a syntax error, say)
PartCheck = Callable[[str, list[Chunk], dict[int, int]], Outcome | None]
#: checks the whole file: its outcome, and whether it may be split into its groups'
WholeCheck = Callable[[dict[int, int]], tuple[Outcome, bool]]

#: at most this many groups to check are checked one by one; more, the file is checked
#: whole (its groups' findings then split by where they are): each group's check costs
#: a little of what the whole check costs
MOST_PARTS = 16
#: groups of earlier versions kept besides the current ones
KEPT_OLDER = 32


def check(
    uri: str, text: str, options_key: str, check_part: PartCheck, check_whole: WholeCheck
) -> Outcome | None:
    """The file's findings, the unchanged groups' read from the start-up cache; None
    when the file cannot be checked by groups (see the module's docstring)."""
    if not results.recording() or not cache.enabled():
        return None
    chunks = split(text)
    if chunks is None:
        return None
    everyone, groups = partition(chunks)
    if len(groups) < 2:
        return None
    places = [c.scenario_at for c in chunks if c.scenario_at is not None]
    numbers = {place: n for n, place in enumerate(places, 1)}
    path = os.path.abspath(uri)  # a file of the same name elsewhere imports other files
    kind, key = _KIND + "-" + cache.digest(path)[:16], {"path": path, "options": options_key}
    entry = cache.load(kind, key)
    if not isinstance(entry, _Entry) or not results.unchanged(entry.dependencies):
        entry = _Entry({}, {})
    included = [sorted(everyone + group) for group in groups]
    shared = set(everyone)
    texts = [
        blake2b(c.text.encode("utf-8", "surrogatepass"), digest_size=16).digest() for c in chunks
    ]
    digests = [_digest(chunks, texts, mine, shared, numbers) for mine in included]
    to_check = [i for i, d in enumerate(digests) if d not in entry.groups]
    keeping: dict[str, _Kept] | None
    if len(to_check) > MOST_PARTS:
        outcome, splittable = check_whole(numbers)
        keeping = _split(outcome, uri, chunks, everyone, included, digests) if splittable else None
    else:
        keeping, outcomes = {}, []
        for i, mine in enumerate(included):
            kept = entry.groups.get(digests[i])
            if kept is None:
                own = {s: n for s, n in numbers.items() if _within(chunks, mine, s)}
                found = check_part(_blanked(text, chunks, mine), [chunks[j] for j in mine], own)
                kept = _relative(found, uri, chunks, mine) if found is not None else None
                if kept is None:
                    return None
            keeping[digests[i]] = kept
            outcomes.append(_absolute(kept, uri, chunks, mine))
        outcome = _union(outcomes)
        if not chunks[0].keyword:  # the comments of the file's first lines: in no group
            outcome.comments[:0] = _comments(uri, text, chunks[0])
    if keeping is not None:
        # the last versions of groups edited since: an edit undone finds its group again
        older = [d for d in entry.groups if d not in keeping][:KEPT_OLDER]
        keeping.update((d, entry.groups[d]) for d in older)
    # (nothing found so far depends on the machine's state: a reason is never taken back)
    if keeping is not None and results.repeatable():
        dependencies = {**entry.dependencies, **results.recorded()}
        dependencies.pop(path, None)
        if results.settled(dependencies):
            cache.store(kind, key, _Entry(dependencies, keeping))
    return outcome


def _split(
    whole: Outcome,
    uri: str,
    chunks: list[Chunk],
    everyone: list[int],
    included: list[list[int]],
    digests: list[str],
) -> dict[str, _Kept] | None:
    """The whole file's outcome as its groups' (kept by their digests); None when a
    finding is in a shared chunk, or has a place in another group's, or a constraint
    left out is written in another file: what the group's own check would find cannot
    be told from it then."""
    if not whole.clean:
        return None  # the flow and the solver did not run: the groups' findings are not all
    group_of = {j: g for g, mine in enumerate(included) for j in mine if j not in everyone}
    starts = [c.start for c in chunks]

    def owner(span: Span) -> int | None:
        if span.uri != uri:
            return None
        return group_of.get(max(bisect_right(starts, span.start) - 1, 0), -1)

    parts = [Outcome([], [], True, set(), []) for _ in included]
    for findings, side in ((whole.before, "before"), (whole.after, "after")):
        for d in findings:
            g = owner(d.span)
            if g is None or g < 0:
                return None
            getattr(parts[g], side).append(d)
    for span, reason in whole.unverified:
        g = owner(span)
        if g is None or g < 0:
            return None
        parts[g].unverified.add((span, reason))
    first_lines = len(chunks[0].text) if not chunks[0].keyword else 0
    for span, comment in whole.comments:
        if span.uri == uri and span.start < first_lines:
            continue  # read again from the text every time
        g = owner(span)
        for part in parts if g is None or g < 0 else [parts[g]]:
            part.comments.append((span, comment))
    kept: dict[str, _Kept] = {}
    for g, part in enumerate(parts):
        part.clean = not any(d.severity is Severity.ERROR for d in part.before)
        moved = _relative(part, uri, chunks, included[g])
        if moved is None:
            return None
        kept[digests[g]] = moved
    return kept


def _within(chunks: list[Chunk], included: list[int], offset: int) -> bool:
    return any(chunks[i].start <= offset < chunks[i].start + len(chunks[i].text) for i in included)


def _digest(
    chunks: list[Chunk],
    texts: list[bytes],
    included: list[int],
    shared: set[int],
    numbers: dict[int, int],
) -> str:
    """A group's key: its chunks' texts (``texts``: each one's digest), in order, whether
    each is shared, and its scenarios' numbers."""
    h = blake2b(digest_size=20)
    for i in included:
        c = chunks[i]
        h.update(b"S" if i in shared else b"G")
        if c.scenario_at is not None:
            h.update(b"%d:" % numbers[c.scenario_at])
        h.update(texts[i])
    return h.hexdigest()


def _blanked(text: str, chunks: list[Chunk], included: list[int]) -> str:
    """The file with every chunk not included made of spaces: the same lines and offsets."""
    keep = set(included)
    parts = []
    for i, c in enumerate(chunks):
        if i in keep:
            parts.append(c.text)
        else:
            parts.append("\n".join(" " * len(line) for line in c.text.split("\n")))
    return "".join(parts)


@dataclass
class _Kept:
    """One group's outcome, each place in the file relative to its chunk (its slot among
    the group's chunks, in the span's file name)."""

    outcome: Outcome


@dataclass
class _Entry:
    dependencies: dict[str, results.Signature]
    groups: dict[str, _Kept]


def _relative(found: Outcome, uri: str, chunks: list[Chunk], included: list[int]) -> _Kept | None:
    """``found`` with its places in the file relative to their chunks; None when one is
    in a chunk the group does not include (or a finding belongs to no chunk)."""
    starts = [c.start for c in chunks]
    slots = {index: slot for slot, index in enumerate(included)}

    def move(span: Span) -> Span:
        if span.uri != uri:
            return span
        index = max(bisect_right(starts, span.start) - 1, 0)
        slot = slots.get(index)
        if slot is None:
            raise _Elsewhere
        c = chunks[index]
        return Span(
            f"{_SLOT}{slot}",
            span.line - c.line,
            span.column,
            span.end_line - c.line,
            span.end_column,
            span.start - c.start,
            span.end - c.start,
        )

    try:
        return _Kept(_moved(found, move))
    except _Elsewhere:
        return None


def _absolute(kept: _Kept, uri: str, chunks: list[Chunk], included: list[int]) -> Outcome:
    def move(span: Span) -> Span:
        if not span.uri.startswith(_SLOT):
            return span
        c = chunks[included[int(span.uri[len(_SLOT) :])]]
        return Span(
            uri,
            span.line + c.line,
            span.column,
            span.end_line + c.line,
            span.end_column,
            span.start + c.start,
            span.end + c.start,
        )

    return _moved(kept.outcome, move)


class _Elsewhere(Exception):
    """A place in a chunk the group does not include."""


def _moved(found: Outcome, move: Callable[[Span], Span]) -> Outcome:
    return Outcome(
        [_diagnostic_moved(d, move) for d in found.before],
        [_diagnostic_moved(d, move) for d in found.after],
        found.clean,
        {(move(span), reason) for span, reason in found.unverified},
        [(move(span), comment) for span, comment in found.comments],
    )


def _diagnostic_moved(d: Diagnostic, move: Callable[[Span], Span]) -> Diagnostic:
    fix = d.fix
    if fix is not None:
        fix = Fix(
            fix.message, tuple(TextEdit(move(e.span), e.new_text) for e in fix.edits), fix.safe
        )
    return replace(
        d,
        span=move(d.span),
        related=tuple(Related(move(r.span), r.message) for r in d.related),
        fix=fix,
    )


def _comments(uri: str, text: str, chunk: Chunk) -> list[tuple[Span, str]]:
    """The comments of a chunk, as the parse gives them (``ParseResult.comment_spans``)."""
    from osc2check.syntax.lexer import tokenize
    from osc2check.syntax.parser import comment_spans

    end = chunk.start + len(chunk.text)
    return comment_spans(uri, tokenize(text, chunk.start, end, chunk.line).comments)


def _union(outcomes: Iterable[Outcome]) -> Outcome:
    """The groups' outcomes as the whole file's: the flow's and the solver's findings
    only when no group has an error before them."""
    outcomes = list(outcomes)
    clean = all(o.clean for o in outcomes)
    before = [d for o in outcomes for d in o.before]
    clean = clean and not any(d.severity is Severity.ERROR for d in before)
    after = [d for o in outcomes for d in o.after] if clean else []
    unverified = set().union(*(o.unverified for o in outcomes)) if clean else set()
    comments = list(dict.fromkeys(c for o in outcomes for c in o.comments))
    return Outcome(before, after, clean, unverified, comments)
