"""The context of a cursor in the text being typed, for completion and signature help.

Requests that come while the user types must not wait for a full analysis of
the document. They are answered from the *current* text plus the latest
snapshot (which may be a version or two behind):

1. the top-level declaration around the cursor (a *chunk*: top-level
   declarations start at column 0) is lexed up to the cursor and driven
   through the LALR table, which tells which terminals, hence which keywords,
   can come next;
2. the chunk is parsed on its own, with a placeholder name at the cursor
   when nothing is written there yet (the way gopls "fixes the source, then
   parses"), and resolved together with a *skeleton* of the rest of the
   program taken from the snapshot: its declarations with their fields,
   events and methods but without bodies. That costs a few milliseconds even
   for a 2,000-line file and gives the checker's own name and type
   resolution for the chunk.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from osc2check.gc_pause import gc_paused
from osc2check.semantics.model import Model
from osc2check.semantics.program import build_program
from osc2check.semantics.scope import Scope
from osc2check.semantics.visibility import node_path, scope_at
from osc2check.source import LINE_BREAK, decode_source, line_of
from osc2check.syntax import ParseResult, ast, expected, parse
from osc2check.syntax.ast import Name, Node  # the class body's `ast` is the field
from osc2check.syntax.indent import indent
from osc2check.syntax.lexer import Token, tokenize
from osc2check.syntax.parser import parse_part
from osc2lsp.lazy import cached_property
from osc2lsp.snapshot import Snapshot
from osc2lsp.text import TextMap

PLACEHOLDER = "__cursor__"
_WORD = re.compile(r"[^\W\d]\w*$")
_WORD_AFTER = re.compile(r"\w*")
_KEEP_MEMBERS = (ast.FieldDecl, ast.EventDecl, ast.MethodDecl)
_LAYOUT = frozenset({"_NL", "_INDENT", "_DEDENT", "NEWLINE"})


# ---- chunks -------------------------------------------------------------------


def _starts_declaration(text: str, line_start: int) -> bool:
    ch = text[line_start : line_start + 1]
    return bool(ch) and ch not in " \t\f\r\n#"


def _line_start(text: str, offset: int) -> int:
    """The offset of the start of the line holding ``offset`` (see ``LINE_BREAK``)."""
    return max(text.rfind("\n", 0, offset), text.rfind("\r", 0, offset)) + 1


def _previous_line_start(text: str, line_start: int) -> int:
    """The start of the line before the one that starts at ``line_start`` (> 0)."""
    return _line_start(text, line_start - (2 if text[line_start - 2 : line_start] == "\r\n" else 1))


def chunk_bounds(text: str, offset: int) -> tuple[int, int]:
    """The top-level declaration around ``offset``: from the nearest line at or above
    the cursor that starts at column 0, to the next such line below."""
    line_start = _line_start(text, offset)
    start = line_start
    if not (_starts_declaration(text, line_start) and offset > line_start):
        start = 0
        probe = line_start
        while probe > 0:
            probe = _previous_line_start(text, probe)
            if _starts_declaration(text, probe) and not _continued(text, probe):
                start = probe
                break
    end = len(text)
    for line_break in LINE_BREAK.finditer(text, offset):
        below = line_break.end()
        if _starts_declaration(text, below) and not _continued(text, below):
            end = below
            break
    return start, end


def _continued(text: str, line_start: int) -> bool:
    """Whether the line before ``line_start`` ends with a `\\` continuation."""
    before = text[max(0, line_start - 3) : line_start].rstrip("\r\n")
    return before.endswith("\\")


# ---- the cursor ---------------------------------------------------------------


@dataclass
class Cursor:
    """Lexical facts about the cursor in the current text (offsets are absolute)."""

    text: str
    offset: int
    chunk: tuple[int, int]
    word: tuple[int, int]  # the identifier being typed (replaced by a completion)
    tokens: list[Token]  # significant tokens of the chunk before the word (chunk-relative)
    state: expected.GrammarState | None
    in_comment: bool = False
    in_string: bool = False
    number: Token | None = None  # a number right before the cursor (`0.5` in `elapsed(0.5`)
    unit_prefix: str = ""
    statement_start: bool = False  # the word starts a statement (first on its logical line)

    @property
    def prefix(self) -> str:
        return self.text[self.word[0] : self.offset]

    @cached_property
    def accepts(self) -> frozenset[str]:
        return self.state.accepts() if self.state is not None else frozenset()

    def previous(self, n: int = 1) -> Token | None:
        """The n-th significant token before the word (1 = the last one)."""
        return self.tokens[-n] if len(self.tokens) >= n else None

    def previous_types(self, n: int) -> list[str]:
        return [t.type for t in self.tokens[-n:]]

    def argument_index(self) -> int | None:
        """How many commas separate the cursor from the innermost unclosed `(`."""
        depth = 0
        commas = 0
        for tok in reversed(self.tokens):
            if tok.type in ("RPAR", "RSQB"):
                depth += 1
            elif tok.type in ("LPAR", "LSQB"):
                if depth == 0:
                    return commas if tok.type == "LPAR" else None
                depth -= 1
            elif tok.type == "COMMA" and depth == 0:
                commas += 1
        return None


def cursor_at(text: str, offset: int) -> Cursor:
    """Lex the chunk around ``offset`` up to the cursor and run the grammar over it."""
    offset = max(0, min(offset, len(text)))
    start, end = chunk_bounds(text, offset)
    before = text[start:offset]
    match = _WORD.search(before)
    word_start = offset - (len(match.group()) if match else 0)
    after = _WORD_AFTER.match(text, offset)
    word_end = after.end() if after else offset
    lexed = tokenize(text[start:word_start])
    rel_word = word_start - start
    cursor = Cursor(text, offset, (start, end), (word_start, word_end), [], None)
    line_start = _line_start(text, offset)
    for comment in lexed.comments:
        if start + comment.offset < offset and start + comment.offset >= line_start:
            cursor.in_comment = True
            return cursor
    if any(err.kind == "string" and err.offset < rel_word for err in lexed.errors):
        cursor.in_string = True
        return cursor
    tokens = lexed.tokens
    if tokens and tokens[-1].end_pos == rel_word and tokens[-1].type in ("INT", "FLOAT"):
        # `0.5|` or `10k|`: a unit is (being) written right after a number
        cursor.number = tokens[-1]
        cursor.unit_prefix = match.group() if match else ""
    line = line_of(before, rel_word)
    column = rel_word - _line_start(before, rel_word) + 1
    sentinel = Token("NAME", "", rel_word, line, column, line, column, rel_word)
    laid_out, _ = indent([*tokens, sentinel], text[start:word_start])
    cut = next((i for i, t in enumerate(laid_out) if t is sentinel), len(laid_out))
    prefix_tokens = laid_out[:cut]
    cursor.statement_start = not prefix_tokens or prefix_tokens[-1].type in _LAYOUT
    cursor.state = expected.run([t.type for t in prefix_tokens])
    cursor.tokens = [t for t in prefix_tokens if t.type not in _LAYOUT]
    return cursor


# ---- the focus: the chunk resolved against a skeleton of the program ---------


def _skeleton_members(members: tuple[ast.Member, ...]) -> tuple[ast.Member, ...]:
    kept: list[ast.Member] = []
    for m in members:
        if isinstance(m, ast.FieldDecl):
            kept.append(
                dataclasses.replace(
                    m, with_members=(), default=None if m.type is not None else m.default
                )
            )
        elif isinstance(m, _KEEP_MEMBERS):
            kept.append(m)
    return tuple(kept)


def skeleton(decl: ast.Declaration) -> ast.Declaration:
    """A declaration without the parts that only matter inside it (bodies, constraints)."""
    if isinstance(decl, (ast.StructuredDecl, ast.ExtendDecl)):
        return dataclasses.replace(decl, members=_skeleton_members(decl.members))
    return decl


def _skeleton_parse(result: ParseResult) -> ParseResult:
    decls = tuple(skeleton(d) for d in result.ast.declarations)
    return ParseResult(
        result.uri, result.text, ast.File(result.ast.span, decls), (), result.comments
    )


def map_offset(old: str, new: str, offset: int, change: TextMap | None = None) -> int:
    """Where ``offset`` of ``new`` was in ``old`` (edits between them are one region;
    an offset inside it maps to the region's start)."""
    change = change if change is not None else TextMap(old, new)
    mapped = change.to_old(offset)
    return change.prefix if mapped is None else mapped


@dataclass
class Focus:
    """The chunk around the cursor, parsed from the current text and resolved."""

    cursor: Cursor
    ast: ast.File
    model: Model
    placeholder: bool

    @cached_property
    def path(self) -> list[Node]:
        return node_path(self.ast, self.cursor.word[0])

    @cached_property
    def scope(self) -> Scope:
        return scope_at(self.model, self.path)

    def name_at_cursor(self) -> Name | None:
        """The Name node written (or inserted) at the cursor."""
        for node in reversed(self.path):
            if isinstance(node, ast.Name) and node.span.start == self.cursor.word[0]:
                return node
        return None


def _placeholder_text(cursor: Cursor) -> str:
    """What to insert at the cursor so that the statement there parses."""
    if cursor.word[1] > cursor.word[0] or cursor.number is not None:
        return ""
    prev = cursor.previous()
    if prev is None:
        return ""
    line_end = LINE_BREAK.search(cursor.text, cursor.offset)
    rest = cursor.text[cursor.offset : line_end.start() if line_end else len(cursor.text)].strip()
    if cursor.statement_start:
        return PLACEHOLDER if not rest or rest[0] == "#" else ""
    if prev.type == "DOT":
        call = not rest or rest[0] in ")],#"
        return PLACEHOLDER + ("()" if call else "")
    if rest and (rest[0].isalnum() or rest[0] in "_(\"'[@"):
        return ""
    if prev.type in (
        "AT",
        "LPAR",
        "COMMA",
        "COLON",
        "REL_OP",
        "ADD_OP",
        "MUL_OP",
        "EQUAL",
        "LSQB",
        "IMPLIES",
        "AND",
        "OR",
        "NOT",
        "IN",
        "BANG",
        "DOTDOT",
        "QMARK",
        "WAIT",
        "UNTIL",
        "IF",
        "KEEP",
        "DOUBLE_COLON",
    ):
        return PLACEHOLDER
    return ""


_LAST: list[
    tuple[Snapshot | None, str, int, Focus]
] = []  # the latest focus: completion and signature help often ask for the same


def focus(snapshot: Snapshot | None, text: str, offset: int, cursor: Cursor | None = None) -> Focus:
    """Parse and resolve the chunk around ``offset`` of ``text`` (the current text)."""
    if _LAST:
        last_snapshot, last_text, last_offset, last_focus = _LAST[0]
        if last_snapshot is snapshot and last_offset == offset and last_text == text:
            return last_focus
    result = _focus(snapshot, text, offset, cursor or cursor_at(text, offset))
    _LAST[:] = [(snapshot, text, offset, result)]
    return result


def _focus(snapshot: Snapshot | None, text: str, offset: int, cursor: Cursor) -> Focus:
    start, end = cursor.chunk
    insert = _placeholder_text(cursor)
    at = cursor.word[0] if not insert else cursor.offset
    edited = text[:at] + insert + text[at:] if insert else text
    key = snapshot.key if snapshot is not None else "<focus>"
    # Only the chunk is lexed and parsed, at its own place in the text.
    result = parse_part(edited, key, start, end + len(insert), line_of(text, start))
    chunk_decls = result.ast.declarations
    decls = list(chunk_decls)
    if snapshot is not None:
        decls = _splice(snapshot, text, start, end, chunk_decls)
    spliced = ParseResult(key, edited, ast.File(result.ast.span, tuple(decls)), (), result.comments)
    with gc_paused():
        config = snapshot.config if snapshot is not None else None
        program = build_program(
            key,
            _reader(snapshot, key, spliced),
            tuple(getattr(config, "implicit_imports", ()) or ()),
            dict(getattr(config, "modules", {}) or {}),
            tuple(str(p) for p in getattr(config, "search_paths", ()) or ()),
        )
    return Focus(cursor, ast.File(result.ast.span, chunk_decls), program.model, bool(insert))


def _splice(
    snapshot: Snapshot,
    text: str,
    start: int,
    end: int,
    chunk_decls: tuple[ast.Declaration, ...],
) -> list[ast.Declaration]:
    """The snapshot's declarations outside the chunk (as skeletons), with the chunk's
    own declarations in their place."""
    cache = snapshot._cache.setdefault("skeleton", {})
    skeletons = cache.get("root")
    if skeletons is None:
        skeletons = cache["root"] = [(d, skeleton(d)) for d in snapshot.ast.declarations]
    old = snapshot.text
    change = TextMap(old, text)
    old_start = map_offset(old, text, start, change)
    old_end = map_offset(old, text, end, change)
    kept = _relevant(skeletons, text[start:end], old_start, old_end)
    result: list[ast.Declaration] = []
    inserted = False
    for decl, skel in skeletons:
        span = decl.span
        if id(decl) not in kept or span.start < old_end and span.end > old_start:
            continue
        if not inserted and span.start >= old_end:
            result.extend(chunk_decls)
            inserted = True
        result.append(skel)
    if not inserted:
        result.extend(chunk_decls)
    return result


_IDENTIFIERS = re.compile(r"[^\W\d]\w*")
_ALWAYS = (
    ast.ImportDecl,
    ast.UseStatement,
    ast.NamespaceDecl,
    ast.ExportDecl,
    ast.PhysicalTypeDecl,
    ast.UnitDecl,
    ast.EnumDecl,
    ast.EnumExtension,
    ast.GlobalDecl,
)


def _type_names(ref: object) -> list[str]:
    match ref:
        case ast.NamedType():
            return [ref.name.name.text]
        case ast.ListType() | ast.RangeType():
            return _type_names(ref.element)
    return []


def _mentions(decl: ast.Node) -> set[str]:
    """Names of declarations that ``decl``'s skeleton refers to."""
    names: set[str] = set()
    if isinstance(decl, ast.StructuredDecl):
        if decl.inherits is not None:
            names.add(decl.inherits.target.name.text)
            if decl.inherits.target.actor is not None:
                names.add(decl.inherits.target.actor.name.text)
        if decl.name.actor is not None:
            names.add(decl.name.actor.name.text)
        if isinstance(decl, ast.ModifierDecl) and decl.of is not None:
            names.add(decl.of.name.text)
    members = getattr(decl, "members", ())
    for m in members:
        if isinstance(m, ast.FieldDecl) and m.type is not None:
            names.update(_type_names(m.type))
        elif isinstance(m, (ast.MethodDecl, ast.EventDecl)):
            for p in m.parameters:
                names.update(_type_names(p.type))
            if isinstance(m, ast.MethodDecl) and m.return_type is not None:
                names.update(_type_names(m.return_type))
    return names


def _relevant(
    skeletons: list[tuple[ast.Declaration, ast.Declaration]],
    chunk_text: str,
    old_start: int,
    old_end: int,
) -> set[int]:
    """The declarations the chunk can reach: those it names, the behaviours and
    extensions of what it names, and what those name in turn (fields' types,
    parents). Resolving only these keeps the focus cheap in a large file."""
    wanted = set(_IDENTIFIERS.findall(chunk_text))
    kept: set[int] = set()
    pending = [(d, s) for d, s in skeletons]
    grew = True
    while grew:
        grew = False
        rest = []
        for decl, skel in pending:
            if isinstance(decl, _ALWAYS):
                hit = True
            elif isinstance(decl, ast.StructuredDecl):
                hit = (
                    decl.name.name.text in wanted
                    or (decl.name.actor is not None and decl.name.actor.name.text in wanted)
                    or (
                        isinstance(decl, ast.ModifierDecl)
                        and decl.of is not None
                        and decl.of.name.text in wanted
                    )
                )
            elif isinstance(decl, ast.ExtendDecl):
                hit = decl.target.name.text in wanted
            else:
                hit = True
            if hit:
                kept.add(id(decl))
                before = len(wanted)
                wanted |= _mentions(skel)
                grew = grew or len(wanted) != before
            else:
                rest.append((decl, skel))
        pending = rest
    return kept


def _reader(
    snapshot: Snapshot | None, key: str, root: ParseResult
) -> Callable[[str], ParseResult | None]:
    def read(uri: str) -> ParseResult | None:
        if uri == key:
            return root
        if snapshot is None:
            return None
        cache = snapshot._cache.setdefault("skeleton", {})
        if uri in cache:
            cached: ParseResult | None = cache[uri]
            return cached
        found = snapshot.analysis.parses.get(uri)
        if found is None:
            try:
                data = Path(uri).read_bytes()
            except OSError:
                cache[uri] = None
                return None
            found = parse(decode_source(data)[0], uri)
        skeletal = cache[uri] = _skeleton_parse(found)
        return skeletal

    return read
