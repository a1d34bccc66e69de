"""Mesh-file fuzz test: corrupted variants of two msh 4.1 meshes must never
crash, hang or print more than the one-line error.

From patch_uniform.msh (scene S2, two bodies) and hertz_0.msh (coarsest Hertz
level) we generate a fixed (seeded) set of corrupted files: truncations,
deleted / duplicated / swapped lines, byte flips, numbers replaced by huge,
negative, non-numeric, NaN and inf values, section headers removed or renamed,
element node tags pointing at missing nodes, element types changed, counts
changed, physical names removed or renamed, coincident coordinates (degenerate
quads), bodies moved apart or into each other, an empty file, binary garbage,
and a few that should be harmless (CRLF, extra blank lines, unknown sections).

Each variant runs with its scene's options (-mesh VARIANT -output_dir DIR
-contact_monitor 0), two at a time, with a timeout. Outcomes:
  ran      exit 0, quiet stderr, output written (the corruption was harmless)
  rejected exit 1 and stderr is exactly one line "mortar2d: error: ..."
  failed   anything else: a signal, another exit code, a timeout, a multi-line
           or unprefixed error, stderr noise on success, .tmp files left over.
The test fails if any variant failed; failing inputs and their output are kept
in WORK/fuzz/failures/ for inspection.

Options: --seed N (default 20240611), --count N (random variants per mesh,
default 130), --jobs N (default 2), --keep (keep every variant)."""
import hashlib
import os
import re
import sys

from m2d import fuzz_args, fuzz_case, fuzz_main, mesh, opts

ARGS, W, VAR, OUTROOT, FAILDIR = fuzz_args("fuzz", 20240611, 130, 30)

SCENES = {
    "patch_uniform": ["-options_file", opts("patch_uniform")],
    "hertz_0": ["-options_file", opts("hertz")],
}

# values that replace a number
HUGE = ["1e299", "-1e299", "1e300", "1e308", "1.7976931348623157e308", "1e400", "-1e400", "9e18",
        "9223372036854775807", "9223372036854775808", "99999999999999999999999", "2147483648", "4294967297"]
NEG = ["-1", "-2", "-1000000", "-9223372036854775808", "-0", "-0.5"]
NONNUM = ["abc", "", "1.2.3", "0x10", "1e", "--1", "+", "1,5", "\"1\"", "$Nodes", "one", "1e5x", "0b101", "\t"]
NONFIN = ["nan", "NaN", "-nan", "inf", "-inf", "Infinity", "INF", "1e-400", "4.9e-324"]
BADVALS = HUGE + NEG + NONNUM + NONFIN + ["0", "1", "3.5", "1e-300"]


