"""Fuzz test of -mesh F.h5 (the file -mesh_save writes): corrupted variants
must never crash, hang or print more than the one-line error (issue 22).

Two files are saved by the program first: S2 (patch_uniform.msh, 1 rank) and
Hertz level 0 (hertz_0.msh, saved on 2 ranks: its point numbering is not the
identity). From each, a fixed (seeded) set of variants:
  bytes       truncations (anywhere, in the last tenth), 1-50 bytes flipped,
              a bit flipped, a block zeroed, garbage inserted or appended;
  indices     entries of topology/order, cones, cells, orientation, of a
              label's or the bodies' indices replaced by -1, 0, n - 1, n,
              n + 1, 2^31 - 1, -2^31, a random or repeated index, a point of
              another kind;
  shapes      a dataset shortened, lengthened, of the wrong type or columns,
              removed, or replaced by a group;
  attributes  ngroup, nbody, group dimensions and names, body names, the
              format: out of range, empty, long, control characters, repeated,
              of the wrong type, removed;
  labels      removed, a value renamed or added;
  coordinates nan, inf, 1e300, two vertices swapped, one vertex moved;
  garbage     an empty file, the signature alone, text, random bytes, the
              program's own result .h5 (HDF5, but no mesh).
Each variant runs with its scene's options, every tenth on 2 ranks, two at
a time, with a timeout; the contract is the mesh fuzz test's (m2d.fuzz_case):
exit 0 with the output written, or exit 1 with one error line; anything else
fails the test, and the failing files are kept in WORK/fuzz_h5/failures/.

Options: --seed N, --count N (variants per file, default 150), --jobs N,
--timeout S, --keep."""
import os
import shutil
import sys

import h5py
import numpy as np
from m2d import fuzz_args, fuzz_case, fuzz_main, mesh, opts, run

ARGS, W, VAR, OUTROOT, FAILDIR = fuzz_args("fuzz_h5", 20251125, 150, 30)
SCENES = {"patch_uniform": (["-options_file", opts("patch_uniform"), "-contact_monitor", "0"], mesh("patch_uniform"), 1),
          "hertz_0": (["-options_file", opts("hertz"), "-contact_monitor", "0"], mesh("hertz_0"), 2)}
BIG = [-1, 0, 2 ** 31 - 1, -2 ** 31, 10 ** 9]


class H5:
    """A saved mesh: its bytes and what its datasets hold (for index mutations)."""

    def __init__(self, path):
        self.path = path
        with open(path, "rb") as f:
            self.data = f.read()
        with h5py.File(path, "r") as f:
            self.dsets = []
            f.visititems(lambda n, o: self.dsets.append(n) if isinstance(o, h5py.Dataset) else None)
            self.attrs = dict(f["m2d"].attrs)
            order, size = np.array(f["topology/order"]).ravel(), np.array(f["topology/cones"]).ravel()
        self.np = len(order)
        self.kind = {k: [int(p) for p, s in zip(order, size) if s == k] for k in (0, 2, 4)}
        self.labels = [d for d in self.dsets if d.startswith("labels/")]


def variant(base, name, edit=None, data=None):
    """a copy of base edited with h5py (edit(f, rng)), or these bytes"""
    p = os.path.join(VAR, name)
    if data is not None:
        with open(p, "wb") as f:
            f.write(data)
    else:
        shutil.copy(base.path, p)
        with h5py.File(p, "r+") as f:
            edit(f)
    return p


def replace(f, name, values):
    """dataset name rewritten (dtype and shape as given by values)"""
    del f[name]
    f.create_dataset(name, data=values)


