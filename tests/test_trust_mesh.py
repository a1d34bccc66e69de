"""Trust in the mesh inputs (issue 22 items 1-5 and 10, issue 21 item 5): every
check of one way in (.msh, -mesh F.h5, -geo) holds on the others, on 1 and 2
ranks; a refusal is exit 1 with one "mortar2d: error:" line naming the input,
and leaves the input and the previous results as they were.
 1. -mesh F.h5 -mesh_scale s: Hertz level 1 saved by -mesh_save, read back at
    scale 2 with -hertz_radius 2, gives the .msh run's contact force (0.86)
    and pressure error.
 2. A contact (mortar or non-mortar), load or u.n curve with an edge between
    two cells is refused, from a .msh, a .h5 (the label edited) and a .geo
    (a line embedded in the surface).
 3. u.n rollers on one curve holding two perpendicular edges hold the corner
    in x and y: S2 exact (<= 1e-10), as with two curves.
 4. A body in two pieces (one drawn inside the other, or apart) is refused from
    a .msh and a .geo; a contact curve with an element on the other body is
    refused from a .msh and a .h5; one with an element on the far side of its
    body is exact, and so is one that turns round a corner of its body.
 5. .h5 label indices out of range or of the wrong kind, cone sizes 0 or
    negative, orientations, point numbers: refused, never a hang.
10. A corrupted .h5 (truncated, bytes flipped) names the file.
21/5. -geo that is not a regular file (/dev/zero, a directory) or not plane is
    refused; the run's directory TMPDIR/m2d_remesh_* is gone after SIGINT or
    SIGTERM during the adaptive loop and after an error exit, and after SIGKILL
    once the next run has started (a live run's kept); gmsh's memory is bounded
    by -adapt_max_dofs (a .geo asking for 1e9 cells: one line)."""
import hashlib
import json
import os
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np
from m2d import EXE, command, mesh, mpi_env, opts, refusal_problems, run, solve, workdir, Tally

os.environ["OMPI_MCA_orte_execute_quiet"] = "1"
W = workdir("trust_mesh")
T = Tally()
S2 = ["-options_file", opts("patch_uniform"), "-output_vtu", "0", "-contact_monitor", "0", "-output_name", "sol"]
HZ = ["-options_file", opts("hertz"), "-output_vtu", "0", "-contact_monitor", "0", "-output_name", "sol"]
BLOCK = ["-options_file", opts("block"), "-output_vtu", "0", "-output_name", "sol"]


def path(name):
    return os.path.join(W, name)


def refused(name, args, culprits, ranks=1, timeout=120):
    out = path("out_refused")
    rc, _, err = run(args + ["-output_dir", out], ranks=ranks, check=False, timeout=timeout)
    line, problems = refusal_problems(rc, [l for l in err.splitlines() if l.strip()], culprits)
    T.check(not problems, "%s [%d rank%s] refused" % (name, ranks, "s" if ranks > 1 else ""), "; ".join(problems) + (": " if problems else "") + line[:400])


def patch_error(s):
    e = s["error"]
    return max(e["sigma_yy_max_rel"], e["sigma_xx_max_rel"], e["sigma_xy_max_rel"])


# ---------------------------------------------------------------- S2 as msh 2.2, to edit
def grid(x0, y0, x1, y1, nx, ny, t0):
    nodes = {t0 + j * (nx + 1) + i: (x0 + (x1 - x0) * i / nx, y0 + (y1 - y0) * j / ny) for j in range(ny + 1) for i in range(nx + 1)}
    quads = [[t0 + j * (nx + 1) + i, t0 + j * (nx + 1) + i + 1, t0 + (j + 1) * (nx + 1) + i + 1, t0 + (j + 1) * (nx + 1) + i]
             for j in range(ny) for i in range(nx)]
    return nodes, quads


