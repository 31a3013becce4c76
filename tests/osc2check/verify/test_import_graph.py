"""The modules of ``osc2check.verify`` import one another without a circle.

Every import counts: module level, function-local and under ``TYPE_CHECKING``, since a
circle hidden in a function or a type-only import is still a circle a reader must
untangle. Read from the source with ``ast``, so nothing is imported.
"""

from __future__ import annotations

import ast
from pathlib import Path

import osc2check.verify

PACKAGE = "osc2check.verify"
FOLDER = Path(osc2check.verify.__file__).resolve().parent


def imported_modules(path: Path, package: str, modules: set[str]) -> set[str]:
    """The modules of ``modules`` (short names inside ``package``) that ``path`` imports."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module is not None and node.level == 0:
            names = [node.module] + [f"{node.module}.{alias.name}" for alias in node.names]
        for name in names:
            if name.startswith(package + "."):
                short = name[len(package) + 1 :].split(".")[0]
                if short in modules:
                    found.add(short)
    found.discard(path.stem)
    return found


def import_graph(folder: Path, package: str) -> dict[str, set[str]]:
    """Each module of the package folder ``folder`` -> the package's modules it imports."""
    files = {path.stem: path for path in sorted(folder.glob("*.py"))}
    return {name: imported_modules(path, package, set(files)) for name, path in files.items()}


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The elementary circles of ``graph``, each from its least module (a bounded walk:
    the graph has a few dozen nodes)."""
    found: list[list[str]] = []

    def walk(start: str, node: str, path: list[str]) -> None:
        for target in sorted(graph[node]):
            if target == start:
                found.append([*path])
            elif target > start and target not in path:
                walk(start, target, [*path, target])

    for start in sorted(graph):
        walk(start, start, [start])
    return found


def test_circles_are_found() -> None:
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert circles(graph) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []


def test_function_local_and_type_checking_imports_count(tmp_path: Path) -> None:
    (tmp_path / "one.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pkg.two import Thing\n",
        encoding="utf-8",
    )
    (tmp_path / "two.py").write_text(
        "def make():\n    from pkg import one\n    return one\n", encoding="utf-8"
    )
    graph = import_graph(tmp_path, "pkg")
    assert graph == {"one": {"two"}, "two": {"one"}}
    assert circles(graph) == [["one", "two"]]


def test_verify_has_no_import_circle() -> None:
    graph = import_graph(FOLDER, PACKAGE)
    assert "check" in graph and "ir" in graph  # the folder read is the package's
    assert circles(graph) == []
