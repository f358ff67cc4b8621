#!/usr/bin/env python3
"""Fails on an #include that runs against the engine's stage order (engine/README.md).

The order is the folder table under "The include order" in engine/README.md, top to bottom: a
file in engine/<folder>/ may include engine/<earlier folder>/ and its own folder, nothing later.
Engine files never include trainer/ or viewer/, and viewer files never include trainer/ (what
both programs share is engine/app/). Prints each offending line as FILE:LINE: and exits 1.

  scripts/check-includes.py [ROOT]     ROOT: the repository (default: this script's parent)
"""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
include = re.compile(r'\s*#\s*include\s+"(engine/([a-z_0-9]+)/|trainer/|viewer/)')


def stage_order():
    text = open(os.path.join(root, "engine", "README.md"), encoding="utf-8").read()
    section = text.split("## The include order", 1)
    if len(section) != 2:
        sys.exit("check-includes: engine/README.md has no 'The include order' section")
    order = re.findall(r"^\| \[([a-z_0-9]+)/\]", section[1], re.M)
    if not order:
        sys.exit("check-includes: engine/README.md's include-order table lists no folder")
    return order


def sources(folder):
    for base, _, names in os.walk(os.path.join(root, folder)):
        for name in sorted(names):
            if name.endswith((".h", ".cpp", ".hpp", ".inl")):
                yield os.path.join(base, name)


def main():
    order = stage_order()
    rank = {name: i for i, name in enumerate(order)}
    problems = []
    engine_dir = os.path.join(root, "engine")
    for folder in sorted(os.listdir(engine_dir)):
        if os.path.isdir(os.path.join(engine_dir, folder)) and folder not in rank:
            problems.append(f"engine/{folder}/: not in engine/README.md's include-order table")
    for top in ("engine", "viewer"):
        for path in sources(top):
            rel = os.path.relpath(path, root)
            here = rel.split(os.sep)[1] if top == "engine" else None
            for number, line in enumerate(open(path, encoding="utf-8", errors="replace"), 1):
                m = include.match(line)
                if not m:
                    continue
                target = m.group(1)
                where = f"{rel}:{number}: {line.strip()}"
                if target.startswith("trainer/") or (top == "engine" and target.startswith("viewer/")):
                    problems.append(f"{where}  ({top}/ must not include {target.rstrip('/')}/)")
                elif here is not None and m.group(2) and m.group(2) != here:
                    there = m.group(2)
                    if there not in rank:
                        problems.append(f"{where}  (engine/{there}/ is not in the include-order table)")
                    elif here in rank and rank[there] > rank[here]:
                        problems.append(f"{where}  (engine/{here}/ includes engine/{there}/, which comes after it)")
    for p in problems:
        print(p)
    if problems:
        print(f"check-includes: {len(problems)} include(s) against the order in engine/README.md", file=sys.stderr)
        return 1
    print(f"check-includes: every include follows the order of engine/README.md ({len(order)} folders)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