def s2():
    """S2 (patch_uniform.geo): lower 10 x 5 on [0,1]x[0,0.5] (nodes 1..), upper 7 x 5 on [0,1]x[0.5,1] (nodes 1001..)"""
    nodes, lq = grid(0, 0, 1, 0.5, 10, 5, 1)
    un, uq = grid(0, 0.5, 1, 1, 7, 5, 1001)
    nodes.update(un)
    lines = {"lower_bottom": [(1 + i, 2 + i) for i in range(10)], "lower_top": [(56 + i, 57 + i) for i in range(10)],
             "lower_left": [(1 + 11 * j, 12 + 11 * j) for j in range(5)], "lower_right": [(11 + 11 * j, 22 + 11 * j) for j in range(5)],
             "upper_bottom": [(1001 + i, 1002 + i) for i in range(7)], "upper_top": [(1041 + i, 1042 + i) for i in range(7)],
             "upper_left": [(1001 + 8 * j, 1009 + 8 * j) for j in range(5)], "upper_right": [(1008 + 8 * j, 1016 + 8 * j) for j in range(5)]}
    points = {"lower_origin": [1], "lower_corner2": [11], "upper_corner": [1001]}
    return nodes, {"lower": lq, "upper": uq}, lines, points


def write_msh(name, nodes, surfaces, lines, points):
    names = [(2, n) for n in surfaces] + [(1, n) for n in lines] + [(0, n) for n in points]
    tag = {n: i + 1 for i, (_, n) in enumerate(names)}
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    out += ['%d %d "%s"' % (d, tag[n], n) for d, n in names] + ["$EndPhysicalNames", "$Nodes", str(len(nodes))]
    out += ["%d %r %r 0" % (t, float(x), float(y)) for t, (x, y) in sorted(nodes.items())] + ["$EndNodes"]
    els = ["15 2 %d 1 %d" % (tag[n], a) for n, ps in points.items() for a in ps]
    els += ["1 2 %d 1 %d %d" % (tag[n], a, b) for n, ls in lines.items() for a, b in ls]
    els += ["3 2 %d 1 %s" % (tag[n], " ".join(map(str, q))) for n, qs in surfaces.items() for q in qs]
    out += ["$Elements", str(len(els))] + ["%d %s" % (i + 1, e) for i, e in enumerate(els)] + ["$EndElements"]
    with open(path(name), "w") as f:
        f.write("\n".join(out) + "\n")
    return path(name)


def sha(p):
    with open(p, "rb") as f:
        return hashlib.sha1(f.read()).hexdigest()


def saved(name, args, ranks=1):
    """-mesh_save of a run (its mesh as built) to W/name"""
    p = path(name)
    run(args + ["-mesh_save", p, "-output_dir", path("out_save")], ranks=ranks)
    return p


def edited_h5(src, name, edit):
    p = path(name)
    shutil.copy(src, p)
    with h5py.File(p, "r+") as f:
        edit(f)
    return p


def set_entries(f, dset, idx, value):
    d = f[dset]
    a = d[...]
    a.reshape(-1)[idx] = value
    d[...] = a


# ---------------------------------------------------------------- 1. -mesh_scale on .h5
h1 = saved("hertz_1.h5", HZ + ["-mesh", mesh("hertz_1")])
for ranks in (1, 2):
    a = solve("trust_mesh/scale_msh_%d" % ranks, HZ + ["-mesh", mesh("hertz_1"), "-mesh_scale", "2", "-hertz_radius", "2"], ranks)
    b = solve("trust_mesh/scale_h5_%d" % ranks, HZ + ["-mesh", h1, "-mesh_scale", "2", "-hertz_radius", "2"], ranks)
    T.check(abs(abs(b["contact_force_y"]) - 0.86) < 1e-9 and abs(b["contact_force_y"] - a["contact_force_y"]) < 1e-12 * abs(a["contact_force_y"]) and abs(b["pressure_l2_rel"] - a["pressure_l2_rel"]) < 1e-12 and b["hertz_radius"] == 2,
            "item 1, %d rank(s): .h5 with -mesh_scale 2 = .msh: vertical contact force %.12g (.msh %.12g; the load 2 x 0.43), pressure error %.4e (.msh %.4e)"
            % (ranks, b["contact_force_y"], a["contact_force_y"], b["pressure_l2_rel"], a["pressure_l2_rel"]))

