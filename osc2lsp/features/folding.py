"""Folding ranges from the layout of the text: indented blocks, comment runs, imports.

Read from the text alone, so folding works whatever state the parse is in.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

_IMPORT = re.compile(r"import\b")


@dataclass(frozen=True, slots=True)
class Fold:
    start_line: int  # 0-based, inclusive
    end_line: int
    kind: str = "region"  # region | comment | imports


def _indent(line: str) -> int:
    width = 0
    for ch in line:
        if ch == " ":
            width += 1
        elif ch == "\t":
            width = (width // 8 + 1) * 8
        else:
            break
    return width


def folding_ranges(text: str) -> list[Fold]:
    lines = re.split(r"\r\n|\r|\n", text)
    folds: list[Fold] = []
    code = [
        (i, _indent(line), line.strip())
        for i, line in enumerate(lines)
        if line.strip() and not line.strip().startswith("#")
    ]
    # indented blocks: a line followed by deeper lines
    open_blocks: list[tuple[int, int]] = []  # (indent, start line)
    previous: tuple[int, int] | None = None
    for k, (i, width, _) in enumerate(code):
        while open_blocks and width <= open_blocks[-1][0]:
            indent, start = open_blocks.pop()
            end = code[k - 1][0]
            if end > start:
                folds.append(Fold(start, end))
        if previous is not None and width > previous[1]:
            open_blocks.append((previous[1], previous[0]))
        previous = (i, width)
    last = code[-1][0] if code else 0
    while open_blocks:
        _, start = open_blocks.pop()
        if last > start:
            folds.append(Fold(start, last))
    # runs of comment lines
    run_start = None
    for i, line in enumerate([*lines, ""]):
        is_comment = line.strip().startswith("#")
        if is_comment and run_start is None:
            run_start = i
        elif not is_comment and run_start is not None:
            if i - 1 > run_start:
                folds.append(Fold(run_start, i - 1, "comment"))
            run_start = None
    # consecutive imports
    imports = [i for i, line in enumerate(lines) if _IMPORT.match(line)]
    if len(imports) > 1:
        folds.append(Fold(imports[0], imports[-1], "imports"))
    folds.sort(key=lambda f: (f.start_line, -f.end_line))
    return folds
