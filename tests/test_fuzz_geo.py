"""Fuzz test of -geo F (the .geo that gmsh meshes inside the program,
src/adapt/remesh.c): corrupted variants must never crash, hang or print more
than the one-line error (issue 22).

From the scenes' own .geo files - hertz.geo (hertz_adapt.opts), seed_patch.geo
(seed_patch_adapt.opts), patch_uniform.geo and block.geo - a fixed (seeded)
set of variants: truncations, deleted / duplicated / swapped lines, byte and
bit flips, numbers replaced (0, -1, scaled by 0.5 or 3, 1e12, nan, inf,
1e400, text), identifiers renamed, brackets and semicolons removed, physical groups
renamed, emptied, repeated or removed, meshing options changed (element order,
recombination, subdivision, the algorithm), a point lifted off the plane, a
third dimension (an extrusion), Include of a missing file or of /dev/zero,
an empty file, binary garbage and a .msh given as a .geo. The sizes a .geo
asks for are kept within a factor 3 (a size of 1e-9 is a legitimate request
for a huge mesh, not a fault of the reader; the cap on the first mesh is
-adapt_max_dofs's; and a coordinate of 1e300 keeps gmsh busy for 40 s before it
crashes - which the program reports in one line, but which would make this test
slow).

Each variant runs its scene with -geo VARIANT -mesh "" -adapt -adapt_max_steps 1
(one mesh: gmsh on the .geo's own sizes), every tenth with -adapt_max_steps 2 (a
second mesh from the size field) and every fifteenth on 2 ranks, two at a time,
with a timeout; the contract is the mesh fuzz test's (m2d.fuzz_case). Failing
inputs are kept in WORK/fuzz_geo/failures/.

Options: --seed N, --count N (variants per .geo, default 75), --jobs N,
--timeout S, --keep."""
import os
import re
import sys

from m2d import SRC, fuzz_args, fuzz_case, fuzz_main, mesh, opts

ARGS, W, VAR, OUTROOT, FAILDIR = fuzz_args("fuzz_geo", 20251125, 75, 60)
ONE = ["-mesh", "", "-adapt", "-adapt_max_steps", "1", "-contact_monitor", "0"]  # no -mesh: the first mesh from the .geo
SCENES = {"hertz": ["-options_file", opts("hertz_adapt")],
          "seed_patch": ["-options_file", opts("seed_patch_adapt")],
          "patch_uniform": ["-options_file", opts("patch_uniform")],
          "block": ["-options_file", opts("block")]}
NUMBER = re.compile(r"(?<![A-Za-z_0-9.])-?\d+\.?\d*(?:[eE][-+]?\d+)?")
IDENT = re.compile(r"\b[A-Za-z_][A-Za-z_0-9]*\b")


def join(lines):
    return ("\n".join(lines) + "\n").encode()


# ---------------------------------------------------------------- mutators: (lines, text, rng) -> (description, bytes)
def m_truncate(L, t, r):
    n = r.randrange(len(t))
    return "truncate at byte %d of %d" % (n, len(t)), t[:n].encode()


def m_delete_line(L, t, r):
    k = r.randrange(len(L))
    n = r.choice([1, 1, 1, 3, 10])
    return "delete lines %d..%d" % (k + 1, k + n), join(L[:k] + L[k + n:])


def m_duplicate_line(L, t, r):
    k = r.randrange(len(L))
    return "duplicate line %d %r" % (k + 1, L[k][:40]), join(L[:k + 1] + L[k:])


def m_swap_lines(L, t, r):
    a, b = r.randrange(len(L)), r.randrange(len(L))
    M = list(L)
    M[a], M[b] = M[b], M[a]
    return "swap lines %d and %d" % (a + 1, b + 1), join(M)


def m_byte_flips(L, t, r):
    b = bytearray(t.encode())
    n = r.choice([1, 1, 2, 5, 20])
    printable = r.random() < 0.7
    pos = sorted(r.randrange(len(b)) for _ in range(n))
    for k in pos:
        b[k] = r.randrange(32, 127) if printable else r.randrange(256)
    return "%d %s byte(s) at %s" % (n, "printable" if printable else "random", pos[:8]), bytes(b)