class Msh:
    """Line-level view of a msh 4.1 ASCII file, with the positions of the
    interesting lines (section headers, counts, nodes, elements, names)."""

    def __init__(self, path):
        with open(path) as f:
            self.text = f.read()
        self.lines = self.text.split("\n")
        if self.lines and self.lines[-1] == "":
            self.lines.pop()
        L = self.lines
        self.sections = {}  # name -> (start, end) line indices of $Name / $EndName
        i = 0
        while i < len(L):
            if L[i].startswith("$") and not L[i].startswith("$End"):
                name = L[i][1:].strip()
                j = L.index("$End" + name, i)
                self.sections[name] = (i, j)
                i = j
            i += 1
        self.count_lines = [s + 1 for s, e in self.sections.values() if e > s + 1]
        # physical names
        s, e = self.sections["PhysicalNames"]
        self.phys_lines = list(range(s + 2, e))
        self.phys = {}  # name -> (dim, tag)
        for k in self.phys_lines:
            dim, tag, name = L[k].split(" ", 2)
            self.phys[name.strip('"')] = (int(dim), int(tag))
        # entities
        s, e = self.sections["Entities"]
        self.entity_lines = list(range(s + 2, e))
        cnt = [int(x) for x in L[s + 1].split()]
        self.entity_dim = {}
        k = s + 2
        for d in range(4):
            for _ in range(cnt[d]):
                self.entity_dim[k] = d
                k += 1
        # nodes
        s, e = self.sections["Nodes"]
        self.node_block_headers, self.node_tag_lines, self.coord_lines = [], [], []
        self.coord_of = {}  # node tag -> line index of its coordinates
        k = s + 2
        nblocks = int(L[s + 1].split()[0])
        for _ in range(nblocks):
            edim, etag, param, nin = (int(x) for x in L[k].split())
            self.node_block_headers.append(k)
            tags = [int(L[k + 1 + i]) for i in range(nin)]
            self.node_tag_lines += list(range(k + 1, k + 1 + nin))
            for i, t in enumerate(tags):
                self.coord_of[t] = k + 1 + nin + i
                self.coord_lines.append(k + 1 + nin + i)
            k += 1 + 2 * nin
        self.max_node = max(self.coord_of)
        # elements
        s, e = self.sections["Elements"]
        self.elem_block_headers, self.elem_lines = [], {}  # type -> [line indices]
        self.elem_block_of = {}
        k = s + 2
        nblocks = int(L[s + 1].split()[0])
        for _ in range(nblocks):
            edim, etag, etype, nin = (int(x) for x in L[k].split())
            self.elem_block_headers.append(k)
            for i in range(nin):
                self.elem_lines.setdefault(etype, []).append(k + 1 + i)
                self.elem_block_of[k + 1 + i] = k
            k += 1 + nin
        self.quads = [[int(x) for x in L[k].split()[1:]] for k in self.elem_lines[3]]
        # boundary lines by physical name, through the entities
        self.curve_phys = {}
        for k in self.entity_lines:
            if self.entity_dim[k] == 1:
                f = L[k].split()
                if int(f[7]) > 0:
                    self.curve_phys[int(f[0])] = int(f[8])
        self.lines_of_phys = {}
        for k in self.elem_lines.get(1, []):
            b = L[self.elem_block_of[k]].split()
            ph = self.curve_phys.get(int(b[1]))
            if ph is not None:
                self.lines_of_phys.setdefault(ph, []).append(k)
        # which node belongs to which body (surface entity of its quads)
        self.body_nodes = {}
        for k in self.elem_lines[3]:
            body = int(L[self.elem_block_of[k]].split()[1])
            for t in L[k].split()[1:]:
                self.body_nodes.setdefault(body, set()).add(int(t))

    def coords(self, tag):
        return [float(x) for x in self.lines[self.coord_of[tag]].split()]


def join(lines):
    return ("\n".join(lines) + "\n").encode()


def tokens_of(line):
    return [m.span() for m in re.finditer(r"\S+", line)]


def replace_token(line, idx, new):
    sp = tokens_of(line)
    a, b = sp[idx]
    return line[:a] + new + line[b:]


def fmt(x):
    return repr(float(x))


# ---------------------------------------------------------------- mutators
# each takes (Msh, rng) and returns (description, bytes)

def m_truncate(M, r):
    n = r.randrange(0, len(M.text))
    return "truncate at byte %d of %d" % (n, len(M.text)), M.text[:n].encode()


def m_truncate_section(M, r):
    name = r.choice(list(M.sections))
    s, e = M.sections[name]
    k = r.randrange(s, e + 1)
    return "truncate after line %d (in $%s)" % (k + 1, name), join(M.lines[:k + 1])


def m_delete_line(M, r):
    L = list(M.lines)
    k = r.randrange(len(L))
    old = L.pop(k)
    return "delete line %d %r" % (k + 1, old[:40]), join(L)


def m_delete_lines(M, r):
    L = list(M.lines)
    k = r.randrange(len(L))
    n = r.randint(2, 20)
    del L[k:k + n]
    return "delete lines %d..%d" % (k + 1, k + n), join(L)


def m_duplicate_line(M, r):
    L = list(M.lines)
    k = r.randrange(len(L))
    L.insert(k, L[k])
    return "duplicate line %d %r" % (k + 1, L[k][:40]), join(L)


def m_swap_lines(M, r):
    L = list(M.lines)
    a, b = r.randrange(len(L)), r.randrange(len(L))
    while L[a] == L[b]:
        b = r.randrange(len(L))
    L[a], L[b] = L[b], L[a]
    return "swap lines %d and %d" % (a + 1, b + 1), join(L)


