#!/usr/bin/env python3
"""Lines per C function and per file, longest first: the project's "a function
fits on a screen (about 80 lines), a file holds one job (about 600 lines)".

  python3 tools/func_lengths.py [--over N] FILE.c ...   (default: src/*.c, N = 0)

A function is counted from its signature line (the line before a '{' in
column 0) to its closing '}' in column 0, both included."""
import glob
import sys


def functions(path):
    lines = open(path).read().split("\n")
    out, start = [], None
    for i, line in enumerate(lines):
        if line.startswith("{") and i > 0:
            k = i - 1
            while k > 0 and lines[k - 1].strip() and not lines[k - 1].rstrip().endswith((";", "}", "*/")) and not lines[k - 1].startswith("#"):
                k -= 1  # a signature spread over several lines
            start = k
            name = lines[k].split("(")[0].split()[-1].lstrip("*") if "(" in lines[k] else lines[k].strip()
        elif line.startswith("}") and start is not None:
            out.append((i - start + 1, name))
            start = None
    return out, len(lines) - (1 if lines and lines[-1] == "" else 0)


def main(argv):
    over = 0
    if len(argv) > 1 and argv[0] == "--over":
        over, argv = int(argv[1]), argv[2:]
    files = argv or sorted(glob.glob("src/*.c"))
    rows = []
    for f in files:
        funcs, n = functions(f)
        print("%5d lines  %s (longest function %d)" % (n, f, max([l for l, _ in funcs] or [0])))
        rows += [(l, name, f) for l, name in funcs]
    print()
    for l, name, f in sorted(rows, reverse=True):
        if l > over:
            print("%5d  %-32s %s" % (l, name, f))


if __name__ == "__main__":
    main(sys.argv[1:])
