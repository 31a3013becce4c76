"""The export options of ``osc2run``: checked before anything runs.

``--export-xosc OUT.xosc`` and ``--export-osi OUT.osi`` write one run's exports
where named; ``--export xosc[,osi]`` writes them into the run's folder (``--out``),
or into every run's folder of a campaign (``runs/<seed>/scenario.xosc``,
``ground_truth.osi``). A bad path, a format that does not exist or a writer
whose extra is not installed is a usage error (one line, exit 2), before the
checker runs.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from osc2runner.export import FORMATS, ExportTargets, missing_extra
from osc2runner.output.files import FolderError, output_folder

__all__ = ["add_export_options", "export_arguments"]


def add_export_options(parser: argparse.ArgumentParser) -> None:
    """The export options, in a group of their own (docs/export.md)."""
    group = parser.add_argument_group("exports for other simulators (docs/export.md)")
    group.add_argument(
        "--export-xosc",
        metavar="OUT.xosc",
        help="write the run as OpenSCENARIO XML 1.2 (and its road network as OUT.xodr)",
    )
    group.add_argument(
        "--export-osi", metavar="OUT.osi", help="write the run's ASAM OSI ground truth"
    )
    group.add_argument(
        "--export",
        metavar="FORMAT[,FORMAT]",
        help="xosc and/or osi: write them into the run's folder (--out), or every run's "
        "folder of a campaign",
    )


def _usage(message: str) -> Exception:
    from osc2runner.cli import UsageError

    return UsageError(message)


def _target(option: str, text: str, suffix: str) -> Path:
    path = Path(text)
    if path.suffix.lower() != suffix:
        raise _usage(f"--{option} {text}: the file name must end in {suffix}")
    if path.is_dir():
        raise _usage(f"--{option} {text}: is a folder, not a file")
    try:
        output_folder(path.parent if str(path.parent) else ".", create=False)
    except FolderError as exc:
        raise _usage(f"--{option} {text}: {exc.why}") from None
    return path


def export_arguments(args: argparse.Namespace) -> None:
    """Check the export options; set ``args.export_formats`` (``--export``) and
    ``args.export_targets`` (one run's files) or raise a UsageError."""
    formats: tuple[str, ...] = ()
    if args.export is not None:
        words = [w.strip() for w in args.export.split(",") if w.strip()]
        unknown = [w for w in words if w not in FORMATS]
        if unknown or not words:
            raise _usage(f"--export {args.export}: formats are {', '.join(FORMATS)}")
        formats = tuple(dict.fromkeys(words))
        if args.out is None:
            raise _usage("--export needs --out DIR (or --runs N --out DIR)")
    named = {"xosc": args.export_xosc, "osi": args.export_osi}
    if args.campaign and any(named.values()):
        raise _usage("--export-xosc and --export-osi are for one run; a campaign takes --export")
    wanted = set(formats) | {f for f, path in named.items() if path is not None}
    why = missing_extra(sorted(wanted))
    if why is not None:
        raise _usage(why)
    args.export_formats = formats
    targets = ExportTargets.in_folder(Path(args.out), formats) if formats else ExportTargets()
    args.export_targets = ExportTargets(
        _target("export-xosc", named["xosc"], ".xosc") if named["xosc"] else targets.xosc,
        _target("export-osi", named["osi"], ".osi") if named["osi"] else targets.osi,
    )