def m_swap_adjacent(M, r):
    L = list(M.lines)
    a = r.randrange(len(L) - 1)
    while L[a] == L[a + 1]:
        a = r.randrange(len(L) - 1)
    L[a], L[a + 1] = L[a + 1], L[a]
    return "swap lines %d and %d" % (a + 1, a + 2), join(L)


def m_byte_flips(M, r):
    b = bytearray(M.text.encode())
    n = r.choice([1, 1, 2, 3, 5, 10, 50])
    printable = r.random() < 0.6
    pos = []
    for _ in range(n):
        k = r.randrange(len(b))
        b[k] = r.randrange(32, 127) if printable else r.randrange(256)
        pos.append(k)
    return "%d %s byte flip(s) at %s" % (n, "printable" if printable else "random", pos[:8]), bytes(b)


def m_bit_flip(M, r):
    b = bytearray(M.text.encode())
    k = r.randrange(len(b))
    bit = r.randrange(8)
    b[k] ^= 1 << bit
    return "bit %d flipped at byte %d (%r -> %r)" % (bit, k, chr(M.text.encode()[k]), chr(b[k])), bytes(b)


def m_any_token(M, r):
    L = list(M.lines)
    k = r.randrange(len(L))
    while not tokens_of(L[k]):
        k = r.randrange(len(L))
    i = r.randrange(len(tokens_of(L[k])))
    v = r.choice(BADVALS)
    L[k] = replace_token(L[k], i, v)
    return "line %d token %d -> %r" % (k + 1, i + 1, v), join(L)


def m_coord(M, r):
    L = list(M.lines)
    k = r.choice(M.coord_lines)
    i = r.randrange(3)
    v = r.choice(HUGE + NEG + NONNUM + NONFIN)
    L[k] = replace_token(L[k], i, v)
    return "coordinate %d of node line %d -> %r" % (i + 1, k + 1, v), join(L)


def m_count(M, r):
    L = list(M.lines)
    k = r.choice(M.count_lines + M.node_block_headers + M.elem_block_headers)
    toks = tokens_of(L[k])
    i = r.randrange(len(toks))
    old = int(L[k][toks[i][0]:toks[i][1]])
    v = r.choice([str(old + 1), str(old - 1), str(old * 2), str(old * 1000 + 7), "0", "-1", "-%d" % old,
                  "9223372036854775807", "99999999999999999999", "2147483647", "4611686018427387904",
                  "1.5", "x", "nan"])
    L[k] = replace_token(L[k], i, v)
    return "count/header line %d %r token %d: %d -> %s" % (k + 1, M.lines[k], i + 1, old, v), join(L)


def m_missing_node(M, r):
    L = list(M.lines)
    etype = r.choice([3, 3] + sorted(M.elem_lines))
    k = r.choice(M.elem_lines[etype])
    toks = tokens_of(L[k])
    i = r.randrange(1, len(toks))
    v = r.choice([M.max_node + 1, M.max_node + 1000, 0, -1, -M.max_node, 2 ** 31, 2 ** 63 - 1, 2 ** 64])
    L[k] = replace_token(L[k], i, str(v))
    return "element line %d node %d -> missing tag %d" % (k + 1, i, v), join(L)


def m_repeat_node(M, r):
    """a quad that uses one node twice (degenerate, 3 distinct corners)"""
    L = list(M.lines)
    k = r.choice(M.elem_lines[3])
    t = L[k].split()
    a, b = r.sample(range(1, 5), 2)
    t[b] = t[a]
    L[k] = " ".join(t) + " "
    return "quad line %d uses node %s twice: %s" % (k + 1, t[a], " ".join(t)), join(L)


def m_node_other_body(M, r):
    """a quad of one body that uses a node of the other body"""
    L = list(M.lines)
    bodies = sorted(M.body_nodes)
    k = r.choice(M.elem_lines[3])
    body = int(L[M.elem_block_of[k]].split()[1])
    other = [b for b in bodies if b != body][0]
    t = L[k].split()
    i = r.randrange(1, 5)
    t[i] = str(r.choice(sorted(M.body_nodes[other] - M.body_nodes[body])))
    L[k] = " ".join(t) + " "
    return "quad line %d uses node %s of the other body" % (k + 1, t[i]), join(L)


