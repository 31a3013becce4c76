"""No import circle inside the packages whose modules are peers (issue 24): every import
counts, at module level, inside a function and under ``TYPE_CHECKING`` (a circle that
works only because one side imports late is still a circle to whoever changes the code).
The graph is read from the source (:mod:`tests.import_graph`); nothing is imported."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.import_graph import circles, import_graph

ROOT = Path(__file__).resolve().parents[1]

#: the packages kept free of circles, and one module each that must be in the graph
PACKAGES = {
    "osc2check.messages": "osc2check.messages.names",
    "osc2check.verify": "osc2check.verify.pipeline",
    "osc2runner.sim": "osc2runner.sim.world",
    "osc2runner.compile": "osc2runner.compile.tree",
    "osc2lsp": "osc2lsp.server",
}


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_the_package_has_no_import_circle(package: str) -> None:
    graph = import_graph(ROOT / package.replace(".", "/"), package)
    assert PACKAGES[package] in graph
    assert circles(graph) == []


def test_the_graph_sees_lazy_and_type_checking_imports() -> None:
    graph = import_graph(ROOT / "osc2lsp", "osc2lsp")
    assert "osc2lsp.snapshot" in graph["osc2lsp.session.analysis"]  # inside analyse()
    assert "osc2lsp.snapshot" in graph["osc2lsp.session.view"]  # under TYPE_CHECKING


def test_the_graph_counts_lazy_relative_and_type_checking_imports(tmp_path: Path) -> None:
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("from pkg.a import A\n")
    (pkg / "a.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pkg.b import B\nA = 1\n"
    )
    (pkg / "b.py").write_text("def f():\n    from . import a\n    return a\n")
    (pkg / "c.py").write_text("import pkg.b\nfrom .sub import d\n")
    (pkg / "sub").mkdir()
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "d.py").write_text("from ..c import x\n")
    graph = import_graph(pkg, "pkg")
    assert graph["pkg"] == {"pkg.a"}
    assert graph["pkg.a"] == {"pkg.b"}
    assert graph["pkg.b"] == {"pkg.a"}
    assert graph["pkg.c"] == {"pkg.b", "pkg.sub.d"}
    assert graph["pkg.sub.d"] == {"pkg.c"}
    assert circles(graph) == [["pkg.a", "pkg.b"], ["pkg.c", "pkg.sub.d"]]


def test_a_circle_of_three_is_found() -> None:
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []
