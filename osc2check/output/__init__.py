"""Output formats: ``render(fmt, diagnostics, texts_by_uri)`` is the one entry.

``full`` (default) and ``concise`` are for people and end with a summary line;
``json``, ``sarif`` and ``github`` are for tools and contain nothing else.

``problems`` are the paths that were not checked (``osc2check.inputs``): the summary
line counts the files that could not be read, and each tool format lists them in
its own place (JSON ``errors`` and ``skipped``, SARIF ``invocations``, GitHub
annotations).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from osc2check.config import OUTPUT_FORMATS
from osc2check.diagnostics import Diagnostic
from osc2check.inputs import InputProblem
from osc2check.output import concise, full
from osc2check.output.summary import statistics, summary_line

__all__ = ["FORMATS", "HUMAN_FORMATS", "render", "render_statistics"]

FORMATS = OUTPUT_FORMATS
HUMAN_FORMATS = ("full", "concise")


def render(
    fmt: str,
    diagnostics: Sequence[Diagnostic],
    texts_by_uri: Mapping[str, str],
    *,
    files_checked: int | None = None,
    quiet: bool = False,
    scenarios: Sequence[dict[str, object]] = (),
    problems: Sequence[InputProblem] = (),
    unverified: int = 0,
) -> str:
    """The findings in format ``fmt``, ready to write to stdout.

    ``texts_by_uri`` gives the source for excerpts; ``files_checked`` (default:
    the number of texts) goes into the summary line of the human formats, which
    ``quiet`` leaves out (and, with no findings, everything). ``problems`` are the
    paths not checked, placed where each format has room for them; ``unverified``
    counts the constraints the solver could not take (the summary line says so).
    """
    if fmt == "full":
        body = full.render(diagnostics, texts_by_uri)
    elif fmt == "concise":
        body = concise.render(diagnostics)
    elif fmt == "json":  # the tool formats are imported when asked for
        from osc2check.output import json

        return json.render(diagnostics, scenarios, problems)
    elif fmt == "sarif":
        from osc2check.output import sarif

        return sarif.render(diagnostics, problems)
    elif fmt == "github":
        from osc2check.output import github

        return github.render(diagnostics, problems)
    else:
        raise ValueError(f"unknown output format {fmt!r}")
    if quiet:
        return body
    checked = len(texts_by_uri) if files_checked is None else files_checked
    separator = "\n" if fmt == "full" and diagnostics else ""
    unreadable = sum(p.is_error for p in problems)
    return body + separator + summary_line(diagnostics, checked, unreadable, unverified) + "\n"


def render_statistics(
    diagnostics: Sequence[Diagnostic],
    *,
    files_checked: int,
    quiet: bool = False,
    problems: Sequence[InputProblem] = (),
    unverified: int = 0,
) -> str:
    """A count per code (``--statistics``), then the summary line unless ``quiet``."""
    table = statistics(diagnostics)
    if quiet:
        return table
    unreadable = sum(p.is_error for p in problems)
    return table + summary_line(diagnostics, files_checked, unreadable, unverified) + "\n"