def m_elem_type(M, r):
    L = list(M.lines)
    k = r.choice(M.elem_block_headers)
    t = L[k].split()
    old = int(t[2])
    choices = {3: [2, 1, 16, 10, 4, 5, 15, 99, 0, -3, 9], 1: [3, 2, 8, 15, 99, 0], 15: [1, 3, 2, 99]}.get(old, [3, 99])
    t[2] = str(r.choice(choices))
    L[k] = " ".join(t)
    return "element block line %d type %d -> %s" % (k + 1, old, t[2]), join(L)


def m_elem_block_entity(M, r):
    L = list(M.lines)
    k = r.choice(M.elem_block_headers)
    t = L[k].split()
    i = r.choice([0, 1])
    old = t[i]
    t[i] = str(r.choice([0, 1, 2, 3, 99, -1, int(old) + 1]))
    L[k] = " ".join(t)
    return "element block line %d %s %s -> %s" % (k + 1, ("dim", "entity")[i], old, t[i]), join(L)


def m_quad_to_triangle(M, r):
    """one quad block relabelled as triangles, with the element lines made to fit"""
    L = list(M.lines)
    quadblocks = [k for k in M.elem_block_headers if L[k].split()[2] == "3"]
    k = r.choice(quadblocks)
    t = L[k].split()
    t[2] = "2"
    L[k] = " ".join(t)
    for j in range(k + 1, k + 1 + int(t[3])):
        L[j] = " ".join(L[j].split()[:4]) + " "
    return "quad block line %d rewritten as triangles" % (k + 1), join(L)


def m_header(M, r):
    L = list(M.lines)
    name = r.choice(list(M.sections))
    s, e = M.sections[name]
    what = r.choice(["remove start", "remove end", "rename start", "rename end", "lowercase start", "remove both",
                     "swap start/end", "indent start", "trailing text"])
    if what == "remove start":
        del L[s]
    elif what == "remove end":
        del L[e]
    elif what == "rename start":
        L[s] = r.choice(["$%sX" % name, "$%s" % name[:-1], "%s" % name, "$Foo", "$"])
    elif what == "rename end":
        L[e] = r.choice(["$End%sX" % name, "$End", "$End%s" % name[:-1], "End%s" % name])
    elif what == "lowercase start":
        L[s] = L[s].lower()
    elif what == "remove both":
        del L[e]
        del L[s]
    elif what == "swap start/end":
        L[s], L[e] = L[e], L[s]
    elif what == "indent start":
        L[s] = "  " + L[s]
    else:
        L[s] = L[s] + " extra"
    return "$%s header: %s" % (name, what), join(L)


def m_remove_section(M, r):
    L = list(M.lines)
    name = r.choice(list(M.sections))
    s, e = M.sections[name]
    del L[s:e + 1]
    return "remove section $%s" % name, join(L)


def m_duplicate_section(M, r):
    L = list(M.lines)
    name = r.choice(list(M.sections))
    s, e = M.sections[name]
    L[e + 1:e + 1] = L[s:e + 1]
    return "duplicate section $%s" % name, join(L)


def m_reorder_sections(M, r):
    names = list(M.sections)
    order = names[:]
    while order == names:
        r.shuffle(order)
    L = []
    for n in order:
        s, e = M.sections[n]
        L += M.lines[s:e + 1]
    return "sections reordered: %s" % ",".join(order), join(L)


def m_physical_name(M, r):
    L = list(M.lines)
    s, e = M.sections["PhysicalNames"]
    k = r.choice(M.phys_lines)
    dim, tag, name = L[k].split(" ", 2)
    what = r.choice(["remove (count adjusted)", "remove (count kept)", "rename", "duplicate name", "empty name",
                     "unquoted", "unterminated", "dim 3", "dim -1", "dim 7", "tag changed", "long name",
                     "name with spaces"])
    if what.startswith("remove"):
        del L[k]
        if "adjusted" in what:
            L[s + 1] = str(int(L[s + 1]) - 1)
    elif what == "rename":
        L[k] = '%s %s "%s_x"' % (dim, tag, name.strip('"'))
    elif what == "duplicate name":
        other = M.lines[r.choice([j for j in M.phys_lines if j != k])].split(" ", 2)[2]
        L[k] = "%s %s %s" % (dim, tag, other)
    elif what == "empty name":
        L[k] = '%s %s ""' % (dim, tag)
    elif what == "unquoted":
        L[k] = "%s %s %s" % (dim, tag, name.strip('"'))
    elif what == "unterminated":
        L[k] = '%s %s "%s' % (dim, tag, name.strip('"'))
    elif what.startswith("dim"):
        L[k] = "%s %s %s" % (what.split()[1], tag, name)
    elif what == "tag changed":
        L[k] = "%s %d %s" % (dim, int(tag) + 1000, name)
    elif what == "long name":
        L[k] = '%s %s "%s"' % (dim, tag, name.strip('"') * 40)
    else:
        L[k] = '%s %s "%s %s"' % (dim, tag, name.strip('"'), name.strip('"'))
    return "physical name line %d %s: %s" % (k + 1, name, what), join(L)