# ---------------------------------------------------------------- mutators: (H5, rng) -> (description, edit or bytes)
def m_truncate(M, r):
    n = r.randrange(len(M.data)) if r.random() < 0.6 else r.randrange(len(M.data) * 9 // 10, len(M.data))
    return "truncate at byte %d of %d" % (n, len(M.data)), M.data[:n]


def m_byte_flips(M, r):
    b = bytearray(M.data)
    n = r.choice([1, 1, 2, 3, 5, 10, 50])
    pos = sorted(r.randrange(len(b)) for _ in range(n))
    for k in pos:
        b[k] = r.randrange(256)
    return "%d byte(s) flipped at %s" % (n, pos[:8]), bytes(b)


def m_bit_flip(M, r):
    b = bytearray(M.data)
    k, bit = r.randrange(len(b)), r.randrange(8)
    b[k] ^= 1 << bit
    return "bit %d flipped at byte %d" % (bit, k), bytes(b)


def m_zero_block(M, r):
    n = r.choice([8, 64, 512, 4096])
    k = r.randrange(max(1, len(M.data) - n))
    return "%d bytes zeroed at %d" % (n, k), M.data[:k] + bytes(n) + M.data[k + n:]


def m_insert(M, r):
    k = r.randrange(len(M.data))
    g = bytes(r.randrange(256) for _ in range(r.choice([1, 7, 100])))
    if r.random() < 0.3:
        return "%d bytes appended" % len(g), M.data + g
    return "%d bytes inserted at %d" % (len(g), k), M.data[:k] + g + M.data[k:]


def index_value(M, r, n):
    kinds = [k for k in M.kind if M.kind[k]]
    return r.choice(BIG + [n - 1, n, n + 1, r.randrange(max(n, 1)), M.np - 1, M.np, M.np + 1, r.choice(M.kind[r.choice(kinds)])])


def m_index(M, r):
    name = r.choice(["topology/order", "topology/cones", "topology/cells", "topology/orientation"] + M.labels * 2)
    k = r.choice([1, 1, 2, 3])
    values = []

    def edit(f):
        a = np.array(f[name])
        flat = a.reshape(-1)
        if not len(flat):
            return
        for _ in range(k):
            i = r.randrange(len(flat))
            v = index_value(M, r, len(flat)) if r.random() < 0.8 else int(flat[r.randrange(len(flat))])
            flat[i] = np.clip(v, np.iinfo(flat.dtype).min, np.iinfo(flat.dtype).max)
            values.append((i, int(flat[i])))
        f[name][...] = a
    edit_desc = "%s: %d entr%s replaced" % (name, k, "y" if k == 1 else "ies")
    return edit_desc, edit


def m_cone_sizes(M, r):
    v = r.choice([0, -1, -4, 1, 3, 5, 2 ** 31 - 1])
    every = r.random() < 0.3

    def edit(f):
        a = np.array(f["topology/cones"])
        if every:
            a[...] = v
        else:
            a.reshape(-1)[r.randrange(a.size)] = v
        f["topology/cones"][...] = a
    return "topology/cones: %s set to %d" % ("every entry" if every else "one entry", v), edit


def m_shape(M, r):
    name = r.choice(M.dsets)
    what = r.choice(["shortened", "lengthened", "as floats", "as integers", "one column", "three columns", "removed", "a group", "empty"])

    def edit(f):
        a = np.array(f[name])
        if what == "shortened":
            replace(f, name, a[: max(0, len(a) - r.choice([1, 2, len(a) // 2 + 1]))])
        elif what == "lengthened":
            replace(f, name, np.concatenate([a, a[: r.choice([1, 3, len(a)])]]))
        elif what == "as floats":
            replace(f, name, a.astype(float) + 0.5)
        elif what == "as integers":
            replace(f, name, a.astype(np.int64))
        elif what == "one column":
            replace(f, name, a.reshape(-1))
        elif what == "three columns":
            replace(f, name, np.repeat(a.reshape(len(a), -1)[:, :1], 3, axis=1))
        elif what == "removed":
            del f[name]
        elif what == "a group":
            del f[name]
            f.create_group(name)
        else:
            replace(f, name, a[:0])
    return "%s %s" % (name, what), edit


def m_attribute(M, r):
    key = r.choice(list(M.attrs))
    old = M.attrs[key]
    if isinstance(old, (bytes, str)):
        others = [v for v in M.attrs.values() if isinstance(v, (bytes, str)) and v != old]
        choices = [b"", b"x" * 300, b"a\x01b", b"a\nb", r.choice(others), old + b"_x", b"m2d:body", np.int32(3)]
    else:
        choices = [np.int32(v) for v in (-1, 0, 1, 2, 3, int(old) + 1, 257, 2 ** 31 - 1)] + [b"2", np.float64(1.5)]
    v = r.choice(choices + ["removed"])

    def edit(f):
        if isinstance(v, str):
            del f["m2d"].attrs[key]
        else:
            f["m2d"].attrs[key] = v
    return "attribute %s: %r -> %r" % (key, old, v if not isinstance(v, bytes) else v[:40]), edit


def m_label(M, r):
    label = r.choice(sorted({"/".join(d.split("/")[:2]) for d in M.labels}))
    what = r.choice(["removed", "value renamed", "value added", "indices doubled"])

    def edit(f):
        g = f[label]
        vals = list(g.keys())
        if what == "removed":
            del f[label]
        elif what == "value renamed":
            g.move(vals[0], str(r.choice([2, 7, -1, 100])))
        elif what == "value added":
            g.copy(vals[0], str(int(vals[-1]) + r.choice([1, 5])))
        else:
            d = "%s/%s/indices" % (label, vals[0])
            a = np.array(f[d])
            replace(f, d, np.concatenate([a, a]))
    return "label %s %s" % (label, what), edit


def m_coordinates(M, r):
    what = r.choice(["nan", "inf", "1e300", "swap", "move", "all equal", "scale 1e-300"])

    def edit(f):
        a = np.array(f["geometry/vertices"])
        i, j = r.randrange(len(a)), r.randrange(len(a))
        if what in ("nan", "inf", "1e300"):
            a[i, r.randrange(2)] = float(what)
        elif what == "swap":
            a[[i, j]] = a[[j, i]]
        elif what == "move":
            a[i] += [r.choice([0.05, -0.3, 2.0]), r.choice([0, 0.05, -0.3])]
        elif what == "all equal":
            a[:] = a[0]
        else:
            a *= 1e-300
        f["geometry/vertices"][...] = a
    return "geometry/vertices: %s" % what, edit


GARBAGE = ["empty", "signature only", "text", "random bytes", "a result file"]


def m_garbage(M, r, what=None):
    what = what or r.choice(GARBAGE)
    if what == "empty":
        return "garbage: empty", b""
    if what == "signature only":
        return "garbage: signature only", M.data[:8]
    if what == "text":
        return "garbage: text", b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    if what == "random bytes":
        return "garbage: random bytes", M.data[:8] + bytes(r.randrange(256) for _ in range(5000))
    with open(RESULT, "rb") as f:
        return "garbage: the program's result .h5", f.read()


MUTATORS = [(m_truncate, 10), (m_byte_flips, 14), (m_bit_flip, 6), (m_zero_block, 5), (m_insert, 3), (m_index, 22),
            (m_cone_sizes, 4), (m_shape, 10), (m_attribute, 10), (m_label, 7), (m_coordinates, 7), (m_garbage, 2)]


def generate(rng, bases):
    variants = []
    for scene, M in bases.items():
        plan = [(f, {}) for f, _ in MUTATORS] + [(m_garbage, {"what": w}) for w in GARBAGE]
        funcs, weights = zip(*MUTATORS)
        plan += [(f, {}) for f in rng.choices(funcs, weights=weights, k=max(0, ARGS.count - len(plan)))]
        for f, kw in plan:
            desc, what = f(M, rng, **kw)
            variants.append((scene, f.__name__[2:], desc, M, what))
    return variants


def run_variant(i, scene, kind, desc, M, what):
    name = "%03d_%s_%s.h5" % (i, scene, kind)
    try:
        p = variant(M, name, edit=what) if callable(what) else variant(M, name, data=what)
    except Exception as e:  # h5py refused the edit itself (e.g. a value that does not fit): the file as it is
        desc += " (edit stopped: %s)" % str(e)[:60]
        p = os.path.join(VAR, name)
    args, _, _ = SCENES[scene]
    ranks = 2 if i % 10 == 3 else 1
    return fuzz_case(i, "%s:%s" % (scene, kind), desc + (" [2 ranks]" if ranks == 2 else ""), args + ["-mesh", p],
                     os.path.join(OUTROOT, "%03d" % i), FAILDIR, ARGS.timeout, ranks=ranks, inputs=[p], keep=ARGS.keep)


def prepare():
    """The scenes' meshes saved as .h5 (the bases of the variants)."""
    global RESULT
    bases = {}
    for scene, (args, msh, ranks) in SCENES.items():
        p = os.path.join(W, scene + ".h5")
        run(args + ["-mesh", msh, "-mesh_save", p, "-output_dir", os.path.join(W, "base_" + scene), "-output_name", "base"], ranks=ranks)
        bases[scene] = H5(p)
    RESULT = os.path.join(W, "base_patch_uniform", "base.h5")
    return (bases,)


def main():
    return fuzz_main(ARGS, FAILDIR, SCENES, generate, run_variant, prepare)

if __name__ == "__main__":
    sys.exit(main())
