#!/usr/bin/env python3
"""Sizes of the C sources: the longest functions and the longest files.

    python3 tools/code_size.py [--top N] [--max-lines 80] [--rev GIT_REVISION]

A function is counted from the line of its name to its closing brace at column
0 (the layout clang-format gives this code). Prints the N longest functions and
files, and every function over --max-lines; exit code 0 always (a report)."""
import argparse
import glob
import os
import re
import subprocess

ap = argparse.ArgumentParser()
ap.add_argument("--top", type=int, default=8)
ap.add_argument("--max-lines", type=int, default=80)
ap.add_argument("--rev", help="measure src/*/*.c of this git revision instead of the working tree")
ap.add_argument("--markdown", metavar="FILE", help="write the figures as a table into FILE between its code_size markers")
args = ap.parse_args()
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def sources():
    """(name, text) of every src/*/*.c"""
    if not args.rev:
        return [(os.path.relpath(p, root), open(p).read()) for p in sorted(glob.glob(os.path.join(root, "src", "*", "*.c")))]
    names = subprocess.run(["git", "-C", root, "ls-tree", "-r", "--name-only", args.rev, "src/"], capture_output=True, text=True, check=True).stdout.split()
    return [(n, subprocess.run(["git", "-C", root, "show", "%s:%s" % (args.rev, n)], capture_output=True, text=True, check=True).stdout) for n in names if n.endswith(".c")]


head = re.compile(r"^(?:static\s+)?(?:inline\s+)?[A-Za-z_][\w\s\*]*?\b(\w+)\s*\([^;]*$")
funcs, files = [], []
for name, text in sources():
    lines = text.split("\n")
    files.append((len(lines) - 1, name))
    start = fname = None
    for i, line in enumerate(lines):
        m = head.match(line)
        if m and start is None and not line.startswith(" ") and not line.rstrip().endswith(";"):
            start, fname = i, m.group(1)
        elif start is not None and line.startswith("}"):
            funcs.append((i - start + 1, "%s:%s" % (name, fname)))
            start = None
funcs.sort(reverse=True)
files.sort(reverse=True)
over = [f for n, f in funcs if n > args.max_lines]
if args.markdown:
    hdr = sum(len(open(h).read().split("\n")) - 1 for h in glob.glob(os.path.join(root, "include", "*", "*.h")))
    nhdr = len(glob.glob(os.path.join(root, "include", "*", "*.h")))
    main = [n for n, f in files if f.endswith("app/main.c")]
    rows = [("C files in `src/`, lines", "%d files, %s lines" % (len(files), format(sum(n for n, f in files), ","))),
            ("headers in `include/`, lines", "%d files, %s lines" % (nhdr, format(hdr, ","))),
            ("functions over %d lines" % args.max_lines, "%d%s" % (len(over), (" (" + ", ".join("`%s`" % f for f in over) + ")") if over else "")),
            ("longest functions", ", ".join("`%s` %d" % (f.split("/")[-1], n) for n, f in funcs[: args.top])),
            ("longest files", ", ".join("`%s` %d" % (f.split("/")[-1], n) for n, f in files[: args.top])),
            ("`main.c`", "%d lines" % main[0] if main else "-")]
    table = "| | now |\n|---|---|\n" + "".join("| %s | %s |\n" % r for r in rows)
    text = open(args.markdown).read()
    a, b = "<!-- code_size -->\n", "<!-- /code_size -->"
    i, j = text.index(a) + len(a), text.index(b)
    open(args.markdown, "w").write(text[:i] + table + text[j:])
    raise SystemExit(0)
print("longest functions (lines):")
for n, f in funcs[: args.top]:
    print("  %4d  %s" % (n, f))
print("longest files (lines):")
for n, f in files[: args.top]:
    print("  %4d  %s" % (n, f))
print("functions over %d lines: %d%s" % (args.max_lines, len(over), (" (" + ", ".join(over) + ")") if over else ""))
