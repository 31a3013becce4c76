"""A program: one root file, everything it imports, and the standard library.

Imports are followed depth first; each file is read and parsed once per
analysis. A FIFO, socket or device is never opened (it could block or never end):
importing one is an unresolved import that says what the path is.

``import osc.standard`` (and the design paper's ``import "domain.osc"``) puts the
library's namespaces on the file's use list; the other ``osc.standard.*`` modules
only make them available for qualified names and ``namespace ... use``. Other
tools' libraries under the standard's reserved name ``osc`` (scenario_execution's
``osc.helpers``) are the files the module map gives them, else looked for in the
search paths (:func:`_tool_module_path`), with a warning (D810) that the module map
(the user's explicit say) does without.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from osc2check import inputs, memory, messages
from osc2check.diagnostics import Diagnostic
from osc2check.semantics.declare import Unit
from osc2check.semantics.model import Context, Model
from osc2check.semantics.profile import LibraryChoice
from osc2check.semantics.resolve import resolve
from osc2check.semantics.stdlib import (
    AUTO_USE,
    STANDARD_FILE_NAMES,
    STANDARD_MODULES,
    comment_lines,
    standard_library,
)
from osc2check.source import Span
from osc2check.syntax import ParseResult, ast

Reader = Callable[[str], ParseResult | None]


@dataclass
class Program:
    root: str
    model: Model
    library: LibraryChoice = field(default_factory=LibraryChoice)
    files: dict[str, ParseResult] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    imports: dict[str, list[str]] = field(default_factory=dict)  # uri -> imported uris


def _resolve_path(importer: str, target: str) -> Path:
    base = Path(importer).parent if importer and not importer.startswith("<") else Path.cwd()
    if target.startswith("file://"):
        target = target[len("file://") :]
    path = Path(target)
    # `a/../lib/x.osc` and `lib/x.osc` are one file, reported under one name
    return Path(os.path.normpath(path if path.is_absolute() else base / path))


def _not_a_source(path: Path) -> str | None:
    """Why the file at ``path`` is not read (a FIFO, a device, a folder), or None when it
    is a regular file or missing (the reader then says whether it has it)."""
    try:
        return inputs.not_regular(inputs.probe(path))
    except inputs.InputError:
        return None


def _not_found(tried: list[Path]) -> str:
    """Why none of the files ``tried`` was imported: what the first special one is, or
    that none exists."""
    for path in tried:
        why = _not_a_source(path)
        if why is not None:
            return f"`{path}` is {why}"
    return "no file " + " or ".join(f"`{path}`" for path in tried)


def _first_file(candidates: list[Path], read: Reader) -> tuple[Path, ParseResult] | None:
    for path in candidates:
        if _not_a_source(path) is None:
            result = read(str(path))
            if result is not None:
                return path, result
    return None


def _module_path(
    importer: str, target: str, search_paths: tuple[str, ...], read: Reader
) -> tuple[Path, ParseResult | None]:
    """The file of ``import a.b``: ``a/b.osc`` beside the importing file, else in the
    first search path that has it; the file beside the importer when none does."""
    relative = target.replace(".", "/") + ".osc"
    first = _resolve_path(importer, relative)
    found = _first_file([first, *(Path(folder) / relative for folder in search_paths)], read)
    return found if found is not None else (first, None)


def _is_tool_module(target: str) -> bool:
    """Whether ``import target`` names a module under ``osc`` that is not the standard's."""
    return (target == "osc" or target.startswith("osc.")) and target not in STANDARD_MODULES


def _tool_module_path(
    importer: str, target: str, search_paths: tuple[str, ...], read: Reader
) -> tuple[Path, ParseResult] | None:
    """The file of another tool's ``import osc.a.b``: ``osc/a/b.osc`` (the standard's
    reading of the name) or ``a/b.osc`` (a tool's library folder, scenario_execution's
    ``lib_osc``), beside the importing file or in a search path."""
    parts = target.split(".")
    names = ["/".join(parts) + ".osc", *(["/".join(parts[1:]) + ".osc"] if len(parts) > 1 else [])]
    folders = [_resolve_path(importer, "."), *(Path(folder) for folder in search_paths)]
    return _first_file([folder / name for folder in folders for name in names], read)


def _carla_file(
    importer: str, target: str, search_paths: tuple[str, ...], read: Reader
) -> tuple[Path, ParseResult, bool] | None:
    """The file ``basic.osc`` of CARLA's ``import basic.osc`` (beside the importer, then in
    the search paths), and whether it is the one beside the importer."""
    if not target.endswith(".osc"):
        return None
    beside = _resolve_path(importer, target)
    found = _first_file([beside, *(Path(folder) / target for folder in search_paths)], read)
    if found is None:
        return None
    return found[0], found[1], found[0] == beside


