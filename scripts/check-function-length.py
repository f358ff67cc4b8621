#!/usr/bin/env python3
"""Fails on a function over 100 lines in engine/, trainer/ or viewer/ (issue 46).

A function is a brace block opened outside any other block but a namespace, whose opening
line is not a struct, class, enum or union definition nor an initialiser ("= {"). Its length
runs from the line that opens its body to the line that closes it. A declarative table may run
longer: the line before its signature says "declarative table" in a comment (e.g. the options
tables). Prints each offender as FILE:LINE: and exits 1.

  scripts/check-function-length.py [ROOT] [--list N]   --list N: print the N longest, pass or fail
"""
import os
import re
import sys

LIMIT = 100
args = [a for a in sys.argv[1:]]
listing = 0
if "--list" in args:
    i = args.index("--list")
    listing = int(args[i + 1])
    del args[i:i + 2]
root = args[0] if args else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def code_of(line, in_comment):
    """The line without comments, string and character literals (braces in them do not count)."""
    out, i = [], 0
    while i < len(line):
        if in_comment:
            end = line.find("*/", i)
            if end < 0:
                return "".join(out), True
            i, in_comment = end + 2, False
        elif line.startswith("//", i):
            break
        elif line.startswith("/*", i):
            in_comment, i = True, i + 2
        elif line[i] in "\"'":
            quote, i = line[i], i + 1
            while i < len(line) and line[i] != quote:
                i += 2 if line[i] == "\\" else 1
            i += 1
        else:
            out.append(line[i])
            i += 1
    return "".join(out), in_comment


def blocks(path):
    lines = open(path, encoding="utf-8", errors="replace").read().split("\n")
    stack, in_comment, raw = [], False, False
    for number, line in enumerate(lines, 1):
        if 'R"' in line:  # raw strings (GLSL sources in C++): skip their lines
            raw = ')"' not in line.split('R"', 1)[1]
            continue
        if raw:
            raw = ')"' not in line
            continue
        code, in_comment = code_of(line, in_comment)
        for ch in code:
            if ch == "{":
                outer = all(kind == "namespace" for kind, _, _ in stack)
                opening = code.strip()
                if re.match(r"^(namespace|extern)\b", opening):
                    kind = "namespace"
                elif outer and not re.match(r"^(struct|class|enum|union|template)\b", opening) and "=" not in opening.split("(")[0] \
                        and not opening.startswith("{") and not re.search(r"=\s*\{", opening):
                    kind = "function"
                else:
                    kind = "block"
                stack.append((kind, number, lines[number - 2] if number > 1 else ""))
            elif ch == "}" and stack:
                kind, start, before = stack.pop()
                if kind == "function":
                    yield start, number, lines[start - 1].strip(), before


def main():
    found = []
    for top in ("engine", "trainer", "viewer"):
        for base, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if name.endswith((".cpp", ".h")):
                    path = os.path.join(base, name)
                    for start, end, signature, before in blocks(path):
                        found.append((end - start + 1, os.path.relpath(path, root), start, signature, "declarative table" in before))
    found.sort(reverse=True)
    for n, path, start, signature, table in found[:listing]:
        print(f"{n:5d} {path}:{start}: {signature[:80]}{'  (declarative table)' if table else ''}")
    over = [f for f in found if f[0] > LIMIT and not f[4]]
    for n, path, start, signature, _ in over:
        print(f"{path}:{start}: {n} lines (over {LIMIT}): {signature[:80]}")
    if over:
        print(f"check-function-length: {len(over)} function(s) over {LIMIT} lines", file=sys.stderr)
        return 1
    print(f"check-function-length: no function over {LIMIT} lines ({len(found)} read)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
