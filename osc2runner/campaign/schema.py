"""A campaign folder is data: what ``campaign.json`` and ``record.json`` may hold.

``--resume DIR`` and ``--out DIR`` read files that anyone could have written, so each
is checked against the shape the campaign writes before anything of it is used: the
JSON types, numbers finite and in range, names that are names, no path that leads out
of the folder. A record that is not a record is a run done again (``read_records``
says why in the log); a ``campaign.json`` that is not a campaign is a
:class:`FolderError` naming the file and the field. Nothing read here is code: the
system under test a ``campaign.json`` names is only imported when the command line
names it too, or with ``--trust-folder`` (``campaign.command``).

Numbers that are not finite (``NaN``, which Python's JSON reads and writes) become
"no value" (None) in both directions: ``finite`` makes what a campaign writes valid
JSON, whatever a KPI computed.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any, Literal, TypeVar, get_args

from osc2check.semantics.profile import DIALECTS, OSC_VERSIONS
from osc2runner.campaign.steering import BinRef
from osc2runner.campaign.worker import RunRecord, run_folder
from osc2runner.execution.outcome import OUTCOME_STATUSES
from osc2runner.export import FORMATS
from osc2runner.options import DT_CONTROL, DT_PHYSICS

__all__ = [
    "STATUSES",
    "CampaignStatus",
    "FolderError",
    "campaign_document",
    "file_name",
    "finite",
    "record_from_json",
]

STATUSES = OUTCOME_STATUSES
#: a campaign's ``status``: running (its ``campaign.json`` before the runs end), complete
#: or interrupted
CampaignStatus = Literal["running", "complete", "interrupted"]
CAMPAIGN_STATUSES: tuple[CampaignStatus, ...] = get_args(CampaignStatus)
Choice = TypeVar("Choice", bound=str)
_SHA256 = re.compile(r"[0-9a-f]{64}")
_FILE_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,120}")
_SCALAR = (str, int, float, bool, type(None))


class FolderError(ValueError):
    """A file of a campaign folder that does not hold what the campaign writes."""


def finite(value: Any) -> Any:
    """``value`` with every number that is not finite (inside lists and dicts too) None."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    return value


def file_name(name: object) -> bool:
    """Whether ``name`` is a plain file name (no folder, no ``..``, no hidden file)."""
    return isinstance(name, str) and bool(_FILE_NAME.fullmatch(name)) and ".." not in name


# ---- the checks, each raising FolderError with the field's path -----------------------------


def _fail(where: str, what: str) -> FolderError:
    return FolderError(f"{where}: {what}")