def m_all_physical_names(M, r):
    L = list(M.lines)
    s, e = M.sections["PhysicalNames"]
    L[s + 1:e] = ["0"]
    return "$PhysicalNames emptied (count 0)", join(L)


def m_entity_phys(M, r):
    """an entity loses its physical tag, gets another one, or gets two"""
    L = list(M.lines)
    k = r.choice(M.entity_lines)
    d = M.entity_dim[k]
    f = L[k].split()
    nfix = 4 if d == 0 else 7
    nph = int(f[nfix])
    phys = f[nfix + 1:nfix + 1 + nph]
    rest = f[nfix + 1 + nph:]
    alltags = sorted({t for _, t in M.phys.values()})
    what = r.choice(["drop", "other", "two", "negative", "unknown"])
    if what == "drop":
        phys = []
    elif what == "other":
        phys = [str(r.choice(alltags))]
    elif what == "two":
        phys = phys + [str(r.choice(alltags))]
    elif what == "negative":
        phys = ["-" + p for p in phys] or ["-1"]
    else:
        phys = ["777"]
    L[k] = " ".join(f[:nfix] + [str(len(phys))] + phys + rest) + " "
    return "entity line %d (dim %d) physical tags: %s -> %s" % (k + 1, d, " ".join(f[nfix + 1:nfix + 1 + nph]) or "none", " ".join(phys) or "none"), join(L)


def m_degenerate_quad(M, r):
    """one corner of a quad moved onto another corner: zero-length edge"""
    L = list(M.lines)
    q = r.choice(M.quads)
    a, b = r.sample(q[1:], 2)
    L[M.coord_of[b]] = L[M.coord_of[a]]
    return "quad %d: node %d moved onto node %d" % (q[0], b, a), join(L)


def m_collapse_quad(M, r):
    L = list(M.lines)
    q = r.choice(M.quads)
    for t in q[2:]:
        L[M.coord_of[t]] = L[M.coord_of[q[1]]]
    return "quad %d: all four nodes at one point" % q[0], join(L)


def m_flat_quad(M, r):
    """all four corners on one line (zero area, no coincident nodes)"""
    L = list(M.lines)
    q = r.choice(M.quads)
    x0, y0, _ = M.coords(q[1])
    for i, t in enumerate(q[2:], 1):
        L[M.coord_of[t]] = "%s %s 0" % (fmt(x0 + 0.01 * i), fmt(y0))
    return "quad %d flattened onto a line" % q[0], join(L)


def m_collapse_all(M, r):
    L = list(M.lines)
    v = r.choice(["0 0 0", "1 1 0", "1e299 1e299 0"])
    for k in M.coord_lines:
        L[k] = v
    return "every node at (%s)" % v, join(L)


def m_collapse_surface(M, r):
    """every node of a contact surface at one point"""
    L = list(M.lines)
    name = r.choice([n for n, (d, _) in M.phys.items() if d == 1 and n in ("upper_bottom", "lower_top", "cylinder_arc", "block_top")])
    nodes = sorted({int(t) for k in M.lines_of_phys[M.phys[name][1]] for t in L[k].split()[1:]})
    for t in nodes[1:]:
        L[M.coord_of[t]] = L[M.coord_of[nodes[0]]]
    return "every node of '%s' at one point" % name, join(L)


