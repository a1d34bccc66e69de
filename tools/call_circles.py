"""Files of src/ that call each other in a circle (directly or through others),
and includes that point up the folders' stack.

  /usr/bin/python3 tools/call_circles.py        # prints each; exit 1 if any

A file calls another when it names a function the other defines without
`static` (a definition starts at column 0). Comments, strings and character
literals are dropped first. Prints the strongly connected components of the
file-call graph with more than one file, and which functions tie them.

The folders are stacked bottom to top in the order of M2D_STAGES in
CMakeLists.txt; a file of src/F or include/F that includes a header of a
folder above F is an arrow back up (each such include printed)."""
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

# the folders' stack and the includes that point up it
stages = re.search(r"set\(M2D_STAGES ([^)]*)\)", open(os.path.join(root, "CMakeLists.txt")).read()).group(1).split()
level = {st: k for k, st in enumerate(stages)}
home = {os.path.basename(h): h.split(os.sep)[-2] for h in glob.glob(os.path.join(root, "include", "*", "*.h"))}
up = []
for f in sorted(files + glob.glob(os.path.join(root, "include", "*", "*.h"))):
    folder = f.split(os.sep)[-2]
    for inc in re.findall(r'^#include\s+"([^"]+)"', open(f).read(), flags=re.M):
        to = home.get(os.path.basename(inc))
        if to and level.get(to, -1) > level.get(folder, -1):
            up.append("%s includes %s (%s above %s)" % (rel(f), inc, to, folder))
for line in up:
    print("up: " + line)
print("%d files, %d functions defined without static, %d circles; folders %s bottom to top, %d includes back up" % (len(files), len(defs), len(comps), " < ".join(stages), len(up)))
sys.exit(1 if comps or up else 0)