def _dict(value: Any, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise _fail(where, "not an object")
    return value


def _int(value: Any, where: str, low: int = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise _fail(where, f"not a whole number of at least {low}")
    return value


def _number(value: Any, where: str, positive: bool = False) -> float | None:
    """A number, or None (for null, and for one that is not finite: "no value");
    ``positive``: a finite number above 0 (or null)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _fail(where, "not a number")
    if positive and not (math.isfinite(value) and value > 0):
        raise _fail(where, "not a positive finite number")
    return float(value) if math.isfinite(value) else None


def _text(value: Any, where: str, limit: int = 10_000) -> str:
    if not isinstance(value, str) or len(value) > limit:
        raise _fail(where, "not a text")
    return value


def _optional_text(value: Any, where: str, limit: int = 10_000) -> str | None:
    return None if value is None else _text(value, where, limit)


def _choice(value: Any, where: str, allowed: tuple[Choice, ...]) -> Choice:
    for choice in allowed:
        if value == choice:
            return choice
    raise _fail(where, f"not one of {', '.join(allowed)}")


def _items(value: Any, where: str, check: Callable[[Any, str], Any]) -> list[Any]:
    if not isinstance(value, list):
        raise _fail(where, "not a list")
    return [check(v, f"{where}[{i}]") for i, v in enumerate(value)]


def _scalar(value: Any, where: str) -> Any:
    """A JSON value without nesting (a KPI, a parameter's value); NaN is None."""
    if not isinstance(value, _SCALAR):
        raise _fail(where, "not a number, text, boolean or null")
    if isinstance(value, str):
        return _text(value, where)
    return finite(value)


def _scalars(value: Any, where: str) -> dict[str, Any]:
    return {_text(k, where): _scalar(v, f"{where}.{k}") for k, v in _dict(value, where).items()}


def _record_value(value: Any, where: str) -> Any:
    """A ``record`` item's value: a scalar, or a list of scalars."""
    if isinstance(value, list):
        return [_scalar(v, f"{where}[{i}]") for i, v in enumerate(value)]
    return _scalar(value, where)


def _parameter(value: Any, where: str) -> dict[str, Any]:
    p = _dict(value, where)
    unknown = set(p) - {"text", "value", "unit"}
    if unknown:
        raise _fail(where, f"has no field `{sorted(unknown)[0]}`")
    return {k: _scalar(v, f"{where}.{k}") for k, v in p.items()}


def _bin(value: Any, where: str) -> BinRef | None:
    if value is None:
        return None
    b = _dict(value, where)
    item = _text(b.get("item"), f"{where}.item", limit=200)
    label = _text(b.get("label", ""), f"{where}.label", limit=200)
    return BinRef(item, _int(b.get("index"), f"{where}.index"), label)


# ---- record.json -----------------------------------------------------------------------


def record_from_json(data: Any, where: str = "record.json") -> RunRecord:
    """The run record ``data`` holds, checked field by field (FolderError when it is
    not one). Its folder is ``runs/<seed>`` whatever the file says, and its files are
    plain names in it."""
    d = _dict(data, where)
    seed = _int(d.get("seed"), f"{where}.seed")
    outcome = _dict(d.get("outcome"), f"{where}.outcome")
    files = _items(d.get("files", []), f"{where}.files", lambda v, w: _text(v, w, limit=200))
    bad = [f for f in files if not file_name(f)]
    if bad:
        raise _fail(f"{where}.files", f"`{bad[0]}` is not a file name of the run's folder")
    coverage = {
        _text(k, f"{where}.coverage", limit=200): _items(
            v, f"{where}.coverage.{k}", lambda b, w: _int(b, w)
        )
        for k, v in _dict(d.get("coverage", {}), f"{where}.coverage").items()
    }
    return RunRecord(
        seed=seed,
        status=_choice(outcome.get("status"), f"{where}.outcome.status", STATUSES),
        reason=_text(outcome.get("reason", ""), f"{where}.outcome.reason"),
        bin=_bin(d.get("bin"), f"{where}.bin"),
        time_s=_number(outcome.get("time", 0.0), f"{where}.outcome.time") or 0.0,
        tick=_int(outcome.get("tick", 0), f"{where}.outcome.tick"),
        parameters={
            _text(k, f"{where}.parameters", limit=200): _parameter(v, f"{where}.parameters.{k}")
            for k, v in _dict(d.get("parameters", {}), f"{where}.parameters").items()
        },
        kpis=_scalars(d.get("kpis", {}), f"{where}.kpis"),
        records={
            _text(k, f"{where}.records", limit=200): _record_value(v, f"{where}.records.{k}")
            for k, v in _dict(d.get("records", {}), f"{where}.records").items()
        },
        coverage=coverage,
        wall_s=_number(d.get("wall_seconds", 0.0), f"{where}.wall_seconds") or 0.0,
        folder=run_folder(seed),
        files=files,
        error=_optional_text(d.get("error"), f"{where}.error", limit=100_000),
    )


# ---- campaign.json ----------------------------------------------------------------------


def campaign_document(data: Any, where: str = "campaign.json") -> dict[str, Any]:
    """The parts of a ``campaign.json`` that ``--resume`` and ``--out`` read, checked
    (FolderError when it is not a campaign of this format): ``source``,
    ``source_sha256``, ``scenario``, ``status``, ``options``, ``plan.seeds``."""
    from osc2runner.campaign.campaign import ENGINES, STRATEGIES
    from osc2runner.campaign.outputs import CAMPAIGN_FORMAT

    d = _dict(data, where)
    if d.get("format") != CAMPAIGN_FORMAT:
        raise _fail(f"{where}.format", f"not {CAMPAIGN_FORMAT}: not a campaign of this osc2run")
    sha = _text(d.get("source_sha256"), f"{where}.source_sha256")
    if not _SHA256.fullmatch(sha):
        raise _fail(f"{where}.source_sha256", "not a SHA-256 in hex")
    o = _dict(d.get("options"), f"{where}.options")
    w = f"{where}.options"
    sut = o.get("sut")
    if sut is not None:
        s = _dict(sut, f"{w}.sut")
        sut = {
            "target": _text(s.get("target"), f"{w}.sut.target", limit=4096),
            "actor": _optional_text(s.get("actor"), f"{w}.sut.actor", limit=200),
            "step_timeout": _number(s.get("step_timeout"), f"{w}.sut.step_timeout", True),
        }
    options = {
        "scenario": _optional_text(o.get("scenario"), f"{w}.scenario", limit=200),
        "duration": _number(o.get("duration"), f"{w}.duration", positive=True),
        "dt_control": _number(o.get("dt_control", DT_CONTROL), f"{w}.dt_control", positive=True),
        "dt_physics": _number(o.get("dt_physics", DT_PHYSICS), f"{w}.dt_physics", positive=True),
        "sut": sut,
        "strategy": _choice(o.get("strategy", "random"), f"{w}.strategy", STRATEGIES),
        "seed": _int(o.get("seed", 0), f"{w}.seed"),
        "runs": _int(o.get("runs", 1), f"{w}.runs", low=1),
        "engine": _choice(o.get("engine", "local"), f"{w}.engine", ENGINES),
        "address": _optional_text(o.get("address"), f"{w}.address", limit=1000),
        "run_timeout": _number(o.get("run_timeout"), f"{w}.run_timeout", positive=True),
        "plot": o.get("plot", False) is True,
        "export": [
            _choice(e, f"{w}.export[{i}]", FORMATS)
            for i, e in enumerate(_items(o.get("export", []), f"{w}.export", _text))
        ],
        **(
            {
                "kinematic": [
                    _text(e, f"{w}.kinematic[{i}]", limit=200)
                    for i, e in enumerate(_items(o["kinematic"], f"{w}.kinematic", _text))
                ]
            }
            if o.get("kinematic")
            else {}
        ),
        # the language the campaign was checked in
        **{
            name: _choice(o[name], f"{w}.{name}", allowed)
            for name, allowed in (("osc_version", OSC_VERSIONS), ("dialect", DIALECTS))
            if o.get(name) is not None
        },
    }
    plan = _dict(d.get("plan", {}), f"{where}.plan")
    return {
        "format": CAMPAIGN_FORMAT,
        "source": _text(d.get("source"), f"{where}.source", limit=4096),
        "source_sha256": sha,
        "scenario": _text(d.get("scenario"), f"{where}.scenario", limit=200),
        "status": _choice(d.get("status"), f"{where}.status", CAMPAIGN_STATUSES),
        "options": options,
        "plan": {"seeds": _items(plan.get("seeds", []), f"{where}.plan.seeds", _int)},
    }