def build_program(
    root: str,
    read: Reader,
    implicit_imports: tuple[str, ...] = (),
    modules: dict[str, str] | None = None,
    search_paths: tuple[str, ...] = (),
    library: LibraryChoice | None = None,
) -> Program:
    """Resolve the program rooted at ``root``; ``read`` returns a parsed file or None.

    ``modules`` maps structured import names to files (``osc.types`` -> a path),
    checked before the standard modules. Other structured imports (``import
    a.b``, §7.7.5.1.2 leaves their resolution to the implementation) name the
    file ``a/b.osc``, looked for beside the importing file and then in each of
    ``search_paths`` in order; a relative search path is taken from the current
    directory, as any relative path a program is given. ``library`` chooses the
    standard library's version (2.1 by default).
    """
    library = library or LibraryChoice()
    state = _Reading(
        program=Program(root, Model(base=standard_library(library.version).model), library),
        read=read,
        modules=modules or {},
        search_paths=search_paths,
    )
    root_result = read(root)
    if root_result is not None:
        _visit(state, root, root_result, implicit_imports)
        state.program.diagnostics.extend(resolve(state.program.model, state.units))
    return state.program


@dataclass
class _Reading:
    """What ``build_program`` keeps while it follows the imports depth first."""

    program: Program
    read: Reader
    modules: dict[str, str]
    search_paths: tuple[str, ...]
    units: list[Unit] = field(default_factory=list)
    visiting: list[str] = field(default_factory=list)  # normalised paths being read, root first
    leads: list[Span] = field(default_factory=list)  # import in visiting[i] to visiting[i + 1]
    done: set[str] = field(default_factory=set)

    @property
    def model(self) -> Model:
        return self.program.model


def _visit(
    state: _Reading, uri: str, result: ParseResult, extra_modules: tuple[str, ...] = ()
) -> None:
    state.visiting.append(os.path.normpath(uri))
    uses: list[str] = []
    imported: list[str] = []
    for module in extra_modules:  # implicit imports also put their namespaces in use
        namespaces, _ = STANDARD_MODULES[module]
        state.model.library_namespaces.update(namespaces)
        uses.extend(namespaces)
    for decl in result.ast.declarations:
        if not isinstance(decl, ast.ImportDecl):
            continue
        target = decl.target
        found: ParseResult | None = None
        if decl.kind == "module" and target in state.modules:
            path = _resolve_path(uri, state.modules[target])  # the user's say: no warning
        elif decl.kind == "module":
            if target in STANDARD_MODULES:
                namespaces, in_use = STANDARD_MODULES[target]
                state.model.library_namespaces.update(namespaces)
                uses.extend(in_use)
                continue
            if _is_tool_module(target):
                tool = _tool_module_path(uri, target, state.search_paths, state.read)
                if tool is None:
                    state.program.diagnostics.append(
                        messages.unresolved_import(
                            decl.target_span,
                            target,
                            "no such module of the standard library (`osc.standard`, "
                            "`osc.standard.all`, `.types`, `.domain`), and no file for it in "
                            "the search paths or the module map (`[tool.osc2check.modules]`)",
                        )
                    )
                    continue
                path, found = tool
                state.program.diagnostics.append(
                    messages.tool_module(decl.target_span, target, str(path))
                )
            else:
                path, found = _module_path(uri, target, state.search_paths, state.read)
            carla = (
                None
                if found is not None or _is_tool_module(target)
                else _carla_file(uri, target, state.search_paths, state.read)
            )
            if carla is not None:
                path, found, beside = carla
                state.program.diagnostics.append(
                    messages.unquoted_file_import(decl.target_span, target, beside)
                )
        else:
            path = _resolve_path(uri, target)
        key = str(path)
        imported_result = found
        if imported_result is None and _not_a_source(path) is None:
            with memory.analysing(decl.span, f"reading the import of `{target}`"):
                imported_result = state.read(key)
        if imported_result is None:
            if decl.kind == "file" and Path(target).name in STANDARD_FILE_NAMES:
                state.program.diagnostics.append(messages.standard_file_import(decl.span, target))
                state.model.library_namespaces.update(STANDARD_MODULES["osc.standard"][0])
                uses.extend(AUTO_USE)
                continue
            tried = [path]
            if decl.kind == "module" and target.endswith(".osc"):
                tried.append(_resolve_path(uri, target))
            state.program.diagnostics.append(
                messages.unresolved_import(decl.target_span, target, _not_found(tried))
            )
            continue
        imported.append(key)
        norm = os.path.normpath(key)
        if norm in state.visiting:
            # Said at the root's own import that leads into the cycle: the root's
            # findings are the ones reported for it.
            chain = state.visiting[state.visiting.index(norm) :] + [norm]
            span = state.leads[0] if state.leads else decl.target_span
            state.program.diagnostics.append(messages.import_cycle(span, chain))
            continue
        if norm not in state.done:
            state.leads.append(decl.target_span)
            _visit(state, key, imported_result)
            state.leads.pop()
    state.visiting.pop()
    state.done.add(os.path.normpath(uri))
    state.program.files[uri] = result
    state.program.imports[uri] = imported
    ctx = Context("", tuple(dict.fromkeys(uses)))
    state.units.append(Unit(uri, result.ast, ctx, comments=comment_lines(result)))