def m_bit_flip(L, t, r):
    b = bytearray(t.encode())
    k, bit = r.randrange(len(b)), r.randrange(8)
    b[k] ^= 1 << bit
    return "bit %d flipped at byte %d" % (bit, k), bytes(b)


def m_number(L, t, r):
    """a number of the .geo replaced: sizes and counts stay within a factor 3"""
    spans = [(k, m.span()) for k, line in enumerate(L) if not line.lstrip().startswith("//") for m in NUMBER.finditer(line)]
    k, (a, b) = r.choice(spans)
    old = L[k][a:b]
    new = r.choice(["0", "-1", "1", "-%s" % old.lstrip("-"), "%.17g" % (0.5 * float(old)), "%.17g" % (3 * float(old)), "1e12", "-1e12", "nan", "inf", "1e400", "x", "", "1.2.3"])
    M = list(L)
    M[k] = L[k][:a] + new + L[k][b:]
    return "line %d: number %s -> %r" % (k + 1, old, new), join(M)


def m_identifier(L, t, r):
    spans = [(k, m.span()) for k, line in enumerate(L) if not line.lstrip().startswith("//") for m in IDENT.finditer(line)]
    k, (a, b) = r.choice(spans)
    old = L[k][a:b]
    new = r.choice([old + "x", old.lower(), old.upper(), "Point", "Surface", "If", "Foo", "_", old[:-1] or "y"])
    M = list(L)
    M[k] = L[k][:a] + new + L[k][b:]
    return "line %d: %s -> %s" % (k + 1, old, new), join(M)


def m_punctuation(L, t, r):
    spans = [m.start() for m in re.finditer(r"[;{}()\[\]=,\"]", t)]
    k = r.choice(spans)
    new = r.choice(["", ";", "{", "}", "(", ")", "\"", ",,"])
    return "byte %d %r -> %r" % (k, t[k], new), (t[:k] + new + t[k + 1:]).encode()


def m_physical(L, t, r):
    ks = [k for k, line in enumerate(L) if line.lstrip().startswith("Physical")]
    k = r.choice(ks)
    what = r.choice(["removed", "renamed", "emptied", "name emptied", "repeated", "other dimension", "two names"])
    M = list(L)
    if what == "removed":
        del M[k]
    elif what == "renamed":
        M[k] = re.sub(r'"([^"]*)"', r'"\1_x"', L[k], count=1)
    elif what == "emptied":
        M[k] = re.sub(r"\{[^}]*\}", "{}", L[k])
    elif what == "name emptied":
        M[k] = re.sub(r'"[^"]*"', '""', L[k], count=1)
    elif what == "repeated":
        M.insert(k, L[r.choice(ks)])
    elif what == "other dimension":
        M[k] = L[k].replace("Curve", "Point", 1) if "Curve" in L[k] else L[k].replace("Surface", "Curve", 1)
    else:
        other = re.search(r'"[^"]*"', L[r.choice(ks)])
        M[k] = re.sub(r'"[^"]*"', other.group(0) if other else '"x"', L[k], count=1)
    return "line %d (physical group) %s" % (k + 1, what), join(M)


OPTIONS = ["Mesh.ElementOrder = 2;", "Mesh.RecombineAll = 0;", "Mesh.SubdivisionAlgorithm = 0;", "Mesh.SubdivisionAlgorithm = 2;",
           "Mesh.RecombinationAlgorithm = 0;", "Mesh.RecombinationAlgorithm = 3;", "Mesh.Algorithm = 1;", "Mesh.Algorithm = 5;",
           "Mesh.Algorithm = 8;", "Mesh.Algorithm = 9;", "Mesh.SaveAll = 1;", "Mesh.MeshSizeFactor = 2;", "Mesh.SecondOrderIncomplete = 1;",
           "Mesh 2;", "Coherence;", "Geometry.Tolerance = 1;", "General.NumThreads = 4;"]


