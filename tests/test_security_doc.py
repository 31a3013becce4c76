"""docs/security.md quotes every budget: each figure it gives is the constant's value now."""

from __future__ import annotations

from pathlib import Path

import pytest

from osc2check import inputs, memory, numbers
from osc2check.verify import check, lower, z3_backend
from osc2check.world import budget
from osc2lsp.transport import framing
from osc2runner.campaign import campaign, outputs
from osc2runner.sut import loading

PAGE = Path(__file__).resolve().parents[1] / "docs" / "security.md"
MIB = 1024 * 1024


def _mib(value: int) -> str:
    assert value % MIB == 0
    return f"{value // MIB} MiB"


QUOTED = [
    (_mib(inputs.MAX_SOURCE_BYTES), "MAX_SOURCE_BYTES"),
    (f"| {numbers.MAX_DIGITS} (", "MAX_DIGITS"),
    (f"10^-{numbers.MAX_MAGNITUDE} .. 10^{numbers.MAX_MAGNITUDE}", "MAX_MAGNITUDE"),
    (f"{numbers.MAX_VALUE_BITS} bits", "MAX_VALUE_BITS"),
    (f"2^±{numbers.MAX_BINARY_MAGNITUDE}", "MAX_BINARY_MAGNITUDE"),
    (f"| {check.MAX_SCENARIOS} (", "MAX_SCENARIOS"),
    (f"| {memory.DEFAULT_MEMORY_LIMIT_MIB} MiB that", "DEFAULT_MEMORY_LIMIT_MIB"),
    (f"a context ({_mib(memory.SOLVER_ROOM)},", "SOLVER_ROOM"),
    (f"z3 resource limit {z3_backend.DEFAULT_RLIMIT:,}", "DEFAULT_RLIMIT"),
    (f"and {z3_backend.DEFAULT_TIMEOUT_MS // 1000} s", "DEFAULT_TIMEOUT_MS"),
    (f"| {lower.MAX_DEPTH} deep", "MAX_DEPTH"),
    (f"| {_mib(budget.MAX_MAP_BYTES)} of XML", "MAX_MAP_BYTES"),
    (f"| {budget.MAX_MAP_ELEMENTS:,} |", "MAX_MAP_ELEMENTS"),
    (f"| {budget.MAX_ROAD_LENGTH / 1000:g} km |", "MAX_ROAD_LENGTH"),
    (f"within {budget.MAX_COORDINATE / 1000:,.0f} km of the origin", "MAX_COORDINATE"),
    (f"{budget.MAX_CURVATURE:g} per metre", "MAX_CURVATURE"),
    (f"at most {budget.MAX_LATERAL:g} m beside", "MAX_LATERAL"),
    (f"within {budget.MAX_ELEVATION / 1000:g} km of height zero", "MAX_ELEVATION"),
    (f"at least {budget.MIN_STEP * 100:g} cm apart", "MIN_STEP"),
    (f"| {budget.MAX_SAMPLES:,} (", "MAX_SAMPLES"),
    (f"| {budget.MAX_BORDER_VALUES:,} (", "MAX_BORDER_VALUES"),
    (f"| {budget.MAX_ROAD_AREA / 1e6:g} km²", "MAX_ROAD_AREA"),
    (_mib(framing.MAX_MESSAGE_BYTES), "MAX_MESSAGE_BYTES"),
    (f"over\n  {_mib(outputs.MAX_CAMPAIGN_BYTES)}", "MAX_CAMPAIGN_BYTES"),
    (f"over {_mib(outputs.MAX_RECORD_BYTES)}", "MAX_RECORD_BYTES"),
    (f"(default {loading.DEFAULT_STEP_TIMEOUT:g} s)", "DEFAULT_STEP_TIMEOUT"),
    (f"(default {campaign.DEFAULT_RUN_TIMEOUT:g} s)", "DEFAULT_RUN_TIMEOUT"),
]


@pytest.mark.parametrize(("text", "name"), QUOTED, ids=[name for _, name in QUOTED])
def test_the_security_page_quotes_each_budget_as_it_is(text, name):
    assert text in PAGE.read_text(encoding="utf-8"), f"docs/security.md: {name} is not {text!r}"
