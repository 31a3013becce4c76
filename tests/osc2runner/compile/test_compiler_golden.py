"""Compiled trees against golden text: ``.osc`` + ``.tree`` (``py_trees.display.unicode_tree``).

Cases are the ``.osc`` files in ``../trees/``, the repository's examples and,
when present, the design paper's scenarios. ``pytest --update-goldens``
rewrites the ``.tree`` files; read the diff before committing.
"""

from __future__ import annotations

from pathlib import Path

import py_trees
import pytest

from osc2runner.runner import compile_file

HERE = Path(__file__).parent
ROOT = HERE.parents[2]
TREES = HERE.parent / "trees"
SEED = Path(__file__).resolve().parents[2] / "data" / "seed"  # vendored

CASES = [(p, TREES / f"{p.stem}.tree") for p in sorted(TREES.glob("*.osc"))]
CASES += [
    (p, TREES / f"example_{p.stem}.tree")
    for p in sorted((ROOT / "examples").glob("*.osc"))
    if p.stem != "unsafe_typos"
]
CASES += [
    (SEED / name, TREES / f"seed_{Path(name).stem}.tree")
    for name in ("cut_in_and_stop.osc", "braking_friction.osc")
]


@pytest.mark.parametrize("source, golden", CASES, ids=[g.stem for _, g in CASES])
def test_compiled_tree_matches_golden(source: Path, golden: Path, update_goldens: bool):
    root = compile_file(source).root
    text = py_trees.display.unicode_tree(root)
    if update_goldens:
        golden.write_text(text, encoding="utf-8")
    assert golden.exists(), f"no golden {golden.name}; run pytest --update-goldens"
    assert text == golden.read_text(encoding="utf-8")
