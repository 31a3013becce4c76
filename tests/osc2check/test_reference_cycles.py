"""An analysis holds no reference cycles: dropping it frees it at once, without the
cyclic garbage collector (the language server replaces one per edit)."""

from __future__ import annotations

import gc
import weakref

import pytest

from osc2check.analysis import AnalysisOptions, SourceInput, analyze
from osc2check.semantics.symbols import SymbolKind

TEXT = """\
import osc.standard

enum mood: [calm, angry]
struct pose:
    x: length = 1m
actor robot inherits vehicle:
    feeling: mood = mood!calm
scenario drive_on:
    hero: robot
    at: pose
    event near
    def double(v: speed) -> speed is v * 2
    do serial:
        hero.drive() with:
            speed(20kph)
        wait elapsed(2s)
"""


def test_a_dropped_analysis_is_freed_by_reference_counting():
    gc.collect()
    gc.disable()
    try:
        analysis = analyze([SourceInput("/tmp/cycles.osc", TEXT)], AnalysisOptions())
        model = analysis.programs["/tmp/cycles.osc"].model
        declared = [s for s in model.symbols if s.kind is not SymbolKind.UNIT]
        assert {s.kind for s in declared} >= {SymbolKind.ENUM, SymbolKind.STRUCT}
        refs = [weakref.ref(model), *(weakref.ref(s) for s in declared)]
        del analysis, model, declared
        assert [r() for r in refs if r() is not None] == []
    finally:
        gc.enable()


def test_a_type_outliving_its_analysis_says_so():
    analysis = analyze([SourceInput("/tmp/cycles.osc", TEXT)], AnalysisOptions(verify=False))
    model = analysis.programs["/tmp/cycles.osc"].model
    pose = next(s for s in model.symbols if s.name == "pose")
    pose_type = pose.type
    assert pose_type is not None and pose_type.symbol is pose and str(pose_type) == "pose"
    del analysis, model, pose
    with pytest.raises(ReferenceError):
        _ = pose_type.symbol
