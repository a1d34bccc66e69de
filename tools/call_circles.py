"""Files of src/ that call each other in a circle (directly or through others).

  /usr/bin/python3 tools/call_circles.py        # prints each circle; exit 1 if any

A file calls another when it names a function the other defines without
`static` (a definition starts at column 0). Comments, strings and character
literals are dropped first. Prints the strongly connected components of the
file-call graph with more than one file, and which functions tie them."""
import collections
import glob
import os
import re
import sys

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
files = sorted(glob.glob(os.path.join(root, "src", "*", "*.c")))
defs = {}
for f in files:
    for line in open(f):
        if re.match(r"^[A-Za-z]", line) and not line.startswith(("static", "typedef", "struct")) and "(" in line \
                and not line.rstrip().endswith(";"):
            m = re.search(r"\b(\w+)\s*\(", line)
            if m and m.group(1) not in ("if", "for", "while", "return"):
                defs.setdefault(m.group(1), f)
calls = collections.defaultdict(dict)
for f in files:
    s = re.sub(r"/\*.*?\*/", "", open(f).read(), flags=re.S)
    s = re.sub(r"//[^\n]*", "", s)
    s = re.sub(r"'(\\.|[^'\\])'", "0", s)
    s = re.sub(r'"(\\.|[^"\\\n])*"', '""', s)
    for name in set(re.findall(r"\b\w+\b", s)):
        g = defs.get(name)
        if g and g != f:
            calls[f].setdefault(g, set()).add(name)

# Tarjan's strongly connected components
sys.setrecursionlimit(10000)
index, low, stack, on, comps, counter = {}, {}, [], set(), [], [0]


def visit(v):
    index[v] = low[v] = counter[0]
    counter[0] += 1
    stack.append(v)
    on.add(v)
    for w in calls.get(v, {}):
        if w not in index:
            visit(w)
            low[v] = min(low[v], low[w])
        elif w in on:
            low[v] = min(low[v], index[w])
    if low[v] == index[v]:
        comp = []
        while True:
            w = stack.pop()
            on.discard(w)
            comp.append(w)
            if w == v:
                break
        if len(comp) > 1:
            comps.append(comp)


for f in files:
    if f not in index:
        visit(f)
rel = lambda f: os.path.relpath(f, root)
for comp in comps:
    print("circle: " + ", ".join(rel(f) for f in sorted(comp)))
    for a in sorted(comp):
        for b in sorted(comp):
            if b in calls[a]:
                print("  %s -> %s: %s" % (rel(a), rel(b), ", ".join(sorted(calls[a][b]))))
print("%d files, %d functions defined without static, %d circles" % (len(files), len(defs), len(comps)))
sys.exit(1 if comps else 0)