def m_option(L, t, r):
    o = r.choice(OPTIONS)
    k = r.choice([len(L), len(L) // 2, 0])
    return "%r at line %d" % (o, k + 1), join(L[:k] + [o] + L[k:])


def m_off_plane(L, t, r):
    ks = [k for k, line in enumerate(L) if re.match(r"\s*Point\(\d+\)\s*=", line)]
    k = r.choice(ks)
    z = r.choice(["0.1", "1e-3", "-2", "1e-14"])
    return "line %d: a point at z = %s" % (k + 1, z), join(L[:k] + [re.sub(r"(\{[^,]*,[^,]*,)\s*[^,}]*", r"\1 " + z, L[k], count=1)] + L[k + 1:])


def m_extra(L, t, r):
    e = r.choice(['Include "no_such_file.geo";', 'Include "/dev/zero";', "Extrude {0, 0, 1} { Surface{1}; }",
                  "Point(9999) = {0.5, 0.5, 0}; Point{9999} In Surface{1};", "Surface Loop(99) = {1}; Volume(99) = {99};",
                  'Physical Volume("v") = {1};', "Delete { Surface{1}; }", "Recursive Delete { Surface{1}; }", "Line(999) = {1, 1};"])
    k = r.choice([len(L), len(L) // 2])
    return "%r at line %d" % (e, k + 1), join(L[:k] + [e] + L[k:])


GARBAGE = ["empty", "blank", "binary", "a .msh", "comment only", "unterminated comment", "nul byte"]


def m_garbage(L, t, r, what=None):
    what = what or r.choice(GARBAGE)
    if what == "empty":
        b = b""
    elif what == "blank":
        b = b" \n\t\n"
    elif what == "binary":
        b = bytes(r.randrange(256) for _ in range(2000))
    elif what == "a .msh":
        with open(mesh("block_4"), "rb") as f:
            b = f.read()
    elif what == "comment only":
        b = b"// nothing here\n"
    elif what == "unterminated comment":
        b = b"/* " + t.encode()
    else:
        b = (t[:len(t) // 2] + "\0" + t[len(t) // 2:]).encode()
    return "garbage: %s" % what, b


MUTATORS = [(m_truncate, 10), (m_delete_line, 10), (m_duplicate_line, 5), (m_swap_lines, 5), (m_byte_flips, 12), (m_bit_flip, 5),
            (m_number, 16), (m_identifier, 8), (m_punctuation, 8), (m_physical, 8), (m_option, 8), (m_off_plane, 3), (m_extra, 5),
            (m_garbage, 2)]


def generate(rng):
    variants = []
    for scene in SCENES:
        with open(os.path.join(SRC, "meshes", scene + ".geo")) as f:
            t = f.read()
        L = t.split("\n")
        plan = [(f, {}) for f, _ in MUTATORS] + [(m_garbage, {"what": w}) for w in GARBAGE]
        funcs, weights = zip(*MUTATORS)
        plan += [(f, {}) for f in rng.choices(funcs, weights=weights, k=max(0, ARGS.count - len(plan)))]
        for f, kw in plan:
            desc, data = f(L, t, rng, **kw)
            variants.append((scene, f.__name__[2:], desc, data))
    return variants


def run_variant(i, scene, kind, desc, data):
    p = os.path.join(VAR, "%03d_%s_%s.geo" % (i, scene, kind))
    with open(p, "wb") as f:
        f.write(data)
    args = SCENES[scene] + ["-geo", p] + ONE
    if i % 10 == 2:
        args += ["-adapt_max_steps", "2"]
        desc += " [2 meshes]"
    ranks = 2 if i % 15 == 4 else 1
    return fuzz_case(i, "%s:%s" % (scene, kind), desc + (" [2 ranks]" if ranks == 2 else ""), args, os.path.join(OUTROOT, "%03d" % i),
                     FAILDIR, ARGS.timeout, ranks=ranks, inputs=[p], keep=ARGS.keep)


def main():
    return fuzz_main(ARGS, FAILDIR, SCENES, generate, run_variant)

if __name__ == "__main__":
    sys.exit(main())
