"""The Markdown tables of docs/ and README.md are well formed.

A GitHub Markdown table is a run of lines starting with '|': a header row, a separator row
(|---|---|) and the body rows. A blank line ends it, so a blank line inside a table turns its
remaining rows into a paragraph of raw '|' text (or, when they look like one, a second table
without a header); a row with more or fewer cells than the header loses cells or shows empty
ones. Each finding names the file and the line.
"""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PAGES = sorted((REPO / "docs").rglob("*.md")) + [REPO / "README.md"]
SEPARATOR = re.compile(r"^\|?\s*:?-+:?\s*(\|\s*:?-+:?\s*)*\|?\s*$")
FENCE = re.compile(r"^\s*(```|~~~)")


def cells(line):
    """Number of cells of a table row.

    As GitHub renders it: every '|' not escaped as '\\|' separates cells, inside a code span
    too (`a|b` in a cell is two cells); the outer pipes are optional.
    """
    row = line.strip()
    row = row[1:] if row.startswith("|") else row
    row = row[:-1] if row.endswith("|") and not row.endswith("\\|") else row
    return len(re.split(r"(?<!\\)\|", row))


def tables(text):
    """(first line number, [(line number, line), ...]) of each table of a page, code left out."""
    blocks, block, fenced = [], [], False
    for number, line in enumerate(text.splitlines(), start=1):
        if FENCE.match(line):
            fenced = not fenced
        if not fenced and line.lstrip().startswith("|"):
            block.append((number, line))
            continue
        if block:
            blocks.append(block)
        block = []
    if block:
        blocks.append(block)
    return blocks


def problems(path, root=REPO):
    """What is wrong with the tables of the page ``path``, each naming its file (relative to
    ``root``) and line."""
    found, previous_end = [], None
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    for block in tables(text):
        start = block[0][0]
        name = f"{path.relative_to(root)}:{start}"
        if len(block) < 2 or not SEPARATOR.match(block[1][1].strip()):
            # a headless run of rows right after a table, across blank lines only: a table
            # broken by a blank line
            between = lines[previous_end:start - 1] if previous_end is not None else ["x"]
            if all(not line.strip() for line in between):
                found.append(f"{name}: rows after a blank line inside the table that ends at "
                             f"line {previous_end}")
            else:
                found.append(f"{name}: table without a separator row (|---|) as its 2nd line")
        else:
            width = cells(block[0][1])
            for number, line in block:
                if cells(line) != width:
                    found.append(f"{path.relative_to(root)}:{number}: {cells(line)} cells, "
                                 f"the header has {width}")
        previous_end = block[-1][0]
    return found


def test_cells_split_as_github_does():
    assert cells("| a | b |") == 2
    assert cells("| a \\| b | c |") == 2
    assert cells("| `a|b` | c |") == 3     # GitHub splits a code span too
    assert cells("|---|---|---|") == 3


def test_a_blank_line_inside_a_table_is_found(tmp_path):
    page = tmp_path / "page.md"
    page.write_text("| k | v |\n|---|---|\n| a | 1 |\n\n| b | 2 |\n\ntext\n")
    assert problems(page, tmp_path) == [
        "page.md:5: rows after a blank line inside the table that ends at line 3"]
    page.write_text("| k | v |\n|---|---|\n| a | 1 | 2 |\n")
    assert problems(page, tmp_path) == ["page.md:3: 3 cells, the header has 2"]
    page.write_text("text\n\n| k | v |\n| a | 1 |\n")
    assert problems(page, tmp_path) == [
        "page.md:3: table without a separator row (|---|) as its 2nd line"]
    page.write_text("```\n| not | a table |\n```\n| k | v |\n|:--|--:|\n| a | 1 |\n")
    assert problems(page, tmp_path) == []
    # a table indented inside a list item is a table too
    page.write_text("1. item\n\n   | k | v |\n   |---|---|\n   | a | 1 |\n")
    assert problems(page, tmp_path) == []
    page.write_text("1. item\n\n   | k | v |\n   | a | 1 |\n")
    assert problems(page, tmp_path) == [
        "page.md:3: table without a separator row (|---|) as its 2nd line"]


@pytest.mark.parametrize("path", PAGES, ids=lambda p: str(p.relative_to(REPO)))
def test_tables_are_well_formed(path):
    assert problems(path) == []