# ---------------------------------------------------------------- 2. curves inside a body
n, q, l, p = s2()
good = write_msh("s2.msh", n, q, l, p)
s2h5 = saved("s2.h5", S2 + ["-mesh", good])
for ranks in (1, 2):
    s = solve("trust_mesh/s2_h5_%d" % ranks, S2 + ["-mesh", s2h5], ranks)
    T.check(patch_error(s) < 1e-10, "S2 from its own .h5, %d rank(s): exact to %.1e" % (ranks, patch_error(s)))
inner = {"lower_top": (45, 46), "upper_bottom": (1012, 1013), "upper_top": (1028, 1029)}  # y = 0.4, 0.6, 0.8
for group, opt, why in (("lower_top", "-contact_mortar", "a contact surface"), ("upper_bottom", "-contact_nonmortar", "a contact surface"),
                        ("upper_top", "-pressure", "a load acts on the boundary")):
    n, q, l, p = s2()
    l[group].append(inner[group])
    f = write_msh("inner_%s.msh" % group, n, q, l, p)
    for ranks in (1, 2):
        refused("item 2: an edge inside the body in %s (.msh)" % group, S2 + ["-mesh", f], [opt, "'%s'" % group, "inside body", why], ranks)
# the same in a .h5: the label gets an interior edge of the same body (point numbers as saved)
with h5py.File(s2h5, "r") as f:
    order, size, cells = (np.array(f["topology/" + k]).ravel() for k in ("order", "cones", "cells"))
    xy = np.array(f["geometry/vertices"])
vstart = int(order[size == 0].min())
off = np.concatenate(([0], np.cumsum(size)[:-1]))
edge_at = {}
for i, pnt in enumerate(order):
    if size[i] == 2:
        a, b = sorted(cells[off[i]:off[i] + 2] - vstart)
        edge_at[(round(xy[a][0], 6), round(xy[a][1], 6), round(xy[b][0], 6), round(xy[b][1], 6))] = int(pnt)


def edge_point(x0, y0, x1, y1):
    for (ax, ay, bx, by), e in edge_at.items():
        if {(ax, ay), (bx, by)} == {(round(x0, 6), round(y0, 6)), (round(x1, 6), round(y1, 6))}:
            return e
    raise KeyError((x0, y0, x1, y1))


e_in = edge_point(3 / 7, 0.8, 4 / 7, 0.8)


def add_edge(label, e):
    def edit(f):
        d = f["labels/%s/1/indices" % label]
        a = np.append(d[...].ravel(), e).astype(d.dtype).reshape(-1, 1)
        del f["labels/%s/1/indices" % label]
        f.create_dataset("labels/%s/1/indices" % label, data=a)
    return edit


h5in = edited_h5(s2h5, "inner_upper_top.h5", add_edge("m2d:upper_top", e_in))
for ranks in (1, 2):
    refused("item 2: an edge inside the body in upper_top (.h5)", S2 + ["-mesh", h5in], ["-pressure", "'upper_top'", "inside body 'upper'"], ranks)
# a .geo whose mortar curve holds a line embedded in the surface
GEO_BLOCK = """Point(1) = {0, 0, 0, 0.25}; Point(2) = {1, 0, 0, 0.25}; Point(3) = {1, 1, 0, 0.25}; Point(4) = {0, 1, 0, 0.25};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
%s
Mesh.RecombineAll = 1; Mesh.SubdivisionAlgorithm = 1;
Physical Surface("block") = {1%s}; Physical Curve("bottom") = {1}; Physical Point("origin") = {1};
Physical Curve("top") = {3%s};
"""


