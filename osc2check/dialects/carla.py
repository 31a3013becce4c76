"""CARLA scenario_runner's OSC2 dialect, read as standard OSC2.

CARLA's examples (``srunner/examples/*.osc``) import its library ``basic.osc``,
which declares bare names (``actor Model3``, ``actor Path``, ``modifier
Path.set_map``) whose meaning lives in scenario_runner's Python. Each form of the
dialect is a rule here or in :mod:`osc2check.dialects.carla_forms`: it says what
the form means as an edit that turns it into standard OSC2 on the toolkit's CARLA
world (``stdlib/carla.osc``, module ``osc2toolkit.carla``), and reports the form
with its own D code. The edited text is what ``osc2check migrate`` writes and
what the checker, the runner and the language server read in CARLA's dialect
(:func:`osc2check.dialects.rewrite.read_through`), so a migrated file runs as
the original does.

A file is read in CARLA's dialect when the dialect is ``carla``, or ``auto``
(the default) and it imports ``basic.osc`` or declares ``modifier Path.set_map``
(:func:`is_carla`). Rules read one file; what they need of another scenario
(the actors a scenario shares by name) is found in the same file, as CARLA's
examples have it. docs/migrating.md lists every form with its meaning.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import PurePosixPath

from osc2check import messages
from osc2check.diagnostics import Diagnostic
from osc2check.dialects.carla_forms import behaviour_forms
from osc2check.dialects.carla_text import CarlaText
from osc2check.dialects.rewrite import Edit
from osc2check.semantics import types as T
from osc2check.semantics.declare import si_dimension
from osc2check.source import Span
from osc2check.syntax import ParseResult, ast

__all__ = ["CARLA_MODULE", "CarlaReading", "carla_reading", "is_carla"]

CARLA_MODULE = "osc2toolkit.carla"
LIBRARY_FILE = "basic.osc"
# What CARLA's basic.osc declares bare, and the toolkit's CARLA world says in OSC2.
WORLD_ACTORS = frozenset({"dut", "Path", "Car", "Model3", "Mkz2017", "Carlacola", "Rubicon"})
WORLD_MODIFIERS = frozenset({"Path.set_map", "Path.path_min_driving_lanes"})
# CARLA's basic.osc gets these factors wrong (57.3 for a degree instead of 1/57.3).
_WRONG_FACTORS = frozenset({"degree", "deg"})


@dataclass(frozen=True)
class CarlaReading:
    """The edits that make a CARLA file standard OSC2, and the findings that name them."""

    edits: tuple[Edit, ...] = ()
    findings: tuple[Diagnostic, ...] = ()


def is_carla(result: ParseResult) -> bool:
    """Whether a file is CARLA's: it imports ``basic.osc`` or declares ``Path.set_map``."""
    for decl in result.ast.declarations:
        if isinstance(decl, ast.ImportDecl) and _imports_library(decl):
            return True
        if isinstance(decl, ast.ModifierDecl) and str(decl.name) in WORLD_MODIFIERS:
            return True
    return False


def _imports_library(decl: ast.ImportDecl) -> bool:
    return PurePosixPath(decl.target.replace("\\", "/")).name == LIBRARY_FILE


def carla_reading(result: ParseResult) -> CarlaReading:
    """The CARLA forms of one file: their edits and findings (see the module docstring)."""
    text = CarlaText(result)
    _library(text)
    behaviour_forms(text)
    return CarlaReading(tuple(text.edits), tuple(text.findings))


# ---- CARLA's library: the import and the declarations it repeats -----------------------


