#!/usr/bin/env python3
"""The libraries' messages name no command-line flag (issue 32).

An error, warning or note written by core, audio, dem or calibrate reaches the command line and
Python alike, so it names an option as its options struct does, in backticks (`first_n=3`,
bouncecal/option_error.h), and each front end spells it: --first 3 on the command line,
first_n=3 in Python. This test reads every string literal of the libraries' sources (their
tests excluded: they may check what the front ends print) and fails on one holding a flag, e.g.
"raise --max-evaluations", naming the file and line.

Usage: library_messages_test.py SOURCE_DIR
"""

import pathlib
import re
import sys

LIBRARIES = ("core", "audio", "dem", "calibrate")
# A string literal (raw or not) or a comment, whichever starts first: comments may name flags.
TOKEN = re.compile(r'R"(?P<delim>[^(\s]*)\((?P<raw>.*?)\)(?P=delim)"'
                   r'|"(?P<text>(?:\\.|[^"\\\n])*)"'
                   r"|'(?:\\.|[^'\\\n])*'"
                   r"|//[^\n]*|/\*.*?\*/", re.S)
FLAG = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]*")


def flags_in(path):
    source = path.read_text(encoding="utf-8")
    for token in TOKEN.finditer(source):
        literal = token.group("raw") if token.group("raw") is not None else token.group("text")
        if literal is None:
            continue
        for flag in FLAG.finditer(literal):
            line = source.count("\n", 0, token.start() + flag.start()) + 1
            yield line, flag.group(0)


def main():
    root = pathlib.Path(sys.argv[1])
    found = []
    for library in LIBRARIES:
        for path in sorted((root / library).rglob("*")):
            if path.suffix not in (".cc", ".h") or path.stem.endswith("_test"):
                continue
            found += [f"{path.relative_to(root)}:{line}: {flag}" for line, flag in flags_in(path)]
    if found:
        print("library messages that name a command-line flag; name the options struct's field "
              "in backticks instead (`field` or `field=value`, bouncecal/option_error.h):")
        print("\n".join(found))
        return 1
    print(f"no flag in the string literals of {', '.join(LIBRARIES)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