def geo(name, extra="", top_extra="", surf_extra=""):
    with open(path(name), "w") as f:
        f.write(GEO_BLOCK % (extra, surf_extra, top_extra))
    return path(name)


GEO = BLOCK + ["-mesh", "", "-adapt", "-adapt_max_steps", "1"]  # no -mesh: the first mesh from the .geo
plain = geo("block.geo")
for ranks in (1, 2):
    s = solve("trust_mesh/geo_block_%d" % ranks, GEO + ["-geo", plain], ranks)
    T.check(patch_error(s) < 1e-10, "the block from a .geo, %d rank(s): exact to %.1e" % (ranks, patch_error(s)))
embedded = geo("block_inner_top.geo", "Point(5) = {0.25, 0.5, 0, 0.25}; Point(6) = {0.75, 0.5, 0, 0.25}; Line(5) = {5, 6}; Line{5} In Surface{1};", ", 5")
for ranks in (1, 2):
    refused("item 2: a line inside the surface in the load's curve (.geo)", GEO + ["-geo", embedded], ["-pressure", "'top'", "inside body 'block'"], ranks)

# ---------------------------------------------------------------- 3. rollers on a corner of one curve
n, q, l, p = s2()
l["lower_bl"] = l["lower_bottom"] + l["lower_left"]
corner = write_msh("corner.msh", n, q, l, p)
for ranks in (1, 2):
    for supports in ("lower_bl:n,upper_left:x", "lower_bottom:n,lower_left:n,upper_left:x"):
        s = solve("trust_mesh/corner_%d" % ranks, S2 + ["-mesh", corner, "-dirichlet", supports], ranks)
        T.check(patch_error(s) < 1e-10, "item 3, %d rank(s), -dirichlet %s: exact to %.1e" % (ranks, supports, patch_error(s)))

# ---------------------------------------------------------------- 4. pieces, elements on the other body
n, q, l, p = s2()
extra = {9001 + k: xy for k, xy in enumerate([(0.3, 0.1), (0.4, 0.1), (0.4, 0.2), (0.3, 0.2)])}
n.update(extra)
q["lower"].append([9001, 9002, 9003, 9004])  # a cell of 'lower' lying on 'lower', sharing no node
nested = write_msh("piece_inside.msh", n, q, l, p)
n, q, l, p = s2()
n.update({9001 + k: (x + 2, y) for k, (x, y) in enumerate(extra.values())})
q["lower"].append([9001, 9002, 9003, 9004])
apart = write_msh("piece_apart.msh", n, q, l, p)
for ranks in (1, 2):
    refused("item 4: a cell of 'lower' inside it, sharing no node (.msh)", S2 + ["-mesh", nested], [nested, "body 'lower'", "more than one piece"], ranks)
    refused("item 4: a cell of 'lower' apart from it (.msh)", S2 + ["-mesh", apart], [apart, "body 'lower'", "more than one piece"], ranks)
inside = geo("block_piece_inside.geo", "Point(5) = {0.3, 0.3, 0, 0.1}; Point(6) = {0.6, 0.3, 0, 0.1}; Point(7) = {0.6, 0.6, 0, 0.1}; Point(8) = {0.3, 0.6, 0, 0.1};"
             "Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5}; Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};",
             surf_extra=", 2")
for ranks in (1, 2):
    refused("item 4: a surface drawn inside the body's surface (.geo)", GEO + ["-geo", inside], [inside, "body 'block'", "more than one piece"], ranks)
for group, opt, far in (("lower_top", "-contact_mortar", (1044, 1045)), ("upper_bottom", "-contact_nonmortar", (4, 5))):
    n, q, l, p = s2()
    l[group][3] = far
    f = write_msh("other_body_%s.msh" % group, n, q, l, p)
    for ranks in (1, 2):
        refused("item 4: an element of %s on the other body (.msh)" % group, S2 + ["-mesh", f], [opt, "'%s'" % group, "more than one body"], ranks)