def _library(text: CarlaText) -> None:
    """``import basic.osc`` -> ``import osc2toolkit.carla``; what CARLA's library declares
    again in the file is commented out; unit exponents are their type's."""
    declarations = text.file.declarations
    imports = [d for d in declarations if isinstance(d, ast.ImportDecl) and _imports_library(d)]
    for imported in imports:
        text.replace(imported.span, f"import {CARLA_MODULE}")
        text.report(messages.carla_world_import(imported.target_span, imported.target))
    world = [d for d in declarations if _repeats_world(text, d)]
    if world and not imports:  # CARLA's library written out in the file itself
        text.insert(0, f"import {CARLA_MODULE}\n")
    for decl in world:
        text.comment_out(decl.span)
        name, what = _described(decl)
        text.report(messages.carla_world_declaration(name, what, _note(decl)))
    for decl in declarations:
        if isinstance(decl, ast.UnitDecl) and decl not in world:
            _unit_dimension(text, decl)


def _repeats_world(text: CarlaText, decl: ast.Declaration) -> bool:
    """Whether ``decl`` is one of CARLA's library declarations that the CARLA world (and
    the standard library under it) says already."""
    match decl:
        case ast.ActorDecl(inherits=None, has_body=False):
            return str(decl.name) in WORLD_ACTORS
        case ast.ModifierDecl(has_body=False):
            return str(decl.name) in WORLD_MODIFIERS
        case ast.PhysicalTypeDecl():
            standard = text.standard_type(decl.name.text)
            return standard is not None and standard.dimension == _dimension(decl.si)
        case ast.UnitDecl():
            unit = text.standard_unit(decl.name.text)
            return unit is not None and unit.dimension == _type_dimension(text, decl.type)
    return False


def _described(decl: ast.Declaration) -> tuple[Span, str]:
    """The name of a declaration of CARLA's library, and how a message calls it."""
    match decl:
        case ast.PhysicalTypeDecl():
            return decl.name.span, f"type `{decl.name.text}`"
        case ast.UnitDecl():
            return decl.name.span, f"unit `{decl.name.text}`"
        case ast.ActorDecl() | ast.ModifierDecl():
            kind = "actor" if isinstance(decl, ast.ActorDecl) else "modifier"
            return decl.name.span, f"{kind} `{decl.name}`"
    return decl.span, "declaration"


def _note(decl: ast.Declaration) -> str:
    if isinstance(decl, ast.UnitDecl) and decl.name.text in _WRONG_FACTORS:
        return "; CARLA's factor for it (57.3) makes a degree 57 radians: the standard's is used"
    if isinstance(decl, ast.PhysicalTypeDecl) and decl.name.text == "velocity":
        return "; CARLA's `velocity` is the standard's `speed`"
    return ""


def _dimension(si: tuple[ast.Argument, ...]) -> T.Dimension:
    """The SI exponents of ``SI(m: 1, s: -1, ...)`` (factor and offset left out)."""
    return si_dimension(si, for_unit=True)[0]


def _type_dimension(text: CarlaText, type_name: ast.QualifiedName) -> T.Dimension | None:
    """The dimension of the type a unit is declared of: the standard's type of that name
    (CARLA's ``velocity`` is speed), else the file's own."""
    standard = text.standard_type(type_name.name.text)
    if standard is not None:
        return standard.dimension
    for other in text.file.declarations:
        if isinstance(other, ast.PhysicalTypeDecl) and other.name.text == type_name.name.text:
            return _dimension(other.si)
    return None


def _unit_dimension(text: CarlaText, decl: ast.UnitDecl) -> None:
    """``unit kphps of acceleration is SI(m: 1, s: -1, ...)``: CARLA takes a unit's
    dimension from its type; the exponents written are made the type's."""
    wanted = _type_dimension(text, decl.type)
    written = _dimension(decl.si)
    if wanted is None or wanted == written or not decl.si:
        return
    exponents = [f"{b}: {e}" for b, e in zip(T.BASE_UNITS, wanted, strict=True) if e]
    scale = [text.source(a) for a in decl.si if text.source(a).startswith(("factor", "offset"))]
    text.replace_between(decl.si[0].span.start, decl.si[-1].span.end, ", ".join(exponents + scale))
    text.report(messages.carla_unit_dimension(decl.name.span, decl.name.text, str(decl.type)))
