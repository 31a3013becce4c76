"""One binder: only the call checker reads which parameter an argument gives a value to.

Every other module reads the checker's bindings (``Model.binding``); binding arguments
again means telling positional arguments from named ones. This scans the source of the
three packages for any use of ``PositionalArgument`` or ``NamedArgument`` (an attribute,
a name, a ``match`` class pattern) and fails on one outside the allow-list below.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
PACKAGES = ("osc2check", "osc2lsp", "osc2runner")
ARGUMENT_CLASSES = frozenset({"PositionalArgument", "NamedArgument"})

#: Modules that may tell argument kinds apart: the syntax (which builds them) and the
#: binder with its records.
ALLOWED_MODULES = {
    "osc2check/syntax/ast.py": "declares the argument nodes",
    "osc2check/syntax/build.py": "builds them from the parse tree",
    "osc2check/semantics/calls.py": "the call checker: the one binder",
    "osc2check/semantics/bindings.py": "the binder's records and value readers",
    "osc2lsp/features/completion.py": "completes text being typed, which no analysis bound",
    "osc2check/dialects/carla_forms.py": "rewrites CARLA's forms as written, before analysis",
}
#: Functions elsewhere that read argument nodes without binding them.
ALLOWED_FUNCTIONS = {
    ("osc2check/semantics/declare.py", "si_dimension"): "SI(m: 1, ...) of a type or unit: no call",
    ("osc2runner/compile/text.py", "unparse"): "prints an argument as written",
}


def uses(source: str) -> list[tuple[str, int]]:
    """The (enclosing function, line) of each use of an argument class in ``source``."""
    tree = ast.parse(source)
    found: list[tuple[str, int]] = []

    def visit(node: ast.AST, function: str) -> None:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            function = node.name if not function else function
        name = None
        if isinstance(node, ast.Attribute):
            name = node.attr
        elif isinstance(node, ast.Name):
            name = node.id
        elif isinstance(node, ast.alias):
            name = node.name.rsplit(".", 1)[-1]
        if name in ARGUMENT_CLASSES:
            found.append((function, getattr(node, "lineno", 0)))
        for child in ast.iter_child_nodes(node):
            visit(child, function)

    visit(tree, "")
    return found


def _sources() -> dict[str, str]:
    return {
        path.relative_to(ROOT).as_posix(): path.read_text(encoding="utf-8")
        for package in PACKAGES
        for path in sorted((ROOT / package).rglob("*.py"))
    }


def test_no_module_outside_the_call_checker_binds_arguments() -> None:
    offending = [
        f"{module}:{line} (in {function or 'module level'})"
        for module, source in _sources().items()
        if module not in ALLOWED_MODULES
        for function, line in uses(source)
        if (module, function) not in ALLOWED_FUNCTIONS
    ]
    assert not offending, (
        "these read argument kinds themselves; read the call checker's binding "
        "(Model.binding) instead:\n" + "\n".join(offending)
    )


def test_the_allow_list_is_current() -> None:
    """Each allowed place still reads argument kinds (the scan sees them: it is no empty
    check), and the binder does."""
    sources = _sources()
    for module in ALLOWED_MODULES:
        assert uses(sources[module]), f"{module} no longer needs its place on the list"
    for module, function in ALLOWED_FUNCTIONS:
        assert function in {f for f, _ in uses(sources[module])}, (module, function)
    assert "check" in {f for f, _ in uses(sources["osc2check/semantics/calls.py"])}


def test_the_scan_finds_a_second_binder() -> None:
    binder = (
        "from osc2check.syntax import ast\n"
        "def bind(params, arguments):\n"
        "    for i, arg in enumerate(arguments):\n"
        "        match arg:\n"
        "            case ast.PositionalArgument():\n"
        "                yield params[i], arg.value\n"
    )
    assert uses(binder) == [("bind", 5)]
    imported = "from osc2check.syntax.ast import NamedArgument as N\n"
    assert uses(imported) == [("", 1)]