e_other = edge_point(0.3, 0.0, 0.4, 0.0)  # on lower_bottom
h5o = edited_h5(s2h5, "other_body_upper_bottom.h5", add_edge("m2d:upper_bottom", e_other))
for ranks in (1, 2):
    refused("item 4: an element of upper_bottom on the other body (.h5)", S2 + ["-mesh", h5o], ["-contact_nonmortar", "'upper_bottom'", "more than one body"], ranks)

# an element of a contact curve on the far side of its own body faces nothing and takes no
# part: exact; one round a corner of its body (the side edge at the end of the curve), on
# either side, from a .msh and a .h5, is exact too: at a corner the rows take each edge's
# own normal (before the 45-degree check: exit 0, stress errors 0.16-0.21, the corner node's
# normal averaged the two sides; then refused)
for group, opt, far, side in (("lower_top", "-contact_mortar", (1, 2), (55, 66)), ("upper_bottom", "-contact_nonmortar", (1041, 1042), (1008, 1016))):
    n, q, l, p = s2()
    l[group] = l[group] + [far]
    f = write_msh("far_side_%s.msh" % group, n, q, l, p)
    n, q, l, p = s2()
    l[group] = l[group] + [side]
    g = write_msh("corner_%s.msh" % group, n, q, l, p)
    for ranks in (1, 2):
        s = solve("trust_mesh/far_%s_%d" % (group, ranks), S2 + ["-mesh", f], ranks)
        T.check(patch_error(s) < 1e-10, "item 4, %d rank(s): an element of %s on the far side of its body: exact to %.1e" % (ranks, group, patch_error(s)))
        s = solve("trust_mesh/corner_%s_%d" % (group, ranks), S2 + ["-mesh", g], ranks)
        T.check(patch_error(s) < 1e-10, "item 4, %d rank(s): %s round the corner of its body (.msh): exact to %.1e" % (ranks, group, patch_error(s)))
h5c = edited_h5(s2h5, "corner_upper_bottom.h5", add_edge("m2d:upper_bottom", edge_point(1, 0.5, 1, 0.6)))
for ranks in (1, 2):
    s = solve("trust_mesh/corner_h5_%d" % ranks, S2 + ["-mesh", h5c], ranks)
    T.check(patch_error(s) < 1e-10, "item 4, %d rank(s): upper_bottom round the corner of its body (.h5): exact to %.1e" % (ranks, patch_error(s)))

# ---------------------------------------------------------------- 5, 10. .h5 indices and corruption
nlab = h5py.File(s2h5, "r")["labels/m2d:upper_top/1/indices"].shape[0]
EDITS = [
    ("label index out of range", lambda f: set_entries(f, "labels/m2d:upper_top/1/indices", 0, 99999), ["'m2d:upper_top'", "outside the mesh"]),
    ("label index negative", lambda f: set_entries(f, "labels/m2d:upper_top/1/indices", slice(None), -5), ["'m2d:upper_top'", "outside the mesh"]),
    ("label naming a vertex", lambda f: set_entries(f, "labels/m2d:upper_top/1/indices", 1, vstart), ["'m2d:upper_top'", "not an edge"]),
    ("body label naming an edge", lambda f: set_entries(f, "labels/m2d:body/0/indices", 0, e_in), ["'m2d:body'", "not a cell"]),
    ("cone sizes 0", lambda f: set_entries(f, "topology/cones", slice(None), 0), ["cone sizes add up to 0"]),
    ("a negative cone size", lambda f: set_entries(f, "topology/cones", 3, -4), ["a cone of -4 points"]),
    ("a cone point out of range", lambda f: set_entries(f, "topology/cells", 5, 10 ** 7), ["not an edge"]),
    ("an orientation of 7", lambda f: set_entries(f, "topology/orientation", 2, 7), ["orientation 7"]),
    ("a point numbered twice", lambda f: set_entries(f, "topology/order", 1, int(order[0])), ["twice"]),
    ("a coordinate nan", lambda f: set_entries(f, "geometry/vertices", 7, np.nan), ["not a finite number"]),
    ("ngroup 5000", lambda f: f["m2d"].attrs.modify("ngroup", np.int32(5000)), ["ngroup = 5000"]),  # the cap is 1024 (mesh.h)
]
for name, edit, culprits in EDITS:
    f = edited_h5(s2h5, "h5_%s.h5" % name.replace(" ", "_"), edit)
    for ranks in (1, 2):
        refused("item 5: .h5 with %s" % name, S2 + ["-mesh", f], [f, "is corrupted"] + culprits, ranks, timeout=60)