def m_invert_quad(M, r):
    L = list(M.lines)
    k = r.choice(M.elem_lines[3])
    t = L[k].split()
    L[k] = " ".join([t[0]] + t[1:][::-1]) + " "
    return "quad line %d listed clockwise" % (k + 1), join(L)


def m_move_node(M, r):
    L = list(M.lines)
    t = r.choice(sorted(M.coord_of))
    x, y, _ = M.coords(t)
    dx, dy = r.choice([(1e6, 0), (0, -1e6), (0.3, 0.3), (-2, 0), (1e-9, 0), (1e150, 1e150), (0, 0.05)])
    L[M.coord_of[t]] = "%s %s 0" % (fmt(x + dx), fmt(y + dy))
    return "node %d moved by (%g, %g)" % (t, dx, dy), join(L)


def m_move_body(M, r):
    """shift or scale every node of one body: apart, overlapping, huge, tiny"""
    L = list(M.lines)
    body = r.choice(sorted(M.body_nodes))
    what = r.choice(["apart", "far apart", "overlap", "deep overlap", "scale 1e-300", "scale 1e150", "mirror"])
    for t in M.body_nodes[body]:
        x, y, _ = M.coords(t)
        if what == "apart":
            y += 0.5 if body == 2 else -0.5
        elif what == "far apart":
            x += 1e8
        elif what == "overlap":
            y += -0.1 if body == 2 else 0.1
        elif what == "deep overlap":
            y += -0.45 if body == 2 else 0.45
        elif what == "scale 1e-300":
            x, y = x * 1e-300, y * 1e-300
        elif what == "scale 1e150":
            x, y = x * 1e150, y * 1e150
        else:
            x = -x
        L[M.coord_of[t]] = "%s %s 0" % (fmt(x), fmt(y))
    return "body (surface %d): %s" % (body, what), join(L)


def m_duplicate_node_tag(M, r):
    L = list(M.lines)
    a, b = r.sample(M.node_tag_lines, 2)
    L[b] = L[a]
    return "node tag line %d set to %s (duplicate tag)" % (b + 1, L[a]), join(L)


def m_format(M, r):
    L = list(M.lines)
    v = r.choice(["4.0 0 8", "2.2 0 8", "4.1 1 8", "4.1 0 4", "4 0 8", "4.10 0 8", "41 0 8", "1e400 0 8",
                  "nan 0 8", "4.1 0", "4.1", "", "4.1 0 8 9", "3 0 8", "4.1 -1 8", "4.1 0 99999999999999999999"])
    L[1] = v
    return "format line -> %r" % v, join(L)


MISC = ["crlf", "blank lines", "tabs", "trailing garbage", "unknown section", "unterminated unknown section", "bom",
        "leading blank", "nul byte", "long line", "no final newline", "node data section", "trailing $End",
        "comment section"]


def m_misc(M, r, what=None):
    what = what or r.choice(MISC)
    t = M.text
    if what == "crlf":
        t = t.replace("\n", "\r\n")
    elif what == "blank lines":
        t = t.replace("\n", "\n\n")
    elif what == "tabs":
        t = t.replace(" ", "\t")
    elif what == "trailing garbage":
        t = t + "garbage 1 2 3\n"
    elif what == "unknown section":
        t = t + "$Periodic\n0\n$EndPeriodic\n"
    elif what == "unterminated unknown section":
        t = t + "$Periodic\n0\n"
    elif what == "bom":
        t = "\ufeff" + t
    elif what == "leading blank":
        t = "\n\n  " + t
    elif what == "nul byte":
        k = len(t) // 2
        t = t[:k] + "\0" + t[k:]
    elif what == "long line":
        k = M.sections["Nodes"][0]
        t = "\n".join(M.lines[:k] + ["$Foo", "x" * 1000000, "$EndFoo"] + M.lines[k:]) + "\n"
    elif what == "no final newline":
        t = t.rstrip("\n")
    elif what == "node data section":
        t = t + "$NodeData\n1\n\"u\"\n1\n0\n3\n0\n1\n1\n1 0\n$EndNodeData\n"
    elif what == "trailing $End":
        t = t + "$End\n"
    else:
        t = t.replace("$Entities", "$Comments\nhello $Nodes $Elements\n$EndComments\n$Entities", 1)
    return "misc: %s" % what, t.encode()


