"""ASAM's quality checkers (asam-qc-openscenarioxml, asam-qc-opendrive) called in-process.

Each runs the bundle's ``run_checks`` on one file, as its command (``qc_openscenario -c
config.xml``) does, and returns what a test asserts on: every checker's status and every
issue it raised (the rule, the severity, the description).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import pytest


@dataclass(frozen=True)
class CheckerRun:
    checker: str
    status: str
    issues: tuple[str, ...]


def _bundle(kind: str) -> tuple[ModuleType, object]:
    if kind == "xosc":
        pytest.importorskip("qc_openscenario")
        from qc_openscenario import constants
        from qc_openscenario.main import run_checks
    else:
        pytest.importorskip("qc_opendrive")
        from qc_opendrive import constants
        from qc_opendrive.main import run_checks
    return constants, run_checks


def asam_check(path: Path) -> list[CheckerRun]:
    """Every checker of ASAM's bundle for ``path`` (``.xosc`` or ``.xodr``) and its issues."""
    from qc_baselib import Configuration, Result

    constants, run_checks = _bundle(path.suffix.lstrip("."))
    config = Configuration()
    config.set_config_param("InputFile", str(path))
    config.register_checker_bundle(constants.BUNDLE_NAME)
    result = Result()
    result.register_checker_bundle(
        name=constants.BUNDLE_NAME, description="", version=constants.BUNDLE_VERSION, summary=""
    )
    result.set_result_version(version=constants.BUNDLE_VERSION)
    quiet = logging.root.manager.disable
    logging.disable(logging.INFO)  # the checkers log every step at INFO
    try:
        run_checks(config, result)  # type: ignore[operator]
    finally:
        logging.disable(quiet)
    bundle = result.get_checker_bundle_result(constants.BUNDLE_NAME)
    return [
        CheckerRun(
            c.checker_id,
            c.status.name,
            tuple(f"{i.level.name}: {i.description} {i.locations}" for i in c.issues),
        )
        for c in bundle.checkers
    ]


def assert_valid(path: Path) -> None:
    """``path`` passes ASAM's checker: no issue, no checker in error, the schema checked."""
    runs = asam_check(path)
    problems = [f"{r.checker}: {r.status} {list(r.issues)}" for r in runs if r.issues]
    problems += [f"{r.checker}: {r.status}" for r in runs if r.status == "ERROR"]
    assert not problems, f"{path.name}: " + "; ".join(problems)
    schema = [r for r in runs if r.checker.endswith("valid_schema")]
    assert schema and schema[0].status == "COMPLETED", schema