data = open(s2h5, "rb").read()
trunc = path("h5_truncated.h5")
open(trunc, "wb").write(data[:len(data) // 2])
flipped = bytearray(data)
for k in range(8, 3000, 97):
    flipped[k] ^= 0x5A
flip = path("h5_flipped.h5")
open(flip, "wb").write(bytes(flipped))
for name, f in (("truncated", trunc), ("bytes flipped in its metadata", flip)):
    for ranks in (1, 2):
        refused("item 10: a .h5 %s" % name, S2 + ["-mesh", f], [f], ranks, timeout=60)

# the input and the previous results are left as they were
prev = path("out_prev")
shutil.rmtree(prev, ignore_errors=True)
run(S2 + ["-mesh", good, "-output_dir", prev, "-output_name", "sol"])
# (the summary is the one file a refusal writes: its status says the run failed)
results = lambda: {k: sha(os.path.join(prev, k)) for k in sorted(os.listdir(prev)) if not k.endswith("_summary.json")}
before = results()
bad = path("h5_label index out of range.h5".replace(" ", "_"))
h_bad = sha(bad)
status = []
for args in (S2 + ["-mesh", bad], GEO + ["-geo", inside]):
    rc, _, _ = run(args + ["-output_dir", prev, "-output_name", "sol"], check=False)
    status.append(json.load(open(os.path.join(prev, "sol_summary.json"))).get("status"))
after = results()
T.check(len(before) >= 3 and before == after and sha(bad) == h_bad and status == ["error", "error"],
        "refusals leave the previous results (%d files) and the input byte for byte, the summary says so (%s)" % (len(before), status))

# ---------------------------------------------------------------- issue 21 item 5: -geo inputs, its temporary
for name, g, culprits in (("/dev/zero", "/dev/zero", ["/dev/zero", "not a regular file", "character device"]),
                          ("a directory", W, [W, "not a regular file", "directory"])):
    for ranks in (1, 2):
        refused("-geo %s" % name, GEO + ["-geo", g], culprits, ranks, timeout=60)
tilted = path("block_tilted.geo")
with open(tilted, "w") as f:
    f.write(GEO_BLOCK.replace("Point(3) = {1, 1, 0,", "Point(3) = {1, 1, 0.2,") % ("", "", ""))
for ranks in (1, 2):
    refused("-geo not plane", GEO + ["-geo", tilted], [tilted, "plane meshes"], ranks)
TMP = path("tmpdir")


def leftovers():
    return [f for f in os.listdir(TMP) if f.startswith("m2d_remesh_")]


def fresh_tmp():
    shutil.rmtree(TMP, ignore_errors=True)
    os.makedirs(TMP)


def gmsh_of(pid, parent=True):
    """the program's live processes (not zombies) in the session of pid (its children, when parent): gmsh's is a fork of it"""
    return subprocess.run(["pgrep", "-x", "-r", "D,R,S,T", "-P" if parent else "-s", str(pid), os.path.basename(EXE)], capture_output=True, text=True).stdout.split()


def start_adapt():
    """hertz_adapt asked for more than it reaches, in its own session; the process once the remesh directory exists, or None"""
    proc = subprocess.Popen(command(ADAPT), cwd=W, env=mpi_env(TMPDIR=TMP), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    t0 = time.time()
    while proc.poll() is None and time.time() - t0 < 120:  # the directory exists from the first remeshing on
        if leftovers():
            return proc
        time.sleep(0.002)
    proc.kill()
    proc.communicate()
    return None


ADAPT = ["-options_file", opts("hertz_adapt"), "-adapt_target", "0.0002", "-adapt_max_dofs", "400000", "-output_dir", path("out_sig")]
for sig in (signal.SIGINT, signal.SIGTERM):
    fresh_tmp()
    proc = start_adapt()
    if proc:
        t0 = time.time()
        while not gmsh_of(proc.pid) and time.time() - t0 < 60:  # while gmsh meshes
            time.sleep(0.001)
        proc.send_signal(sig)
        try:
            _, err = proc.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            proc.kill()
            _, err = proc.communicate()
        lines = [l for l in err.decode(errors="replace").splitlines() if l.strip()]
    T.check(proc and proc.returncode == 1 and not leftovers() and len(lines) == 1 and "interrupted by %s" % sig.name in lines[0],
            "%s during the adaptive loop: exit %s, no m2d_remesh_* left (%s), %s" % (sig.name, proc and proc.returncode, leftovers(), proc and lines))
# SIGKILL while gmsh meshes (nothing of the program runs): its directory stays
# until the next run starts, which removes it (nobody holds its lock); gmsh's
# process ends with it. A run alive meanwhile keeps its own.
fresh_tmp()
live, dead = start_adapt(), start_adapt()
if live and dead:
    t0 = time.time()
    # the moment gmsh meshes for the second run: its own directory made (a child
    # named like the program before that is Open MPI's daemon between fork and exec)
    while not (len(leftovers()) >= 2 and gmsh_of(dead.pid)) and time.time() - t0 < 60:
        time.sleep(0.001)
    os.kill(dead.pid, signal.SIGKILL)
    dead.wait()
    time.sleep(0.3)
    before = leftovers()
    gmsh_left = gmsh_of(dead.pid, parent=False)
    rc, _, err = run(S2 + ["-mesh", mesh("patch_uniform"), "-output_dir", path("out_next")], check=False, env={"TMPDIR": TMP})
    after = leftovers()
    live.send_signal(signal.SIGTERM)
    live.communicate(timeout=60)
    T.check(len(before) == 2 and rc == 0 and len(after) == 1 and not gmsh_left and not leftovers(),
            "SIGKILL during the adaptive loop: %s left, no process of it left (%s); the next run (exit %d) removes the dead run's and keeps the live one's (%s); that one gone at its end" % (before, gmsh_left, rc, after))
else:
    T.check(False, "SIGKILL during the adaptive loop: the runs did not reach their first remeshing")
fresh_tmp()
withx = geo("block_x.geo", "x = 0.5;")  # (a -geo_setnumber name the .geo never uses is refused before gmsh runs)
rc, _, err = run(GEO + ["-geo", withx, "-geo_setnumber", "x=1", "-output_dir", path("out_x")], check=False, env={"TMPDIR": TMP})
typo = geo("block_typo.geo", "x = 0.5; Line(9) = {1, 77};")
rc2, _, err2 = run(GEO + ["-geo", typo, "-geo_setnumber", "x=1", "-output_dir", path("out_x")], check=False, env={"TMPDIR": TMP})
T.check(rc == 0 and rc2 == 1 and not leftovers(), "no m2d_remesh_* left after a run with -geo_setnumber (exit %d) and after a gmsh error (exit %d): %s" % (rc, rc2, err2.strip()[:200]))
# a .geo asking for 1e9 cells under -adapt_max_dofs 1000: gmsh's memory is bounded by the cap's mesh
for ranks in (1, 2):
    refused("-geo_setnumber nlx=1e9 -adapt_max_dofs 1000", ["-options_file", opts("seed_patch_adapt"), "-geo_setnumber", "nlx=1e9", "-adapt_max_dofs", "1000"],
            ["seed_patch.geo", "MB allowed for a mesh of at most 500 nodes", "-adapt_max_dofs"], ranks, timeout=60)
T.finish()