GARBAGE = ["empty", "whitespace", "binary", "binary no NUL", "ascii noise", "header only", "header + garbage",
           "text numbers", "control characters"]


def m_garbage(M, r, what=None):
    what = what or r.choice(GARBAGE)
    if what == "empty":
        b = b""
    elif what == "whitespace":
        b = b" \n\t\n  \r\n"
    elif what == "binary":
        b = bytes(r.randrange(256) for _ in range(r.choice([1, 100, 5000])))
    elif what == "binary no NUL":
        b = bytes(r.randrange(1, 256) for _ in range(r.choice([1, 100, 5000])))
    elif what == "ascii noise":
        b = "".join(r.choice("$0123456789 .-e\n\"abcEndNodes") for _ in range(3000)).encode()
    elif what == "header only":
        b = join(M.lines[:3])
    elif what == "header + garbage":
        b = join(M.lines[:3]) + bytes(r.randrange(1, 256) for _ in range(2000))
    elif what == "text numbers":
        b = " ".join(str(r.randint(-5, 200)) for _ in range(2000)).encode()
    else:  # printable words glued with control characters (no newline, no NUL)
        b = "".join(r.choice(["$Mesh", "Format", "4.1", "\x0b", "\x0c", "\x1c", "\x1d", "\x1e", "\x1b[2J", "\x7f", "\x08"])
                    for _ in range(30)).encode() + b"\n"
    return "garbage: %s" % what, b


MUTATORS = [
    (m_truncate, 12), (m_truncate_section, 4), (m_delete_line, 8), (m_delete_lines, 4), (m_duplicate_line, 6),
    (m_swap_lines, 5), (m_swap_adjacent, 3), (m_byte_flips, 10), (m_bit_flip, 5), (m_any_token, 10),
    (m_coord, 8), (m_count, 8), (m_missing_node, 5), (m_repeat_node, 3), (m_node_other_body, 2),
    (m_elem_type, 5), (m_elem_block_entity, 3), (m_quad_to_triangle, 1), (m_header, 6), (m_remove_section, 3),
    (m_duplicate_section, 2), (m_reorder_sections, 2), (m_physical_name, 6), (m_all_physical_names, 1),
    (m_entity_phys, 5), (m_degenerate_quad, 4), (m_collapse_quad, 2), (m_flat_quad, 2), (m_collapse_all, 1),
    (m_collapse_surface, 2), (m_invert_quad, 2), (m_move_node, 4), (m_move_body, 4), (m_duplicate_node_tag, 2),
    (m_format, 3), (m_misc, 4), (m_garbage, 3),
]


def generate(rng):
    variants, seen = [], set()
    for scene in SCENES:
        M = Msh(mesh(scene))
        seen.add(hashlib.sha1(M.text.encode()).hexdigest())
        # every mutator at least once per mesh, every garbage and misc kind
        # once, then weighted random picks
        plan = [(f, {}) for f, _ in MUTATORS]
        plan += [(m_garbage, {"what": w}) for w in GARBAGE] + [(m_misc, {"what": w}) for w in MISC]
        funcs, weights = zip(*MUTATORS)
        plan += [(f, {}) for f in rng.choices(funcs, weights=weights, k=max(0, ARGS.count - len(plan)))]
        for f, kw in plan:
            for _ in range(20):  # retry until the variant is new
                desc, data = f(M, rng, **kw)
                h = hashlib.sha1(data).hexdigest()
                if h not in seen:
                    break
            else:
                continue
            seen.add(h)
            variants.append((scene, f.__name__[2:], desc, data))
    return variants


def run_variant(i, scene, kind, desc, data):
    path = os.path.join(VAR, "%03d_%s_%s.msh" % (i, scene, kind))
    with open(path, "wb") as f:
        f.write(data)
    return fuzz_case(i, "%s:%s" % (scene, kind), desc, SCENES[scene] + ["-mesh", path, "-contact_monitor", "0"],
                     os.path.join(OUTROOT, "%03d" % i), FAILDIR, ARGS.timeout, inputs=[path], keep=ARGS.keep)


def main():
    return fuzz_main(ARGS, FAILDIR, SCENES, generate, run_variant)

if __name__ == "__main__":
    sys.exit(main())
