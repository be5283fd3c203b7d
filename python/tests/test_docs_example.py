"""The worked example of docs/python.md runs, and prints what the page says it prints.

Every ```python block of the page runs, in order, in one namespace, in a scratch folder where
samples/ is the repository's; a block right after the line <!-- not run by the tests: REASON -->
is skipped. A ```text block right after a python block is the output that block must print."""

import contextlib
import io
import os
import re

from conftest import SOURCE_DIR

PAGE = SOURCE_DIR / "docs" / "python.md"
SKIP = re.compile(r"<!-- not run by the tests: .+ -->\s*$")
BLOCK = re.compile(r"^```(\w*)\n(.*?)^```\n", re.S | re.M)


def blocks(text):
    """(code, expected output or None, skipped) for every python block, in order."""
    found = []
    matches = list(BLOCK.finditer(text))
    for index, match in enumerate(matches):
        if match.group(1) != "python":
            continue
        before = text[:match.start()].rstrip("\n").splitlines()[-1:] or [""]
        following = matches[index + 1] if index + 1 < len(matches) else None
        output = None
        if (following is not None and following.group(1) == "text"
                and text[match.end():following.start()].strip() == ""):
            output = following.group(2)
        found.append((match.group(2), output, bool(SKIP.search(before[0]))))
    return found


def test_the_page_has_a_worked_example():
    found = blocks(PAGE.read_text())
    assert len([b for b in found if not b[2]]) >= 4
    assert all(output is not None for _, output, skipped in found if not skipped)


def test_the_worked_example_runs_and_prints_what_the_page_shows(tmp_path):
    os.symlink(SOURCE_DIR / "samples", tmp_path / "samples")
    namespace = {"__name__": "__docs_example__"}
    previous = os.getcwd()
    os.chdir(tmp_path)
    try:
        for number, (code, expected, skipped) in enumerate(blocks(PAGE.read_text())):
            if skipped:
                continue
            printed = io.StringIO()
            with contextlib.redirect_stdout(printed):
                exec(compile(code, f"docs/python.md block {number + 1}", "exec"), namespace)
            assert printed.getvalue() == expected, f"block {number + 1} of docs/python.md"
    finally:
        os.chdir(previous)
    assert (tmp_path / "steel.json").is_file()
    assert (tmp_path / "deck-lammps" / "in.drop").is_file()


def test_only_a_block_the_page_says_why_it_skips_is_skipped():
    text = "<!-- not run by the tests: needs matplotlib -->\n```python\nimport x\n```\n"
    assert blocks(text) == [("import x\n", None, True)]
    text = "```python\nprint(1)\n```\n\n```text\n1\n```\n"
    assert blocks(text) == [("print(1)\n", "1\n", False)]
