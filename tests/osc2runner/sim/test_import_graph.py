"""No import circle inside ``osc2runner/sim/``, lazy and ``TYPE_CHECKING`` imports counted."""

from __future__ import annotations

from pathlib import Path

import osc2runner.sim
from tests.import_graph import circles, import_graph

SIM = Path(osc2runner.sim.__file__).parent


def test_sim_has_no_import_circle():
    graph = import_graph(SIM, "osc2runner.sim")
    assert "osc2runner.sim.world" in graph
    assert circles(graph) == []


def test_the_graph_counts_lazy_and_type_checking_imports(tmp_path):
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
