"""Every relative link of the documentation resolves. The files: README.md,
docs/*.md and every other markdown file of the tree they link to (e.g.
meshes/README.md).

* A link `[text](path)`, `[text](path#anchor)` or an image `![alt](path)`
  whose target is not a URL (http:, https:, mailto:, ...) names a file or
  folder that exists, relative to the linking file's folder.
* `#anchor` into a markdown file (or `(#anchor)` into the same file) is the
  GitHub slug of one of its headings: lowercase, inline markup dropped, every
  character but letters, digits, spaces, '-' and '_' removed, spaces to '-'; a
  repeated heading's slug gets -1, -2, ...
* A link to a markdown file followed by a section name in italics,
  `[trust.md](trust.md), *the mesh inputs*`, names a heading of that file (or
  the bold start of one of its paragraphs or list items): the name is found in
  one of them, ignoring case.
* A markdown file named in the text without a link (`docs/speed.md`,
  "see trust.md") exists, relative to the naming file's folder or to the
  source tree's root: no file of another repository or an older layout.

Fenced code blocks are skipped; `code spans` are not links (but are read for
named files).
Needs no build: only M2D_SOURCE (default: the parent of this directory)."""
import glob
import os
import re

from m2d import SRC, Tally

LINK = re.compile(r"(!?)\[((?:[^\[\]]|\[[^\]]*\])*)\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
SECTION = re.compile(r"\]\(([^)\s#]+\.md)\)[,:]?\s+\*([^*]+)\*")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
BOLD_LEAD = re.compile(r"^\s*(?:[*+-]\s+|\d+\.\s+)?\*\*(.+?)\*\*")
URL = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")
NAMED = re.compile(r"(?<![\w./-])([\w./-]*\w\.md)\b")


def prose(text, spans=False):
    """The text with fenced code blocks blanked and code spans removed (kept
    with spans=True; line numbers kept)."""
    out, fence = [], None
    for line in text.split("\n"):
        m = re.match(r"^\s*(`{3,}|~{3,})", line)
        if fence is None and m:
            fence = m.group(1)[0] * len(m.group(1))
            out.append("")
        elif fence is not None:
            if line.strip().startswith(fence):
                fence = None
            out.append("")
        else:
            out.append(line if spans else re.sub(r"(`+)(?:(?!\1).)+?\1", "", line))
    return out


def slug(heading):
    """GitHub's anchor for a heading's text."""
    s = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link's text only
    s = s.replace("`", "").lower()
    s = re.sub(r"[^\w\- ]", "", s)  # \w: letters, digits, '_'
    return s.replace(" ", "-")


def headings(path):
    """The heading texts of a markdown file, in order."""
    with open(path, encoding="utf-8") as f:
        lines = prose(f.read(), spans=True)
    return [m.group(2) for m in (HEADING.match(l) for l in lines) if m]


def anchors(path):
    seen, out = {}, set()
    for h in headings(path):
        s = slug(h)
        n = seen.get(s, 0)
        out.add(s if n == 0 else "%s-%d" % (s, n))
        seen[s] = n + 1
    return out


def sections(path):
    """Where an italic section name may point: headings and bold leads."""
    with open(path, encoding="utf-8") as f:
        lines = prose(f.read(), spans=True)
    names = [m.group(2) for m in (HEADING.match(l) for l in lines) if m]
    names += [m.group(1) for m in (BOLD_LEAD.match(l) for l in lines) if m]
    return [n.lower() for n in names]


t = Tally()
todo = [os.path.join(SRC, "README.md")] + sorted(glob.glob(os.path.join(SRC, "docs", "*.md")))
t.check(os.path.isfile(todo[0]) and len(todo) > 3, "README.md and docs/*.md found under %s" % SRC)
done, nlinks, nanchors, nsections, nnamed = set(), 0, 0, 0, 0
while todo:
    path = os.path.realpath(todo.pop(0))
    if path in done:
        continue
    done.add(path)
    rel = os.path.relpath(path, SRC)
    with open(path, encoding="utf-8") as f:
        lines = prose(f.read())
    folder = os.path.dirname(path)
    for no, line in enumerate(lines, 1):
        for m in LINK.finditer(line):
            target = m.group(3)
            if not target or URL.match(target):
                continue
            nlinks += 1
            where = "%s:%d: %s" % (rel, no, m.group(0)[:120])
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(folder, file_part)) if file_part else path
            if not t.check(os.path.exists(dest), "%s: %s exists" % (where, os.path.relpath(dest, SRC))):
                continue
            if dest.endswith(".md") and os.path.isfile(dest):
                todo.append(dest)
                if anchor:
                    nanchors += 1
                    t.check(anchor in anchors(dest), "%s: #%s is a heading of %s" % (where, anchor, os.path.relpath(dest, SRC)),
                            "its anchors: " + ", ".join(sorted(anchors(dest))))
    # markdown files named without a link
    with open(path, encoding="utf-8") as f:
        for no, line in enumerate(prose(f.read(), spans=True), 1):
            for m in NAMED.finditer(LINK.sub("", line)):
                name = m.group(1)
                found = [d for d in (folder, SRC) if os.path.isfile(os.path.join(d, name))]
                nnamed += 1
                t.check(bool(found), "%s:%d: %s names a file of the tree" % (rel, no, name))
    # a section named after a link: [x.md](x.md), *Section*  (the name may run onto the next line)
    joined = " ".join(lines)
    for m in SECTION.finditer(joined):
        dest = os.path.normpath(os.path.join(folder, m.group(1)))
        if not os.path.isfile(dest):
            continue  # reported above
        name = " ".join(m.group(2).split()).lower()
        nsections += 1
        t.check(any(name in s for s in sections(dest)),
                "%s: *%s* names a section of %s" % (rel, m.group(2), os.path.relpath(dest, SRC)))

t.check(nlinks > 20, "%d relative links, %d anchors, %d named sections, %d files named in %d files" % (nlinks, nanchors, nsections, nnamed, len(done)))
t.finish()
